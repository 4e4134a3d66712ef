#include "render/hdr_photo_set.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <exception>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "hdr/exposure_stack.h"
#include "io/atomic_file.h"
#include "io/exr.h"
#include "io/image.h"
#include "io/workspace.h"

namespace hdribr::render {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// File-name-safe stem of a view name ("sub/dir/a.jpg" -> "sub_dir_a").
std::string SafeStem(const std::string& name) {
  std::string stem = fs::path(name).replace_extension().string();
  for (char& c : stem) {
    if (c == '/' || c == '\\' || c == ' ' || c == ':') c = '_';
  }
  return stem.empty() ? "view" : stem;
}

json ViewToJson(const HdrSetView& v) {
  const Camera& c = v.view.camera;
  const Eigen::Quaterniond& q = v.view.cam_from_world.rotation;
  const Eigen::Vector3d& t = v.view.cam_from_world.translation;
  json j = {{"name", v.view.name},
            {"radiance", v.radiance_file},
            {"aligned", v.aligned_files},
            {"masks", v.mask_files},
            {"valid_fraction", v.valid_fraction},
            {"width", c.width},
            {"height", c.height},
            {"fx", c.fx()},
            {"fy", c.fy()},
            {"cx", c.cx()},
            {"cy", c.cy()},
            {"cam_from_world",
             {{"qvec", {q.w(), q.x(), q.y(), q.z()}}, {"tvec", {t.x(), t.y(), t.z()}}}}};
  j["photo_index"] = v.photo_index;
  return j;
}

HdrSetView ViewFromJson(const json& j, const fs::path& index) {
  try {
    HdrSetView v;
    v.view.name = j.at("name").get<std::string>();
    v.radiance_file = j.at("radiance").get<std::string>();
    v.aligned_files = j.value("aligned", std::vector<std::string>{});
    v.mask_files = j.value("masks", std::vector<std::string>{});
    v.valid_fraction = j.value("valid_fraction", 0.0);
    v.photo_index = j.value("photo_index", -1);
    const int w = j.at("width").get<int>(), h = j.at("height").get<int>();
    if (w <= 0 || h <= 0) throw InputError(index, "view '" + v.view.name + "' has no size");
    v.view.camera = Camera::Pinhole(-1, w, h, j.at("fx").get<double>(), j.at("fy").get<double>(),
                                    j.at("cx").get<double>(), j.at("cy").get<double>());
    const auto q = j.at("cam_from_world").at("qvec").get<std::vector<double>>();
    const auto t = j.at("cam_from_world").at("tvec").get<std::vector<double>>();
    if (q.size() != 4 || t.size() != 3) throw InputError(index, "bad cam_from_world");
    v.view.cam_from_world.rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    v.view.cam_from_world.translation = Eigen::Vector3d(t[0], t[1], t[2]);
    if (!IsValidRotation(v.view.cam_from_world.rotation)) {
      throw InputError(index, "view '" + v.view.name + "' has a non-unit quaternion");
    }
    return v;
  } catch (const json::exception& e) {
    throw InputError(index, std::string("bad view entry: ") + e.what());
  }
}

fs::path SetFolder(const fs::path& folder) {
  if (fs::exists(folder / kHdrSetIndex)) return folder;
  if (fs::exists(folder / kHdrSetFolder / kHdrSetIndex)) return folder / kHdrSetFolder;
  return folder.filename() == kHdrSetFolder ? folder : folder / kHdrSetFolder;
}

}  // namespace

HdrPhotoSet PlanHdrPhotoSet(const Scene& scene, const HdrPhotoSetOptions& options) {
  const int n_series = static_cast<int>(scene.series.size());
  if (n_series < 2) {
    throw UsageError("workspace " + scene.workspace.string() + " has " + std::to_string(n_series) +
                     " exposure series: HDR needs at least two (see series.json)");
  }
  if (!(options.scale > 0 && options.scale <= 4)) throw UsageError("scale must be in (0, 4]");
  HdrPhotoSet set;
  set.folder =
      fs::absolute(options.output.empty() ? scene.workspace / kHdrSetFolder : options.output);
  for (const ExposureSeries& s : scene.series) {
    set.series_names.push_back(s.name);
    set.series_exposures.push_back(s.relative_exposure);
    if (!(s.relative_exposure > 0) || !std::isfinite(s.relative_exposure)) {
      throw UsageError("series '" + s.name + "' has no positive relative exposure");
    }
  }
  for (int a = 0; a < n_series; ++a) {
    for (int b = a + 1; b < n_series; ++b) {
      if (std::abs(std::log2(set.series_exposures[a] / set.series_exposures[b])) < 1e-3) {
        throw UsageError("series '" + set.series_names[a] + "' and '" + set.series_names[b] +
                         "' have the same exposure: nothing to merge");
      }
    }
  }

  double log_sum = 0;
  for (double t : set.series_exposures) log_sum += std::log(t);
  set.radiance_scale = std::exp(log_sum / n_series);

  // Reference viewpoints.
  std::vector<HdrSetView> views;
  if (!options.views.empty()) {
    for (const View& v : options.views) {
      HdrSetView hv;
      hv.view = v;
      hv.photo_index = scene.FindPhoto(v.name);
      views.push_back(hv);
    }
  } else {
    const int ref = options.reference_series < 0 ? n_series / 2 : options.reference_series;
    if (ref >= n_series) {
      throw UsageError("reference series " + std::to_string(ref) + " does not exist (" +
                       std::to_string(n_series) + " series)");
    }
    set.reference_series = ref;
    for (int idx : scene.series[ref].photo_indices) {
      const Photo& p = scene.photos[idx];
      HdrSetView hv;
      hv.view = View{p.name, scene.CameraOf(p), p.cam_from_world};
      hv.photo_index = idx;
      views.push_back(hv);
    }
  }
  if (views.empty()) throw UsageError("no reference viewpoint to build an HDR photo set from");
  for (HdrSetView& v : views) {
    const int w = std::max(1, static_cast<int>(std::lround(v.view.camera.width * options.scale)));
    const int h = std::max(1, static_cast<int>(std::lround(v.view.camera.height * options.scale)));
    v.view.camera = v.view.camera.Scaled(w, h);
  }

  set.views = std::move(views);
  return set;
}

HdrPhotoSet WriteHdrPhotoSet(HdrPhotoSet set, const std::vector<ExposureStack>& stacks,
                             const HdrPhotoSetOptions& options,
                             const std::vector<std::vector<cv::Mat>>& sample_masks) {
  const int n_series = static_cast<int>(set.series_names.size());
  HDRIBR_CHECK(stacks.size() == set.views.size() && n_series >= 2);
  std::vector<HdrSetView>& views = set.views;
  std::vector<std::vector<cv::Mat>> images(views.size()), masks(views.size());
  for (size_t i = 0; i < views.size(); ++i) {
    stacks[i].Validate();
    HDRIBR_CHECK(static_cast<int>(stacks[i].images.size()) == n_series &&
                 stacks[i].masks.size() == stacks[i].images.size());
    images[i] = stacks[i].images;
    masks[i] = stacks[i].masks;
  }
  HDRIBR_CHECK(sample_masks.empty() || sample_masks.size() == views.size());
  // Response: given, or calibrated from all reference stacks side by side (one mosaic per
  // series, so that samples spread over every view; masks keep only all-series-valid pixels).
  ResponseCurve response;
  if (options.response_file) {
    response = ReadResponseCurve(*options.response_file);
  } else {
    ExposureStack mosaic;
    mosaic.times = set.series_exposures;
    long overlap = 0;
    for (int s = 0; s < n_series; ++s) {
      std::vector<cv::Mat> row_images, row_masks;
      for (size_t i = 0; i < views.size(); ++i) {
        // Views may differ in size: pad to the tallest with invalid pixels.
        row_images.push_back(images[i][s]);
        row_masks.push_back(sample_masks.empty() ? masks[i][s] : sample_masks[i][s]);
      }
      int max_h = 0;
      for (const cv::Mat& m : row_images) max_h = std::max(max_h, m.rows);
      for (size_t i = 0; i < row_images.size(); ++i) {
        const int pad = max_h - row_images[i].rows;
        if (pad > 0) {
          cv::copyMakeBorder(row_images[i], row_images[i], 0, pad, 0, 0, cv::BORDER_CONSTANT);
          cv::copyMakeBorder(row_masks[i], row_masks[i], 0, pad, 0, 0, cv::BORDER_CONSTANT);
        }
      }
      cv::Mat img, mask;
      cv::hconcat(row_images, img);
      cv::hconcat(row_masks, mask);
      mosaic.images.push_back(img);
      mosaic.masks.push_back(mask);
    }
    cv::Mat all = mosaic.masks[0].clone();
    for (int s = 1; s < n_series; ++s) cv::bitwise_and(all, mosaic.masks[s], all);
    overlap = cv::countNonZero(all);
    if (overlap == 0) {
      throw UsageError(
          "no pixel of the reference views is valid in all " + std::to_string(n_series) +
          " series: the series do not overlap, cannot calibrate (give a response curve)");
    }
    CalibrationStats stats;
    response = CalibrateDebevec(mosaic, options.calibration, &stats);
    spdlog::info(
        "calibrated the response from {} views x {} series ({} overlapping pixels, "
        "{}/{}/{} samples B/G/R)",
        views.size(), n_series, overlap, stats.samples_used[0], stats.samples_used[1],
        stats.samples_used[2]);
  }
  fs::create_directories(set.folder);
  WriteResponseCurve(set.folder / set.response_file, response);

  // Merge (eq. 7) per view; write EXR and aligned exports.
  for (size_t i = 0; i < views.size(); ++i) {
    HdrSetView& hv = views[i];
    const std::string stem = SafeStem(hv.view.name);
    ExposureStack stack;
    stack.images = images[i];
    stack.masks = masks[i];
    stack.times = set.series_exposures;
    cv::Mat valid;
    cv::Mat radiance = MergeDebevec(stack, response, &valid);
    cv::patchNaNs(radiance, 0.0);
    radiance *= set.radiance_scale;
    cv::min(radiance, 65504.0, radiance);  // half's largest finite value
    hv.radiance_file = "radiance/" + stem + ".exr";
    fs::create_directories(set.folder / "radiance");
    WriteExrWithMask(set.folder / hv.radiance_file, radiance, valid, "valid", ExrPixel::kHalf);
    hv.valid_fraction = static_cast<double>(cv::countNonZero(valid)) / valid.total();
    hv.aligned_files.clear();
    hv.mask_files.clear();
    if (options.export_aligned) {
      for (int s = 0; s < n_series; ++s) {
        const std::string dir = "aligned/" + SafeStem(set.series_names[s]);
        fs::create_directories(set.folder / dir);
        hv.aligned_files.push_back(dir + "/" + stem + ".png");
        hv.mask_files.push_back(dir + "/" + stem + "_mask.png");
        WriteImage(set.folder / hv.aligned_files.back(), images[i][s]);
        WriteImage(set.folder / hv.mask_files.back(), masks[i][s]);
      }
    }
  }

  json series = json::array();
  for (int s = 0; s < n_series; ++s) {
    series.push_back(
        {{"name", set.series_names[s]}, {"relative_exposure", set.series_exposures[s]}});
  }
  json jviews = json::array();
  for (const HdrSetView& v : set.views) jviews.push_back(ViewToJson(v));
  json doc = {{"format", "hdribr-hdr-set"},
              {"version", 1},
              {"series", series},
              {"reference_series", set.reference_series},
              {"response", set.response_file},
              {"radiance_scale", set.radiance_scale},
              {"views", jviews}};
  WriteFileAtomic(set.folder / kHdrSetIndex, doc.dump(2) + "\n");
  return set;
}

HdrPhotoSet ReadHdrPhotoSet(const fs::path& folder) {
  HdrPhotoSet set;
  set.folder = fs::absolute(SetFolder(folder));
  const fs::path index = set.folder / kHdrSetIndex;
  if (!fs::exists(index)) {
    throw InputError(index, "no HDR photo set here (run `hdribr hdr` on the workspace first)");
  }
  json doc;
  try {
    doc = json::parse(ReadFileToString(index));
  } catch (const json::exception& e) {
    throw InputError(index, std::string("bad JSON: ") + e.what());
  }
  try {
    if (doc.value("format", "") != "hdribr-hdr-set") {
      throw InputError(index, "not an HDR photo set index (format must be 'hdribr-hdr-set')");
    }
    for (const json& s : doc.at("series")) {
      set.series_names.push_back(s.at("name").get<std::string>());
      set.series_exposures.push_back(s.at("relative_exposure").get<double>());
    }
    set.reference_series = doc.value("reference_series", -1);
    set.response_file = doc.value("response", std::string("response.json"));
    set.radiance_scale = doc.value("radiance_scale", 1.0);
    if (!(set.radiance_scale > 0) || !std::isfinite(set.radiance_scale)) {
      throw InputError(index, "radiance_scale must be positive");
    }
    for (const json& v : doc.at("views")) set.views.push_back(ViewFromJson(v, index));
  } catch (const json::exception& e) {
    throw InputError(index, std::string("bad HDR photo set index: ") + e.what());
  }
  if (set.views.empty()) throw InputError(index, "the HDR photo set has no views");
  return set;
}

LoadedHdrPhotoSet LoadHdrPhotoSet(const Scene& scene, const fs::path& folder) {
  LoadedHdrPhotoSet out;
  out.index = ReadHdrPhotoSet(folder);
  out.response = ReadResponseCurve(out.index.folder / out.index.response_file);
  out.scene.workspace = scene.workspace;
  out.scene.points = scene.points;
  ExposureSeries series;
  series.id = 0;
  series.name = "hdr";
  series.relative_exposure = 1.0;
  int next_camera_id = 1;
  for (const auto& [id, cam] : scene.cameras) next_camera_id = std::max(next_camera_id, id + 1);
  for (size_t i = 0; i < out.index.views.size(); ++i) {
    const HdrSetView& v = out.index.views[i];
    const fs::path file = out.index.folder / v.radiance_file;
    cv::Mat radiance = ReadExr(file);
    if (radiance.type() != CV_32FC3) throw InputError(file, "expected an RGB radiance EXR");
    if (radiance.cols != v.view.camera.width || radiance.rows != v.view.camera.height) {
      throw InputError(file, "size differs from the set index");
    }
    cv::patchNaNs(radiance, 0.0);
    cv::Mat valid = ReadExrMask(file, "valid", radiance.size());
    Camera camera = v.view.camera;
    camera.id = next_camera_id++;
    out.scene.cameras[camera.id] = camera;
    Photo photo;
    photo.id = static_cast<int>(i) + 1;
    photo.name = v.view.name;
    photo.image_path = file;
    photo.camera_id = camera.id;
    photo.cam_from_world = v.view.cam_from_world;
    photo.series_id = 0;
    series.photo_indices.push_back(static_cast<int>(i));
    out.scene.photos.push_back(photo);
    out.images.push_back(radiance);
    out.valid.push_back(valid);
  }
  out.scene.series.push_back(series);
  out.scene.UpdateDerived();
  return out;
}

LoadedHdrPhotoSet LoadHdrPhotoSet(const fs::path& workspace) {
  return LoadHdrPhotoSet(LoadWorkspace(workspace), workspace / kHdrSetFolder);
}

}  // namespace hdribr::render
