// Image-quality metrics over a validity mask: PSNR, SSIM, coverage.
#pragma once

#include <opencv2/core.hpp>

namespace hdribr {

struct ImageScores {
  double psnr_db = 0;    // over masked pixels, peak = 255 for 8-bit, 1 for float images
  double ssim = 0;       // mean SSIM (Wang et al. 2004, 11x11 Gaussian, sigma 1.5) over the mask
  double coverage = 0;   // share of pixels in the mask
  long long pixels = 0;  // number of pixels compared
};

// Compares two images of the same size and type (CV_8UC3/CV_8UC1 or CV_32FC3/CV_32FC1) on the
// pixels where mask (CV_8UC1, non-zero = valid) is set; an empty mask means all pixels. PSNR is
// capped at 100 dB for identical inputs. Throws std::invalid_argument on mismatched inputs.
ImageScores CompareImages(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& mask = {});

// Mean squared error over the mask, in the images' own units, averaged over channels.
double MaskedMse(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& mask);

// Per-pixel SSIM map (CV_32FC1, channel mean), computed on grey-level-equivalent units.
cv::Mat SsimMap(const cv::Mat& reference, const cv::Mat& test);

}  // namespace hdribr
