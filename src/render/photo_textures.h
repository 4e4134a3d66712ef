// The scene's photos on the GPU: one mipmapped 2D array texture, layer i = scene.photos[i]
// (Lechelek et al. 2019, sec. 4: the photos are sampled by the blend pass).
#pragma once

#include <epoxy/gl.h>

#include <opencv2/core.hpp>
#include <vector>

#include "core/scene.h"
#include "gl/objects.h"

namespace hdribr::render {

// A 2D array texture with a full mipmap chain (gl::Texture::Create2DArray makes one level).
class MipmappedArray : public gl::Object<gl::TextureTraits> {
 public:
  MipmappedArray() = default;
  MipmappedArray(GLenum internal_format, int width, int height, int layers, int levels);
};

class PhotoTextures {
 public:
  // Needs a current GL context. Uploads every photo: `images` (one per scene photo, CV_8UC3 or
  // CV_32FC3 BGR) when not empty, else the files at scene.photos[i].image_path (InputError
  // naming the file when one cannot be read). Photos whose longest side exceeds `max_size`
  // (> 0) or the GL limit are downscaled (area filter). 8-bit photos go to RGBA8, float ones
  // to RGBA16F; the array is sized to the largest photo, smaller ones fill the top-left corner.
  PhotoTextures(const Scene& scene, const std::vector<cv::Mat>& images, int max_size = 0);

  GLuint id() const { return texture_.id(); }
  int width() const { return width_; }
  int height() const { return height_; }
  int layers() const { return static_cast<int>(sizes_.size()); }
  int levels() const { return levels_; }
  bool is_float() const { return is_float_; }
  // Size of photo i on the GPU (after downscaling).
  const cv::Size& layer_size(int i) const { return sizes_[static_cast<size_t>(i)]; }
  // GPU memory of the array with its mipmaps, bytes.
  size_t bytes() const { return bytes_; }

 private:
  MipmappedArray texture_;
  std::vector<cv::Size> sizes_;
  int width_ = 1, height_ = 1, levels_ = 1;
  bool is_float_ = false;
  size_t bytes_ = 0;
};

}  // namespace hdribr::render
