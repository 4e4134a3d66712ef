// The blend pass (Lechelek et al. 2019, sec. 4, eqs. 1-5): blends the photos that see each
// pixel's surface point, from the new view's depth and the photos' depth maps.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"
#include "core/scene.h"
#include "gl/objects.h"
#include "gl/shader_library.h"
#include "render/blend_options.h"
#include "render/blend_params.h"
#include "render/depth_pass.h"
#include "render/photo_cache.h"
#include "render/photo_depth_maps.h"
#include "render/photo_textures.h"

namespace hdribr::render {

// The sphere of Background::kSphere (world frame: centre, radius): centred on the points'
// centroid, its radius the larger of the 99th-percentile distance of the points (the far
// points themselves win over the sphere where they exist) and 1.25 times the farthest camera's.
Eigen::Vector4d BackgroundSphere(const Scene& scene);

class BlendPass {
 public:
  // Needs a current GL 4.5 context.
  explicit BlendPass(const gl::ShaderLibrary& shaders);

  // Uploads the per-photo geometry (poses, intrinsics, texture and depth-map scales) of every
  // scene photo; `textures` and `depth_maps` hold layer i = scene.photos[i].
  void SetPhotos(const Scene& scene, const PhotoTextures& textures,
                 const PhotoDepthMaps& depth_maps);
  // The same for photos in a cache (photo_cache.h): photo i is sampled from its slot when the
  // cache's slot map gives one, else from its coarse copy. `cache` must outlive the pass.
  void SetPhotos(const Scene& scene, const PhotoCache& cache, const PhotoDepthMaps& depth_maps);
  // Photos that may contribute (indices into scene.photos).
  void SetActive(const std::vector<int>& photo_indices);
  int active_count() const { return active_count_; }

  // Every program (shader file, modes) that an option can reach: each option's values with the
  // others at their defaults, and the photo cache's and HDR photo sets' modes (for the shader
  // portability test; the passes build theirs on first use).
  static std::vector<std::pair<std::string, gl::Defines>> ReachablePrograms();

  // Blends into color (RGBA32F: rgb value, a validity) and aux (RGBA32F: r count, g the debug
  // photo's normalised weight). `camera` has the target's size. response: 256 x 1 RGB32F
  // texture of g(Z), needed by PhotoEncoding::kRadiance.
  void Process(const Camera& camera, const Rigid3d& cam_from_world, const DepthTarget& depth,
               const BlendOptions& options, const gl::Texture* response, gl::Texture& color,
               gl::Texture& aux) const;

 private:
  void SetPhotos(const Scene& scene, const PhotoLayout& layout, GLuint texture,
                 const PhotoDepthMaps& depth_maps, const PhotoCache* cache);
  // The program of shader `file` compiled with `modes` (the defines of
  // shaders/blend_common.glsl: the length of the per-pixel list, the weights, encoding,
  // background, ...), built on first use.
  const gl::Program& ProgramFor(const char* file, const gl::Defines& modes) const;

  const gl::ShaderLibrary& shaders_;
  // By shader file and modes.
  mutable std::map<std::pair<std::string, gl::Defines>, gl::Program> programs_;
  gl::Buffer params_buffer_;  // the uniform block BlendParams
  // The pixels without a point (Holes in shaders/blend_common.glsl), grown to the largest target.
  mutable gl::Buffer holes_;
  gl::Buffer photos_;
  gl::Buffer active_;
  GLuint photo_texture_ = 0;
  GLuint depth_maps_ = 0;
  const PhotoCache* cache_ = nullptr;  // null: photo_texture_ holds every photo (else 0)
  bool cached_depth_ = false;          // depth_maps_ holds the cache's depth slots
  bool float_photos_ = false;          // RGBA16F photos (an HDR photo set), not 8-bit
  int photo_count_ = 0;
  int active_count_ = 0;
  // The scene's parameters (photo texels, scene scale, BackgroundSphere, FindDominantPlane's
  // plane: zero when invalid); Process adds the frame's.
  BlendParamsGpu params_{};
};

}  // namespace hdribr::render
