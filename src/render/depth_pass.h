// The splat depth pass (Lechelek et al. 2019, sec. 4 "Point cloud rendering"): per-pixel
// camera-space depth, normal and validity of a point cloud seen from any pinhole camera.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"
#include "gl/objects.h"
#include "gl/shader_library.h"
#include "render/point_buffer.h"
#include "render/pull_push.h"

namespace hdribr::render {

enum class DepthMode {
  kPlain,      // elliptical splats with depth test only (paper step 1)
  kMarroquim,  // Marroquim et al. 2007 pull-push over all points
  kLechelek,   // the paper's five steps (default)
};

// Values of DepthTarget::classes (written by the resolve step). plain and marroquim write
// kFront on every valid pixel; lechelek writes kBackground where the background pull-push
// filled a hole of the foreground (step 5), kFront elsewhere (foreground pull-push, or the
// step-1 splat as a last resort).
enum class DepthClass : std::uint8_t { kInvalid = 0, kFront = 1, kBackground = 2 };

// "plain", "marroquim", "lechelek"; ParseDepthMode throws UsageError for anything else.
std::string DepthModeName(DepthMode mode);
DepthMode ParseDepthMode(const std::string& name);
std::vector<DepthMode> AllDepthModes();

// How the point steps (1: splats, 2: projection) are rasterised; both cover the same pixels.
enum class PointRaster {
  kCompute,   // compute shaders, one invocation per point, nearest depth by image atomicMin
  kPipeline,  // GL_POINTS sprites through the graphics pipeline and its depth test
};

// Every PointRaster value, in declaration order.
inline constexpr PointRaster kAllPointRasters[] = {PointRaster::kCompute, PointRaster::kPipeline};

// "compute", "pipeline"; ParsePointRaster throws UsageError for anything else.
std::string PointRasterName(PointRaster raster);
PointRaster ParsePointRaster(const std::string& name);

// Output of the pass, at any resolution: camera z (R32F, positive forward, 0 = invalid),
// camera-space unit normal facing the camera (RGBA16F, xyz; COLMAP axes), validity (R8,
// 1 = valid) and the pixel class (R8UI, DepthClass). Row 0 is the top image row.
struct DepthTarget {
  gl::Texture depth;
  gl::Texture normal;
  gl::Texture valid;
  gl::Texture classes;

  static DepthTarget Create(int width, int height);
  int width() const { return depth.width(); }
  int height() const { return depth.height(); }
};

// Options of the depth pass. A field that changes the pass's output must be part of the key of
// the photos' depth-map cache (PhotoDepthMapsKey, render/photo_depth_key.cc).
struct DepthPassOptions {
  DepthMode mode = DepthMode::kLechelek;
  PointRaster raster = PointRaster::kCompute;
  // Step 2: a point is front when z <= z1 + front_radii * r + front_rel * z1, z1 the step-1
  // depth at its centre pixel and r its splat radius (world units).
  float front_radii = 2.0f;
  float front_rel = 0.005f;
  // Lechelek resolve: silhouette trim window (pixels each side of a pushed foreground pixel),
  // 0 = off. Such a pixel takes a farther surface when the nearest front point centre in the
  // window lies on it (shaders/resolve.comp, TrimOverhang; docs/algorithms/depth-pass.md).
  int silhouette_trim = 2;
  // Pipeline raster: step 2 in one layered draw when ARB_shader_viewport_layer_array is there
  // (else two draws). The compute raster always fills both layers in one dispatch.
  bool layered_classify = true;
  // Compute raster: points per dispatch, 0 = as many as one storage block holds (the cloud is
  // split into several dispatches beyond that); smaller only to test the split.
  size_t points_per_dispatch = 0;
  // Measure each step: GL timestamp queries (GPU time) and wall time with glFinish() after
  // each step (which serialises the frame: use for per-step figures only).
  bool profile = false;
};

// Time of each step of the last Process() call (profile on), milliseconds: index 0 splat
// (step 1), 1 projection/classification (step 2), 2 pull-push (step 3), 3 resolve (steps 4-5).
struct DepthStepTimes {
  static constexpr int kSteps = 4;
  static constexpr const char* kNames[kSteps] = {"splat", "project", "pullpush", "resolve"};
  double gpu_ms[kSteps] = {0, 0, 0, 0};   // GL timestamp queries
  double wall_ms[kSteps] = {0, 0, 0, 0};  // CPU clock with glFinish() after each step
  double gpu_total_ms() const { return gpu_ms[0] + gpu_ms[1] + gpu_ms[2] + gpu_ms[3]; }
  double wall_total_ms() const { return wall_ms[0] + wall_ms[1] + wall_ms[2] + wall_ms[3]; }
};

class DepthPass {
 public:
  // Needs a current GL 4.5 context; compiles the shaders of every mode.
  explicit DepthPass(const gl::ShaderLibrary& shaders, DepthPassOptions options = {});
  ~DepthPass();
  DepthPass(const DepthPass&) = delete;
  DepthPass& operator=(const DepthPass&) = delete;

  // Uploads the cloud (replacing the previous one). Radii: see PointBuffer.
  void SetPoints(const PointCloud& cloud, float radius_override = 0.0f);
  const PointBuffer& points() const { return points_; }

  // Renders the cloud seen by `camera` (pinhole; intrinsics are rescaled to the target size
  // when it differs from camera.width x camera.height) into `target`. `detail` in (0, 1]: the
  // target's size per axis relative to the picture it previews; below 1 a coarser level of the
  // cloud may be drawn (every k-th point, k a power of 2 from 4 up to 1 / (2 detail^2), splats
  // sqrt(k) times wider), so that a pixel meets about twice the points of a full-size pixel.
  void Process(const Camera& camera, const Rigid3d& cam_from_world, DepthTarget& target,
               double detail = 1.0);
  // Points drawn by the newest Process().
  size_t last_point_count() const { return last_point_count_; }

  DepthPassOptions& options() { return options_; }
  const DepthPassOptions& options() const { return options_; }
  const DepthStepTimes& last_times() const { return times_; }
  // Hash of the sources of every program of the pass (and its pull-push), as compiled.
  std::uint64_t program_hash() const { return program_hash_; }

 private:
  struct Buffers;
  struct Frame;
  Buffers& BuffersFor(int width, int height);
  void SplatStep(const Frame& f, Buffers& buf);
  void ProjectStep(const Frame& f, Buffers& buf);
  size_t PointsPerDispatch() const;  // compute raster: points per dispatch (options, limits)
  const PointBuffer& PointsFor(double detail);  // the level Process draws, built when first asked

  DepthPassOptions options_;
  size_t first_program_;  // index in the library's built() of the pass's first program
  gl::Program splat_;
  gl::Program project_all_;
  gl::Program project_front_;
  gl::Program project_back_;
  gl::Program project_layered_;  // empty without ARB_shader_viewport_layer_array
  gl::Program splat_compute_;
  gl::Program splat_normal_compute_;
  gl::Program project_compute_[2][2];  // [classify][stage - 1]
  gl::Program resolve_[3];             // per DepthMode
  gl::Program resolve_holes_;
  PullPushPass pull_push_;
  PointBuffer points_;
  std::map<size_t, PointBuffer> coarse_;  // stride -> every stride-th point of points_ (PointsFor)
  size_t last_point_count_ = 0;
  std::unique_ptr<Buffers> buffers_;
  std::vector<gl::TimestampQuery> stamps_;
  DepthStepTimes times_;
  float max_point_size_ = 64.0f;
  size_t max_points_per_dispatch_ = 1;  // points in one storage block (compute raster)
  size_t dispatch_step_ = 1;            // a range's first point: a multiple of this
  std::uint64_t program_hash_ = 0;
};

}  // namespace hdribr::render
