// Scripted measurements of the viewer: the exposure-change vs camera-move benchmark and the
// soak run (many frames alternating both, watching resident memory and GL objects).
#pragma once

#include "viewer/camera_controller.h"
#include "viewer/frame_renderer.h"
#include "viewer/view_state.h"

namespace hdribr::viewer {

// Times 10 camera moves then 10 exposure changes at full quality and prints one line; then,
// with a frame budget of `budget_ms`, an orbit of 40 frames (frames per second over the last
// 30, the mean rendered size) and the time from the camera's stop to the full-quality picture,
// and prints a second line. Frames are timed with the blit into the window.
void RunBenchmark(FrameRenderer& renderer, CameraController& controller, ViewState& state,
                  HdrSource source, double budget_ms);

// One soak step for frame `frame`: even frames orbit, odd frames change the exposure (by
// +-0.1 EV in turn, so that it stays bounded).
void SoakStep(int frame, CameraController& controller, ViewState& state);

struct ResourceSample {
  long rss_kb = 0;     // VmRSS of this process
  int gl_objects = 0;  // live GL object names of the current context
};
// Needs a current GL context. GL objects are counted by probing glIs* over names 1 ... 4096
// (textures, buffers, framebuffers, renderbuffers, vertex arrays, programs, shaders, queries,
// samplers, program pipelines).
ResourceSample SampleResources();

}  // namespace hdribr::viewer
