// The named synthetic scenes and the seeded random one: layouts that each stress what breaks
// image-based rendering (holes, thin structures, concave corners, open background, occluders
// near the cameras, glossy and textureless surfaces). datasets/README.md lists them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "synth/synth_scene.h"

namespace hdribr::synth {

// Names accepted by MakeScene, in the order `synth --help` lists them.
std::vector<std::string> SceneNames();

// Builds a named scene; "random" draws its layout from `seed` (the other scenes ignore it).
// Throws UsageError for an unknown name.
SynthScene MakeScene(const std::string& name, std::uint64_t seed = 1);

}  // namespace hdribr::synth
