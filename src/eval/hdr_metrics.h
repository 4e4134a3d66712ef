// HDR-NeRF's (Huang et al. 2022) figure for radiance: PSNR and SSIM of mu-law tone-mapped
// radiance normalised by the ground truth's maximum.
#pragma once

#include <opencv2/core.hpp>

#include "eval/metrics.h"

namespace hdribr::eval {

// `test` (CV_32FC3) times, per channel, the median over the mask of reference / test: radiance
// calibrated from photos is known up to one factor per channel.
cv::Mat MatchScalePerChannel(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& mask);

// T(x) = ln(1 + mu x) / ln(1 + mu) of radiance / peak, x clamped to [0, 1] (CV_32FC3).
cv::Mat MuLaw(const cv::Mat& radiance, double peak, double mu = 5000.0);

// Scores of `test` against the GT radiance `gt` over the mask (CV_8UC1): `test` brought to the
// GT's scale per channel, both normalised by the GT's maximum over the mask and mu-law tone
// mapped; PSNR with peak 1.
ImageScores CompareHdr(const cv::Mat& gt, const cv::Mat& test, const cv::Mat& mask,
                       double mu = 5000.0);

}  // namespace hdribr::eval
