#include "io/camera_spec.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr {
namespace {

using nlohmann::json;

// Camera file fields of a json object (docs/formats.md "Camera file"); `where` names the
// file in errors.
View ViewFromJson(const json& j, const std::filesystem::path& where) {
  View view;
  view.camera = Camera::Pinhole(0, j.at("width").get<int>(), j.at("height").get<int>(),
                                j.at("fx").get<double>(), j.at("fy").get<double>(),
                                j.at("cx").get<double>(), j.at("cy").get<double>());
  const auto q = j.at("cam_from_world").at("qvec").get<std::vector<double>>();
  const auto t = j.at("cam_from_world").at("tvec").get<std::vector<double>>();
  if (q.size() != 4 || t.size() != 3) throw InputError(where, "qvec needs 4 and tvec 3 numbers");
  for (double v : q) {
    if (!std::isfinite(v)) throw InputError(where, "qvec has a non-finite number");
  }
  for (double v : t) {
    if (!std::isfinite(v)) throw InputError(where, "tvec has a non-finite number");
  }
  const Camera& cam = view.camera;
  if (cam.width <= 0 || cam.height <= 0 || !(cam.fx() > 0) || !(cam.fy() > 0) ||
      !std::isfinite(cam.cx()) || !std::isfinite(cam.cy()) || !std::isfinite(cam.fx()) ||
      !std::isfinite(cam.fy())) {
    throw InputError(where, "width, height, fx and fy must be positive (and all finite)");
  }
  if (cam.width > 16384 || cam.height > 16384) {
    throw InputError(where, "width and height must be at most 16384");
  }
  view.cam_from_world = Rigid3d(Eigen::Quaterniond(q[0], q[1], q[2], q[3]), {t[0], t[1], t[2]});
  if (!IsValidRotation(view.cam_from_world.rotation)) {
    throw InputError(where, "qvec is not a unit quaternion");
  }
  view.cam_from_world.rotation.normalize();
  if (j.contains("name")) view.name = j.at("name").get<std::string>();
  return view;
}

json ViewToJson(const View& view) {
  const Eigen::Quaterniond& q = view.cam_from_world.rotation;
  const Eigen::Vector3d& t = view.cam_from_world.translation;
  json j;
  if (!view.name.empty()) j["name"] = view.name;
  j["width"] = view.camera.width;
  j["height"] = view.camera.height;
  j["fx"] = view.camera.fx();
  j["fy"] = view.camera.fy();
  j["cx"] = view.camera.cx();
  j["cy"] = view.camera.cy();
  j["cam_from_world"] = {{"qvec", {q.w(), q.x(), q.y(), q.z()}}, {"tvec", {t.x(), t.y(), t.z()}}};
  return j;
}

// Parses "QW QX QY QZ TX TY TZ [CAMERA_ID [NAME]]"; false when it is not 7+ numbers.
bool ParsePoseLine(const std::string& spec, const Scene& scene, View& view) {
  std::istringstream in(spec);
  double v[7];
  for (double& x : v) {
    if (!(in >> x)) return false;
  }
  for (double x : v) {
    if (!std::isfinite(x)) throw UsageError("camera spec '" + spec + "': non-finite number");
  }
  std::string id_text, name, extra;
  in >> id_text >> name >> extra;
  if (!extra.empty()) {
    throw UsageError("camera spec '" + spec +
                     "': expected QW QX QY QZ TX TY TZ [CAMERA_ID [NAME]]");
  }
  int camera_id = -1;
  if (!id_text.empty()) {
    size_t used = 0;
    try {
      camera_id = std::stoi(id_text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != id_text.size()) {
      throw UsageError("camera spec '" + spec + "': CAMERA_ID '" + id_text + "' is not an integer");
    }
    if (scene.cameras.count(camera_id) == 0) {
      throw UsageError("camera spec '" + spec + "': unknown camera id " + id_text);
    }
  } else if (!scene.photos.empty()) {
    camera_id = scene.photos.front().camera_id;
  } else if (!scene.cameras.empty()) {
    camera_id = scene.cameras.begin()->first;
  } else {
    throw UsageError("camera spec '" + spec + "': the scene has no camera to take intrinsics from");
  }
  view.camera = scene.cameras.at(camera_id);
  view.cam_from_world = Rigid3d(Eigen::Quaterniond(v[0], v[1], v[2], v[3]), {v[4], v[5], v[6]});
  if (!IsValidRotation(view.cam_from_world.rotation)) {
    throw UsageError("camera spec '" + spec + "': QW QX QY QZ is not a unit quaternion");
  }
  view.cam_from_world.rotation.normalize();
  view.name = name.empty() ? "view" : name;
  return true;
}

}  // namespace

View ParseCameraSpec(const std::string& spec, const Scene& scene) {
  if (spec.empty()) throw UsageError("empty camera spec");
  const int photo = scene.FindPhoto(spec);
  if (photo >= 0) {
    const Photo& p = scene.photos[static_cast<size_t>(photo)];
    return View{p.name, scene.CameraOf(p), p.cam_from_world};
  }
  View view;
  if (ParsePoseLine(spec, scene, view)) return view;
  const std::filesystem::path path(spec);
  std::error_code ec;
  if (path.extension() == ".json" || std::filesystem::is_regular_file(path, ec)) {
    return ReadCameraFile(path);
  }
  throw UsageError("camera spec '" + spec +
                   "' is neither a photo of the scene, a pose line \"QW QX QY QZ TX TY TZ "
                   "[CAMERA_ID [NAME]]\" nor a camera file");
}

View ReadCameraFile(const std::filesystem::path& path) {
  const std::string text = ReadFileToString(path);
  try {
    View view = ViewFromJson(json::parse(text), path);
    if (view.name.empty()) view.name = path.stem().string();
    return view;
  } catch (const json::exception& e) {
    throw InputError(path, std::string("bad camera file: ") + e.what());
  }
}

void WriteCameraFile(const std::filesystem::path& path, const View& view) {
  WriteFileAtomic(path, ViewToJson(view).dump(1) + "\n");
}

int CameraPath::FrameCount() const {
  if (keyframes.empty()) return 0;
  if (!(fps > 0)) return 1;
  return static_cast<int>(std::floor(duration_s() * fps + 1e-6)) + 1;
}

View CameraPath::Frame(int i) const {
  HDRIBR_CHECK(!keyframes.empty() && keyframes.size() == times_s.size());
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%04d", i);
  View out;
  out.name = name;
  out.camera = keyframes.front().camera;
  const double t = times_s.front() + (fps > 0 ? i / fps : 0.0);
  size_t k = 0;
  while (k + 1 < times_s.size() && times_s[k + 1] <= t) ++k;
  if (k + 1 >= keyframes.size()) {
    out.cam_from_world = keyframes.back().cam_from_world;
    return out;
  }
  const double span = times_s[k + 1] - times_s[k];
  const double a = span > 0 ? std::clamp((t - times_s[k]) / span, 0.0, 1.0) : 0.0;
  const Rigid3d w0 = keyframes[k].cam_from_world.Inverse();
  const Rigid3d w1 = keyframes[k + 1].cam_from_world.Inverse();
  const Rigid3d world_from_cam(w0.rotation.slerp(a, w1.rotation).normalized(),
                               (1.0 - a) * w0.translation + a * w1.translation);
  out.cam_from_world = world_from_cam.Inverse();
  return out;
}

CameraPath ReadCameraPath(const std::filesystem::path& path) {
  const std::string text = ReadFileToString(path);
  CameraPath out;
  try {
    const json j = json::parse(text);
    if (j.value("format", std::string()) != "hdribr-camera-path") {
      throw InputError(path, "not a camera path (\"format\" must be \"hdribr-camera-path\")");
    }
    if (j.value("version", 0) != 1) throw InputError(path, "unsupported camera path version");
    out.fps = j.value("fps", 30.0);
    if (!(out.fps > 0) || !std::isfinite(out.fps) || out.fps > 1000) {
      throw InputError(path, "fps must be in (0, 1000]");
    }
    const json& frames = j.at("keyframes");
    if (!frames.is_array() || frames.empty()) throw InputError(path, "no keyframes");
    for (const json& f : frames) {
      const double t = f.at("time").get<double>();
      if (!std::isfinite(t)) throw InputError(path, "keyframe time is not finite");
      if (!out.times_s.empty() && !(t > out.times_s.back())) {
        throw InputError(path, "keyframe times must increase");
      }
      out.times_s.push_back(t);
      out.keyframes.push_back(ViewFromJson(f, path));
    }
    if (out.duration_s() * out.fps > 1e6) throw InputError(path, "path too long (over 1e6 frames)");
  } catch (const json::exception& e) {
    throw InputError(path, std::string("bad camera path: ") + e.what());
  }
  return out;
}

void WriteCameraPath(const std::filesystem::path& path, const CameraPath& path_data) {
  HDRIBR_CHECK(path_data.keyframes.size() == path_data.times_s.size());
  json j;
  j["format"] = "hdribr-camera-path";
  j["version"] = 1;
  j["fps"] = path_data.fps;
  json frames = json::array();
  for (size_t i = 0; i < path_data.keyframes.size(); ++i) {
    json f = ViewToJson(path_data.keyframes[i]);
    f["time"] = path_data.times_s[i];
    frames.push_back(f);
  }
  j["keyframes"] = frames;
  WriteFileAtomic(path, j.dump(1) + "\n");
}

}  // namespace hdribr
