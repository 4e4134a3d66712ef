// The point cloud on the GPU: one vertex buffer (position, normal, radius) and its layout.
#pragma once

#include <vector>

#include "core/point_cloud.h"
#include "gl/objects.h"

namespace hdribr::render {

// Splat radius used when a cloud has no radii: the diagonal of the bounding box over
// sqrt(N), the point spacing of N points spread over a surface of about diagonal^2 (for a
// surface sampled uniformly this makes neighbouring splats overlap). 0 for an empty cloud.
float DefaultSplatRadius(const PointCloud& cloud);

class PointBuffer {
 public:
  PointBuffer() = default;
  // Uploads positions, normals (zero when absent: view-facing discs) and radii (the
  // DefaultSplatRadius heuristic when absent, or `radius_override` when > 0), in Morton order
  // of the positions (not the cloud's order).
  explicit PointBuffer(const PointCloud& cloud, float radius_override = 0.0f);
  // A coarser level of this cloud: every `stride`-th point of the Morton order (a spatially
  // even subset), radii times sqrt(stride) so that its splats cover the same surface. Reads the
  // buffer back from the GPU.
  PointBuffer Decimated(int stride) const;
  PointBuffer(PointBuffer&&) noexcept = default;
  PointBuffer& operator=(PointBuffer&&) noexcept = default;

  size_t size() const { return count_; }
  // World-space bounds, including the splat radii.
  const Bounds& bounds() const { return bounds_; }
  // Binds the vertex array (attributes 0: position, 1: normal, 2: radius).
  void Bind() const;
  // The buffer itself, 8 floats per point (position, normal, radius, padding), for shaders
  // that read it as storage (shaders/points_buffer.glsl).
  const gl::Buffer& buffer() const { return buffer_; }

 private:
  struct GpuPoint;
  PointBuffer(const std::vector<GpuPoint>& points, const Bounds& bounds);

  gl::Buffer buffer_;
  gl::VertexArray vao_;
  size_t count_ = 0;
  Bounds bounds_;
};

}  // namespace hdribr::render
