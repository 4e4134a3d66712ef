#include "frontend/point_attributes.h"

#include <pcl/features/normal_3d_omp.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "frontend/parallel.h"

namespace hdribr {

namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr ToPcl(const PointCloud& cloud) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr pc(new pcl::PointCloud<pcl::PointXYZ>);
  pc->resize(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    (*pc)[i].x = cloud.positions[i].x();
    (*pc)[i].y = cloud.positions[i].y();
    (*pc)[i].z = cloud.positions[i].z();
  }
  return pc;
}

// Per point: the mean distance to its k nearest neighbours (itself excluded), 0 without any;
// the searches on `threads` threads.
std::vector<double> MeanNeighbourDistances(const PointCloud& cloud, int k, int threads) {
  const size_t n = cloud.size();
  std::vector<double> mean(n, 0.0);
  const auto pc = ToPcl(cloud);
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(pc);
  const int search = std::min<int>(k + 1, static_cast<int>(n));
  constexpr int kBlock = 4096;
  const int blocks = static_cast<int>((n + kBlock - 1) / kBlock);
  ParallelFor(blocks, ThreadCount(threads), [&](int b) {
    pcl::Indices idx;
    std::vector<float> d2;
    const size_t end = std::min(n, size_t(b + 1) * kBlock);
    for (size_t i = size_t(b) * kBlock; i < end; ++i) {
      const int found = tree.nearestKSearch((*pc)[i], search, idx, d2);
      double sum = 0;
      int count = 0;
      for (int j = 0; j < found; ++j) {
        if (static_cast<size_t>(idx[j]) == i) continue;  // the point itself
        sum += std::sqrt(d2[j]);
        ++count;
      }
      mean[i] = count ? sum / count : 0.0;
    }
  });
  return mean;
}

template <typename T>
void KeepIndices(std::vector<T>& v, const pcl::Indices& keep) {
  if (v.empty()) return;
  std::vector<T> out;
  out.reserve(keep.size());
  for (auto i : keep) out.push_back(v[static_cast<size_t>(i)]);
  v.swap(out);
}

// Unit `nrm` flipped to face `view`; `view` (or +z) where nrm is not a usable direction.
Eigen::Vector3f OrientedNormal(Eigen::Vector3f nrm, const Eigen::Vector3f& view) {
  if (!nrm.allFinite() || nrm.norm() < 0.5f) {
    return view.norm() > 0 ? view.normalized() : Eigen::Vector3f::UnitZ();
  }
  nrm.normalize();
  return nrm.dot(view) < 0 ? -nrm : nrm;
}

}  // namespace

size_t RemoveOutliers(PointCloud& cloud, std::vector<Eigen::Vector3f>& view_dirs,
                      const std::vector<Eigen::Vector3d>& centers,
                      const AttributeOptions& options) {
  const size_t n = cloud.size();
  if (n <= static_cast<size_t>(options.outlier_neighbors)) return 0;
  // Per point: the mean distance to its neighbours, and that over its distance to the nearest
  // camera.
  const std::vector<double> spread =
      MeanNeighbourDistances(cloud, options.outlier_neighbors, options.threads);
  std::vector<double> ratio(n, 0.0);
  for (size_t i = 0; i < n && !centers.empty(); ++i) {
    double nearest2 = std::numeric_limits<double>::infinity();
    const Eigen::Vector3d p = cloud.positions[i].cast<double>();
    for (const Eigen::Vector3d& c : centers) nearest2 = std::min(nearest2, (c - p).squaredNorm());
    ratio[i] = spread[i] / std::max(std::sqrt(nearest2), 1e-9);
  }
  // Mean + outlier_stddev standard deviations (sample) of v.
  const auto limit = [&](const std::vector<double>& v) {
    double mean = 0, sq = 0;
    for (double x : v) mean += x;
    mean /= n;
    for (double x : v) sq += (x - mean) * (x - mean);
    return mean + options.outlier_stddev * std::sqrt(sq / (n - 1));
  };
  const double spread_limit = limit(spread), ratio_limit = limit(ratio);
  pcl::Indices keep;
  keep.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    if (spread[i] <= spread_limit || (!centers.empty() && ratio[i] <= ratio_limit)) {
      keep.push_back(static_cast<pcl::index_t>(i));
    }
  }
  const size_t removed = n - keep.size();
  KeepIndices(cloud.positions, keep);
  KeepIndices(cloud.normals, keep);
  KeepIndices(cloud.colors, keep);
  KeepIndices(cloud.radii, keep);
  KeepIndices(view_dirs, keep);
  return removed;
}

void EstimateNormals(PointCloud& cloud, const std::vector<Eigen::Vector3f>& view_dirs,
                     const AttributeOptions& options) {
  if (cloud.normals.size() == cloud.size()) {
    for (size_t i = 0; i < cloud.size(); ++i) {
      const Eigen::Vector3f view =
          i < view_dirs.size() ? view_dirs[i] : Eigen::Vector3f(0.f, 0.f, 0.f);
      cloud.normals[i] = OrientedNormal(cloud.normals[i], view);
    }
    return;
  }
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> ne(ThreadCount(options.threads));
  ne.setInputCloud(ToPcl(cloud));
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  ne.setSearchMethod(tree);
  ne.setKSearch(std::min<int>(options.normal_neighbors, static_cast<int>(cloud.size())));
  pcl::PointCloud<pcl::Normal> normals;
  ne.compute(normals);
  cloud.normals.resize(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f nrm(normals[i].normal_x, normals[i].normal_y, normals[i].normal_z);
    const Eigen::Vector3f view =
        i < view_dirs.size() ? view_dirs[i] : Eigen::Vector3f(0.f, 0.f, 0.f);
    cloud.normals[i] = OrientedNormal(nrm, view);
  }
}

void EstimateRadii(PointCloud& cloud, const AttributeOptions& options) {
  cloud.radii.assign(cloud.size(), 0.f);
  if (cloud.size() < 2) {
    if (!cloud.empty()) cloud.radii[0] = 1.f;
    return;
  }
  const std::vector<double> mean =
      MeanNeighbourDistances(cloud, options.radius_neighbors, options.threads);
  for (size_t i = 0; i < cloud.size(); ++i) cloud.radii[i] = static_cast<float>(mean[i]);
  std::vector<float> sorted = cloud.radii;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  float median = sorted[sorted.size() / 2];
  if (!(median > 0)) median = 1e-3f;
  for (float& r : cloud.radii) r = std::clamp(r, 0.25f * median, 4.f * median);
}

std::vector<Eigen::Vector3f> ViewDirsFromCameras(const PointCloud& cloud,
                                                 const std::vector<Eigen::Vector3d>& centers) {
  std::vector<Eigen::Vector3f> dirs(cloud.size(), Eigen::Vector3f::Zero());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = cloud.positions[i].cast<double>();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& c : centers) sum += (c - p).normalized();
    if (sum.norm() > 0) dirs[i] = sum.normalized().cast<float>();
  }
  return dirs;
}

}  // namespace hdribr
