#include "eval/alignment.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hdribr {

SimilarityAlignment AlignSimilarity(const std::vector<Eigen::Vector3d>& src,
                                    const std::vector<Eigen::Vector3d>& dst) {
  if (src.size() != dst.size()) throw std::invalid_argument("AlignSimilarity: sizes differ");
  if (src.size() < 3) throw std::invalid_argument("AlignSimilarity: needs at least 3 pairs");
  const Eigen::Index n = static_cast<Eigen::Index>(src.size());
  Eigen::Matrix3Xd x(3, n), y(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    x.col(i) = src[static_cast<size_t>(i)];
    y.col(i) = dst[static_cast<size_t>(i)];
  }
  // Eigen::umeyama does not report a degenerate problem: the covariance of the centred sets
  // must have rank 2 at least (src not collinear, dst not collapsed).
  const Eigen::Matrix3Xd xc = x.colwise() - x.rowwise().mean();
  const Eigen::Matrix3Xd yc = y.colwise() - y.rowwise().mean();
  const Eigen::Vector3d d =
      Eigen::JacobiSVD<Eigen::Matrix3d>(yc * xc.transpose() / static_cast<double>(n))
          .singularValues();
  if (xc.squaredNorm() <= 0 || d(1) <= 1e-12 * std::max(1.0, d(0))) {
    throw std::invalid_argument("AlignSimilarity: degenerate (collinear or coincident) points");
  }
  const Eigen::Matrix4d m = Eigen::umeyama(x, y, /*with_scaling=*/true);
  SimilarityAlignment out;
  Sim3d& t = out.dst_from_src;
  t.scale = m.topLeftCorner<3, 3>().col(0).norm();
  t.rotation = m.topLeftCorner<3, 3>() / t.scale;
  t.translation = m.topRightCorner<3, 1>();
  double sum_sq = 0;
  for (size_t i = 0; i < src.size(); ++i) {
    const double r = (dst[i] - t * src[i]).norm();
    out.residuals.push_back(r);
    sum_sq += r * r;
  }
  out.rms = std::sqrt(sum_sq / static_cast<double>(n));
  std::vector<double> sorted = out.residuals;
  std::sort(sorted.begin(), sorted.end());
  const size_t k = sorted.size();
  out.median = k % 2 ? sorted[k / 2] : 0.5 * (sorted[k / 2 - 1] + sorted[k / 2]);
  out.max = sorted.back();
  return out;
}

}  // namespace hdribr
