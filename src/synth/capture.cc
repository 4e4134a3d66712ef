#include "synth/capture.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <future>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/exposure_series.h"
#include "core/photo.h"
#include "hdr/response_curve.h"
#include "io/atomic_file.h"
#include "io/colmap_model.h"
#include "io/exif.h"
#include "io/exr.h"
#include "io/image.h"
#include "io/ply.h"
#include "io/series_json.h"
#include "synth/point_sampler.h"

namespace hdribr::synth {
namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;

constexpr double kSensorWidthMm = 6.4;
constexpr double kDeg = std::numbers::pi / 180.0;

std::uint64_t Mix(std::uint64_t seed, std::uint64_t stream) {
  SplitMix64 rng(seed * 0x9E3779B97F4A7C15ull ^ (stream + 0x632BE59BD9B4E019ull));
  return rng.Next();
}

// Camera on the arc around the scene's look-at point: azimuth 0 looks along +y.
Rigid3d ArcCamera(const SynthScene& scene, double azimuth, double distance, double height,
                  const Vector3d& target_offset, double roll) {
  const Vector3d eye =
      scene.look_at + Vector3d(distance * std::sin(azimuth), -distance * std::cos(azimuth), height);
  const Rigid3d look = LookAt(eye, scene.look_at + target_offset, Vector3d::UnitZ());
  const Eigen::Quaterniond roll_q(Eigen::AngleAxisd(roll, Vector3d::UnitZ()));
  // Roll about the optical axis: cam_from_world = roll_from_cam * cam_from_world.
  return Rigid3d(roll_q, Vector3d::Zero()) * look;
}

// Camera of a walk along a facade: `x` along the walk from the look-at point, `distance` in
// front of it (-y), `height` above it; it aims at the facade ahead, a little towards the walk's
// centre.
Rigid3d FacadeCamera(const SynthScene& scene, double x, double distance, double height,
                     const Vector3d& target_offset, double roll) {
  const Vector3d eye = scene.look_at + Vector3d(x, -distance, height);
  const Vector3d target = scene.look_at + Vector3d(0.6 * x, 0, 0) + target_offset;
  const Rigid3d look = LookAt(eye, target, Vector3d::UnitZ());
  const Eigen::Quaterniond roll_q(Eigen::AngleAxisd(roll, Vector3d::UnitZ()));
  return Rigid3d(roll_q, Vector3d::Zero()) * look;
}

std::string Stem(const std::string& name) { return fs::path(name).stem().string(); }

ColmapModel ModelOf(const Camera& camera, const std::vector<PlannedView>& views,
                    bool with_extension) {
  ColmapModel model;
  model.cameras[camera.id] = camera;
  for (const PlannedView& v : views) {
    ColmapImage im;
    im.id = v.image_id;
    im.camera_id = camera.id;
    im.name = with_extension ? v.name : v.name + ".exr";
    im.cam_from_world = v.cam_from_world;
    model.images[im.id] = im;
  }
  return model;
}

cv::Mat Luminance(const cv::Mat& bgr) {
  cv::Mat lum(bgr.size(), CV_32FC1);
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3f c = bgr.at<cv::Vec3f>(y, x);
      lum.at<float>(y, x) = 0.2126f * c[2] + 0.7152f * c[1] + 0.0722f * c[0];
    }
  }
  return lum;
}

double Percentile(std::vector<float>& v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

void WriteViewTruth(const fs::path& dir, const std::string& stem, const RenderedView& view) {
  WriteExr(dir / "radiance" / (stem + ".exr"), view.radiance, ExrPixel::kHalf);
  WriteExr(dir / "depth" / (stem + ".exr"), view.depth, ExrPixel::kFloat, "Z");
}

// Auto exposure: each photo's EXIF time puts the geometric mean luminance of its view (metered
// on a 80-pixel-wide render) at kMeterKey of saturation, times 2^(its series' offset), rounded
// to the nearest 1/3 stop.
void MeterExposures(CapturePlan& plan) {
  constexpr double kMeterKey = 0.18;
  const CaptureOptions& o = plan.options;
  const int mw = std::min(80, o.width);
  const int mh = std::max(1, static_cast<int>(std::lround(double(mw) * o.height / o.width)));
  const Camera meter = plan.camera.Scaled(mw, mh);
  RenderOptions ro;
  ro.threads = o.threads;
  for (PlannedView& v : plan.photos) {
    const cv::Mat lum = Luminance(RenderView(plan.scene, meter, v.cam_from_world, ro).radiance);
    double sum_log = 0;
    for (int y = 0; y < lum.rows; ++y) {
      for (int x = 0; x < lum.cols; ++x) sum_log += std::log(std::max(lum.at<float>(y, x), 1e-6f));
    }
    const double mean_lum = std::exp(sum_log / lum.total());
    const double bias_ev = o.ev_step * (v.series - 0.5 * (o.series - 1));
    const double t = kMeterKey * plan.response.x_sat / mean_lum * std::pow(2.0, bias_ev);
    // Shutter speeds below a second are written as 1/n, like cameras do.
    const double third_stop = std::exp2(std::round(3 * std::log2(t)) / 3);
    v.exif_time_s = third_stop < 1 ? 1.0 / std::round(1.0 / third_stop) : third_stop;
  }
}

}  // namespace

CapturePlan PlanCapture(const CaptureOptions& o) {
  if (o.series < 1) throw OptionError("series", "must be at least 1");
  if (o.views < 1) throw OptionError("views", "must be at least 1");
  if (o.novel_views < 0) throw OptionError("novel_views", "must be at least 0");
  // Series of equal or non-finite exposure make no HDR capture (exposure times 2^(k ev_step)).
  if (!(o.ev_step > 0) || !std::isfinite(o.ev_step) || o.ev_step > 8) {
    throw OptionError("ev_step", "must be in (0, 8] stops");
  }
  if (o.threads < 0) throw OptionError("threads", "must be >= 0 (0 = all cores)");
  if (o.width < 16 || o.width > 8192) throw OptionError("width", "must be in [16, 8192]");
  if (o.height < 16 || o.height > 8192) throw OptionError("height", "must be in [16, 8192]");
  if (o.jpeg_quality < 1 || o.jpeg_quality > 100)
    throw OptionError("jpeg_quality", "must be in [1, 100]");
  if (!(o.toe >= 0 && o.toe <= 0.1)) {
    throw OptionError("toe", "must be in [0, 0.1] (0 = a pure power law down to black)");
  }
  if (o.exposure != "series" && o.exposure != "auto") {
    throw OptionError("exposure", "must be series or auto, got '" + o.exposure + "'");
  }
  if (!(o.exif_error >= 0 && o.exif_error <= 0.5)) {
    throw OptionError("exif_error", "must be in [0, 0.5] (a standard deviation in ln t)");
  }
  CapturePlan plan;
  plan.options = o;
  plan.response.toe = o.toe;
  plan.scene = MakeScene(o.scene, o.seed);
  const double f = 0.9 * o.width;
  plan.camera = Camera::Pinhole(1, o.width, o.height, f, f, 0.5 * o.width, 0.5 * o.height);
  plan.focal_mm = f / o.width * kSensorWidthMm;

  // Hand-held: the series interleave along a 120-degree arc (or a walk along the facade); each
  // view is jittered in azimuth (position along the walk), distance, height, aim and roll.
  const bool facade = plan.scene.path == CameraPath::kFacade;
  const double arc = facade ? 1.5 * plan.scene.size : 120 * kDeg;
  const double step = arc / o.views;
  SplitMix64 rng(Mix(o.seed, 1));
  int id = 1;
  for (int s = 0; s < o.series; ++s) {
    const double ev = o.ev_step * (s - 0.5 * (o.series - 1));
    const double t = std::ldexp(1.0, -7) * std::pow(2.0, ev);
    for (int v = 0; v < o.views; ++v) {
      const double az =
          -0.5 * arc + step * (v + (s + 0.5) / o.series) + rng.Uniform(-0.2, 0.2) * step / o.series;
      const double dist = 2.2 * plan.scene.size + rng.Uniform(-0.12, 0.12);
      const double height = 0.95 * plan.scene.size + rng.Uniform(-0.12, 0.12);
      const Vector3d aim(rng.Uniform(-0.06, 0.06), rng.Uniform(-0.06, 0.06),
                         rng.Uniform(-0.05, 0.05));
      const double roll = rng.Uniform(-3, 3) * kDeg;
      char name[64];
      std::snprintf(name, sizeof(name), "s%d_v%02d.jpg", s, v);
      const Rigid3d cam_from_world =
          facade
              ? FacadeCamera(plan.scene, az, 0.75 * dist, height - 0.8 * plan.scene.size, aim, roll)
              : ArcCamera(plan.scene, az, dist, height, aim, roll);
      plan.photos.push_back({name, id++, s, t, t, cam_from_world});
    }
  }
  if (o.exposure == "auto") MeterExposures(plan);
  SplitMix64 exif_rng(Mix(o.seed, 2));
  for (PlannedView& v : plan.photos) {
    v.exposure_time_s = v.exif_time_s * std::exp(o.exif_error * exif_rng.Gaussian());
  }
  // Novel views: a steadier, slightly closer and lower arc inside the captured one.
  for (int k = 0; k < o.novel_views; ++k) {
    const double u = o.novel_views == 1 ? 0.0 : -1 + 2.0 * k / (o.novel_views - 1);
    char name[64];
    std::snprintf(name, sizeof(name), "novel_%02d", k);
    const Rigid3d cam_from_world =
        facade ? FacadeCamera(plan.scene, 0.5 * u * plan.scene.size, 1.5 * plan.scene.size,
                              -0.05 * plan.scene.size, Vector3d::Zero(), 0.0)
               : ArcCamera(plan.scene, 50 * kDeg * u, 1.9 * plan.scene.size, 0.75 * plan.scene.size,
                           Vector3d::Zero(), 0.0);
    plan.novel.push_back(
        {name, k + 1, -1, std::ldexp(1.0, -7), std::ldexp(1.0, -7), cam_from_world});
  }
  return plan;
}

cv::Mat MakePreview(const CapturePlan& plan) {
  const PlannedView& view = plan.photos.front();
  RenderOptions ro;
  ro.threads = plan.options.threads;
  const RenderedView r = RenderView(plan.scene, plan.camera, view.cam_from_world, ro);
  std::vector<cv::Mat> tiles;
  for (int s = 0; s < plan.options.series; ++s) {
    const double t = plan.photos[static_cast<size_t>(s * plan.options.views)].exposure_time_s;
    cv::Mat photo(r.radiance.size(), CV_8UC3);
    for (int y = 0; y < photo.rows; ++y) {
      for (int x = 0; x < photo.cols; ++x) {
        const cv::Vec3f l = r.radiance.at<cv::Vec3f>(y, x);
        for (int c = 0; c < 3; ++c) {
          photo.at<cv::Vec3b>(y, x)[c] =
              static_cast<std::uint8_t>(std::lround(plan.response.ValueFromExposure(c, l[c] * t)));
        }
      }
    }
    tiles.push_back(photo);
  }
  double max_depth = 0;
  cv::minMaxLoc(r.depth, nullptr, &max_depth);
  cv::Mat depth8;
  r.depth.convertTo(depth8, CV_8UC1, max_depth > 0 ? 255.0 / max_depth : 1.0);
  cv::Mat depth_colour;
  cv::applyColorMap(depth8, depth_colour, cv::COLORMAP_VIRIDIS);
  depth_colour.setTo(cv::Scalar(0, 0, 0), r.depth <= 0);
  tiles.push_back(depth_colour);
  cv::Mat out;
  cv::hconcat(tiles, out);
  return out;
}

CaptureSummary WriteCapture(const CaptureOptions& options, const fs::path& out) {
  const auto t_start = std::chrono::steady_clock::now();
  const CapturePlan plan = PlanCapture(options);
  std::error_code ec;
  if (fs::exists(out) && !(fs::is_directory(out) && fs::is_empty(out))) {
    throw InputError(out, "exists and is not an empty folder; refusing to overwrite it");
  }
  const fs::path target = fs::absolute(out).lexically_normal();
  const fs::path tmp = target.parent_path() /
                       ("." + target.filename().string() + ".partial-" + std::to_string(getpid()));
  fs::remove_all(tmp, ec);
  struct Cleanup {
    fs::path dir;
    bool keep = false;
    ~Cleanup() {
      std::error_code e;
      if (!keep) fs::remove_all(dir, e);
    }
  } cleanup{tmp};
  for (const char* d : {"photos", "calib", "gt/radiance", "gt/depth", "gt/novel/radiance",
                        "gt/novel/depth", "workspace/images"}) {
    fs::create_directories(tmp / d);
  }

  RenderOptions ro;
  ro.threads = options.threads;
  const SyntheticResponse& response = plan.response;
  // Display colours of the points: the middle series' exposure.
  const double mid_time = plan.photos[plan.photos.size() / 2].exposure_time_s;
  PointSampler sampler(0.008 * plan.scene.size, 3);
  std::vector<float> lum_samples;
  double render_s = 0;
  std::vector<Photo> photos;
  // The files of view i are written (and its photo exposed) on a second thread while view i + 1
  // renders; the point sampler and statistics stay in view order (deterministic output).
  std::future<void> pending;
  auto enqueue = [&](std::function<void()> job) {
    if (pending.valid()) pending.get();
    pending = std::async(std::launch::async, std::move(job));
  };
  for (const PlannedView& v : plan.photos) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = std::make_shared<const RenderedView>(
        RenderView(plan.scene, plan.camera, v.cam_from_world, ro));
    render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ExifInfo exif;
    exif.exposure.time_s = v.exif_time_s;
    exif.exposure.iso = plan.iso;
    exif.exposure.f_number = plan.f_number;
    exif.exposure.focal_mm = plan.focal_mm;
    exif.make = "hdribr";
    exif.model = "synth " + plan.scene.name;
    enqueue([&, r, v, exif] {
      WriteViewTruth(tmp / "gt", Stem(v.name), *r);
      const cv::Mat photo = response.Expose(r->radiance, v.exposure_time_s,
                                            Mix(options.seed, 1000 + v.image_id), options.threads);
      const fs::path photo_path = tmp / "photos" / v.name;
      WriteImage(photo_path, photo, options.jpeg_quality);
      WriteExif(photo_path, exif);
      fs::copy_file(photo_path, tmp / "workspace/images" / v.name);
    });
    sampler.AddView(*r, plan.camera, v.cam_from_world, mid_time / response.x_sat);
    const cv::Mat lum = Luminance(r->radiance);
    for (int y = 0; y < lum.rows; y += 2) {
      for (int x = 0; x < lum.cols; x += 2) lum_samples.push_back(lum.at<float>(y, x));
    }
    Photo p;
    p.id = v.image_id;
    p.name = v.name;
    p.camera_id = plan.camera.id;
    p.cam_from_world = v.cam_from_world;
    p.exposure = exif.exposure;
    photos.push_back(p);
  }
  for (const PlannedView& v : plan.novel) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = std::make_shared<const RenderedView>(
        RenderView(plan.scene, plan.camera, v.cam_from_world, ro));
    render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    enqueue([&, r, v] { WriteViewTruth(tmp / "gt/novel", v.name, *r); });
  }
  if (pending.valid()) pending.get();

  // Cameras: gt/ (photos), gt/novel/, and the workspace's sparse model.
  WriteColmapModel(ModelOf(plan.camera, plan.photos, true), tmp / "gt", ColmapFormat::kText);
  WriteColmapModel(ModelOf(plan.camera, plan.novel, false), tmp / "gt/novel", ColmapFormat::kText);
  WriteColmapModel(ModelOf(plan.camera, plan.photos, true), tmp / "workspace/sparse",
                   ColmapFormat::kText);
  WritePly(tmp / "gt/points.ply", sampler.cloud(), true);
  WritePly(tmp / "workspace/points.ply", sampler.cloud(), true);
  WriteResponseCurve(tmp / "calib/response.json", response.Curve());

  // Fixed exposures: the capture's series. Auto exposure: the photos as their EXIF groups them
  // (what `reconstruct` finds in the same photos).
  std::vector<ExposureSeries> series;
  if (options.exposure == "auto") {
    series = GroupByExposure(photos);
  } else {
    series.resize(static_cast<size_t>(options.series));
    for (int s = 0; s < options.series; ++s) {
      series[s].id = s;
      series[s].name = "series" + std::to_string(s);
      series[s].relative_exposure =
          photos[static_cast<size_t>(s * options.views)].exposure.Relative();
      for (int v = 0; v < options.views; ++v)
        series[s].photo_indices.push_back(s * options.views + v);
    }
    for (size_t i = 0; i < photos.size(); ++i) photos[i].series_id = plan.photos[i].series;
  }
  WriteSeriesJson(tmp / "workspace/series.json", series, photos);

  CaptureSummary summary;
  summary.photos = static_cast<int>(plan.photos.size());
  summary.novel = static_cast<int>(plan.novel.size());
  summary.points = sampler.cloud().size();
  summary.radiance_p001 = Percentile(lum_samples, 0.001);
  summary.radiance_p999 = Percentile(lum_samples, 0.999);

  // Everything that is true about the capture and not in the files above (no timings: the
  // output is byte-identical for a seed).
  nlohmann::json j;
  j["format"] = "hdribr-synth-capture";
  j["version"] = 1;
  j["scene"] = plan.scene.name;
  j["seed"] = options.seed;
  j["series"] = options.series;
  j["views"] = options.views;
  j["width"] = options.width;
  j["height"] = options.height;
  j["ev_step"] = options.ev_step;
  j["exposure"] = options.exposure;
  j["exif_error"] = options.exif_error;
  j["jpeg_quality"] = options.jpeg_quality;
  j["iso"] = plan.iso;
  j["f_number"] = plan.f_number;
  j["focal_mm"] = plan.focal_mm;
  j["sensor_width_mm"] = kSensorWidthMm;
  if (options.exposure == "series") {
    nlohmann::json times = nlohmann::json::array();
    for (int s = 0; s < options.series; ++s) {
      times.push_back(plan.photos[static_cast<size_t>(s * options.views)].exif_time_s);
    }
    j["exposure_times_s"] = times;
  }
  nlohmann::json per_photo = nlohmann::json::array();
  for (const PlannedView& v : plan.photos) {
    per_photo.push_back(
        {{"name", v.name}, {"exif_time_s", v.exif_time_s}, {"exposure_time_s", v.exposure_time_s}});
  }
  j["photos"] = per_photo;
  j["response"] = {{"model",
                    "z = 255 h(s(x)), s(x) = phi x below x = toe, (1 + a) x^(1/gamma) - a above "
                    "(value and slope continuous), h(y) = y (1 + k) / (y + k), x = X / x_sat"},
                   {"gamma_bgr", response.gamma},
                   {"toe", response.toe},
                   {"knee_bgr", response.knee},
                   {"x_sat", response.x_sat},
                   {"noise_shot", response.shot},
                   {"noise_read", response.read}};
  j["radiance_luminance_p001"] = summary.radiance_p001;
  j["radiance_luminance_p999"] = summary.radiance_p999;
  j["points"] = summary.points;
  j["scene_size"] = plan.scene.size;
  WriteFileAtomic(tmp / "gt/capture.json", j.dump(2) + "\n");

  if (fs::exists(target)) fs::remove(target);  // an empty folder (checked above)
  fs::rename(tmp, target);
  cleanup.keep = true;
  summary.render_seconds = render_s;
  summary.total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return summary;
}

}  // namespace hdribr::synth
