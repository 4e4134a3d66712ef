#version 450 core
// Input camera frustums in the viewer: world-space line vertices through the view's
// cam_from_world and ClipFromCam (core/projection.h); the camera z goes to the fragment
// shader for the test against the scene depth.
layout(location = 0) uniform mat4 u_cam_from_world;
layout(location = 1) uniform mat4 u_clip_from_cam;
layout(location = 0) in vec3 a_position;  // world
layout(location = 1) in float a_photo;    // photo index

out float v_z;
flat out int v_photo;

void main() {
  vec4 p = u_cam_from_world * vec4(a_position, 1.0);
  v_z = p.z;
  v_photo = int(a_photo + 0.5);
  gl_Position = u_clip_from_cam * p;
}
