// Procedural solid textures (functions of the world position) for the synthetic scenes.
#pragma once

#include <Eigen/Core>

namespace hdribr::synth {

enum class TextureKind { kSolid, kChecker, kNoise, kStripes };

// Albedo pattern: mixes colour_a and colour_b (linear RGB, in [0, 1]) by a pattern of the
// position; `scale` is the pattern frequency in cycles per scene unit.
struct Texture {
  TextureKind kind = TextureKind::kSolid;
  Eigen::Vector3d colour_a = Eigen::Vector3d::Constant(0.5);
  Eigen::Vector3d colour_b = Eigen::Vector3d::Constant(0.5);
  double scale = 1.0;
  Eigen::Vector3d stripe_axis = Eigen::Vector3d::UnitZ();  // kStripes: normal of the stripes
  // Multiplicative fine noise on every kind (0 = none), so that surfaces are never featureless.
  double grain = 0.0;

  // Linear RGB albedo at world position p.
  Eigen::Vector3d Albedo(const Eigen::Vector3d& p) const;
};

// Smooth value noise in [0, 1] (trilinear, quintic fade), deterministic: a fixed hash lattice.
double ValueNoise(const Eigen::Vector3d& p);
// Fractal sum of 4 octaves of ValueNoise, in [0, 1].
double FractalNoise(const Eigen::Vector3d& p);

}  // namespace hdribr::synth
