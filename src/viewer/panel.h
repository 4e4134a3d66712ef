// The viewer's Dear ImGui windows: the control panel (timings, tone mapping, renderer settings,
// display mode and its legend) and the key help overlay. Needs a current ImGui frame.
#pragma once

#include "core/scene.h"
#include "viewer/frame_renderer.h"
#include "viewer/view_state.h"

namespace hdribr::viewer {

// What the panel shows besides the state it edits.
struct PanelInfo {
  const Scene* scene = nullptr;
  const FrameStats* stats = nullptr;
  double fps = 0;
  bool point_colours_known = true;
  bool recording = false;
  bool camera_curve = false;  // the loaded source has a camera response
};

// The panel (when state.panel) and the help overlay (when state.help); edits go to `state`.
void DrawUi(ViewState& state, const PanelInfo& info);

}  // namespace hdribr::viewer
