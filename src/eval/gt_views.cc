#include "eval/gt_views.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/colmap_model.h"

namespace hdribr::eval {

std::vector<GtView> ReadGtNovelViews(const std::filesystem::path& capture_dir) {
  const std::filesystem::path dir = capture_dir / "gt" / "novel";
  if (!IsColmapModelDir(dir)) {
    throw InputError(dir, "no ground-truth novel views (a COLMAP model from `hdribr synth`)");
  }
  const ColmapModel model = ReadColmapModel(dir);
  std::vector<GtView> views;
  for (const auto& [id, image] : model.images) {
    GtView v;
    v.name = std::filesystem::path(image.name).stem().string();
    const auto cam = model.cameras.find(image.camera_id);
    if (cam == model.cameras.end()) {
      throw InputError(dir, "image '" + image.name + "' has an unknown camera id");
    }
    v.camera = cam->second;
    v.cam_from_world = image.cam_from_world;
    v.radiance_path = dir / "radiance" / (v.name + ".exr");
    if (!std::filesystem::exists(v.radiance_path)) {
      throw InputError(v.radiance_path, "ground-truth radiance missing");
    }
    views.push_back(v);
  }
  if (views.empty()) throw InputError(dir, "no novel views in the model");
  return views;
}

synth::SyntheticResponse ReadCaptureResponse(const std::filesystem::path& capture_dir) {
  const std::filesystem::path path = capture_dir / "gt" / "capture.json";
  synth::SyntheticResponse r;
  try {
    const nlohmann::json j = nlohmann::json::parse(ReadFileToString(path));
    const nlohmann::json& resp = j.at("response");
    for (int c = 0; c < 3; ++c) {
      r.gamma[static_cast<size_t>(c)] = resp.at("gamma_bgr").at(static_cast<size_t>(c));
      r.knee[static_cast<size_t>(c)] = resp.at("knee_bgr").at(static_cast<size_t>(c));
    }
    r.x_sat = resp.at("x_sat");
    r.toe = resp.value("toe", 0.0);  // captures made before the toe: a pure power law
    r.shot = resp.value("noise_shot", r.shot);
    r.read = resp.value("noise_read", r.read);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, std::string("not a capture description: ") + e.what());
  }
  if (!(r.x_sat > 0)) throw InputError(path, "response x_sat must be positive");
  if (!(r.toe >= 0 && r.toe < 1)) throw InputError(path, "response toe must be in [0, 1)");
  return r;
}

cv::Mat RadianceToLdr(const cv::Mat& radiance, const synth::SyntheticResponse& response,
                      double time_s) {
  HDRIBR_CHECK(radiance.type() == CV_32FC3);
  cv::Mat out(radiance.size(), CV_8UC3);
  for (int y = 0; y < radiance.rows; ++y) {
    const auto* l = radiance.ptr<cv::Vec3f>(y);
    auto* z = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < radiance.cols; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double exposure = std::max(0.0, static_cast<double>(l[x][c])) * time_s;
        z[x][c] = static_cast<std::uint8_t>(std::lround(response.ValueFromExposure(c, exposure)));
      }
    }
  }
  return out;
}

}  // namespace hdribr::eval
