#include "synth/texture.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace hdribr::synth {
namespace {

double Hash(std::int64_t x, std::int64_t y, std::int64_t z) {
  std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull ^
                    static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full ^
                    static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull;
  h ^= h >> 33;
  h *= 0xFF51AFD7ED558CCDull;
  h ^= h >> 33;
  h *= 0xC4CEB9FE1A85EC53ull;
  h ^= h >> 33;
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

double Fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }

}  // namespace

double ValueNoise(const Eigen::Vector3d& p) {
  const double fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy),
             iz = static_cast<std::int64_t>(fz);
  const double u = Fade(p.x() - fx), v = Fade(p.y() - fy), w = Fade(p.z() - fz);
  double c[2][2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int d = 0; d < 2; ++d) c[a][b][d] = Hash(ix + a, iy + b, iz + d);
  auto lerp = [](double x0, double x1, double t) { return x0 + (x1 - x0) * t; };
  const double x00 = lerp(c[0][0][0], c[1][0][0], u), x10 = lerp(c[0][1][0], c[1][1][0], u);
  const double x01 = lerp(c[0][0][1], c[1][0][1], u), x11 = lerp(c[0][1][1], c[1][1][1], u);
  return lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
}

double FractalNoise(const Eigen::Vector3d& p) {
  double sum = 0, amp = 0.5, norm = 0;
  Eigen::Vector3d q = p;
  for (int i = 0; i < 4; ++i) {
    sum += amp * ValueNoise(q);
    norm += amp;
    amp *= 0.5;
    q = 2.03 * q + Eigen::Vector3d(17.1, 3.7, 9.3);
  }
  return sum / norm;
}

Eigen::Vector3d Texture::Albedo(const Eigen::Vector3d& p) const {
  double t = 0;
  const Eigen::Vector3d q = scale * p;
  switch (kind) {
    case TextureKind::kSolid:
      t = 0;
      break;
    case TextureKind::kChecker: {
      // Small offset so that the cells do not align with axis-aligned faces at integer cells.
      const Eigen::Vector3d s = q + Eigen::Vector3d(1e-4, 2e-4, 3e-4);
      const auto sum = static_cast<std::int64_t>(std::floor(s.x())) +
                       static_cast<std::int64_t>(std::floor(s.y())) +
                       static_cast<std::int64_t>(std::floor(s.z()));
      t = (sum & 1) ? 1.0 : 0.0;
      break;
    }
    case TextureKind::kNoise:
      t = std::clamp(1.6 * (FractalNoise(q) - 0.5) + 0.5, 0.0, 1.0);
      break;
    case TextureKind::kStripes: {
      const double s = q.dot(stripe_axis) + 0.3 * ValueNoise(0.5 * q);
      t = (s - std::floor(s)) < 0.5 ? 0.0 : 1.0;
      break;
    }
  }
  Eigen::Vector3d albedo = (1 - t) * colour_a + t * colour_b;
  if (grain > 0) albedo *= 1.0 - grain + 2.0 * grain * ValueNoise(40.0 * p);
  return albedo;
}

}  // namespace hdribr::synth
