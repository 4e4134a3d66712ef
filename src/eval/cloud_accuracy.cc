#include "eval/cloud_accuracy.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/error.h"

namespace hdribr::eval {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// ICP works on at most this many reconstructed points (every k-th), for at most this many
// iterations.
constexpr size_t kIcpPoints = 30000;
constexpr int kIcpIterations = 50;

Cloud::Ptr ToPcl(const std::vector<Eigen::Vector3d>& points) {
  Cloud::Ptr c(new Cloud);
  c->reserve(points.size());
  for (const auto& p : points)
    c->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  return c;
}

// Share of `query` points with a point of `tree` within `tolerance`.
double ShareWithin(const Cloud& query, const pcl::KdTreeFLANN<pcl::PointXYZ>& tree,
                   double tolerance) {
  pcl::Indices idx(1);
  std::vector<float> d2(1);
  size_t ok = 0;
  for (const auto& q : query) {
    if (tree.nearestKSearch(q, 1, idx, d2) == 1 && d2[0] <= tolerance * tolerance) ++ok;
  }
  return query.empty() ? 0.0 : double(ok) / double(query.size());
}

CloudScore Score(const std::vector<Eigen::Vector3d>& rec, const Cloud::Ptr& gt,
                 const pcl::KdTreeFLANN<pcl::PointXYZ>& gt_tree, double tolerance) {
  const Cloud::Ptr r = ToPcl(rec);
  pcl::KdTreeFLANN<pcl::PointXYZ> rec_tree;
  rec_tree.setInputCloud(r);
  return {ShareWithin(*r, gt_tree, tolerance), ShareWithin(*gt, rec_tree, tolerance)};
}

}  // namespace

CloudAccuracy CompareClouds(const PointCloud& reconstruction, const Sim3d& gt_from_reconstruction,
                            const PointCloud& gt, double tolerance) {
  if (reconstruction.size() == 0) throw UsageError("the reconstructed point cloud is empty");
  if (gt.size() == 0) throw UsageError("the ground-truth point cloud is empty");
  CloudAccuracy a;
  a.tolerance = tolerance;
  std::vector<Eigen::Vector3d> rec, gt_points;
  rec.reserve(reconstruction.size());
  for (const auto& p : reconstruction.positions)
    rec.push_back(gt_from_reconstruction * p.cast<double>());
  for (const auto& p : gt.positions) gt_points.push_back(p.cast<double>());
  const Cloud::Ptr g = ToPcl(gt_points);
  pcl::KdTreeFLANN<pcl::PointXYZ> gt_tree;
  gt_tree.setInputCloud(g);
  a.cameras = Score(rec, g, gt_tree, tolerance);

  // Point-to-point ICP with scale (Besl and McKay 1992; Umeyama in each step) from the
  // cameras' alignment; pairs farther apart than twice the tolerance are left out.
  const size_t step = std::max<size_t>(1, rec.size() / kIcpPoints);
  std::vector<Eigen::Vector3d> sample;
  for (size_t i = 0; i < rec.size(); i += step) sample.push_back(rec[i]);
  const double max_d2 = 4 * tolerance * tolerance;
  pcl::Indices idx(1);
  std::vector<float> d2(1);
  for (int it = 0; it < kIcpIterations; ++it) {
    std::vector<Eigen::Vector3d> src, dst;
    for (const auto& p : sample) {
      const Eigen::Vector3d q = a.refinement * p;
      const pcl::PointXYZ pq(float(q.x()), float(q.y()), float(q.z()));
      if (gt_tree.nearestKSearch(pq, 1, idx, d2) == 1 && d2[0] <= max_d2) {
        src.push_back(p);
        dst.push_back(gt_points[static_cast<size_t>(idx[0])]);
      }
    }
    if (src.size() < 3) break;
    Sim3d next;
    try {
      next = AlignSimilarity(src, dst).dst_from_src;
    } catch (const std::invalid_argument&) {
      break;  // the matched points are degenerate (collinear): keep the last alignment
    }
    const double change = (next.translation - a.refinement.translation).norm() +
                          (next.rotation - a.refinement.rotation).norm() * tolerance +
                          std::abs(next.scale - a.refinement.scale) * tolerance;
    a.refinement = next;
    if (change < 1e-4 * tolerance) break;
  }
  a.refinement_deg = Eigen::AngleAxisd(a.refinement.rotation).angle() * 180.0 / M_PI;
  for (auto& p : rec) p = a.refinement * p;
  a.refined = Score(rec, g, gt_tree, tolerance);
  return a;
}

std::string FormatCloudAccuracy(const CloudAccuracy& a) {
  char buf[512];
  std::snprintf(buf, sizeof(buf),
                "dense cloud at %.4g (GT units): accuracy %.2f%%, completeness %.2f%% aligned by "
                "the cameras; %.2f%%, %.2f%% after ICP (rotation %.3f deg, scale %.5f)\n",
                a.tolerance, a.cameras.accuracy * 100, a.cameras.completeness * 100,
                a.refined.accuracy * 100, a.refined.completeness * 100, a.refinement_deg,
                a.refinement.scale);
  return buf;
}

}  // namespace hdribr::eval
