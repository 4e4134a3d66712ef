// The key of a scene's photo depth maps in the depth-map cache (io/depth_map_cache.h): a hash
// of everything the depth maps depend on, so that changing any of it gives another key.
#pragma once

#include <cstdint>

#include "core/scene.h"
#include "render/depth_pass.h"

namespace hdribr::render {

// Hash of the GL implementation, the pass's shader sources, the options that change its output,
// its uploaded points, `scale` and each photo's camera and pose, in layer order. Needs the
// current context of `pass`.
std::uint64_t PhotoDepthMapsKey(const Scene& scene, const DepthPass& pass, double scale);

}  // namespace hdribr::render
