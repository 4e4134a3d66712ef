// Similarity alignment of two point sets (camera centres): Umeyama 1991.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace hdribr {

// y = scale * rotation * x + translation.
struct Sim3d {
  double scale = 1;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator*(const Eigen::Vector3d& x) const {
    return scale * (rotation * x) + translation;
  }
};

struct SimilarityAlignment {
  Sim3d dst_from_src;
  std::vector<double> residuals;  // |dst_i - dst_from_src * src_i|, in dst units
  double rms = 0;
  double median = 0;
  double max = 0;
};

// Least-squares similarity mapping src onto dst (Umeyama, "Least-squares estimation of
// transformation parameters between two point patterns", PAMI 1991, as Eigen::umeyama computes
// it: never a reflection). Throws std::invalid_argument for fewer than 3 pairs, different sizes, or
// a degenerate (collinear) src set.
SimilarityAlignment AlignSimilarity(const std::vector<Eigen::Vector3d>& src,
                                    const std::vector<Eigen::Vector3d>& dst);

}  // namespace hdribr
