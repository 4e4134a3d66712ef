#include "render/depth_pass.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/error.h"
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
  gl::Texture splat_depth, splat_normal, splat_zbuffer;
  gl::Framebuffer splat_fb;
  // Level 0 of both pyramids: layers 0 (foreground) and 1 (background) of 2D arrays, so that
  // step 2 can fill both in one layered draw; the pyramids see them through layer views.
  gl::Texture level0_a, level0_b, level0_z;
  gl::Framebuffer layered_fb;
  PullPushPyramid front, back;
  gl::Texture front_zbuffer, back_zbuffer;
  gl::Framebuffer front_fb, back_fb;
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
  b->splat_depth = gl::Texture::Create2D(GL_R32F, width, height);
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
  buffers_ = std::move(b);
  return *buffers_;
}

DepthPass::DepthPass(const gl::ShaderLibrary& shaders, DepthPassOptions options)
    : options_(options),
      splat_(shaders.Build({"splat.vert", "splat.frag"})),
      project_all_(shaders.Build({"project.vert", "project.frag"}, {{"CLASSIFY", "0"}})),
      project_front_(shaders.Build({"project.vert", "project.frag"}, {{"CLASSIFY", "1"}})),
      project_back_(shaders.Build({"project.vert", "project.frag"}, {{"CLASSIFY", "2"}})),
      project_layered_(epoxy_has_gl_extension("GL_ARB_shader_viewport_layer_array")
                           ? shaders.Build({"project.vert", "project.frag"}, {{"CLASSIFY", "3"}})
                           : gl::Program()),
      resolve_{shaders.Build({"resolve.comp"}, {{"MODE", "0"}}),
               shaders.Build({"resolve.comp"}, {{"MODE", "1"}}),
               shaders.Build({"resolve.comp"}, {{"MODE", "2"}})},
      pull_push_(shaders) {
  float range[2] = {1, 64};
  glGetFloatv(GL_POINT_SIZE_RANGE, range);
  max_point_size_ = range[1];
  for (int i = 0; i <= DepthStepTimes::kSteps; ++i) {
    stamps_.push_back(gl::TimestampQuery::Create());
  }
}

DepthPass::~DepthPass() = default;

void DepthPass::SetPoints(const PointCloud& cloud, float radius_override) {
  points_ = PointBuffer(cloud, radius_override);
}

void DepthPass::Process(const Camera& camera, const Rigid3d& cam_from_world, DepthTarget& target) {
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
  const Eigen::Matrix4d cam_from_world_m = cam_from_world.Matrix4();
  double zmax = 0.0;
  if (points_.size() > 0) {
    const Bounds& bb = points_.bounds();
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d corner((i & 1) ? bb.max.x() : bb.min.x(),
                                   (i & 2) ? bb.max.y() : bb.min.y(),
                                   (i & 4) ? bb.max.z() : bb.min.z());
      zmax = std::max(zmax, (cam_from_world * corner).z());
    }
  }
  const bool draw = points_.size() > 0 && zmax > 0.0;
  const float far = static_cast<float>(draw ? zmax * 1.01 : 1.0);
  const float near = far * 1e-5f;
  const Eigen::Matrix4f clip_from_cam = ClipFromCam(cam, near, far);
  const Eigen::Matrix4f cfw = cam_from_world_m.cast<float>();
  const float intr[4] = {static_cast<float>(cam.fx()), static_cast<float>(cam.fy()),
                         static_cast<float>(cam.cx()), static_cast<float>(cam.cy())};
  const float size[2] = {static_cast<float>(width), static_cast<float>(height)};
  auto set_camera = [&](const gl::Program& p) {
    glProgramUniformMatrix4fv(p.id(), 0, 1, GL_FALSE, cfw.data());
    glProgramUniformMatrix4fv(p.id(), 1, 1, GL_FALSE, clip_from_cam.data());
    glProgramUniform4fv(p.id(), 2, 1, intr);
    glProgramUniform2fv(p.id(), 3, 1, size);
    glProgramUniform1f(p.id(), 4, max_point_size_);
  };
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

  const DepthMode mode = options_.mode;
  glEnable(GL_PROGRAM_POINT_SIZE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);

  // Step 1: elliptical splats with depth test (plain and lechelek).
  begin(0);
  // The step-1 normal is the output of plain only; lechelek needs depth and coverage.
  buf.splat_fb.SetDrawBuffers(mode == DepthMode::kPlain ? 2 : 1);
  ClearTarget(buf.splat_fb);
  if (draw && mode != DepthMode::kMarroquim) {
    buf.splat_fb.Bind(width, height);
    set_camera(splat_);
    splat_.Use();
    points_.Bind();
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(points_.size()));
  }
  end(0);

  // Step 2: projection of point centres (classified front/back for lechelek).
  begin(1);
  const bool layered = project_layered_ && options_.layered_classify;
  if (mode == DepthMode::kMarroquim || !layered) {
    ClearTarget(buf.front_fb);
    ClearTarget(buf.back_fb);
  } else {
    ClearTarget(buf.layered_fb);  // both layers
  }
  if (draw && mode != DepthMode::kPlain) {
    points_.Bind();
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindTextureUnit(0, buf.splat_depth.id());
    auto set_classify = [&](const gl::Program& p) {
      set_camera(p);
      glProgramUniform1f(p.id(), 5, options_.front_radii);
      glProgramUniform1f(p.id(), 6, options_.front_rel);
      p.Use();
    };
    const auto count = static_cast<GLsizei>(points_.size());
    if (mode == DepthMode::kMarroquim) {
      buf.front_fb.Bind(width, height);
      set_camera(project_all_);
      project_all_.Use();
      glDrawArrays(GL_POINTS, 0, count);
    } else if (layered) {
      buf.layered_fb.Bind(width, height);  // one draw: front -> layer 0, back -> layer 1
      set_classify(project_layered_);
      glDrawArrays(GL_POINTS, 0, count);
    } else {
      buf.front_fb.Bind(width, height);
      set_classify(project_front_);
      glDrawArrays(GL_POINTS, 0, count);
      buf.back_fb.Bind(width, height);
      set_classify(project_back_);
      glDrawArrays(GL_POINTS, 0, count);
    }
  }
  end(1);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);

  // Step 3: pull-push (on the foreground and background separately for lechelek).
  begin(2);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  // The background's last push (level 1 to 0) is left to the resolve, which needs it only
  // where the foreground has a hole.
  const bool push_back_in_resolve = buf.back.levels() >= 2;
  if (draw && mode != DepthMode::kPlain) {
    pull_push_.Process(buf.front, intr);
    if (mode == DepthMode::kLechelek) {
      pull_push_.Process(buf.back, intr, push_back_in_resolve ? 1 : 0);
    }
  }
  end(2);

  // Steps 4-5: coverage mask and merge.
  begin(3);
  const gl::Program& resolve = resolve_[static_cast<int>(mode)];
  set_camera(resolve);
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
  if (mode == DepthMode::kLechelek) {
    glProgramUniform1i(resolve.id(), 7, push_back_in_resolve && draw ? 1 : 0);
  }
  glBindImageTexture(0, target.depth.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glBindImageTexture(1, target.normal.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
  glBindImageTexture(2, target.valid.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R8);
  glBindImageTexture(3, target.classes.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R8UI);
  glDispatchCompute(static_cast<GLuint>((width + 7) / 8), static_cast<GLuint>((height + 7) / 8), 1);
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
