#include "render/point_color_pass.h"

#include <algorithm>

#include "core/error.h"
#include "core/projection.h"
#include "render/point_buffer.h"

namespace hdribr::render {
namespace {

struct GpuColorPoint {
  float position[3];
  float normal[3];
  float radius;
  float color[3];
};
static_assert(sizeof(GpuColorPoint) == 40);

}  // namespace

PointColorPass::PointColorPass(const gl::ShaderLibrary& shaders)
    : program_(shaders.Build({"point_color.vert", "point_color.frag"})) {
  float range[2] = {1, 64};
  glGetFloatv(GL_POINT_SIZE_RANGE, range);
  max_point_size_ = range[1];
}

PointColorPass::~PointColorPass() = default;

void PointColorPass::SetPoints(const PointCloud& cloud,
                               const std::vector<Eigen::Vector3f>& colors_bgr,
                               float radius_override) {
  HDRIBR_CHECK(colors_bgr.size() == cloud.size());
  const float default_radius = radius_override > 0.0f
                                   ? radius_override
                                   : (cloud.HasRadii() ? 0.0f : DefaultSplatRadius(cloud));
  std::vector<GpuColorPoint> points;
  points.reserve(cloud.size());
  bounds_ = Bounds();
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f& c = colors_bgr[i];
    if (c.minCoeff() < 0.0f) continue;
    const Eigen::Vector3f& p = cloud.positions[i];
    const Eigen::Vector3f n = cloud.HasNormals() ? cloud.normals[i] : Eigen::Vector3f::Zero();
    const float r = default_radius > 0.0f ? default_radius : cloud.radii[i];
    // The shader's colour attribute is RGB (like every texture on the GPU).
    points.push_back({{p.x(), p.y(), p.z()}, {n.x(), n.y(), n.z()}, r, {c.z(), c.y(), c.x()}});
    const Eigen::Vector3d rv = Eigen::Vector3d::Constant(r);
    bounds_.Extend(p.cast<double>() - rv);
    bounds_.Extend(p.cast<double>() + rv);
  }
  count_ = points.size();
  vao_ = gl::VertexArray::Create();
  if (points.empty()) {
    buffer_ = gl::Buffer();
    return;
  }
  buffer_ = gl::Buffer(points.size() * sizeof(GpuColorPoint), points.data());
  glVertexArrayVertexBuffer(vao_.id(), 0, buffer_.id(), 0, sizeof(GpuColorPoint));
  const GLuint offsets[4] = {0, 12, 24, 28};
  const GLint sizes[4] = {3, 3, 1, 3};
  for (GLuint a = 0; a < 4; ++a) {
    glEnableVertexArrayAttrib(vao_.id(), a);
    glVertexArrayAttribFormat(vao_.id(), a, sizes[a], GL_FLOAT, GL_FALSE, offsets[a]);
    glVertexArrayAttribBinding(vao_.id(), a, 0);
  }
}

PointColorImages PointColorPass::Render(const Camera& camera, const Rigid3d& cam_from_world,
                                        int width, int height) {
  HDRIBR_CHECK(width > 0 && height > 0);
  if (!camera.IsPinhole() && !camera.HasZeroDistortion()) {
    throw UsageError("colour-per-point splatting needs an undistorted (pinhole) camera, got " +
                     CameraModelName(camera.model));
  }
  const Camera cam =
      (camera.width == width && camera.height == height) ? camera : camera.Scaled(width, height);
  if (!fb_ || color_.width() != width || color_.height() != height) {
    color_ = gl::Texture::Create2D(GL_RGBA32F, width, height);
    zbuffer_ = gl::Texture::Create2D(GL_DEPTH_COMPONENT32F, width, height);
    fb_ = gl::Framebuffer::Create();
    fb_.AttachColor(0, color_);
    fb_.AttachDepth(zbuffer_);
    fb_.SetDrawBuffers(1);
    fb_.CheckComplete();
  }
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(fb_.id(), GL_COLOR, 0, zero);
  const float one = 1.0f;
  glClearNamedFramebufferfv(fb_.id(), GL_DEPTH, 0, &one);

  // Clip range from the bounds in camera space, as in the depth pass.
  double zmax = 0.0;
  if (count_ > 0) {
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d corner((i & 1) ? bounds_.max.x() : bounds_.min.x(),
                                   (i & 2) ? bounds_.max.y() : bounds_.min.y(),
                                   (i & 4) ? bounds_.max.z() : bounds_.min.z());
      zmax = std::max(zmax, (cam_from_world * corner).z());
    }
  }
  if (count_ > 0 && zmax > 0.0) {
    const float far = static_cast<float>(zmax * 1.01);
    const float near = far * 1e-5f;
    const Eigen::Matrix4f clip_from_cam = ClipFromCam(cam, near, far);
    const Eigen::Matrix4f cfw = cam_from_world.Matrix4().cast<float>();
    const float intr[4] = {static_cast<float>(cam.fx()), static_cast<float>(cam.fy()),
                           static_cast<float>(cam.cx()), static_cast<float>(cam.cy())};
    const float size[2] = {static_cast<float>(width), static_cast<float>(height)};
    const GLuint p = program_.id();
    glProgramUniformMatrix4fv(p, 0, 1, GL_FALSE, cfw.data());
    glProgramUniformMatrix4fv(p, 1, 1, GL_FALSE, clip_from_cam.data());
    glProgramUniform4fv(p, 2, 1, intr);
    glProgramUniform2fv(p, 3, 1, size);
    glProgramUniform1f(p, 4, max_point_size_);
    glProgramUniform2f(p, 9, near, far);  // shaders/points.glsl
    glEnable(GL_PROGRAM_POINT_SIZE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    fb_.Bind(width, height);
    program_.Use();
    glBindVertexArray(vao_.id());
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(count_));
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  cv::Mat rgba(height, width, CV_32FC4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(color_.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(rgba.total() * 16),
                    rgba.data);
  PointColorImages out;
  out.color.create(height, width, CV_32FC3);
  out.valid.create(height, width, CV_8UC1);
  for (int y = 0; y < height; ++y) {
    const auto* src = rgba.ptr<cv::Vec4f>(y);
    auto* dst = out.color.ptr<cv::Vec3f>(y);
    auto* v = out.valid.ptr<std::uint8_t>(y);
    for (int x = 0; x < width; ++x) {
      dst[x] = cv::Vec3f(src[x][2], src[x][1], src[x][0]);
      v[x] = src[x][3] > 0.5f ? 255 : 0;
    }
  }
  return out;
}

}  // namespace hdribr::render
