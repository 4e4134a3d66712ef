// `hdribr view`: the interactive viewer (GLFW window, OpenGL 4.5, Dear ImGui). This file wires
// the parts: view state (view_state.h), input (input.h), frame renderer (frame_renderer.h),
// panel (panel.h), camera paths (path_control.h).
#pragma once

#include "viewer/viewer_options.h"

namespace hdribr::viewer {

// Runs the viewer; returns the process exit code. Throws std::runtime_error when no window can
// be made, InputError / UsageError for bad input.
int RunViewer(const ViewerOptions& options);

// True when a display server is reachable and a GL 4.5 window can be created.
bool CanOpenWindow();

}  // namespace hdribr::viewer
