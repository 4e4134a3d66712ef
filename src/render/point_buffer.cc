#include "render/point_buffer.h"

#include <cmath>
#include <vector>

namespace hdribr::render {
namespace {

struct GpuPoint {
  float position[3];
  float normal[3];
  float radius;
  float pad;
};
static_assert(sizeof(GpuPoint) == 32);

}  // namespace

float DefaultSplatRadius(const PointCloud& cloud) {
  if (cloud.empty()) return 0.0f;
  Bounds b;
  for (const auto& p : cloud.positions) b.Extend(p.cast<double>());
  double diag = b.Diagonal();
  if (diag <= 0.0) diag = 1.0;  // a single point or coincident points
  return static_cast<float>(diag / std::sqrt(static_cast<double>(cloud.size())));
}

PointBuffer::PointBuffer(const PointCloud& cloud, float radius_override) : count_(cloud.size()) {
  const float default_radius = radius_override > 0.0f
                                   ? radius_override
                                   : (cloud.HasRadii() ? 0.0f : DefaultSplatRadius(cloud));
  std::vector<GpuPoint> points(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    GpuPoint& g = points[i];
    const Eigen::Vector3f& p = cloud.positions[i];
    const Eigen::Vector3f n = cloud.HasNormals() ? cloud.normals[i] : Eigen::Vector3f::Zero();
    g = {{p.x(), p.y(), p.z()},
         {n.x(), n.y(), n.z()},
         radius_override > 0.0f || !cloud.HasRadii() ? default_radius : cloud.radii[i],
         0.0f};
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(g.radius);
    bounds_.Extend(p.cast<double>() - r);
    bounds_.Extend(p.cast<double>() + r);
  }
  buffer_ = gl::Buffer(points.size() * sizeof(GpuPoint), points.data());
  vao_ = gl::VertexArray::Create();
  glVertexArrayVertexBuffer(vao_.id(), 0, buffer_.id(), 0, sizeof(GpuPoint));
  const GLuint offsets[3] = {0, 12, 24};
  const GLint sizes[3] = {3, 3, 1};
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexArrayAttrib(vao_.id(), a);
    glVertexArrayAttribFormat(vao_.id(), a, sizes[a], GL_FLOAT, GL_FALSE, offsets[a]);
    glVertexArrayAttribBinding(vao_.id(), a, 0);
  }
}

void PointBuffer::Bind() const { glBindVertexArray(vao_.id()); }

}  // namespace hdribr::render
