// Analytic scenes for the synthetic captures: primitives, materials, lights (world frame z up,
// scene units of about 1 across) and ray queries on them.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "synth/texture.h"

namespace hdribr::synth {

// Surface appearance. Radiance is linear RGB in arbitrary radiometric units.
struct Material {
  Texture texture;
  double specular = 0;                                 // Blinn-Phong specular albedo (0 = matte)
  double shininess = 100;                              // Blinn-Phong exponent
  Eigen::Vector3d emission = Eigen::Vector3d::Zero();  // emitted radiance (emissive element)
};

enum class ShapeKind {
  kRectangle,  // centre, axis_u, axis_v (unit, orthogonal), half sizes in half_size.x/.y
  kSphere,     // centre, radius
  kBox,        // centre, half_size, rotated by `yaw` radians about world z
  kCylinder,   // vertical (world z), base centre `centre`, radius, height = half_size.z * 2, capped
};

struct Shape {
  ShapeKind kind = ShapeKind::kSphere;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX();
  Eigen::Vector3d axis_v = Eigen::Vector3d::UnitY();
  Eigen::Vector3d half_size = Eigen::Vector3d::Constant(0.5);
  double radius = 0.5;
  double yaw = 0;
  bool two_sided = true;  // rectangles: visible and shading from both sides
  int material = 0;
};

// How a capture's hand-held cameras move (synth/capture.cc).
enum class CameraPath {
  kArc,     // a 120-degree arc around look_at, 2.2 scene sizes away
  kFacade,  // a straight walk along x, 1.5 scene sizes long, in front of look_at, facing +y
};

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;  // unit length
};

struct Hit {
  double t = 0;  // distance along the ray
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, facing the ray origin
  int shape = -1;                                    // -1 = no hit (sky)
};

// A point light (the emissive element also lights its surroundings with it).
struct PointLight {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d intensity = Eigen::Vector3d::Zero();  // radiant intensity, falls off as 1/d^2
};

class SynthScene {
 public:
  std::string name;
  std::vector<Shape> shapes;
  std::vector<Material> materials;
  Eigen::Vector3d sun_direction = Eigen::Vector3d::UnitZ();  // unit, towards the sun
  Eigen::Vector3d sun_irradiance = Eigen::Vector3d::Ones();  // on a surface facing the sun
  Eigen::Vector3d ambient = Eigen::Vector3d::Constant(0.1);  // sky irradiance, upward surface
  std::vector<PointLight> point_lights;
  Eigen::Vector3d look_at = Eigen::Vector3d::Zero();  // where the capture cameras aim
  double size = 1.0;                                  // scene extent used for camera placement
  CameraPath path = CameraPath::kArc;                 // how a capture's cameras move

  // Nearest hit with t in (t_min, t_max); Hit::shape = -1 when none.
  Hit Intersect(const Ray& ray, double t_min = 1e-6, double t_max = 1e30) const;
  // True when anything is hit with t in (t_min, t_max).
  bool Occluded(const Ray& ray, double t_min, double t_max) const;
  // Radiance leaving a hit towards the ray's origin (hard sun shadows, ambient, point lights,
  // Blinn-Phong specular of the sun and the point lights, emission).
  Eigen::Vector3d Shade(const Ray& ray, const Hit& hit) const;
  // Radiance of the sky in a direction (rays that hit nothing).
  Eigen::Vector3d Sky(const Eigen::Vector3d& direction) const;
  // Radiance along a ray.
  Eigen::Vector3d Trace(const Ray& ray, Hit* hit_out = nullptr) const;

 private:
  bool material_emits(const Shape& s) const;
};

}  // namespace hdribr::synth
