// Camera intrinsics in COLMAP conventions: x right, y down, z forward; the centre of the
// top-left pixel is at (0.5, 0.5).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace hdribr {

// COLMAP camera model ids (same numbering as COLMAP's binary format).
enum class CameraModel : int {
  kSimplePinhole = 0,
  kPinhole = 1,
  kSimpleRadial = 2,
  kRadial = 3,
  kOpenCV = 4,
  kOpenCVFisheye = 5,
  kFullOpenCV = 6,
  kFOV = 7,
  kSimpleRadialFisheye = 8,
  kRadialFisheye = 9,
  kThinPrismFisheye = 10,
};

// COLMAP's model name ("PINHOLE") and its parameter count; throws std::invalid_argument if
// the id or name is unknown.
std::string CameraModelName(CameraModel model);
CameraModel CameraModelFromName(const std::string& name);
CameraModel CameraModelFromId(int id);
int CameraModelNumParams(CameraModel model);

struct Camera {
  int id = -1;
  CameraModel model = CameraModel::kPinhole;
  int width = 0;
  int height = 0;
  std::vector<double> params;  // COLMAP order, e.g. PINHOLE: fx, fy, cx, cy (pixels)

  static Camera Pinhole(int id, int width, int height, double fx, double fy, double cx, double cy);

  // True for SIMPLE_PINHOLE and PINHOLE, the models used without undistortion.
  bool IsPinhole() const;
  // True for models with distortion parameters that are all zero (usable as pinhole).
  bool HasZeroDistortion() const;
  double fx() const;
  double fy() const;
  double cx() const;
  double cy() const;
  Eigen::Matrix3d K() const;

  // Pixel coordinates (continuous, COLMAP convention) of a camera-space point; ignores
  // distortion (the camera must be pinhole). Precondition: p.z() != 0.
  Eigen::Vector2d PixelFromCam(const Eigen::Vector3d& p) const;
  // Unit-depth ray (z = 1) in camera space through a pixel position.
  Eigen::Vector3d CamFromPixel(const Eigen::Vector2d& px) const;
  // Same intrinsics for an image resized to (w, h).
  Camera Scaled(int w, int h) const;
  // True when a w x h image is this camera's frame at some scale (aspect within a pixel), as
  // the renderer samples photos; false for another shape.
  bool FitsImage(int w, int h) const;
  // Horizontal and vertical field of view in radians.
  double FovX() const;
  double FovY() const;
};

}  // namespace hdribr
