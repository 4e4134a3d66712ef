#include "core/camera.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace hdribr {
namespace {

struct ModelInfo {
  CameraModel model;
  const char* name;
  int num_params;
};

constexpr std::array<ModelInfo, 11> kModels = {{
    {CameraModel::kSimplePinhole, "SIMPLE_PINHOLE", 3},
    {CameraModel::kPinhole, "PINHOLE", 4},
    {CameraModel::kSimpleRadial, "SIMPLE_RADIAL", 4},
    {CameraModel::kRadial, "RADIAL", 5},
    {CameraModel::kOpenCV, "OPENCV", 8},
    {CameraModel::kOpenCVFisheye, "OPENCV_FISHEYE", 8},
    {CameraModel::kFullOpenCV, "FULL_OPENCV", 12},
    {CameraModel::kFOV, "FOV", 5},
    {CameraModel::kSimpleRadialFisheye, "SIMPLE_RADIAL_FISHEYE", 4},
    {CameraModel::kRadialFisheye, "RADIAL_FISHEYE", 5},
    {CameraModel::kThinPrismFisheye, "THIN_PRISM_FISHEYE", 12},
}};

const ModelInfo& Info(CameraModel model) {
  for (const auto& m : kModels) {
    if (m.model == model) return m;
  }
  throw std::invalid_argument("unknown camera model id " + std::to_string(static_cast<int>(model)));
}

}  // namespace

std::string CameraModelName(CameraModel model) { return Info(model).name; }

CameraModel CameraModelFromName(const std::string& name) {
  for (const auto& m : kModels) {
    if (name == m.name) return m.model;
  }
  throw std::invalid_argument("unknown camera model '" + name + "'");
}

CameraModel CameraModelFromId(int id) {
  for (const auto& m : kModels) {
    if (static_cast<int>(m.model) == id) return m.model;
  }
  throw std::invalid_argument("unknown camera model id " + std::to_string(id));
}

int CameraModelNumParams(CameraModel model) { return Info(model).num_params; }

Camera Camera::Pinhole(int id, int width, int height, double fx, double fy, double cx, double cy) {
  Camera c;
  c.id = id;
  c.model = CameraModel::kPinhole;
  c.width = width;
  c.height = height;
  c.params = {fx, fy, cx, cy};
  return c;
}

bool Camera::IsPinhole() const {
  return model == CameraModel::kSimplePinhole || model == CameraModel::kPinhole;
}

bool Camera::HasZeroDistortion() const {
  switch (model) {
    case CameraModel::kSimplePinhole:
    case CameraModel::kPinhole:
      return true;
    case CameraModel::kSimpleRadial:
      return params.size() == 4 && params[3] == 0.0;
    case CameraModel::kRadial:
      return params.size() == 5 && params[3] == 0.0 && params[4] == 0.0;
    case CameraModel::kOpenCV:
    case CameraModel::kFullOpenCV:
      for (size_t i = 4; i < params.size(); ++i) {
        if (params[i] != 0.0) return false;
      }
      return true;
    default:
      return false;
  }
}

// SIMPLE_* models store f, cx, cy first; the others fx, fy, cx, cy.
static bool SingleFocal(CameraModel m) {
  return m == CameraModel::kSimplePinhole || m == CameraModel::kSimpleRadial ||
         m == CameraModel::kRadial || m == CameraModel::kSimpleRadialFisheye ||
         m == CameraModel::kRadialFisheye;
}

double Camera::fx() const { return params.at(0); }
double Camera::fy() const { return SingleFocal(model) ? params.at(0) : params.at(1); }
double Camera::cx() const { return SingleFocal(model) ? params.at(1) : params.at(2); }
double Camera::cy() const { return SingleFocal(model) ? params.at(2) : params.at(3); }

Eigen::Matrix3d Camera::K() const {
  Eigen::Matrix3d k = Eigen::Matrix3d::Identity();
  k(0, 0) = fx();
  k(1, 1) = fy();
  k(0, 2) = cx();
  k(1, 2) = cy();
  return k;
}

Eigen::Vector2d Camera::PixelFromCam(const Eigen::Vector3d& p) const {
  return {fx() * p.x() / p.z() + cx(), fy() * p.y() / p.z() + cy()};
}

Eigen::Vector3d Camera::CamFromPixel(const Eigen::Vector2d& px) const {
  return {(px.x() - cx()) / fx(), (px.y() - cy()) / fy(), 1.0};
}

Camera Camera::Scaled(int w, int h) const {
  const double sx = static_cast<double>(w) / width;
  const double sy = static_cast<double>(h) / height;
  Camera c = Pinhole(id, w, h, fx() * sx, fy() * sy, cx() * sx, cy() * sy);
  return c;
}

bool Camera::FitsImage(int w, int h) const {
  if (w <= 0 || h <= 0) return false;
  return std::abs(static_cast<double>(h) * width - static_cast<double>(w) * height) <=
         std::max(width, w);
}

double Camera::FovX() const { return 2.0 * std::atan(0.5 * width / fx()); }
double Camera::FovY() const { return 2.0 * std::atan(0.5 * height / fy()); }

}  // namespace hdribr
