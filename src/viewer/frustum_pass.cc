#include "viewer/frustum_pass.h"

#include <algorithm>
#include <cstddef>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <utility>

#include "core/error.h"
#include "core/projection.h"
#include "viewer/glm_eigen.h"

namespace hdribr::viewer {

FrustumLines MakeFrustumLines(const Scene& scene, double depth) {
  FrustumLines out;
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    const Photo& p = scene.photos[i];
    const Camera& cam = scene.CameraOf(p);
    const Rigid3d world_from_cam = p.cam_from_world.Inverse();
    const Eigen::Vector2d px[4] = {{0, 0},
                                   {double(cam.width), 0},
                                   {double(cam.width), double(cam.height)},
                                   {0, double(cam.height)}};
    Eigen::Vector3f corner[4];
    for (int c = 0; c < 4; ++c) {
      // CamFromPixel is the ray with z = 1: scaled to camera z = depth.
      corner[c] = (world_from_cam * (cam.CamFromPixel(px[c]) * depth)).cast<float>();
    }
    const Eigen::Vector3f apex = world_from_cam.translation.cast<float>();
    for (int c = 0; c < 4; ++c) {
      for (const Eigen::Vector3f& q : {apex, corner[c], corner[c], corner[(c + 1) % 4]}) {
        out.points.push_back(q);
        out.photo.push_back(static_cast<int>(i));
      }
    }
  }
  return out;
}

FrustumPass::FrustumPass(const gl::ShaderLibrary& shaders)
    : program_(shaders.Build({"viewer_frustum.vert", "viewer_frustum.frag"})),
      vao_(gl::VertexArray::Create()) {}

void FrustumPass::SetLines(const FrustumLines& lines) {
  HDRIBR_CHECK(lines.points.size() == lines.photo.size() && lines.points.size() % 2 == 0);
  // Attribute 0: world position; attribute 1: photo index (a float, exact below 2^24).
  struct Vertex {
    glm::vec3 position;
    float photo;
  };
  static_assert(sizeof(Vertex) == 4 * sizeof(float));
  std::vector<Vertex> vertices;
  vertices.reserve(lines.points.size());
  points_.clear();
  points_.reserve(lines.points.size());
  for (size_t i = 0; i < lines.points.size(); ++i) {
    points_.push_back(ToGlm(lines.points[i]));
    vertices.push_back({points_.back(), static_cast<float>(lines.photo[i])});
  }
  count_ = vertices.size();
  int photos = 0;
  for (int k : lines.photo) photos = std::max(photos, k + 1);
  flags_.assign(static_cast<size_t>(std::max(photos, 1)), 0);
  candidate_flags_ = gl::Buffer(flags_.size() * sizeof(int), flags_.data());
  vao_ = gl::VertexArray::Create();
  if (vertices.empty()) {
    buffer_ = gl::Buffer();
    return;
  }
  buffer_ = gl::Buffer(vertices.size() * sizeof(Vertex), vertices.data());
  glVertexArrayVertexBuffer(vao_.id(), 0, buffer_.id(), 0, sizeof(Vertex));
  glEnableVertexArrayAttrib(vao_.id(), 0);
  glVertexArrayAttribFormat(vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao_.id(), 0, 0);
  glEnableVertexArrayAttrib(vao_.id(), 1);
  glVertexArrayAttribFormat(vao_.id(), 1, 1, GL_FLOAT, GL_FALSE, offsetof(Vertex, photo));
  glVertexArrayAttribBinding(vao_.id(), 1, 0);
}

void FrustumPass::SetCandidates(const std::vector<int>& photos) {
  std::vector<int> flags(flags_.size(), 0);
  for (int k : photos) {
    if (k >= 0 && static_cast<size_t>(k) < flags.size()) flags[static_cast<size_t>(k)] = 1;
  }
  if (flags == flags_) return;
  flags_ = std::move(flags);
  candidate_flags_ = gl::Buffer(flags_.size() * sizeof(int), flags_.data());
}

void FrustumPass::Draw(const Camera& camera, const Rigid3d& cam_from_world,
                       const gl::Texture& scene_depth, const gl::Framebuffer& fb, int highlight,
                       float tolerance) {
  if (count_ == 0) return;
  HDRIBR_CHECK(scene_depth.format() == GL_R32F);
  const int w = scene_depth.width(), h = scene_depth.height();
  const Camera cam = (camera.width == w && camera.height == h) ? camera : camera.Scaled(w, h);
  // Clip range: the farthest line vertex; near small against it (GL clips segments crossing
  // the near plane, so lines through the viewpoint stay correct).
  const glm::mat4 cfw(ToGlm(cam_from_world));
  float zmax = 0;
  for (const glm::vec3& p : points_) {
    zmax = std::max(zmax, (cfw * glm::vec4(p, 1.0f)).z);
  }
  if (!(zmax > 0)) return;  // every line behind the camera
  const float far = zmax * 1.01f;
  const glm::mat4 clip_from_cam = ToGlm(ClipFromCam(cam, far * 1e-4f, far));
  // GLM matrices are column-major, as GL expects with transpose = GL_FALSE.
  const GLuint p = program_.id();
  glProgramUniformMatrix4fv(p, 0, 1, GL_FALSE, glm::value_ptr(cfw));
  glProgramUniformMatrix4fv(p, 1, 1, GL_FALSE, glm::value_ptr(clip_from_cam));
  glProgramUniform1f(p, 2, tolerance);
  glProgramUniform1i(p, 3, highlight);
  glProgramUniform4fv(p, 4, 1, glm::value_ptr(colour));
  glProgramUniform4fv(p, 5, 1, glm::value_ptr(highlight_colour));
  glProgramUniform4fv(p, 6, 1, glm::value_ptr(candidate_colour));
  glProgramUniform1i(p, 7, static_cast<int>(flags_.size()));
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  fb.Bind(w, h);
  program_.Use();
  glBindTextureUnit(0, scene_depth.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, candidate_flags_.id());
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(count_));
  glBindVertexArray(0);
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace hdribr::viewer
