#include "render/photo_textures.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "io/image.h"

namespace hdribr::render {

MipmappedArray::MipmappedArray(GLenum internal_format, int width, int height, int layers,
                               int levels) {
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id_);
  glTextureStorage3D(id_, levels, internal_format, width, height, layers);
  glTextureParameteri(id_, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(id_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(id_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(id_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

namespace {

// The photo's pixels as uploaded: read (or taken from `images`) and downscaled.
cv::Mat LoadPhoto(const Scene& scene, const std::vector<cv::Mat>& images, size_t i, int limit) {
  cv::Mat img;
  if (!images.empty()) {
    img = images[i];
    if (img.empty() || (img.type() != CV_8UC3 && img.type() != CV_32FC3)) {
      throw InputError(scene.photos[i].image_path,
                       "photo image " + std::to_string(i) + " is empty or not CV_8UC3/CV_32FC3");
    }
  } else {
    img = ReadImage(scene.photos[i].image_path);
  }
  const int longest = std::max(img.cols, img.rows);
  if (longest > limit) {
    const double s = static_cast<double>(limit) / longest;
    cv::Mat small;
    cv::resize(img, small,
               cv::Size(std::max(1, static_cast<int>(std::lround(img.cols * s))),
                        std::max(1, static_cast<int>(std::lround(img.rows * s)))),
               0, 0, cv::INTER_AREA);
    img = small;
  }
  return img.isContinuous() ? img : img.clone();
}

}  // namespace

PhotoTextures::PhotoTextures(const Scene& scene, const std::vector<cv::Mat>& images, int max_size) {
  HDRIBR_CHECK(images.empty() || images.size() == scene.photos.size());
  GLint gl_max = 4096;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &gl_max);
  const int limit = max_size > 0 ? std::min(max_size, static_cast<int>(gl_max)) : gl_max;
  is_float_ = !images.empty() && images.front().type() == CV_32FC3;
  const size_t n = scene.photos.size();
  // The sizes first (from the images or the file headers), to allocate the array once.
  for (size_t i = 0; i < n; ++i) {
    cv::Size s;
    if (!images.empty()) {
      s = images[i].size();
    } else {
      s = ReadImageSize(scene.photos[i].image_path);
    }
    // The blend maps the camera's pixels onto the photo by its size, so a photo may be the
    // camera's frame at any scale, but not of another shape (it would be sampled stretched).
    const Camera& cam = scene.CameraOf(scene.photos[i]);
    if (!cam.FitsImage(s.width, s.height)) {
      throw InputError(scene.photos[i].image_path,
                       "image is " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                           ", not the shape of camera " + std::to_string(cam.id) + " (" +
                           std::to_string(cam.width) + "x" + std::to_string(cam.height) + ")");
    }
    const int longest = std::max(s.width, s.height);
    if (longest > limit) {
      const double f = static_cast<double>(limit) / longest;
      s = cv::Size(std::max(1, static_cast<int>(std::lround(s.width * f))),
                   std::max(1, static_cast<int>(std::lround(s.height * f))));
    }
    sizes_.push_back(s);
    width_ = std::max(width_, s.width);
    height_ = std::max(height_, s.height);
  }
  levels_ = 1 + static_cast<int>(std::floor(std::log2(std::max(width_, height_))));
  const int layers = std::max<int>(1, static_cast<int>(n));
  const GLenum format = is_float_ ? GL_RGBA16F : GL_RGBA8;
  texture_ = MipmappedArray(format, width_, height_, layers, levels_);
  // Zero the array so that the unused border of smaller photos is black in every level.
  const float zero[4] = {0, 0, 0, 0};
  for (int l = 0; l < levels_; ++l) glClearTexImage(texture_.id(), l, GL_RGBA, GL_FLOAT, zero);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (size_t i = 0; i < n; ++i) {
    const cv::Mat img = LoadPhoto(scene, images, i, limit);
    if (img.size() != sizes_[i] || (img.type() == CV_32FC3) != is_float_) {
      throw InputError(scene.photos[i].image_path,
                       "photo changed size or type while loading (expected " +
                           std::to_string(sizes_[i].width) + "x" +
                           std::to_string(sizes_[i].height) + ")");
    }
    glTextureSubImage3D(texture_.id(), 0, 0, 0, static_cast<GLint>(i), img.cols, img.rows, 1,
                        GL_BGR, is_float_ ? GL_FLOAT : GL_UNSIGNED_BYTE, img.data);
  }
  glGenerateTextureMipmap(texture_.id());
  const size_t texel = is_float_ ? 8 : 4;
  for (int l = 0; l < levels_; ++l) {
    bytes_ += static_cast<size_t>(std::max(1, width_ >> l)) *
              static_cast<size_t>(std::max(1, height_ >> l)) * static_cast<size_t>(layers) * texel;
  }
}

}  // namespace hdribr::render
