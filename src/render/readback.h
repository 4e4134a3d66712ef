// CPU read-back of depth-pass outputs (tests, `hdribr depth`, exports).
#pragma once

#include <opencv2/core.hpp>

#include "gl/objects.h"
#include "render/depth_pass.h"

namespace hdribr::render {

struct DepthImages {
  cv::Mat depth;   // CV_32FC1 camera z, 0 = invalid
  cv::Mat normal;  // CV_32FC3 camera-space normal, channels (x, y, z) in that order
  cv::Mat valid;   // CV_8UC1, 255 = valid
};

// Reads level 0 of a single-channel float texture (R32F) as CV_32FC1; row 0 = top row.
cv::Mat ReadTextureR32F(const gl::Texture& texture);
// Reads one layer of a 2D-array R32F texture.
cv::Mat ReadTextureLayerR32F(const gl::Texture& texture, int layer);
DepthImages ReadDepthTarget(const DepthTarget& target);

}  // namespace hdribr::render
