// The scene's photos on the GPU: one mipmapped 2D array texture, layer i = scene.photos[i]
// (Lechelek et al. 2019, sec. 4: the photos are sampled by the blend pass).
#pragma once

#include <epoxy/gl.h>

#include <algorithm>
#include <opencv2/core.hpp>
#include <vector>

#include "core/scene.h"
#include "gl/objects.h"
#include "render/photo_layout.h"

namespace hdribr::render {

// A 2D array texture with a full mipmap chain (gl::Texture::Create2DArray makes one level).
class MipmappedArray : public gl::Object<gl::TextureTraits> {
 public:
  MipmappedArray() = default;
  MipmappedArray(GLenum internal_format, int width, int height, int layers, int levels);
};

// Needs a current GL context (for GL_MAX_TEXTURE_SIZE). The layout of the scene's photos:
// `images` (one per scene photo) when not empty, else the headers of the files; photos whose
// longest side exceeds `max_size` (> 0) or the GL limit are downscaled. Throws InputError
// naming the file when one cannot be read or is not its camera's shape.
PhotoLayout MeasurePhotos(const Scene& scene, const std::vector<cv::Mat>& images, int max_size);

// Photo i's pixels as uploaded (CV_8UC3 or CV_32FC3 BGR, continuous, layout.sizes[i]): taken
// from `images` when not empty, else read from its file; downscaled (area filter). Throws
// InputError naming the file. Needs no GL context (the cache's loader thread calls it).
cv::Mat LoadPhotoPixels(const Scene& scene, const std::vector<cv::Mat>& images,
                        const PhotoLayout& layout, size_t i);

// Writes `img` into level 0 of `layer` of `texture` (top-left corner).
void UploadLayer(GLuint texture, int layer, const cv::Mat& img);

class PhotoTextures {
 public:
  // Needs a current GL context. Uploads every photo of `layout` (MeasurePhotos): `images` (one
  // per scene photo, CV_8UC3 or CV_32FC3 BGR) when not empty, else the files at
  // scene.photos[i].image_path (InputError naming the file when one cannot be read). 8-bit
  // photos go to RGBA8, float ones to RGBA16F; the array is sized to the largest photo,
  // smaller ones fill the top-left corner.
  PhotoTextures(const Scene& scene, const std::vector<cv::Mat>& images, PhotoLayout layout);
  // The same with the layout measured here.
  PhotoTextures(const Scene& scene, const std::vector<cv::Mat>& images, int max_size = 0);

  GLuint id() const { return texture_.id(); }
  int width() const { return layout_.width; }
  int height() const { return layout_.height; }
  int layers() const { return static_cast<int>(layout_.sizes.size()); }
  int levels() const { return layout_.levels; }
  bool is_float() const { return layout_.is_float; }
  const PhotoLayout& layout() const { return layout_; }
  // Size of photo i on the GPU (after downscaling).
  const cv::Size& layer_size(int i) const { return layout_.sizes[static_cast<size_t>(i)]; }
  // GPU memory of the array with its mipmaps, bytes.
  size_t bytes() const { return layout_.Bytes(); }

 private:
  MipmappedArray texture_;
  PhotoLayout layout_;
};

}  // namespace hdribr::render
