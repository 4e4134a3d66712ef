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
  const double n = static_cast<double>(src.size());
  Eigen::Vector3d mu_x = Eigen::Vector3d::Zero(), mu_y = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < src.size(); ++i) {
    mu_x += src[i];
    mu_y += dst[i];
  }
  mu_x /= n;
  mu_y /= n;
  // Eq. 36: variance of src; eq. 38: covariance Sigma_xy = 1/n sum (y - mu_y)(x - mu_x)^T.
  double var_x = 0;
  Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < src.size(); ++i) {
    const Eigen::Vector3d dx = src[i] - mu_x;
    var_x += dx.squaredNorm();
    sigma += (dst[i] - mu_y) * dx.transpose();
  }
  var_x /= n;
  sigma /= n;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();
  if (var_x <= 0 || d(1) <= 1e-12 * std::max(1.0, d(0))) {
    throw std::invalid_argument("AlignSimilarity: degenerate (collinear or coincident) points");
  }
  // Eq. 39: S = diag(1, 1, -1) when det(Sigma) < 0 (a reflection would fit better).
  Eigen::Vector3d s = Eigen::Vector3d::Ones();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) s(2) = -1;
  SimilarityAlignment out;
  Sim3d& t = out.dst_from_src;
  t.rotation = svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();  // eq. 40
  t.scale = d.dot(s) / var_x;                                               // eq. 42
  t.translation = mu_y - t.scale * t.rotation * mu_x;                       // eq. 41
  double sum_sq = 0;
  for (size_t i = 0; i < src.size(); ++i) {
    const double r = (dst[i] - t * src[i]).norm();
    out.residuals.push_back(r);
    sum_sq += r * r;
  }
  out.rms = std::sqrt(sum_sq / n);
  std::vector<double> sorted = out.residuals;
  std::sort(sorted.begin(), sorted.end());
  const size_t m = sorted.size();
  out.median = m % 2 ? sorted[m / 2] : 0.5 * (sorted[m / 2 - 1] + sorted[m / 2]);
  out.max = sorted.back();
  return out;
}

}  // namespace hdribr
