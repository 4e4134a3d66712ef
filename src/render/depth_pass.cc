#include "render/depth_pass.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <numeric>

#include "core/error.h"
#include "core/hash.h"
#include "core/projection.h"

namespace hdribr::render {

std::string DepthModeName(DepthMode mode) {
  switch (mode) {
    case DepthMode::kPlain:
      return "plain";
    case DepthMode::kMarroquim:
      return "marroquim";
    case DepthMode::kLechelek:
      return "lechelek";
  }
  return "?";
}

DepthMode ParseDepthMode(const std::string& name) {
  for (DepthMode m : AllDepthModes()) {
    if (DepthModeName(m) == name) return m;
  }
  throw UsageError("unknown depth mode '" + name + "' (plain, marroquim, lechelek)");
}

std::vector<DepthMode> AllDepthModes() {
  return {DepthMode::kPlain, DepthMode::kMarroquim, DepthMode::kLechelek};
}

std::string PointRasterName(PointRaster raster) {
  return raster == PointRaster::kCompute ? "compute" : "pipeline";
}

PointRaster ParsePointRaster(const std::string& name) {
  for (PointRaster r : kAllPointRasters) {
    if (PointRasterName(r) == name) return r;
  }
  throw UsageError("unknown point raster '" + name + "' (compute, pipeline)");
}

DepthTarget DepthTarget::Create(int width, int height) {
  HDRIBR_CHECK(width > 0 && height > 0);
  DepthTarget t;
  t.depth = gl::Texture::Create2D(GL_R32F, width, height);
  t.normal = gl::Texture::Create2D(GL_RGBA16F, width, height);
  t.valid = gl::Texture::Create2D(GL_R8, width, height);
  t.classes = gl::Texture::Create2D(GL_R8UI, width, height);
  return t;
}

// Size-dependent intermediate buffers: step-1 splat buffer and the two pull-push pyramids.
struct DepthPass::Buffers {
  int width = 0, height = 0;
  // Step-1 depth as R32UI (shaders/splat_depth.glsl), normal (plain only), z-buffer.
  gl::Texture splat_depth, splat_normal, splat_zbuffer;
  gl::Framebuffer splat_fb;
  // Level 0 of both pyramids: layers 0 (foreground) and 1 (background) of 2D arrays, so that
  // step 2 can fill both in one layered draw or dispatch; the pyramids see them through layer
  // views. level0_nearest: the compute raster's per-layer nearest depth (R32UI).
  gl::Texture level0_a, level0_b, level0_z, level0_nearest;
  gl::Framebuffer layered_fb;
  PullPushPyramid front, back;
  gl::Texture front_zbuffer, back_zbuffer;
  gl::Framebuffer front_fb, back_fb;
  // Lechelek's foreground holes: indirect dispatch arguments (groups x, y, z), count, pixels
  // (shaders/resolve.comp, MODE 2 and 3).
  gl::Buffer holes;
};

namespace {

void MakeProjectionTarget(PullPushPyramid& pyr, gl::Texture& zbuffer, gl::Framebuffer& fb) {
  zbuffer = gl::Texture::Create2D(GL_DEPTH_COMPONENT32F, pyr.width, pyr.height);
  fb = gl::Framebuffer::Create();
  fb.AttachColor(0, pyr.a[0]);
  fb.AttachColor(1, pyr.b[0]);
  fb.AttachDepth(zbuffer);
  fb.SetDrawBuffers(2);
  fb.CheckComplete();
}

constexpr GLuint kNoSplat = 0xFFFFFFFFu;  // shaders/splat_depth.glsl

void ClearTarget(const gl::Framebuffer& fb) {
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(fb.id(), GL_COLOR, 0, zero);
  glClearNamedFramebufferfv(fb.id(), GL_COLOR, 1, zero);
  const float one = 1.0f;
  glClearNamedFramebufferfv(fb.id(), GL_DEPTH, 0, &one);
}

}  // namespace

DepthPass::Buffers& DepthPass::BuffersFor(int width, int height) {
  if (buffers_ && buffers_->width == width && buffers_->height == height) return *buffers_;
  auto b = std::make_unique<Buffers>();
  b->width = width;
  b->height = height;
  b->splat_depth = gl::Texture::Create2D(GL_R32UI, width, height);
  b->splat_normal = gl::Texture::Create2D(GL_RGBA16F, width, height);
  b->splat_zbuffer = gl::Texture::Create2D(GL_DEPTH_COMPONENT32F, width, height);
  b->splat_fb = gl::Framebuffer::Create();
  b->splat_fb.AttachColor(0, b->splat_depth);
  b->splat_fb.AttachColor(1, b->splat_normal);
  b->splat_fb.AttachDepth(b->splat_zbuffer);
  b->splat_fb.SetDrawBuffers(2);
  b->splat_fb.CheckComplete();
  b->level0_a = gl::Texture::Create2DArray(GL_RGBA32F, width, height, 2);
  b->level0_b = gl::Texture::Create2DArray(GL_RGBA32F, width, height, 2);
  b->level0_z = gl::Texture::Create2DArray(GL_DEPTH_COMPONENT32F, width, height, 2);
  b->level0_nearest = gl::Texture::Create2DArray(GL_R32UI, width, height, 2);
  b->layered_fb = gl::Framebuffer::Create();
  b->layered_fb.AttachColor(0, b->level0_a);
  b->layered_fb.AttachColor(1, b->level0_b);
  b->layered_fb.AttachDepth(b->level0_z);
  b->layered_fb.SetDrawBuffers(2);
  b->layered_fb.CheckComplete();
  b->front = PullPushPyramid::Create(gl::Texture::LayerView(b->level0_a, 0),
                                     gl::Texture::LayerView(b->level0_b, 0));
  b->back = PullPushPyramid::Create(gl::Texture::LayerView(b->level0_a, 1),
                                    gl::Texture::LayerView(b->level0_b, 1));
  MakeProjectionTarget(b->front, b->front_zbuffer, b->front_fb);
  MakeProjectionTarget(b->back, b->back_zbuffer, b->back_fb);
  b->holes = gl::Buffer(sizeof(GLuint) * (4 + static_cast<size_t>(width) * height), nullptr,
                        GL_DYNAMIC_STORAGE_BIT);
  buffers_ = std::move(b);
  return *buffers_;
}

DepthPass::DepthPass(const gl::ShaderLibrary& shaders, DepthPassOptions options)
    : options_(options),
      first_program_(shaders.built().size()),
      splat_(shaders.Build({"splat.vert", "splat.frag"})),
      project_all_(shaders.Build({"project.vert", "project.frag"}, {{"CLASSIFY", "0"}})),
      project_front_(shaders.Build({"project.vert", "project.frag"}, {{"CLASSIFY", "1"}})),
      project_back_(shaders.Build({"project.vert", "project.frag"}, {{"CLASSIFY", "2"}})),
      project_layered_(epoxy_has_gl_extension("GL_ARB_shader_viewport_layer_array")
                           ? shaders.Build({"project.vert", "project.frag"}, {{"CLASSIFY", "3"}})
                           : gl::Program()),
      splat_compute_(shaders.Build({"splat.comp"}, {{"WRITE_NORMAL", "0"}})),
      splat_normal_compute_(shaders.Build({"splat.comp"}, {{"WRITE_NORMAL", "1"}})),
      project_compute_{{shaders.Build({"project.comp"}, {{"CLASSIFY", "0"}, {"STAGE", "1"}}),
                        shaders.Build({"project.comp"}, {{"CLASSIFY", "0"}, {"STAGE", "2"}})},
                       {shaders.Build({"project.comp"}, {{"CLASSIFY", "1"}, {"STAGE", "1"}}),
                        shaders.Build({"project.comp"}, {{"CLASSIFY", "1"}, {"STAGE", "2"}})}},
      resolve_{shaders.Build({"resolve.comp"}, {{"MODE", "0"}}),
               shaders.Build({"resolve.comp"}, {{"MODE", "1"}}),
               shaders.Build({"resolve.comp"}, {{"MODE", "2"}})},
      resolve_holes_(shaders.Build({"resolve.comp"}, {{"MODE", "3"}})),
      pull_push_(shaders) {
  float range[2] = {1, 64};
  glGetFloatv(GL_POINT_SIZE_RANGE, range);
  max_point_size_ = range[1];
  GLint64 block = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
  GLint align = 16;
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
  // Whole points per block, and range offsets (multiples of 32 bytes) on the alignment.
  dispatch_step_ = static_cast<size_t>(std::max(1, align / std::gcd(align, 32)));
  max_points_per_dispatch_ = std::max<size_t>(
      dispatch_step_, static_cast<size_t>(block) / 32 / dispatch_step_ * dispatch_step_);
  for (int i = 0; i <= DepthStepTimes::kSteps; ++i) {
    stamps_.push_back(gl::TimestampQuery::Create());
  }
  Fnv1a64 hash;
  for (size_t i = first_program_; i < shaders.built().size(); ++i) {
    hash.Add(shaders.built()[i].source_hash);
  }
  program_hash_ = hash.value();
}

DepthPass::~DepthPass() = default;

size_t DepthPass::PointsPerDispatch() const {
  const size_t asked = options_.points_per_dispatch;
  if (asked == 0) return max_points_per_dispatch_;
  const size_t aligned = (asked + dispatch_step_ - 1) / dispatch_step_ * dispatch_step_;
  return std::min(aligned, max_points_per_dispatch_);
}

void DepthPass::SetPoints(const PointCloud& cloud, float radius_override) {
  points_ = PointBuffer(cloud, radius_override);
  coarse_.clear();
}

const PointBuffer& DepthPass::PointsFor(double detail) {
  // Every k-th point, k the largest power of 2 up to 1 / (2 detail^2) (at most 64) that leaves
  // at least kMinLevelPoints (below that the per-point steps cost little): a pixel meets twice
  // the points of a full-size pixel. No level below every 4th point: every 2nd saves at most half
  // of the per-point steps, and at half size it strays further from the full-size picture than
  // every point does (docs/decisions/0031).
  constexpr size_t kMinStride = 4, kMaxStride = 64, kMinLevelPoints = 16384;
  const double max_stride = detail > 0 && detail < 1 ? 0.5 / (detail * detail) : 1.0;
  size_t stride = 1;
  while (stride < kMaxStride && static_cast<double>(2 * stride) <= max_stride &&
         points_.size() / (2 * stride) >= kMinLevelPoints) {
    stride *= 2;
  }
  if (stride < kMinStride) return points_;
  auto it = coarse_.lower_bound(stride);
  if (it != coarse_.end() && it->first == stride) return it->second;
  // From the finest level already built (every stride is a power of 2, so a finer one divides
  // it: the same points, and less to read back than the whole cloud).
  if (it != coarse_.begin()) {
    const auto& [finer_stride, finer] = *std::prev(it);
    return coarse_
        .emplace_hint(it, stride, finer.Decimated(static_cast<int>(stride / finer_stride)))
        ->second;
  }
  return coarse_.emplace_hint(it, stride, points_.Decimated(static_cast<int>(stride)))->second;
}

// What the steps of one Process() call share.
struct DepthPass::Frame {
  const PointBuffer* points;  // the level of the cloud drawn
  DepthMode mode;
  bool draw;  // some point may be in front of the camera
  int width, height;
  Eigen::Matrix4f cam_from_world, clip_from_cam;
  float intrinsics[4];  // fx, fy, cx, cy in target pixels
  float size[2];
  float near, far;
  float max_point_size;

  // Uniforms of shaders/camera.glsl (and the compute raster's near plane).
  void SetCamera(const gl::Program& p) const {
    glProgramUniformMatrix4fv(p.id(), 0, 1, GL_FALSE, cam_from_world.data());
    glProgramUniformMatrix4fv(p.id(), 1, 1, GL_FALSE, clip_from_cam.data());
    glProgramUniform4fv(p.id(), 2, 1, intrinsics);
    glProgramUniform2fv(p.id(), 3, 1, size);
    glProgramUniform1f(p.id(), 4, max_point_size);
  }
  // The clip range of the point draws (shaders/points.glsl; graphics pipeline only).
  void SetDepthRange(const gl::Program& p) const { glProgramUniform2f(p.id(), 9, near, far); }
};

namespace {

// One invocation per point (shaders/points_buffer.glsl), groups of 64, 2D beyond 65535 groups;
// clouds larger than one storage block (GL_MAX_SHADER_STORAGE_BLOCK_SIZE, 128 MiB = 4M points
// on llvmpipe) in several dispatches over ranges of the buffer.
void DispatchPoints(const gl::Program& p, const PointBuffer& points, float near,
                    size_t max_points_per_dispatch) {
  glProgramUniform1f(p.id(), 9, near);
  p.Use();
  constexpr size_t kStride = 32;  // bytes per point (render/point_buffer.cc)
  for (size_t first = 0; first < points.size(); first += max_points_per_dispatch) {
    const size_t n = std::min(points.size() - first, max_points_per_dispatch);
    glProgramUniform1ui(p.id(), 8, static_cast<GLuint>(n));
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, points.buffer().id(),
                      static_cast<GLintptr>(first * kStride), static_cast<GLsizeiptr>(n * kStride));
    const auto groups = static_cast<GLuint>((n + 63) / 64);
    const GLuint gx = std::min<GLuint>(groups, 65535);
    glDispatchCompute(gx, (groups + gx - 1) / gx, 1);
  }
}

void ClearLayer(const gl::Texture& array, int layer, GLenum format, GLenum type,
                const void* value) {
  glClearTexSubImage(array.id(), 0, 0, 0, layer, array.width(), array.height(), 1, format, type,
                     value);
}

}  // namespace

void DepthPass::SplatStep(const Frame& f, Buffers& buf) {
  const bool plain = f.mode == DepthMode::kPlain;
  if (f.mode == DepthMode::kMarroquim) return;  // reads no step-1 output
  glClearTexImage(buf.splat_depth.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &kNoSplat);
  if (plain) glClearTexImage(buf.splat_normal.id(), 0, GL_RGBA, GL_FLOAT, nullptr);
  if (!f.draw) return;
  if (options_.raster == PointRaster::kCompute) {
    f.SetCamera(splat_compute_);
    glBindImageTexture(0, buf.splat_depth.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    DispatchPoints(splat_compute_, *f.points, f.near, PointsPerDispatch());
    if (plain) {
      glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
      f.SetCamera(splat_normal_compute_);
      glBindImageTexture(1, buf.splat_normal.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
      DispatchPoints(splat_normal_compute_, *f.points, f.near, PointsPerDispatch());
    }
    return;
  }
  // The step-1 normal is the output of plain only; lechelek needs depth and coverage.
  buf.splat_fb.SetDrawBuffers(plain ? 2 : 1);
  const float one = 1.0f;
  glClearNamedFramebufferfv(buf.splat_fb.id(), GL_DEPTH, 0, &one);
  buf.splat_fb.Bind(f.width, f.height);
  f.SetCamera(splat_);
  f.SetDepthRange(splat_);
  splat_.Use();
  f.points->Bind();
  glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(f.points->size()));
}

void DepthPass::ProjectStep(const Frame& f, Buffers& buf) {
  if (f.mode == DepthMode::kPlain) return;
  const bool classify = f.mode == DepthMode::kLechelek;
  const int layers = classify ? 2 : 1;  // marroquim reads the foreground pyramid only
  const auto count = static_cast<GLsizei>(f.points->size());
  // Camera and (lechelek) classification uniforms, then the program in use.
  auto use = [&](const gl::Program& p) {
    f.SetCamera(p);
    if (classify) {
      glProgramUniform1f(p.id(), 5, options_.front_radii);
      glProgramUniform1f(p.id(), 6, options_.front_rel);
    }
    p.Use();
  };
  if (options_.raster == PointRaster::kCompute) {
    for (int l = 0; l < layers; ++l) {
      // Texel a is read only where b's weight marks the texel valid: b alone is cleared.
      ClearLayer(buf.level0_b, l, GL_RGBA, GL_FLOAT, nullptr);
      ClearLayer(buf.level0_nearest, l, GL_RED_INTEGER, GL_UNSIGNED_INT, &kNoSplat);
    }
    if (!f.draw) return;
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glBindTextureUnit(0, buf.splat_depth.id());
    glBindImageTexture(0, buf.level0_nearest.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(1, buf.level0_a.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(2, buf.level0_b.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    for (int stage = 0; stage < 2; ++stage) {
      const gl::Program& p = project_compute_[classify ? 1 : 0][stage];
      use(p);
      if (stage == 1) glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
      DispatchPoints(p, *f.points, f.near, PointsPerDispatch());
    }
    return;
  }
  const bool layered = classify && project_layered_ && options_.layered_classify;
  if (layered) {
    ClearTarget(buf.layered_fb);  // both layers
  } else {
    ClearTarget(buf.front_fb);
    if (classify) ClearTarget(buf.back_fb);
  }
  if (!f.draw) return;
  f.points->Bind();
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  glBindTextureUnit(0, buf.splat_depth.id());
  auto draw = [&](const gl::Framebuffer& fb, const gl::Program& p) {
    fb.Bind(f.width, f.height);
    f.SetDepthRange(p);
    use(p);
    glDrawArrays(GL_POINTS, 0, count);
  };
  if (!classify) {
    draw(buf.front_fb, project_all_);
  } else if (layered) {
    draw(buf.layered_fb, project_layered_);  // one draw: front -> layer 0, back -> layer 1
  } else {
    draw(buf.front_fb, project_front_);
    draw(buf.back_fb, project_back_);
  }
}

void DepthPass::Process(const Camera& camera, const Rigid3d& cam_from_world, DepthTarget& target,
                        double detail) {
  const int width = target.width();
  const int height = target.height();
  if (!camera.IsPinhole() && !camera.HasZeroDistortion()) {
    throw UsageError("the depth pass needs an undistorted (pinhole) camera, got " +
                     CameraModelName(camera.model));
  }
  const Camera cam =
      (camera.width == width && camera.height == height) ? camera : camera.Scaled(width, height);
  Buffers& buf = BuffersFor(width, height);
  times_ = {};

  // Clip range from the cloud's bounds in camera space. Points behind the camera are clipped.
  const PointBuffer& points = PointsFor(detail);
  last_point_count_ = points.size();
  double zmax = 0.0;
  if (points.size() > 0) {
    const Bounds& bb = points.bounds();
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d corner((i & 1) ? bb.max.x() : bb.min.x(),
                                   (i & 2) ? bb.max.y() : bb.min.y(),
                                   (i & 4) ? bb.max.z() : bb.min.z());
      zmax = std::max(zmax, (cam_from_world * corner).z());
    }
  }
  Frame f;
  f.points = &points;
  f.mode = options_.mode;
  f.draw = points.size() > 0 && zmax > 0.0;
  f.width = width;
  f.height = height;
  f.far = static_cast<float>(f.draw ? zmax * 1.01 : 1.0);
  f.near = f.far * 1e-5f;
  f.clip_from_cam = ClipFromCam(cam, f.near, f.far);
  f.cam_from_world = cam_from_world.Matrix4().cast<float>();
  const double intr[4] = {cam.fx(), cam.fy(), cam.cx(), cam.cy()};
  for (int i = 0; i < 4; ++i) f.intrinsics[i] = static_cast<float>(intr[i]);
  f.size[0] = static_cast<float>(width);
  f.size[1] = static_cast<float>(height);
  f.max_point_size = max_point_size_;

  const bool profile = options_.profile;
  using Clock = std::chrono::steady_clock;
  Clock::time_point wall[DepthStepTimes::kSteps + 1];
  auto begin = [&](int i) {
    if (!profile) return;
    glFinish();
    wall[i] = Clock::now();
    stamps_[static_cast<size_t>(i)].Stamp();
  };
  auto end = [&](int i) {
    if (!profile) return;
    stamps_[static_cast<size_t>(i) + 1].Stamp();
    glFinish();
    wall[i + 1] = Clock::now();
  };

  glEnable(GL_PROGRAM_POINT_SIZE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);

  // Step 1: elliptical splats with depth test (plain and lechelek).
  begin(0);
  SplatStep(f, buf);
  end(0);

  // Step 2: projection of point centres (classified front/back for lechelek).
  begin(1);
  ProjectStep(f, buf);
  end(1);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);

  // Step 3: pull-push (on the foreground and background separately for lechelek).
  begin(2);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  // The background's last push (level 1 to 0) is left to the resolve, which needs it only
  // where the foreground has a hole.
  const bool push_back_in_resolve = buf.back.levels() >= 2;
  if (f.draw && f.mode != DepthMode::kPlain) {
    pull_push_.Process(buf.front, f.intrinsics);
    if (f.mode == DepthMode::kLechelek) {
      pull_push_.Process(buf.back, f.intrinsics, push_back_in_resolve ? 1 : 0);
    }
  }
  end(2);

  // Steps 4-5: coverage mask and merge.
  begin(3);
  const gl::Program& resolve = resolve_[static_cast<int>(f.mode)];
  f.SetCamera(resolve);
  if (f.mode == DepthMode::kLechelek) {
    glProgramUniform1f(resolve.id(), 5, options_.front_radii);
    glProgramUniform1f(resolve.id(), 6, options_.front_rel);
    glProgramUniform1i(resolve.id(), 8, options_.silhouette_trim);
  }
  resolve.Use();
  glBindTextureUnit(0, buf.splat_depth.id());
  glBindTextureUnit(1, buf.splat_normal.id());
  glBindTextureUnit(2, buf.front.a[0].id());
  glBindTextureUnit(3, buf.front.b[0].id());
  glBindTextureUnit(4, buf.back.a[0].id());
  glBindTextureUnit(5, buf.back.b[0].id());
  const size_t back1 = push_back_in_resolve ? 1 : 0;
  glBindTextureUnit(6, buf.back.a[back1].id());
  glBindTextureUnit(7, buf.back.b[back1].id());
  const bool lechelek = f.mode == DepthMode::kLechelek;
  if (lechelek) {
    const GLuint reset[4] = {0, 1, 1, 0};  // no group, no hole yet
    glNamedBufferSubData(buf.holes.id(), 0, sizeof(reset), reset);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf.holes.id());
  }
  glBindImageTexture(0, target.depth.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glBindImageTexture(1, target.normal.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
  glBindImageTexture(2, target.valid.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R8);
  glBindImageTexture(3, target.classes.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R8UI);
  glDispatchCompute(static_cast<GLuint>((width + 7) / 8), static_cast<GLuint>((height + 7) / 8), 1);
  if (lechelek && f.draw) {
    // The background (and its last push) at the listed foreground holes only.
    glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                    GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glProgramUniform1i(resolve_holes_.id(), 7, push_back_in_resolve ? 1 : 0);
    f.SetCamera(resolve_holes_);
    resolve_holes_.Use();
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, buf.holes.id());
    glDispatchComputeIndirect(0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  }
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  end(3);
  for (int u = 0; u < 8; ++u) glBindTextureUnit(static_cast<GLuint>(u), 0);
  glUseProgram(0);

  if (profile) {
    for (int i = 0; i < DepthStepTimes::kSteps; ++i) {
      const auto u = static_cast<size_t>(i);
      times_.gpu_ms[i] =
          static_cast<double>(stamps_[u + 1].ResultNs() - stamps_[u].ResultNs()) * 1e-6;
      times_.wall_ms[i] = std::chrono::duration<double, std::milli>(wall[i + 1] - wall[i]).count();
    }
  }
}

}  // namespace hdribr::render
