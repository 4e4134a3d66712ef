// Multithreaded CPU ray tracer: ground-truth radiance and depth of a synthetic scene seen by a
// pinhole camera (COLMAP conventions: x right, y down, z forward, pixel centres at +0.5).
#pragma once

#include <functional>
#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/rigid3.h"
#include "synth/synth_scene.h"

namespace hdribr::synth {

struct RenderOptions {
  int threads = 0;  // 0 = std::thread::hardware_concurrency()
  // Pixels whose centre sample differs from a neighbour's (other surface, or radiance ratio
  // above edge_ratio) get a 3x3 stratified supersample (anti-aliasing of edges and textures).
  bool antialias = true;
  double edge_ratio = 1.15;
};

struct RenderedView {
  cv::Mat radiance;  // CV_32FC3, linear BGR radiance (mean over the pixel's samples)
  cv::Mat depth;     // CV_32FC1, camera-space z of the pixel-centre ray's hit; 0 = sky
  cv::Mat normal;    // CV_32FC3, world-space unit normal (x, y, z) of that hit; 0 = sky
  cv::Mat shape;     // CV_32SC1, index of the shape hit by the centre ray; -1 = sky
};

// Renders one view. Deterministic: the result does not depend on the number of threads.
RenderedView RenderView(const SynthScene& scene, const Camera& camera,
                        const Rigid3d& cam_from_world, const RenderOptions& options = {});

// The world-space ray through a (continuous) pixel position.
Ray PixelRay(const Camera& camera, const Rigid3d& world_from_cam, double x, double y);

// Runs body(row) for every row in [0, rows) on `threads` threads (0 = hardware concurrency).
void ParallelRows(int rows, int threads, const std::function<void(int)>& body);

}  // namespace hdribr::synth
