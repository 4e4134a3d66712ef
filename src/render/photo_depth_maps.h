// Depth maps of every photo of a scene, computed once with the depth pass into a texture
// array (layer i = scene.photos[i]), for the occlusion test of the blend pass; optionally
// kept in a cache folder (io/depth_map_cache.h) so that the next start reads them instead.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

#include "core/scene.h"
#include "gl/objects.h"
#include "render/depth_pass.h"

namespace hdribr::render {

class PhotoDepthMaps {
 public:
  // Renders each photo's view at its camera size times `scale` (> 0), rounded, into layer i
  // of an R32F array sized to the largest; smaller photos use the top-left corner. The depth
  // pass must already hold the scene's points. With a `cache_dir`, the depth maps are read
  // from the file of their key (PhotoDepthMapsKey) when it is there and sound, else computed
  // and written to it; a cache that cannot be read or written costs a warning, never a failure.
  PhotoDepthMaps(const Scene& scene, DepthPass& pass, double scale = 1.0,
                 const std::filesystem::path& cache_dir = {});
  // Given depth maps instead (CV_32FC1 camera z, 0 = none, one per photo in scene order, of
  // the photo's aspect), resized to the layers by nearest neighbour: a perfect-depth reference.
  PhotoDepthMaps(const Scene& scene, const std::vector<cv::Mat>& given, double scale = 1.0);

  const gl::Texture& depth() const { return depth_; }
  // Size of layer i's valid region in pixels.
  const cv::Size& layer_size(int i) const { return sizes_[static_cast<size_t>(i)]; }
  int count() const { return static_cast<int>(sizes_.size()); }
  // Reads every layer back (CV_32FC1, layer_size(i)) and frees the GPU array (depth() is then
  // empty; the sizes stay): for the photo cache, which uploads them on demand.
  std::vector<cv::Mat> TakeLayers();
  // True when the depth maps were read from the cache rather than computed.
  bool from_cache() const { return from_cache_; }

 private:
  // Sizes the layers and creates the cleared array.
  void Allocate(const Scene& scene, double scale);

  gl::Texture depth_;
  std::vector<cv::Size> sizes_;
  bool from_cache_ = false;
};

}  // namespace hdribr::render
