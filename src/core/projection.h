// The one conversion from COLMAP intrinsics to an OpenGL clip-space matrix.
#pragma once

#include <Eigen/Core>

#include "core/camera.h"

namespace hdribr {

// clip_from_cam for a COLMAP camera (x right, y down, z forward; pixel centres at +0.5).
// Flips y (image rows grow downward, NDC y grows upward) and uses w_clip = +z so that points
// in front have positive w. NDC z maps camera z in [near, far] to [-1, 1]. With the render
// layer's glClipControl(GL_UPPER_LEFT, GL_NEGATIVE_ONE_TO_ONE), gl_FragCoord.xy equals the COLMAP
// pixel position and framebuffer row 0 is the top image row.
Eigen::Matrix4f ClipFromCam(const Camera& camera, float near, float far);

// Window position (pixels, top-left origin) of a clip-space point, the inverse of the above for
// a viewport of width x height.
Eigen::Vector2d WindowFromClip(const Eigen::Vector4f& clip, int width, int height);

}  // namespace hdribr
