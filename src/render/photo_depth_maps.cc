#include "render/photo_depth_maps.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/error.h"

namespace hdribr::render {

PhotoDepthMaps::PhotoDepthMaps(const Scene& scene, DepthPass& pass, double scale) {
  HDRIBR_CHECK(scale > 0.0);
  int max_w = 1, max_h = 1;
  for (const Photo& photo : scene.photos) {
    const Camera& cam = scene.CameraOf(photo);
    const cv::Size s(std::max(1, static_cast<int>(std::lround(cam.width * scale))),
                     std::max(1, static_cast<int>(std::lround(cam.height * scale))));
    sizes_.push_back(s);
    max_w = std::max(max_w, s.width);
    max_h = std::max(max_h, s.height);
  }
  const int layers = std::max<int>(1, static_cast<int>(scene.photos.size()));
  depth_ = gl::Texture::Create2DArray(GL_R32F, max_w, max_h, layers);
  const float zero = 0.0f;
  glClearTexImage(depth_.id(), 0, GL_RED, GL_FLOAT, &zero);
  std::optional<DepthTarget> target;
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    const cv::Size s = sizes_[i];
    if (!target || target->width() != s.width || target->height() != s.height) {
      target = DepthTarget::Create(s.width, s.height);
    }
    pass.Process(scene.CameraOf(scene.photos[i]), scene.photos[i].cam_from_world, *target);
    glCopyImageSubData(target->depth.id(), GL_TEXTURE_2D, 0, 0, 0, 0, depth_.id(),
                       GL_TEXTURE_2D_ARRAY, 0, 0, 0, static_cast<GLint>(i), s.width, s.height, 1);
  }
}

}  // namespace hdribr::render
