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

PhotoLayout MeasurePhotos(const Scene& scene, const std::vector<cv::Mat>& images, int max_size) {
  HDRIBR_CHECK(images.empty() || images.size() == scene.photos.size());
  GLint gl_max = 4096;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &gl_max);
  PhotoLayout layout;
  layout.limit = max_size > 0 ? std::min(max_size, static_cast<int>(gl_max)) : gl_max;
  layout.is_float = !images.empty() && images.front().type() == CV_32FC3;
  // The sizes from the images or the file headers, to allocate the array once.
  for (size_t i = 0; i < scene.photos.size(); ++i) {
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
    if (longest > layout.limit) {
      const double f = static_cast<double>(layout.limit) / longest;
      s = cv::Size(std::max(1, static_cast<int>(std::lround(s.width * f))),
                   std::max(1, static_cast<int>(std::lround(s.height * f))));
    }
    layout.sizes.push_back(s);
    layout.width = std::max(layout.width, s.width);
    layout.height = std::max(layout.height, s.height);
  }
  layout.levels =
      1 + static_cast<int>(std::floor(std::log2(std::max(layout.width, layout.height))));
  return layout;
}

cv::Mat LoadPhotoPixels(const Scene& scene, const std::vector<cv::Mat>& images,
                        const PhotoLayout& layout, size_t i) {
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
  if (longest > layout.limit) {
    const double s = static_cast<double>(layout.limit) / longest;
    cv::Mat small;
    cv::resize(img, small,
               cv::Size(std::max(1, static_cast<int>(std::lround(img.cols * s))),
                        std::max(1, static_cast<int>(std::lround(img.rows * s)))),
               0, 0, cv::INTER_AREA);
    img = small;
  }
  const cv::Size expected = layout.sizes[i];
  if (img.size() != expected || (img.type() == CV_32FC3) != layout.is_float) {
    throw InputError(scene.photos[i].image_path,
                     "photo changed size or type while loading (expected " +
                         std::to_string(expected.width) + "x" + std::to_string(expected.height) +
                         ")");
  }
  return img.isContinuous() ? img : img.clone();
}

void UploadLayer(GLuint texture, int layer, const cv::Mat& img) {
  HDRIBR_CHECK(img.isContinuous());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage3D(texture, 0, 0, 0, layer, img.cols, img.rows, 1, GL_BGR,
                      img.depth() == CV_32F ? GL_FLOAT : GL_UNSIGNED_BYTE, img.data);
}

PhotoTextures::PhotoTextures(const Scene& scene, const std::vector<cv::Mat>& images, int max_size)
    : PhotoTextures(scene, images, MeasurePhotos(scene, images, max_size)) {}

PhotoTextures::PhotoTextures(const Scene& scene, const std::vector<cv::Mat>& images,
                             PhotoLayout layout)
    : layout_(std::move(layout)) {
  HDRIBR_CHECK(layout_.sizes.size() == scene.photos.size());
  const int n_layers = std::max<int>(1, layers());
  const GLenum format = layout_.is_float ? GL_RGBA16F : GL_RGBA8;
  texture_ = MipmappedArray(format, layout_.width, layout_.height, n_layers, layout_.levels);
  // Zero the array so that the unused border of smaller photos is black in every level.
  const float zero[4] = {0, 0, 0, 0};
  for (int l = 0; l < layout_.levels; ++l) {
    glClearTexImage(texture_.id(), l, GL_RGBA, GL_FLOAT, zero);
  }
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    UploadLayer(texture_.id(), static_cast<int>(i), LoadPhotoPixels(scene, images, layout_, i));
  }
  glGenerateTextureMipmap(texture_.id());
}

}  // namespace hdribr::render
