#include "synth/synth_scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace hdribr::synth {
namespace {

using Eigen::Vector3d;

constexpr double kInvPi = 1.0 / std::numbers::pi;

// Ray-shape intersection: distance t in (t_min, t_max) and the outward normal, or false.
bool IntersectRectangle(const Shape& s, const Ray& r, double t_min, double t_max, double* t,
                        Vector3d* n) {
  const Vector3d normal = s.axis_u.cross(s.axis_v);
  const double denom = r.direction.dot(normal);
  if (std::abs(denom) < 1e-12) return false;
  const double tt = (s.centre - r.origin).dot(normal) / denom;
  if (tt <= t_min || tt >= t_max) return false;
  const Vector3d d = r.origin + tt * r.direction - s.centre;
  if (std::abs(d.dot(s.axis_u)) > s.half_size.x() || std::abs(d.dot(s.axis_v)) > s.half_size.y())
    return false;
  *t = tt;
  *n = normal;
  return true;
}

bool IntersectSphere(const Shape& s, const Ray& r, double t_min, double t_max, double* t,
                     Vector3d* n) {
  const Vector3d oc = r.origin - s.centre;
  const double b = oc.dot(r.direction);
  const double c = oc.squaredNorm() - s.radius * s.radius;
  const double disc = b * b - c;
  if (disc < 0) return false;
  const double sq = std::sqrt(disc);
  double tt = -b - sq;
  if (tt <= t_min) tt = -b + sq;
  if (tt <= t_min || tt >= t_max) return false;
  *t = tt;
  *n = (r.origin + tt * r.direction - s.centre) / s.radius;
  return true;
}

// Slab test in the box frame (rotated by yaw about z).
bool IntersectBox(const Shape& s, const Ray& r, double t_min, double t_max, double* t,
                  Vector3d* n) {
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  auto to_local = [&](const Vector3d& v) {
    return Vector3d(c * v.x() + sn * v.y(), -sn * v.x() + c * v.y(), v.z());
  };
  const Vector3d o = to_local(r.origin - s.centre);
  const Vector3d d = to_local(r.direction);
  double t0 = -1e300, t1 = 1e300;
  int axis0 = -1, axis1 = -1;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-15) {
      if (std::abs(o[a]) > s.half_size[a]) return false;
      continue;
    }
    double ta = (-s.half_size[a] - o[a]) / d[a];
    double tb = (s.half_size[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    if (ta > t0) {
      t0 = ta;
      axis0 = a;
    }
    if (tb < t1) {
      t1 = tb;
      axis1 = a;
    }
    if (t0 > t1) return false;
  }
  double tt = t0;
  int axis = axis0;
  if (tt <= t_min) {
    tt = t1;
    axis = axis1;
  }
  if (tt <= t_min || tt >= t_max || axis < 0) return false;
  Vector3d ln = Vector3d::Zero();
  ln[axis] = (o[axis] + tt * d[axis]) > 0 ? 1.0 : -1.0;
  *t = tt;
  *n = Vector3d(c * ln.x() - sn * ln.y(), sn * ln.x() + c * ln.y(), ln.z());
  return true;
}

bool IntersectCylinder(const Shape& s, const Ray& r, double t_min, double t_max, double* t,
                       Vector3d* n) {
  const double z0 = s.centre.z(), z1 = s.centre.z() + 2 * s.half_size.z();
  bool found = false;
  double best = t_max;
  // Side: (o + t d - c)_xy has length radius.
  const double ox = r.origin.x() - s.centre.x(), oy = r.origin.y() - s.centre.y();
  const double dx = r.direction.x(), dy = r.direction.y();
  const double a = dx * dx + dy * dy;
  if (a > 1e-15) {
    const double b = ox * dx + oy * dy;
    const double c = ox * ox + oy * oy - s.radius * s.radius;
    const double disc = b * b - a * c;
    if (disc >= 0) {
      const double sq = std::sqrt(disc);
      for (double tt : {(-b - sq) / a, (-b + sq) / a}) {
        if (tt <= t_min || tt >= best) continue;
        const double z = r.origin.z() + tt * r.direction.z();
        if (z < z0 || z > z1) continue;
        best = tt;
        *n = Vector3d(ox + tt * dx, oy + tt * dy, 0) / s.radius;
        found = true;
        break;
      }
    }
  }
  // Caps.
  if (std::abs(r.direction.z()) > 1e-15) {
    for (double zc : {z0, z1}) {
      const double tt = (zc - r.origin.z()) / r.direction.z();
      if (tt <= t_min || tt >= best) continue;
      const double px = ox + tt * dx, py = oy + tt * dy;
      if (px * px + py * py > s.radius * s.radius) continue;
      best = tt;
      *n = Vector3d(0, 0, zc == z1 ? 1.0 : -1.0);
      found = true;
    }
  }
  if (found) *t = best;
  return found;
}

bool IntersectShape(const Shape& s, const Ray& r, double t_min, double t_max, double* t,
                    Vector3d* n) {
  switch (s.kind) {
    case ShapeKind::kRectangle:
      return IntersectRectangle(s, r, t_min, t_max, t, n);
    case ShapeKind::kSphere:
      return IntersectSphere(s, r, t_min, t_max, t, n);
    case ShapeKind::kBox:
      return IntersectBox(s, r, t_min, t_max, t, n);
    case ShapeKind::kCylinder:
      return IntersectCylinder(s, r, t_min, t_max, t, n);
  }
  return false;
}

// Normalised Blinn-Phong lobe (energy-conserving form): (n + 8) / (8 pi) (N.H)^n.
double BlinnPhong(const Vector3d& n, const Vector3d& l, const Vector3d& v, double shininess) {
  const Vector3d h = (l + v).normalized();
  const double nh = std::max(0.0, n.dot(h));
  return (shininess + 8.0) / (8.0 * std::numbers::pi) * std::pow(nh, shininess);
}

}  // namespace

Hit SynthScene::Intersect(const Ray& ray, double t_min, double t_max) const {
  Hit hit;
  double best = t_max;
  Vector3d n;
  for (size_t i = 0; i < shapes.size(); ++i) {
    double t;
    if (IntersectShape(shapes[i], ray, t_min, best, &t, &n)) {
      best = t;
      hit.t = t;
      hit.normal = n;
      hit.shape = static_cast<int>(i);
    }
  }
  if (hit.shape >= 0) {
    hit.position = ray.origin + hit.t * ray.direction;
    if (hit.normal.dot(ray.direction) > 0) hit.normal = -hit.normal;
  }
  return hit;
}

bool SynthScene::Occluded(const Ray& ray, double t_min, double t_max) const {
  Vector3d n;
  double t;
  for (const Shape& s : shapes) {
    if (material_emits(s)) continue;
    if (IntersectShape(s, ray, t_min, t_max, &t, &n)) return true;
  }
  return false;
}

bool SynthScene::material_emits(const Shape& s) const {
  return materials[s.material].emission.maxCoeff() > 0;
}

Vector3d SynthScene::Shade(const Ray& ray, const Hit& hit) const {
  const Material& m = materials[shapes[hit.shape].material];
  const Vector3d& n = hit.normal;
  const Vector3d v = -ray.direction;
  const Vector3d p = hit.position + 1e-7 * size * n;  // offset against self-shadowing
  const Vector3d albedo = m.texture.Albedo(hit.position);

  // Sky light: more from above than from the ground (a cheap hemisphere model).
  Vector3d irradiance = ambient * (0.55 + 0.45 * n.z());
  Vector3d specular = Vector3d::Zero();
  const double nl_sun = n.dot(sun_direction);
  if (nl_sun > 0 && !Occluded({p, sun_direction}, 1e-9, 1e30)) {
    irradiance += sun_irradiance * nl_sun;
    if (m.specular > 0)
      specular += sun_irradiance * (nl_sun * BlinnPhong(n, sun_direction, v, m.shininess));
  }
  for (const PointLight& light : point_lights) {
    Vector3d l = light.position - p;
    const double d2 = l.squaredNorm();
    const double d = std::sqrt(d2);
    l /= d;
    const double nl = n.dot(l);
    if (nl <= 0 || Occluded({p, l}, 1e-9, d * (1 - 1e-6))) continue;
    irradiance += light.intensity * (nl / d2);
    if (m.specular > 0) specular += light.intensity * (nl / d2 * BlinnPhong(n, l, v, m.shininess));
  }
  return albedo.cwiseProduct(irradiance) * kInvPi + m.specular * specular + m.emission;
}

Vector3d SynthScene::Sky(const Vector3d& direction) const {
  const double up = std::clamp(direction.z(), 0.0, 1.0);
  return Vector3d(0.30, 0.42, 0.65) * (0.7 + 0.6 * up);
}

Vector3d SynthScene::Trace(const Ray& ray, Hit* hit_out) const {
  const Hit hit = Intersect(ray);
  if (hit_out) *hit_out = hit;
  if (hit.shape < 0) return Sky(ray.direction);
  return Shade(ray, hit);
}

}  // namespace hdribr::synth
