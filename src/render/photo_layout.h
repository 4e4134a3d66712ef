// The layout of the photos in a mipmapped 2D array texture: sizes and bytes, no GL.
#pragma once

#include <algorithm>
#include <cstddef>
#include <opencv2/core.hpp>
#include <vector>

namespace hdribr::render {

// The sizes of the photos on the GPU and of the array that holds them, without their pixels.
struct PhotoLayout {
  std::vector<cv::Size> sizes;  // photo i after downscaling
  int width = 1, height = 1;    // the array: the largest photo
  int levels = 1;               // full mipmap chain of width x height
  int limit = 0;                // longest side allowed (max_size and the GL limit)
  bool is_float = false;        // RGBA16F (CV_32FC3 photos) instead of RGBA8

  // Bytes of one layer with its mipmaps.
  size_t LayerBytes() const;
  // Bytes of the whole array (every photo) with its mipmaps.
  size_t Bytes() const { return LayerBytes() * std::max<size_t>(1, sizes.size()); }
};

}  // namespace hdribr::render
