#include "core/projection.h"

#include "core/error.h"

namespace hdribr {

Eigen::Matrix4f ClipFromCam(const Camera& camera, float near, float far) {
  HDRIBR_CHECK(near > 0.0f && far > near);
  const double w = camera.width;
  const double h = camera.height;
  Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
  m(0, 0) = static_cast<float>(2.0 * camera.fx() / w);
  m(0, 2) = static_cast<float>(2.0 * camera.cx() / w - 1.0);
  m(1, 1) = static_cast<float>(-2.0 * camera.fy() / h);
  m(1, 2) = static_cast<float>(1.0 - 2.0 * camera.cy() / h);
  m(2, 2) = (far + near) / (far - near);
  m(2, 3) = -2.0f * far * near / (far - near);
  m(3, 2) = 1.0f;
  return m;
}

Eigen::Vector2d WindowFromClip(const Eigen::Vector4f& clip, int width, int height) {
  const double x_ndc = clip.x() / clip.w();
  const double y_ndc = clip.y() / clip.w();
  return {(x_ndc + 1.0) * 0.5 * width, (1.0 - y_ndc) * 0.5 * height};
}

}  // namespace hdribr
