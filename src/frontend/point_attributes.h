// Point cloud clean-up and splat attributes with PCL: outliers, normals, radii.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/point_cloud.h"

namespace hdribr {

// Version of the clean-up (RemoveOutliers), recorded in a workspace's dense-stage marker like
// kDenseVersion: raised when its code keeps other points of the same cloud.
inline constexpr int kCleanupVersion = 2;

struct AttributeOptions {
  int outlier_neighbors = 16;   // statistical outlier removal: neighbours per point
  double outlier_stddev = 2.0;  // ... and the threshold in standard deviations
  int normal_neighbors = 16;    // k for the PCA normal
  int radius_neighbors = 6;     // k for the splat radius (mean distance to them)
  int threads = 0;              // 0: hardware concurrency
};

// Removes statistical outliers (pcl::StatisticalOutlierRemoval's rule, on two measures): a
// point goes when its mean distance to its outlier_neighbors nearest neighbours exceeds the
// cloud's mean by outlier_stddev standard deviations, and so does that distance divided by its
// distance to the nearest of `centers` (world frame; empty: the first test alone). A depth map
// samples a surface at a spacing that grows with its depth: on the first measure alone a facade
// across a square, sampled several times more sparsely than the foreground, would go as a
// whole, and on the second alone the foreground's sparser parts. Keeps the attribute arrays and
// `view_dirs` (if not empty) in step. Returns the number removed.
size_t RemoveOutliers(PointCloud& cloud, std::vector<Eigen::Vector3f>& view_dirs,
                      const std::vector<Eigen::Vector3d>& centers, const AttributeOptions& options);

// PCA normals (pcl::NormalEstimationOMP), flipped to face `view_dirs[i]` (the direction from the
// point toward the cameras that see it). Points whose normal cannot be estimated get view_dirs[i].
// A cloud that already has a normal per point (e.g. PatchMatch planes) keeps them, oriented the
// same way.
void EstimateNormals(PointCloud& cloud, const std::vector<Eigen::Vector3f>& view_dirs,
                     const AttributeOptions& options);

// Splat radius = mean distance to the k nearest neighbours, clamped to [0.25, 4] x the median,
// so that splats of neighbouring points overlap (r > half the spacing).
void EstimateRadii(PointCloud& cloud, const AttributeOptions& options);

// Unit mean direction from each point toward all camera centres (used when the observing
// cameras are not known, e.g. for COLMAP's fused.ply).
std::vector<Eigen::Vector3f> ViewDirsFromCameras(const PointCloud& cloud,
                                                 const std::vector<Eigen::Vector3d>& centers);

}  // namespace hdribr
