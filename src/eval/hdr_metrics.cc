#include "eval/hdr_metrics.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"

namespace hdribr::eval {

cv::Mat MatchScalePerChannel(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& mask) {
  HDRIBR_CHECK(reference.type() == CV_32FC3 && test.type() == CV_32FC3 &&
               reference.size() == test.size());
  cv::Mat out = test.clone();
  for (int c = 0; c < 3; ++c) {
    std::vector<double> ratios;
    for (int y = 0; y < test.rows; ++y) {
      for (int x = 0; x < test.cols; ++x) {
        if (!mask.empty() && mask.at<std::uint8_t>(y, x) == 0) continue;
        const double r = reference.at<cv::Vec3f>(y, x)[c], t = test.at<cv::Vec3f>(y, x)[c];
        if (r > 0 && t > 0) ratios.push_back(r / t);
      }
    }
    if (ratios.empty()) continue;
    std::nth_element(ratios.begin(),
                     ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2), ratios.end());
    const double s = ratios[ratios.size() / 2];
    for (int y = 0; y < out.rows; ++y) {
      for (int x = 0; x < out.cols; ++x) out.at<cv::Vec3f>(y, x)[c] *= static_cast<float>(s);
    }
  }
  return out;
}

cv::Mat MuLaw(const cv::Mat& radiance, double peak, double mu) {
  HDRIBR_CHECK(radiance.type() == CV_32FC3 && peak > 0 && mu > 0);
  cv::Mat out(radiance.size(), CV_32FC3);
  const double norm = 1.0 / std::log1p(mu);
  for (int y = 0; y < radiance.rows; ++y) {
    for (int x = 0; x < radiance.cols; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double v = std::clamp(radiance.at<cv::Vec3f>(y, x)[c] / peak, 0.0, 1.0);
        out.at<cv::Vec3f>(y, x)[c] = static_cast<float>(std::log1p(mu * v) * norm);
      }
    }
  }
  return out;
}

ImageScores CompareHdr(const cv::Mat& gt, const cv::Mat& test, const cv::Mat& mask, double mu) {
  const cv::Mat scaled = MatchScalePerChannel(gt, test, mask);
  double peak = 0;
  for (int y = 0; y < gt.rows; ++y) {
    for (int x = 0; x < gt.cols; ++x) {
      if (!mask.empty() && mask.at<std::uint8_t>(y, x) == 0) continue;
      const cv::Vec3f v = gt.at<cv::Vec3f>(y, x);
      peak = std::max({peak, double(v[0]), double(v[1]), double(v[2])});
    }
  }
  if (!(peak > 0)) return {};
  return CompareImages(MuLaw(gt, peak, mu), MuLaw(scaled, peak, mu), mask);
}

}  // namespace hdribr::eval
