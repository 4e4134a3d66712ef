// A circular camera orbit around a capture (the demo's headless output, viewer reset views).
#pragma once

#include "core/scene.h"
#include "io/camera_spec.h"

namespace hdribr::viewer {

// `frames` views on a circle about the scene up axis (SceneUp) through the mean photo centre,
// centred on the points' centroid, all looking at the centroid with the first photo's camera
// (scaled to width x height when > 0). Views are named "frame_%04d". Throws UsageError for a
// scene without photos or frames < 1.
CameraPath OrbitPath(const Scene& scene, int frames, double fps = 12, int width = 0,
                     int height = 0);

}  // namespace hdribr::viewer
