// Normalised cross-correlation, the exposure-robust photo-consistency of the CPU densifier.
#pragma once

#include <opencv2/core.hpp>

namespace hdribr {

// NCC of two same-size single-channel float patches, in [-1, 1]; invariant to a gain and an
// offset of either patch (so to exposure differences between series). Returns -1 when either
// patch is flat (variance below min_variance).
double Ncc(const cv::Mat& a, const cv::Mat& b, double min_variance = 1e-6);

// Per-pixel NCC of `a` and `b` over (2r+1)^2 windows, computed with box filters. `a_mean` and
// `a_var` are a's window mean and variance (precomputed once per reference image). Pixels where
// a window is flat get -1.
cv::Mat NccMap(const cv::Mat& a, const cv::Mat& a_mean, const cv::Mat& a_var, const cv::Mat& b,
               int r, float min_variance = 1e-6f);

// Window mean and variance of a single-channel float image.
void WindowStats(const cv::Mat& a, int r, cv::Mat& mean, cv::Mat& var);

}  // namespace hdribr
