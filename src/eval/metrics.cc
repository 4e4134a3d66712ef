#include "eval/metrics.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hdribr {
namespace {

void CheckInputs(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask) {
  if (a.empty() || a.size() != b.size() || a.type() != b.type()) {
    throw std::invalid_argument("CompareImages: images differ in size or type");
  }
  if (a.depth() != CV_8U && a.depth() != CV_32F) {
    throw std::invalid_argument("CompareImages: only 8-bit and float images");
  }
  if (!mask.empty() && (mask.size() != a.size() || mask.type() != CV_8UC1)) {
    throw std::invalid_argument("CompareImages: mask must be CV_8UC1 of the image size");
  }
}

double Peak(const cv::Mat& m) { return m.depth() == CV_8U ? 255.0 : 1.0; }

}  // namespace

double MaskedMse(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& mask) {
  CheckInputs(reference, test, mask);
  cv::Mat a, b;
  reference.convertTo(a, CV_64F);
  test.convertTo(b, CV_64F);
  cv::Mat diff = a - b;
  diff = diff.mul(diff);
  const cv::Scalar sum = mask.empty() ? cv::sum(diff) : cv::sum(diff.setTo(0, mask == 0));
  const double n = mask.empty() ? static_cast<double>(a.total()) : cv::countNonZero(mask);
  if (n == 0) return 0;
  double total = 0;
  for (int c = 0; c < a.channels(); ++c) total += sum[c];
  return total / (n * a.channels());
}

cv::Mat SsimMap(const cv::Mat& reference, const cv::Mat& test) {
  // Constants of Wang et al. 2004 for a dynamic range L.
  const double l = Peak(reference);
  // The constants for every channel, said explicitly: OpenCV 4.6 adds a plain double to every
  // channel of a multi-channel expression but warns on each call that this may change
  // (opencv/opencv#16739), which printed two warnings per evaluated view.
  const cv::Scalar c1 = cv::Scalar::all((0.01 * l) * (0.01 * l));
  const cv::Scalar c2 = cv::Scalar::all((0.03 * l) * (0.03 * l));
  cv::Mat x, y;
  reference.convertTo(x, CV_32F);
  test.convertTo(y, CV_32F);
  const cv::Size win(11, 11);
  const double sigma = 1.5;
  cv::Mat mu_x, mu_y, xx, yy, xy;
  cv::GaussianBlur(x, mu_x, win, sigma);
  cv::GaussianBlur(y, mu_y, win, sigma);
  cv::GaussianBlur(x.mul(x), xx, win, sigma);
  cv::GaussianBlur(y.mul(y), yy, win, sigma);
  cv::GaussianBlur(x.mul(y), xy, win, sigma);
  const cv::Mat mu_xx = mu_x.mul(mu_x), mu_yy = mu_y.mul(mu_y), mu_xy = mu_x.mul(mu_y);
  const cv::Mat sigma_x = xx - mu_xx, sigma_y = yy - mu_yy, sigma_xy = xy - mu_xy;
  cv::Mat num = (2 * mu_xy + c1).mul(2 * sigma_xy + c2);
  cv::Mat den = (mu_xx + mu_yy + c1).mul(sigma_x + sigma_y + c2);
  cv::Mat ssim;
  cv::divide(num, den, ssim);
  if (ssim.channels() > 1) {
    cv::Mat flat = ssim.reshape(1, static_cast<int>(ssim.total()));
    cv::Mat mean;
    cv::reduce(flat, mean, 1, cv::REDUCE_AVG);
    ssim = mean.reshape(1, reference.rows);
  }
  return ssim;
}

ImageScores CompareImages(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& mask) {
  CheckInputs(reference, test, mask);
  ImageScores s;
  s.pixels = mask.empty() ? static_cast<long long>(reference.total()) : cv::countNonZero(mask);
  s.coverage = static_cast<double>(s.pixels) / static_cast<double>(reference.total());
  if (s.pixels == 0) return s;
  const double mse = MaskedMse(reference, test, mask);
  const double peak = Peak(reference);
  s.psnr_db = mse <= 0 ? 100.0 : std::min(100.0, 10.0 * std::log10(peak * peak / mse));
  const cv::Mat ssim = SsimMap(reference, test);
  s.ssim = mask.empty() ? cv::mean(ssim)[0] : cv::mean(ssim, mask)[0];
  return s;
}

}  // namespace hdribr
