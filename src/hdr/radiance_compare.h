// Comparison of radiance maps up to scale, the measure used against OpenCV and ground truth.
#pragma once

#include <opencv2/core.hpp>

namespace hdribr {

// Median |ln(a / b) - s| over pixel-channels where both are positive (and `mask`, optional
// CV_8UC1, is nonzero), s being the median log ratio: a robust global scale fit. With
// `per_channel`, s is fitted per channel: Debevec-Malik fixes g(128) = 0 in each channel, so
// a recovered curve knows each channel only up to its own factor (the white balance).
// Returns +infinity when no pixel-channel is comparable. Both maps CV_32FC3 of equal size.
double MedianAbsLogRatio(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask = {},
                         bool per_channel = false);

}  // namespace hdribr
