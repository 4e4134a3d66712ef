#include "frontend/ncc.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace hdribr {

double Ncc(const cv::Mat& a, const cv::Mat& b, double min_variance) {
  CV_Assert(a.size() == b.size() && a.type() == CV_32F && b.type() == CV_32F);
  const double n = static_cast<double>(a.total());
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  for (int y = 0; y < a.rows; ++y) {
    const float* pa = a.ptr<float>(y);
    const float* pb = b.ptr<float>(y);
    for (int x = 0; x < a.cols; ++x) {
      sa += pa[x];
      sb += pb[x];
      saa += double(pa[x]) * pa[x];
      sbb += double(pb[x]) * pb[x];
      sab += double(pa[x]) * pb[x];
    }
  }
  const double ma = sa / n, mb = sb / n;
  const double va = saa / n - ma * ma, vb = sbb / n - mb * mb;
  if (va < min_variance || vb < min_variance) return -1.0;
  return (sab / n - ma * mb) / std::sqrt(va * vb);
}

void WindowStats(const cv::Mat& a, int r, cv::Mat& mean, cv::Mat& var) {
  const cv::Size k(2 * r + 1, 2 * r + 1);
  cv::boxFilter(a, mean, CV_32F, k, cv::Point(-1, -1), true, cv::BORDER_REFLECT);
  cv::Mat sq;
  cv::boxFilter(a.mul(a), sq, CV_32F, k, cv::Point(-1, -1), true, cv::BORDER_REFLECT);
  var = sq - mean.mul(mean);
}

cv::Mat NccMap(const cv::Mat& a, const cv::Mat& a_mean, const cv::Mat& a_var, const cv::Mat& b,
               int r, float min_variance) {
  cv::Mat b_mean, b_var, ab;
  WindowStats(b, r, b_mean, b_var);
  const cv::Size k(2 * r + 1, 2 * r + 1);
  cv::boxFilter(a.mul(b), ab, CV_32F, k, cv::Point(-1, -1), true, cv::BORDER_REFLECT);
  cv::Mat out(a.size(), CV_32F);
  for (int y = 0; y < a.rows; ++y) {
    const float* pam = a_mean.ptr<float>(y);
    const float* pav = a_var.ptr<float>(y);
    const float* pbm = b_mean.ptr<float>(y);
    const float* pbv = b_var.ptr<float>(y);
    const float* pab = ab.ptr<float>(y);
    float* po = out.ptr<float>(y);
    for (int x = 0; x < a.cols; ++x) {
      if (pav[x] < min_variance || pbv[x] < min_variance) {
        po[x] = -1.f;
      } else {
        po[x] = (pab[x] - pam[x] * pbm[x]) / std::sqrt(pav[x] * pbv[x]);
      }
    }
  }
  return out;
}

}  // namespace hdribr
