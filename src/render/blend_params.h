// The blend pass's per-frame parameters as the shaders read them: the std140 uniform block
// BlendParams of shaders/blend_common.glsl, member for member.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace hdribr::render {

// std140 mirror of the uniform block BlendParams (binding 0): frames and units as there.
struct BlendParamsGpu {
  float world_from_cam[16];  // column-major, like GLSL
  float intrinsics[4];       // new view: fx, fy, cx, cy in pixels of the target
  float sphere[4];           // background sphere: centre (world), radius
  float plane[4];            // background plane: n, offset
  float plane_u[4];          // its in-plane axes (xyz)
  float plane_v[4];
  float plane_extent[4];  // u min, u max, v min, v max
  int32_t size[2];        // target size in pixels
  float photo_texels[2];  // the full-size photo array's size in texels
  int32_t active_count;   // photos in the active list
  float lambda;           // BlendOptions::lambda
  float tolerance;        // BlendOptions::occlusion_tolerance
  float inv_scene_scale;  // 1 / Scene::scene_scale
  int32_t debug_photo;    // BlendOptions::debug_photo
  float filter;           // BlendOptions::filter
  float outlier_scale;    // BlendOptions::outlier_scale
  float refine;           // BlendOptions::refine_depth
};
static_assert(sizeof(BlendParamsGpu) == 208, "std140 size of BlendParams");

// The block member's GLSL name and its byte offset in BlendParamsGpu, for every member (the
// shader portability test checks them against the compiled block).
inline std::vector<std::pair<std::string, size_t>> BlendParamsLayout() {
  return {{"u_world_from_cam", offsetof(BlendParamsGpu, world_from_cam)},
          {"u_intrinsics", offsetof(BlendParamsGpu, intrinsics)},
          {"u_sphere", offsetof(BlendParamsGpu, sphere)},
          {"u_plane", offsetof(BlendParamsGpu, plane)},
          {"u_plane_u", offsetof(BlendParamsGpu, plane_u)},
          {"u_plane_v", offsetof(BlendParamsGpu, plane_v)},
          {"u_plane_extent", offsetof(BlendParamsGpu, plane_extent)},
          {"u_size", offsetof(BlendParamsGpu, size)},
          {"u_photo_texels", offsetof(BlendParamsGpu, photo_texels)},
          {"u_active_count", offsetof(BlendParamsGpu, active_count)},
          {"u_lambda", offsetof(BlendParamsGpu, lambda)},
          {"u_tolerance", offsetof(BlendParamsGpu, tolerance)},
          {"u_inv_scene_scale", offsetof(BlendParamsGpu, inv_scene_scale)},
          {"u_debug_photo", offsetof(BlendParamsGpu, debug_photo)},
          {"u_filter", offsetof(BlendParamsGpu, filter)},
          {"u_outlier_scale", offsetof(BlendParamsGpu, outlier_scale)},
          {"u_refine", offsetof(BlendParamsGpu, refine)}};
}

}  // namespace hdribr::render
