// Input camera frustums drawn in 3D over the viewer's picture: GL lines projected like the
// renderer (core/projection.h), hidden where the scene's depth is nearer.
#pragma once

#include <Eigen/Core>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"
#include "core/scene.h"
#include "gl/objects.h"
#include "gl/shader_library.h"

namespace hdribr::viewer {

// Line segments (pairs of world points) of each photo's frustum: apex to the four image
// corners at camera depth `depth` (world units), and the rectangle joining them.
struct FrustumLines {
  std::vector<Eigen::Vector3f> points;  // 2 per segment
  std::vector<int> photo;               // photo index of each point
};
FrustumLines MakeFrustumLines(const Scene& scene, double depth);

class FrustumPass {
 public:
  // Needs a current GL 4.5 context.
  explicit FrustumPass(const gl::ShaderLibrary& shaders);

  void SetLines(const FrustumLines& lines);
  size_t segments() const { return count_ / 2; }
  // Photos drawn in the candidate colour (the renderer's candidates of the frame).
  void SetCandidates(const std::vector<int>& photos);

  // Draws the lines seen by `camera` (pinhole, the framebuffer's size) into `fb`, whose row 0
  // is the top image row, discarding fragments farther than `scene_depth` (R32F camera z,
  // 0 = none, same size) by more than `tolerance` x depth. Photo `highlight` (-1: none) gets
  // the highlight colour, the candidates the candidate colour. Colours are RGBA in [0, 1].
  void Draw(const Camera& camera, const Rigid3d& cam_from_world, const gl::Texture& scene_depth,
            const gl::Framebuffer& fb, int highlight = -1, float tolerance = 0.01f);

  glm::vec4 colour{0.31f, 0.78f, 1.0f, 1.0f};
  glm::vec4 highlight_colour{1.0f, 0.78f, 0.0f, 1.0f};
  glm::vec4 candidate_colour{0.35f, 1.0f, 0.35f, 1.0f};

 private:
  gl::Program program_;
  gl::Buffer buffer_;
  gl::Buffer candidate_flags_;  // int per photo: 1 = candidate
  std::vector<int> flags_;      // what candidate_flags_ holds
  gl::VertexArray vao_;
  std::vector<glm::vec3> points_;  // world, for the clip range
  size_t count_ = 0;
};

}  // namespace hdribr::viewer
