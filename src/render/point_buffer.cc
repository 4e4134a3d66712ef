#include "render/point_buffer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace hdribr::render {

struct PointBuffer::GpuPoint {
  float position[3];
  float normal[3];
  float radius;
  float pad;
};

namespace {

// Spreads the low 10 bits of v to every third bit (bit i -> bit 3 i).
std::uint32_t SpreadBits(std::uint32_t v) {
  v &= 0x3FF;
  v = (v | (v << 16)) & 0x030000FF;
  v = (v | (v << 8)) & 0x0300F00F;
  v = (v | (v << 4)) & 0x030C30C3;
  v = (v | (v << 2)) & 0x09249249;
  return v;
}

// Indices of the points in Morton (Z-curve) order of their positions on a 1024^3 grid over
// the bounds: consecutive points are then near each other, so the compute raster's
// neighbouring invocations touch nearby pixels with splats of similar size (the vertex order
// optimisation of Schuetz et al. 2021).
std::vector<std::uint32_t> MortonOrder(const PointCloud& cloud) {
  Bounds b;
  for (const auto& p : cloud.positions) b.Extend(p.cast<double>());
  const Eigen::Vector3d extent = (b.max - b.min).cwiseMax(1e-12);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d u =
        ((cloud.positions[i].cast<double>() - b.min).cwiseQuotient(extent) * 1023.0)
            .cwiseMax(0.0)
            .cwiseMin(1023.0);
    const std::uint32_t code = SpreadBits(static_cast<std::uint32_t>(u.x())) |
                               (SpreadBits(static_cast<std::uint32_t>(u.y())) << 1) |
                               (SpreadBits(static_cast<std::uint32_t>(u.z())) << 2);
    keyed[i] = {code, static_cast<std::uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(cloud.size());
  for (size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

}  // namespace

float DefaultSplatRadius(const PointCloud& cloud) {
  if (cloud.empty()) return 0.0f;
  Bounds b;
  for (const auto& p : cloud.positions) b.Extend(p.cast<double>());
  double diag = b.Diagonal();
  if (diag <= 0.0) diag = 1.0;  // a single point or coincident points
  return static_cast<float>(diag / std::sqrt(static_cast<double>(cloud.size())));
}

PointBuffer::PointBuffer(const PointCloud& cloud, float radius_override) {
  const float default_radius = radius_override > 0.0f
                                   ? radius_override
                                   : (cloud.HasRadii() ? 0.0f : DefaultSplatRadius(cloud));
  const std::vector<std::uint32_t> order = MortonOrder(cloud);
  std::vector<GpuPoint> points(cloud.size());
  Bounds bounds;
  for (size_t k = 0; k < cloud.size(); ++k) {
    GpuPoint& g = points[k];
    const size_t i = order[k];
    const Eigen::Vector3f& p = cloud.positions[i];
    const Eigen::Vector3f n = cloud.HasNormals() ? cloud.normals[i] : Eigen::Vector3f::Zero();
    g = {{p.x(), p.y(), p.z()},
         {n.x(), n.y(), n.z()},
         radius_override > 0.0f || !cloud.HasRadii() ? default_radius : cloud.radii[i],
         0.0f};
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(g.radius);
    bounds.Extend(p.cast<double>() - r);
    bounds.Extend(p.cast<double>() + r);
  }
  *this = PointBuffer(points, bounds);
}

PointBuffer::PointBuffer(const std::vector<GpuPoint>& points, const Bounds& bounds)
    : count_(points.size()), bounds_(bounds) {
  static_assert(sizeof(GpuPoint) == 32);  // shaders/points_buffer.glsl
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

PointBuffer PointBuffer::Decimated(int stride) const {
  const size_t step = static_cast<size_t>(std::max(1, stride));
  std::vector<GpuPoint> all(count_);
  if (count_ > 0) {
    glGetNamedBufferSubData(buffer_.id(), 0, static_cast<GLsizeiptr>(count_ * sizeof(GpuPoint)),
                            all.data());
  }
  const auto scale = static_cast<float>(std::sqrt(static_cast<double>(step)));
  std::vector<GpuPoint> points;
  points.reserve(count_ / step + 1);
  Bounds bounds;
  for (size_t k = 0; k < count_; k += step) {
    GpuPoint g = all[k];
    g.radius *= scale;
    const Eigen::Vector3d p(g.position[0], g.position[1], g.position[2]);
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(g.radius);
    bounds.Extend(p - r);
    bounds.Extend(p + r);
    points.push_back(g);
  }
  return PointBuffer(points, bounds);
}

void PointBuffer::Bind() const { glBindVertexArray(vao_.id()); }

}  // namespace hdribr::render
