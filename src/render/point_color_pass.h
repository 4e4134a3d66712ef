// Colour-per-point splatting, the baseline the paper compares image-based blending with
// (Lechelek et al. 2019, Fig. 8): every point drawn as an elliptical splat of one colour,
// depth-tested, without pull-push or blending.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "core/camera.h"
#include "core/point_cloud.h"
#include "core/rigid3.h"
#include "gl/objects.h"
#include "gl/shader_library.h"

namespace hdribr::render {

// CPU read-back of a colour-per-point render. Rows top to bottom.
struct PointColorImages {
  cv::Mat color;  // CV_32FC3 BGR, the splat colours; 0 where no splat covers the pixel
  cv::Mat valid;  // CV_8UC1, 255 where a splat covers the pixel
};

class PointColorPass {
 public:
  // Needs a current GL 4.5 context.
  explicit PointColorPass(const gl::ShaderLibrary& shaders);
  ~PointColorPass();
  PointColorPass(const PointColorPass&) = delete;
  PointColorPass& operator=(const PointColorPass&) = delete;

  // Uploads the points with one colour each (BGR, any unit; one entry per point). Points whose
  // colour has a negative component (no colour known) are left out. Normals and radii as in
  // PointBuffer (DefaultSplatRadius when the cloud has no radii, or radius_override > 0).
  void SetPoints(const PointCloud& cloud, const std::vector<Eigen::Vector3f>& colors_bgr,
                 float radius_override = 0.0f);
  size_t size() const { return count_; }

  // Renders the coloured splats seen by `camera` (pinhole; intrinsics rescaled to the output
  // size when it differs) and reads them back.
  PointColorImages Render(const Camera& camera, const Rigid3d& cam_from_world, int width,
                          int height);

 private:
  gl::Program program_;
  gl::Buffer buffer_;
  gl::VertexArray vao_;
  size_t count_ = 0;
  Bounds bounds_;
  gl::Texture color_, zbuffer_;
  gl::Framebuffer fb_;
  float max_point_size_ = 64.0f;
};

}  // namespace hdribr::render
