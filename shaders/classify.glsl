// Step 2 of the depth pass (Lechelek et al. 2019, sec. 4): a point is front or back against
// the step-1 splat depth at its centre pixel (render::DepthPassOptions::front_radii and
// front_rel).
layout(location = 5) uniform float u_front_radii;  // tolerance in splat radii
layout(location = 6) uniform float u_front_rel;    // plus this fraction of the depth

// True for a point at camera z with splat radius r (world units) when z <= z1 +
// u_front_radii r + u_front_rel z1, z1 the step-1 camera z at its centre pixel; also where
// no splat covers that pixel (z1 = 0).
bool IsFront(float z, float radius, float z1) {
  return z1 <= 0.0 || z <= z1 + u_front_radii * radius + u_front_rel * z1;
}
