#include "render/photo_depth_maps.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>
#include <string>

#include "core/error.h"
#include "io/depth_map_cache.h"
#include "render/photo_depth_key.h"

namespace hdribr::render {
namespace fs = std::filesystem;
namespace {

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Each photo's depth map by the pass, copied into its layer of `depth`.
void ComputeLayers(const Scene& scene, DepthPass& pass, const std::vector<cv::Size>& sizes,
                   const gl::Texture& depth) {
  std::optional<DepthTarget> target;
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    const cv::Size s = sizes[i];
    if (!target || target->width() != s.width || target->height() != s.height) {
      target = DepthTarget::Create(s.width, s.height);
    }
    pass.Process(scene.CameraOf(scene.photos[i]), scene.photos[i].cam_from_world, *target);
    glCopyImageSubData(target->depth.id(), GL_TEXTURE_2D, 0, 0, 0, 0, depth.id(),
                       GL_TEXTURE_2D_ARRAY, 0, 0, 0, static_cast<GLint>(i), s.width, s.height, 1);
  }
}

// The valid region of each layer, read back (CV_32FC1).
std::vector<cv::Mat> ReadLayers(const gl::Texture& depth, const std::vector<cv::Size>& sizes) {
  std::vector<cv::Mat> layers;
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  for (size_t i = 0; i < sizes.size(); ++i) {
    cv::Mat layer(sizes[i], CV_32FC1);
    glGetTextureSubImage(depth.id(), 0, 0, 0, static_cast<GLint>(i), layer.cols, layer.rows, 1,
                         GL_RED, GL_FLOAT, static_cast<GLsizei>(layer.total() * sizeof(float)),
                         layer.data);
    layers.push_back(std::move(layer));
  }
  return layers;
}

// Uploads layers[i] (CV_32FC1, continuous) into the top-left corner of layer i.
void UploadLayers(const gl::Texture& depth, const std::vector<cv::Mat>& layers) {
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (size_t i = 0; i < layers.size(); ++i) {
    HDRIBR_CHECK(layers[i].type() == CV_32FC1 && layers[i].isContinuous());
    glTextureSubImage3D(depth.id(), 0, 0, 0, static_cast<GLint>(i), layers[i].cols, layers[i].rows,
                        1, GL_RED, GL_FLOAT, layers[i].data);
  }
}

// A warning about a cache folder that cannot be written, given once per folder and process
// (a viewer may build several renderers).
void WarnUnwritableOnce(const fs::path& dir, const std::string& problem) {
  static std::mutex mutex;
  static std::set<fs::path> warned;
  const std::lock_guard<std::mutex> lock(mutex);
  if (!warned.insert(dir).second) return;
  spdlog::warn("photo depth maps: not cached ({}); they are computed at every start", problem);
}

}  // namespace

std::vector<cv::Mat> PhotoDepthMaps::TakeLayers() {
  std::vector<cv::Mat> layers = ReadLayers(depth_, sizes_);
  depth_ = gl::Texture();
  return layers;
}

void PhotoDepthMaps::Allocate(const Scene& scene, double scale) {
  HDRIBR_CHECK(scale > 0.0);
  int max_w = 1, max_h = 1;
  for (const Photo& photo : scene.photos) {
    const Camera& cam = scene.CameraOf(photo);
    const cv::Size s(std::max(1, static_cast<int>(std::lround(cam.width * scale))),
                     std::max(1, static_cast<int>(std::lround(cam.height * scale))));
    sizes_.push_back(s);
    max_w = std::max(max_w, s.width);
    max_h = std::max(max_h, s.height);
  }
  const int layers = std::max<int>(1, static_cast<int>(scene.photos.size()));
  depth_ = gl::Texture::Create2DArray(GL_R32F, max_w, max_h, layers);
  const float zero = 0.0f;
  glClearTexImage(depth_.id(), 0, GL_RED, GL_FLOAT, &zero);
}

PhotoDepthMaps::PhotoDepthMaps(const Scene& scene, const std::vector<cv::Mat>& given,
                               double scale) {
  HDRIBR_CHECK(given.size() == scene.photos.size());
  Allocate(scene, scale);
  std::vector<cv::Mat> layers(given.size());
  for (size_t i = 0; i < given.size(); ++i) {
    HDRIBR_CHECK(given[i].type() == CV_32FC1);
    cv::resize(given[i], layers[i], sizes_[i], 0, 0, cv::INTER_NEAREST);
  }
  UploadLayers(depth_, layers);
  spdlog::info("photo depth maps: {} given", count());
}

PhotoDepthMaps::PhotoDepthMaps(const Scene& scene, DepthPass& pass, double scale,
                               const fs::path& cache_dir) {
  const auto t0 = std::chrono::steady_clock::now();
  Allocate(scene, scale);
  if (cache_dir.empty()) {
    ComputeLayers(scene, pass, sizes_, depth_);
    spdlog::info("photo depth maps: {} computed in {:.2f} s (no cache)", count(), Since(t0));
    return;
  }

  const std::uint64_t key = PhotoDepthMapsKey(scene, pass, scale);
  const fs::path file = DepthMapCacheFile(cache_dir, key);
  std::error_code ec;
  if (fs::exists(file, ec)) {
    try {
      UploadLayers(depth_, ReadDepthMapCache(file, key, sizes_));
      from_cache_ = true;
      TouchDepthMapCache(file);  // most recently used: kept by the pruning
      spdlog::info("photo depth maps: {} from cache {} in {:.2f} s", count(), file.string(),
                   Since(t0));
      return;
    } catch (const std::exception& e) {  // InputError naming the file and its problem
      spdlog::warn("photo depth maps: ignoring the cache ({}); computing them", e.what());
    }
  }

  const auto t1 = std::chrono::steady_clock::now();
  ComputeLayers(scene, pass, sizes_, depth_);
  const double seconds = Since(t1);
  try {
    WriteDepthMapCache(file, key, ReadLayers(depth_, sizes_));
  } catch (const std::exception& e) {
    WarnUnwritableOnce(cache_dir, e.what());
    spdlog::info("photo depth maps: {} computed in {:.2f} s", count(), seconds);
    return;
  }
  PruneDepthMapCache(cache_dir);
  spdlog::info("photo depth maps: {} computed in {:.2f} s, cached to {}", count(), seconds,
               file.string());
}

}  // namespace hdribr::render
