#include "eval/leave_one_out.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "core/error.h"
#include "eval/depth_accuracy.h"
#include "eval/gt_views.h"
#include "eval/point_colors.h"
#include "eval/radiance_setup.h"
#include "io/exr.h"
#include "io/image.h"
#include "render/point_color_pass.h"
#include "render/readback.h"

namespace hdribr::eval {
namespace {

// A view to evaluate: where it is seen from, its reference picture and the photos that render
// it (all of its series but itself in leave-one-out).
struct EvalView {
  std::string name;
  Camera camera;
  Rigid3d cam_from_world;
  int series = -1;
  int held_out = -1;  // photo index, -1 for GT views
  std::filesystem::path gt_radiance;
  std::filesystem::path gt_depth;
};

cv::Size ScaledSize(const Camera& camera, double scale) {
  return {std::max(1, static_cast<int>(std::lround(camera.width * scale))),
          std::max(1, static_cast<int>(std::lround(camera.height * scale)))};
}

cv::Mat ResizeTo(const cv::Mat& image, cv::Size size) {
  if (image.size() == size) return image;
  cv::Mat out;
  cv::resize(image, out, size, 0, 0, cv::INTER_AREA);
  return out;
}

std::string FileStem(const std::string& name) {
  std::string s = std::filesystem::path(name).replace_extension().string();
  std::replace(s.begin(), s.end(), '/', '_');
  std::replace(s.begin(), s.end(), '\\', '_');
  return s;
}

std::vector<int> SeriesPhotos(const Scene& scene, int series) {
  return scene.series[static_cast<size_t>(series)].photo_indices;
}

// Colour-per-point colours for one series: every photo of the series sampled once at the
// evaluation scale; Colors(held_out) then leaves the held-out photo out.
class SeriesPointColors {
 public:
  SeriesPointColors(const Scene& scene, render::Renderer& renderer, int series, double scale,
                    float tolerance)
      : sampler_(scene.points) {
    size_t total = 0;
    for (int i : SeriesPhotos(scene, series)) {
      const Photo& photo = scene.photos[static_cast<size_t>(i)];
      const Camera& camera = scene.CameraOf(photo);
      const cv::Size size = ScaledSize(camera, scale);
      render::DepthTarget target = render::DepthTarget::Create(size.width, size.height);
      renderer.depth_pass().Process(camera, photo.cam_from_world, target);
      const cv::Mat depth = render::ReadTextureR32F(target.depth);
      const cv::Mat image = ResizeTo(ReadImage(photo.image_path), size);
      total += sampler_.AddPhoto(i, image, depth, camera, photo.cam_from_world, tolerance);
    }
    spdlog::info("point colours of series {}: {} samples over {} points", series, total,
                 scene.points.size());
  }
  std::vector<Eigen::Vector3f> Colors(int exclude) const { return sampler_.Colors(exclude); }

 private:
  PointColorSampler sampler_;
};

std::vector<Eigen::Vector3f> CloudColors(const PointCloud& cloud) {
  std::vector<Eigen::Vector3f> out(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const auto& c = cloud.colors[i];  // RGB
    out[i] = Eigen::Vector3f(c[2], c[1], c[0]) / 255.0f;
  }
  return out;
}

// Series exposure time (seconds) for converting GT radiance: the photos' EXIF time.
double SeriesTime(const Scene& scene, int series) {
  for (int i : SeriesPhotos(scene, series)) {
    const Exposure& e = scene.photos[static_cast<size_t>(i)].exposure;
    if (e.time_s) return *e.time_s;
  }
  throw UsageError("series '" + scene.series[static_cast<size_t>(series)].name +
                   "' has no exposure time: cannot convert the GT radiance");
}

}  // namespace

int ResolveSeries(const Scene& scene, const std::string& name_or_index) {
  if (scene.series.empty()) throw UsageError("the workspace has no exposure series");
  if (name_or_index.empty()) return static_cast<int>(scene.series.size() - 1) / 2;
  for (size_t s = 0; s < scene.series.size(); ++s) {
    if (scene.series[s].name == name_or_index) return static_cast<int>(s);
  }
  if (!name_or_index.empty() &&
      name_or_index.find_first_not_of("0123456789") == std::string::npos) {
    const int s = std::stoi(name_or_index);
    if (s >= 0 && s < static_cast<int>(scene.series.size())) return s;
  }
  std::string names;
  for (const ExposureSeries& s : scene.series) names += (names.empty() ? "" : ", ") + s.name;
  throw UsageError("unknown series '" + name_or_index + "' (have: " + names + ", or an index)");
}

EvalReport RunEvaluation(const Scene& scene, const gl::ShaderLibrary& shaders,
                         const EvalOptions& options) {
  if (!(options.size_scale > 0.0 && options.size_scale <= 1.0)) {
    throw UsageError("the render size scale must be in (0, 1]");
  }
  if (options.point_colors != "photos" && options.point_colors != "cloud") {
    throw UsageError("point colours must come from 'photos' or the 'cloud'");
  }
  if (options.baselines && options.point_colors == "cloud" && !scene.points.HasColors()) {
    throw UsageError("point colours from the cloud: the point cloud has no colours");
  }
  if (scene.points.empty()) throw UsageError("the workspace has no points: nothing to render");
  if (options.depth_source != "auto" && options.depth_source != "gt" &&
      options.depth_source != "splat") {
    throw UsageError("the depth source must be auto, gt or splat, got '" + options.depth_source +
                     "'");
  }
  const bool gt = !options.gt_capture.empty();
  // "all" (leave-one-out only): every photo, each rendered from the rest of its own series.
  const bool all_series = options.series == "all";
  if (all_series && gt) throw UsageError("series 'all' applies to leave-one-out evaluation only");
  const int default_series = ResolveSeries(scene, all_series ? "" : options.series);
  // LDR-OE: with several exposures, every photo is rendered in radiance from all the others
  // and re-exposed at its own exposure through the response.
  const bool in_radiance = all_series && options.photos.empty() && scene.series.size() >= 2;

  // The views.
  std::vector<EvalView> views;
  if (gt) {
    if (!options.photos.empty())
      throw UsageError("held-out photos apply to leave-one-out evaluation only");
    for (const GtView& g : ReadGtNovelViews(options.gt_capture)) {
      views.push_back(
          {g.name, g.camera, g.cam_from_world, default_series, -1, g.radiance_path, g.depth_path});
    }
  } else {
    std::vector<int> chosen;
    if (options.photos.empty() && all_series) {
      for (size_t i = 0; i < scene.photos.size(); ++i) chosen.push_back(static_cast<int>(i));
    } else if (options.photos.empty()) {
      chosen = SeriesPhotos(scene, default_series);
    } else {
      for (const std::string& name : options.photos) {
        const int i = scene.FindPhoto(name);
        if (i < 0) throw UsageError("no photo named '" + name + "' in the workspace");
        chosen.push_back(i);
      }
    }
    for (int i : chosen) {
      const Photo& p = scene.photos[static_cast<size_t>(i)];
      if (p.series_id < 0) throw UsageError("photo '" + p.name + "' belongs to no series");
      views.push_back({p.name, scene.CameraOf(p), p.cam_from_world, p.series_id, i, {}, {}});
    }
  }
  // The photos that render a view: every other photo in radiance, else the other photos of
  // its series.
  const auto active_photos = [&](const EvalView& v) {
    std::vector<int> active;
    if (in_radiance) {
      for (size_t i = 0; i < scene.photos.size(); ++i) active.push_back(static_cast<int>(i));
    } else {
      active = SeriesPhotos(scene, v.series);
    }
    std::erase(active, v.held_out);
    return active;
  };
  // A photo alone in its series cannot be rendered from its own exposure: an error when it
  // was asked for, skipped (and listed in the report's settings) with --series all.
  std::string skipped;
  std::erase_if(views, [&](const EvalView& v) {
    const std::vector<int> active = active_photos(v);
    if (!active.empty()) return false;
    if (!all_series) {
      throw UsageError("view '" + v.name + "': its series has no other photo to render from");
    }
    spdlog::warn("skipping {}: the only photo of its series", v.name);
    skipped += (skipped.empty() ? "" : " ") + v.name;
    return true;
  });
  if (views.empty()) throw UsageError("no views to evaluate (empty selection)");

  std::unique_ptr<synth::SyntheticResponse> response;
  if (gt) {
    response = std::make_unique<synth::SyntheticResponse>(ReadCaptureResponse(options.gt_capture));
  }
  // The response and exposures of the re-exposure: the workspace's calibration, else one from
  // the point cloud now.
  std::optional<RadianceSetup> setup;
  if (in_radiance) setup.emplace(scene, shaders, options.response, options.renderer);
  const Scene* render_scene = setup ? &setup->scene() : &scene;
  const render::RendererOptions renderer_options =
      setup ? setup->RendererOptionsFor(options.renderer) : options.renderer;
  // 8-bit image of a rendered value: re-exposed radiance, or display values.
  const auto to_ldr = [&](const cv::Mat& color, const EvalView& v) {
    if (!setup) return ToLdr8(color);
    return setup->Expose(color, render_scene->RelativeExposureOf(
                                    render_scene->photos[static_cast<size_t>(v.held_out)]));
  };
  render::Renderer renderer(shaders, *render_scene, renderer_options);
  // The GT depth maps of the photos (a synthetic capture's own workspace): the depth pass is
  // scored against them, and the perfect-depth reference blends on them.
  const std::filesystem::path depth_capture = FindGtCapture(scene, options.gt_capture);
  if (options.depth_source == "gt" && depth_capture.empty()) {
    throw UsageError(
        "--depth-source gt: the workspace's cameras are not a synthetic capture's "
        "ground truth (use the capture's own workspace)");
  }
  std::vector<cv::Mat> gt_depths;
  if (!depth_capture.empty()) gt_depths = ReadGtPhotoDepths(scene, depth_capture);
  std::unique_ptr<render::Renderer> gt_renderer;
  if (!depth_capture.empty() && options.depth_source != "splat") {
    render::RendererOptions o = renderer_options;
    o.photo_depths = gt_depths;
    gt_renderer = std::make_unique<render::Renderer>(shaders, *render_scene, o);
  }
  std::unique_ptr<render::PointColorPass> point_pass;
  if (options.baselines) point_pass = std::make_unique<render::PointColorPass>(shaders);
  std::map<int, std::unique_ptr<SeriesPointColors>> series_colors;
  std::vector<Eigen::Vector3f> cloud_colors;
  if (options.baselines && options.point_colors == "cloud") {
    cloud_colors = CloudColors(scene.points);
    point_pass->SetPoints(scene.points, cloud_colors);
  }

  EvalReport report;
  report.kind = gt ? "gt-novel" : "leave-one-out";
  report.workspace = scene.workspace.string();
  report.series = all_series ? "all" : scene.series[static_cast<size_t>(default_series)].name;
  report.settings["size_scale"] = std::to_string(options.size_scale);
  report.settings["point_colors"] = options.point_colors;
  report.settings["common_mask"] =
      "intersection of every method's valid pixels" + std::string(gt ? " and GT non-sky" : "");
  if (gt) report.settings["gt_capture"] = options.gt_capture.string();
  if (gt_renderer) report.settings["gt_depth"] = (depth_capture / "gt").string();
  if (!skipped.empty()) report.settings["skipped_alone_in_series"] = skipped;
  if (in_radiance) {
    report.settings["protocol"] =
        "LDR-OE: radiance from every other photo, re-exposed at the held-out photo's exposure";
    report.settings["response"] = setup->source();
  }
  if (!options.out_dir.empty()) std::filesystem::create_directories(options.out_dir / "views");

  const render::BlendMode mode = renderer.blend_options().mode;
  for (const EvalView& v : views) {
    const cv::Size size = ScaledSize(v.camera, options.size_scale);
    const std::vector<int> active = active_photos(v);
    renderer.SetActivePhotos(active);
    if (gt_renderer) gt_renderer->SetActivePhotos(active);

    // Reference picture.
    cv::Mat reference;
    cv::Mat reference_mask;
    cv::Mat view_gt_depth;  // full size
    if (gt) {
      const cv::Mat radiance = ReadExr(v.gt_radiance);
      if (radiance.type() != CV_32FC3) throw InputError(v.gt_radiance, "expected RGB radiance");
      const double t = SeriesTime(scene, v.series);
      reference = ResizeTo(RadianceToLdr(radiance, *response, t), size);
      // Sky (no surface) has no points behind it: compared only where the GT depth is valid.
      if (std::filesystem::exists(v.gt_depth)) {
        view_gt_depth = ReadExr(v.gt_depth);
        cv::Mat surface = view_gt_depth > 0;
        cv::resize(surface, reference_mask, size, 0, 0, cv::INTER_NEAREST);
      }
    } else {
      reference =
          ResizeTo(ReadImage(scene.photos[static_cast<size_t>(v.held_out)].image_path), size);
      if (!gt_depths.empty()) view_gt_depth = gt_depths[static_cast<size_t>(v.held_out)];
    }

    struct MethodImage {
      std::string method;
      cv::Mat color8;
      cv::Mat valid;
      cv::Mat from_points;  // valid pixels rendered from points, not the background
      cv::Mat filled;       // pixels filled where no photo shows (empty: none)
    };
    std::vector<MethodImage> images;
    renderer.blend_options().mode = mode;
    render::RenderImages r =
        renderer.RenderToImages(v.camera, v.cam_from_world, size.width, size.height);
    images.push_back({"hdribr", to_ldr(r.color, v), r.valid, r.valid & (r.depth > 0), r.filled});
    // The depth pass against GT depth, pixel for pixel: at the view's full size only.
    std::optional<DepthCounts> depth_counts;
    if (view_gt_depth.type() == CV_32FC1) {
      if (view_gt_depth.size() == size) {
        depth_counts = CompareDepth(r.depth, view_gt_depth);
      } else {
        report.settings["depth_accuracy"] = "needs --size-scale 1";
      }
    }
    if (gt_renderer) {
      if (view_gt_depth.type() != CV_32FC1) {
        throw InputError(depth_capture / "gt", "no ground-truth depth of view '" + v.name + "'");
      }
      render::GivenDepth given;
      cv::resize(view_gt_depth, given.depth, size, 0, 0, cv::INTER_NEAREST);
      given.normal = NormalsFromDepth(given.depth, v.camera.Scaled(size.width, size.height));
      const render::RenderImages g =
          gt_renderer->RenderToImages(v.camera, v.cam_from_world, size.width, size.height, &given);
      images.push_back(
          {"gt_depth", to_ldr(g.color, v), g.valid, g.valid & (g.depth > 0), g.filled});
    }
    if (options.baselines) {
      renderer.blend_options().mode = render::BlendMode::kNearestPhoto;
      r = renderer.RenderToImages(v.camera, v.cam_from_world, size.width, size.height);
      renderer.blend_options().mode = mode;
      images.push_back(
          {"nearest_photo", to_ldr(r.color, v), r.valid, r.valid & (r.depth > 0), r.filled});
    }
    // Colour per point blends display values of one exposure: not in radiance.
    if (options.baselines && !in_radiance) {
      if (options.point_colors == "photos") {
        auto& sc = series_colors[v.series];
        if (!sc) {
          sc = std::make_unique<SeriesPointColors>(scene, renderer, v.series, options.size_scale,
                                                   options.point_color_tolerance);
        }
        point_pass->SetPoints(scene.points, sc->Colors(v.held_out));
      }
      const render::PointColorImages p =
          point_pass->Render(v.camera, v.cam_from_world, size.width, size.height);
      images.push_back({"point_colors", ToLdr8(p.color), p.valid, p.valid, {}});
    }

    std::vector<cv::Mat> masks;
    for (const MethodImage& m : images) masks.push_back(m.valid);
    if (!reference_mask.empty()) masks.push_back(reference_mask);
    const cv::Mat common = CommonMask(masks);
    ViewReport vr;
    vr.name = v.name;
    vr.width = size.width;
    vr.height = size.height;
    vr.depth = depth_counts;
    const double total = static_cast<double>(size.area());
    for (const MethodImage& m : images) {
      MethodScores s;
      s.method = m.method;
      if (cv::countNonZero(common) > 0) s.scores = CompareImages(reference, m.color8, common);
      s.own_coverage = cv::countNonZero(m.valid) / total;
      s.point_coverage = cv::countNonZero(m.from_points) / total;
      // The reference is valid everywhere (a GT view's sky too): every rendered pixel counts.
      if (cv::countNonZero(m.valid) > 0) {
        s.own_scores = CompareImages(reference, m.color8, m.valid);
      }
      if (!m.filled.empty() && cv::countNonZero(m.filled) > 0) {
        s.filled_coverage = cv::countNonZero(m.filled) / total;
        s.fill_scores = CompareImages(reference, m.color8, m.filled);
      }
      vr.methods.push_back(s);
    }
    std::string line = "view " + v.name + ":";
    for (const MethodScores& s : vr.methods) {
      line += fmt::format("  {} {:.2f} dB (own {:.2f} dB, cov. {:.1f}%, filled {:.1f}%)", s.method,
                          s.scores.psnr_db, s.own_scores.psnr_db, 100.0 * s.own_coverage,
                          100.0 * s.filled_coverage);
    }
    spdlog::info("{} (common {:.1f}%)", line, 100.0 * cv::countNonZero(common) / total);
    report.views.push_back(vr);

    if (!options.out_dir.empty()) {
      std::vector<cv::Mat> top = {reference};
      std::vector<std::string> top_captions = {gt ? "ground truth" : "photo (held out)"};
      cv::Mat mask_panel;
      cv::cvtColor(common, mask_panel, cv::COLOR_GRAY2BGR);
      std::vector<cv::Mat> bottom = {mask_panel};
      std::vector<std::string> bottom_captions = {"common mask"};
      for (size_t k = 0; k < images.size(); ++k) {
        top.push_back(images[k].color8);
        top_captions.push_back(images[k].method +
                               fmt::format(" {:.2f} dB", vr.methods[k].scores.psnr_db));
        bottom.push_back(ErrorMap(reference, images[k].color8, images[k].valid));
        bottom_captions.push_back("|error| " + images[k].method);
      }
      cv::Mat sheet;
      cv::vconcat(SideBySide(top, top_captions), SideBySide(bottom, bottom_captions), sheet);
      WriteImage(options.out_dir / "views" / (FileStem(v.name) + ".png"), sheet);
    }
  }
  if (!options.out_dir.empty()) {
    WriteReport(report, options.out_dir / "eval.csv", options.out_dir / "eval.json");
  }
  return report;
}

}  // namespace hdribr::eval
