#include "core/dominant_plane.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace hdribr {
namespace {

constexpr size_t kMaxSample = 50000;
constexpr int kHypotheses = 500;
constexpr double kCameraSide = 0.9;

// The value at fraction f of the sorted values (nearest rank).
double Percentile(std::vector<double> values, double f) {
  const auto at = values.begin() + static_cast<std::ptrdiff_t>(f * (values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

}  // namespace

// RANSAC is written here rather than taken from PCL's SACSegmentation: a hypothesis must pass
// the cameras' side before it is scored (a wall that the cameras circle holds many points but
// is no background), and core links Eigen alone.
DominantPlane FindDominantPlane(const Scene& scene) {
  DominantPlane plane;
  const auto& positions = scene.points.positions;
  if (positions.size() < 3 || scene.photos.empty()) return plane;
  const size_t stride = std::max<size_t>(1, positions.size() / kMaxSample);
  std::vector<Eigen::Vector3d> sample;
  sample.reserve(positions.size() / stride + 1);
  for (size_t i = 0; i < positions.size(); i += stride)
    sample.push_back(positions[i].cast<double>());
  std::vector<Eigen::Vector3d> centres;
  for (const Photo& photo : scene.photos) centres.push_back(photo.Center());
  const double tolerance = kDominantPlaneTolerance * scene.scene_scale;
  // A plane's side for the cameras: +1 or -1 when at least kCameraSide of them are on it, else 0.
  auto camera_side = [&](const Eigen::Vector3d& n, double offset) {
    int positive = 0;
    for (const Eigen::Vector3d& c : centres) positive += n.dot(c) + offset > 0.0;
    const double share = static_cast<double>(positive) / static_cast<double>(centres.size());
    return share >= kCameraSide ? 1 : share <= 1.0 - kCameraSide ? -1 : 0;
  };
  auto inliers_of = [&](const Eigen::Vector3d& n, double offset) {
    size_t count = 0;
    for (const Eigen::Vector3d& p : sample) count += std::abs(n.dot(p) + offset) <= tolerance;
    return count;
  };
  std::mt19937 rng(1);
  std::uniform_int_distribution<size_t> pick(0, sample.size() - 1);
  size_t best = 0;
  Eigen::Vector3d best_n = Eigen::Vector3d::Zero();
  double best_offset = 0.0;
  for (int h = 0; h < kHypotheses; ++h) {
    const Eigen::Vector3d& a = sample[pick(rng)];
    Eigen::Vector3d n = (sample[pick(rng)] - a).cross(sample[pick(rng)] - a);
    if (n.norm() <= 1e-12 * scene.scene_scale * scene.scene_scale) continue;
    n.normalize();
    const double offset = -n.dot(a);
    if (camera_side(n, offset) == 0) continue;
    const size_t count = inliers_of(n, offset);
    if (count > best) {
      best = count;
      best_n = n;
      best_offset = offset;
    }
  }
  if (best < 3 || static_cast<double>(best) < kDominantPlaneMinShare * sample.size()) return plane;
  // Least squares on the inliers: the normal is the covariance's smallest eigenvector, the
  // in-plane axes the other two.
  std::vector<Eigen::Vector3d> inliers;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : sample) {
    if (std::abs(best_n.dot(p) + best_offset) <= tolerance) {
      inliers.push_back(p);
      mean += p;
    }
  }
  mean /= static_cast<double>(inliers.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : inliers) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Eigen::Vector3d n = eig.eigenvectors().col(0).normalized();
  double offset = -n.dot(mean);
  const int side = camera_side(n, offset);
  if (side == 0) return plane;
  n *= side;
  offset *= side;
  plane.normal = n;
  plane.offset = offset;
  plane.axis_u = eig.eigenvectors().col(2).normalized();
  plane.axis_v = n.cross(plane.axis_u);
  std::vector<double> u, v;
  for (const Eigen::Vector3d& p : inliers) {
    u.push_back(plane.axis_u.dot(p));
    v.push_back(plane.axis_v.dot(p));
  }
  const double u0 = Percentile(u, 0.01), u1 = Percentile(u, 0.99);
  const double v0 = Percentile(v, 0.01), v1 = Percentile(v, 0.99);
  const double du = kDominantPlaneMargin * (u1 - u0), dv = kDominantPlaneMargin * (v1 - v0);
  plane.extent = {u0 - du, u1 + du, v0 - dv, v1 + dv};
  plane.inlier_share = static_cast<double>(inliers_of(n, offset)) / sample.size();
  return plane;
}

}  // namespace hdribr
