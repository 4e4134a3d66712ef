#include "viewer/benchmark.h"

#include <epoxy/gl.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

namespace hdribr::viewer {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

long ResidentKb() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmRSS:") {
      long kb = 0;
      status >> kb;
      return kb;
    }
    status.ignore(1 << 12, '\n');
  }
  return -1;
}

}  // namespace

void RunBenchmark(FrameRenderer& renderer, CameraController& controller, ViewState& state,
                  HdrSource source, double budget_ms) {
  const int n = 10;
  const int w = renderer.width(), h = renderer.height();
  const auto frame = [&] {
    renderer.Render(state, controller.cam_from_world(), w, h);
    renderer.Blit(w, h, false, 0);
    glFinish();
  };
  state.frame_budget_ms = 0;
  double move_ms = 0, expo_ms = 0, move_gpu = 0, expo_gpu = 0, depth_gpu = 0, blend_gpu = 0;
  for (int i = 0; i < n; ++i) {
    controller.Orbit(0.01, 0);
    const auto t0 = Clock::now();
    frame();
    move_ms += MsSince(t0);
    const FrameStats& s = renderer.stats();
    move_gpu +=
        s.render_gpu.depth_ms + s.render_gpu.blend_ms + s.render_gpu.fill_ms + s.tonemap_gpu_ms;
    depth_gpu += s.render_gpu.depth_ms;
    blend_gpu += s.render_gpu.blend_ms;
  }
  for (int i = 0; i < n; ++i) {
    state.exposure_ev += 0.1f;
    renderer.MarkDisplayDirty();
    const auto t0 = Clock::now();
    frame();
    expo_ms += MsSince(t0);
    expo_gpu += renderer.stats().tonemap_gpu_ms;
  }
  std::printf(
      "viewer benchmark %dx%d, %zu photos, %s: camera move %.2f ms/frame (GPU %.2f ms: depth "
      "%.2f, blend %.2f), exposure change %.2f ms/frame (GPU %.2f ms)\n",
      w, h, renderer.photo_count(), HdrSourceName(source).c_str(), move_ms / n, move_gpu / n,
      depth_gpu / n, blend_gpu / n, expo_ms / n, expo_gpu / n);
  if (budget_ms <= 0) return;
  // Progressive: the first frames find the size that fits the budget, the rest are timed.
  state.frame_budget_ms = budget_ms;
  const int warm_up = 10, timed = 30;
  double orbit_ms = 0, scale = 0;
  for (int i = 0; i < warm_up + timed; ++i) {
    controller.Orbit(0.01, 0);
    const auto t0 = Clock::now();
    frame();
    if (i < warm_up) continue;
    orbit_ms += MsSince(t0);
    scale += renderer.stats().scale;
  }
  const auto stop = Clock::now();
  // The first full-size picture (before the one with the depth search).
  double full_size_ms = renderer.full_quality() ? 0 : -1;
  while (!renderer.settled()) {
    frame();
    if (full_size_ms < 0 && renderer.full_quality()) full_size_ms = MsSince(stop);
  }
  std::printf(
      "viewer benchmark progressive, budget %.0f ms: orbit %.1f frames/s (%.1f ms/frame, mean "
      "size %.1f%% of the window), full size %.0f ms, full quality %.0f ms after the camera "
      "stops\n",
      budget_ms, 1000.0 * timed / orbit_ms, orbit_ms / timed, 100 * scale / timed, full_size_ms,
      MsSince(stop));
}

void SoakStep(int frame, CameraController& controller, ViewState& state) {
  if (frame % 2 == 0) {
    controller.Orbit(0.01, 0);
  } else {
    state.AddExposure(frame % 4 == 1 ? 0.1f : -0.1f);
  }
}

ResourceSample SampleResources() {
  ResourceSample s;
  s.rss_kb = ResidentKb();
  using IsObject = GLboolean (*)(GLuint);
  // epoxy's entry points are function pointers resolved at first call: wrap them.
  const IsObject probes[] = {
      [](GLuint id) { return glIsTexture(id); },
      [](GLuint id) { return glIsBuffer(id); },
      [](GLuint id) { return glIsFramebuffer(id); },
      [](GLuint id) { return glIsRenderbuffer(id); },
      [](GLuint id) { return glIsVertexArray(id); },
      [](GLuint id) { return glIsProgram(id); },
      [](GLuint id) { return glIsShader(id); },
      [](GLuint id) { return glIsQuery(id); },
      [](GLuint id) { return glIsSampler(id); },
      [](GLuint id) { return glIsProgramPipeline(id); },
  };
  for (const IsObject is : probes) {
    for (GLuint id = 1; id <= 4096; ++id) s.gl_objects += is(id) == GL_TRUE ? 1 : 0;
  }
  return s;
}

}  // namespace hdribr::viewer
