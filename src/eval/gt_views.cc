#include "eval/gt_views.h"

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/colmap_model.h"
#include "io/exr.h"

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
    v.depth_path = dir / "depth" / (v.name + ".exr");
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

cv::Mat NormalsFromDepth(const cv::Mat& depth, const Camera& camera) {
  HDRIBR_CHECK(depth.type() == CV_32FC1);
  const int w = depth.cols, h = depth.rows;
  auto point = [&](int x, int y) {
    return Eigen::Vector3d(camera.CamFromPixel({x + 0.5, y + 0.5}) *
                           static_cast<double>(depth.at<float>(y, x)));
  };
  // The neighbour (at +-1 along one axis) with depth closest to z, as a difference vector.
  auto tangent = [&](int x, int y, int dx, int dy) -> std::optional<Eigen::Vector3d> {
    const float z = depth.at<float>(y, x);
    std::optional<Eigen::Vector3d> best;
    float best_gap = 0;
    for (int s : {-1, 1}) {
      const int u = x + s * dx, v = y + s * dy;
      if (u < 0 || v < 0 || u >= w || v >= h) continue;
      const float zn = depth.at<float>(v, u);
      if (zn <= 0) continue;
      const float gap = std::abs(zn - z);
      if (best && gap >= best_gap) continue;
      best = (point(u, v) - point(x, y)) * s;
      best_gap = gap;
    }
    return best;
  };
  cv::Mat normal(depth.size(), CV_32FC3, cv::Scalar::all(0));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (depth.at<float>(y, x) <= 0) continue;
      const Eigen::Vector3d ray = camera.CamFromPixel({x + 0.5, y + 0.5}).normalized();
      const auto tx = tangent(x, y, 1, 0), ty = tangent(x, y, 0, 1);
      Eigen::Vector3d n = -ray;
      if (tx && ty && tx->cross(*ty).norm() > 0) n = tx->cross(*ty).normalized();
      if (n.dot(ray) > 0) n = -n;
      normal.at<cv::Vec3f>(y, x) = cv::Vec3f(float(n.x()), float(n.y()), float(n.z()));
    }
  }
  return normal;
}

std::filesystem::path FindGtCapture(const Scene& scene, const std::filesystem::path& capture_dir) {
  const std::filesystem::path capture =
      capture_dir.empty() ? scene.workspace.parent_path() : capture_dir;
  const std::filesystem::path gt = capture / "gt";
  if (!IsColmapModelDir(gt) || !std::filesystem::is_directory(gt / "depth")) return {};
  const ColmapModel model = ReadColmapModel(gt);
  std::map<std::string, Rigid3d> poses;
  for (const auto& [id, image] : model.images) poses[image.name] = image.cam_from_world;
  for (const Photo& photo : scene.photos) {
    const auto it = poses.find(photo.name);
    if (it == poses.end()) return {};
    const Rigid3d d = it->second * photo.cam_from_world.Inverse();
    if (d.translation.norm() > 1e-6 * std::max(scene.scene_scale, 1e-12) ||
        d.rotation.angularDistance(Eigen::Quaterniond::Identity()) > 1e-6) {
      return {};
    }
  }
  return capture;
}

std::vector<cv::Mat> ReadGtPhotoDepths(const Scene& scene, const std::filesystem::path& capture) {
  std::vector<cv::Mat> depths;
  for (const Photo& photo : scene.photos) {
    const std::filesystem::path path =
        capture / "gt" / "depth" / (std::filesystem::path(photo.name).stem().string() + ".exr");
    if (!std::filesystem::exists(path)) throw InputError(path, "ground-truth depth missing");
    cv::Mat d = ReadExr(path);
    if (d.type() != CV_32FC1) throw InputError(path, "expected a single-channel depth map");
    depths.push_back(std::move(d));
  }
  return depths;
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
