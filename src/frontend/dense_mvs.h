// Built-in CPU multi-view stereo (used when COLMAP has no CUDA): per-photo depth maps by PatchMatch
// (frontend/patch_match.h) or a fronto-parallel plane sweep, geometric consistency filtering
// across photos, fusion.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <map>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "core/point_cloud.h"
#include "io/colmap_model.h"

namespace hdribr {

// Depth map algorithm of the CPU densifier.
enum class DenseMethod { kPatchMatch, kSweep };

// Version of the CPU densifier's algorithms (PatchMatch, the sweep, consistency and fusion),
// recorded in a workspace's dense-stage marker: a change of the code that alters the clouds it
// makes from the same photos and options increments it, so that `reconstruct` redoes the dense
// stage of workspaces made before.
inline constexpr int kDenseVersion = 3;

// PatchMatch stereo parameters (frontend/patch_match.h).
struct PatchMatchOptions {
  int window_radius = 5;     // NCC window (2r+1)^2 ...
  int window_step = 2;       // ... sampled every step-th pixel
  float sigma_color = 0.1f;  // bilateral weight: intensity scale ([0, 1] intensities)
  // Pyramid levels (coarse to fine, halving the size). Two by default: with more, the coarse
  // planes, upsampled and held by their geometric guidance, bias small curved objects toward
  // what surrounds them more than they help weak texture (docs/decisions/0024).
  int num_levels = 2;
  int coarse_iterations = 4;    // iterations at the coarsest level
  int iterations = 2;           // iterations at each finer level
  int geom_iterations = 1;      // iterations of the geometric-consistency pass (0: none)
  float geom_weight = 0.2f;     // cost per pixel of forward-backward reprojection error
  float geom_max_error = 3.0f;  // reprojection error clamp (pixels at the finest level)
  int best_views = 0;           // source costs averaged per pixel, of those framing it (0: half)
  float min_ncc = 0.3f;         // NCC of the best views needed to keep a depth
  float min_texture = 2e-5f;    // intensity variance of the window needed to keep a depth
  int seed_radius = 1;          // sparse-point depth seeds cover this radius at the coarsest
  bool coarse_fill = true;      // pixels failing at full size keep a passing coarser plane
};

struct DenseOptions {
  DenseMethod method = DenseMethod::kPatchMatch;  // reconstruct sets it from --dense
  // Largest side of the depth maps (pixels); 0: from the photo count (DepthMapSize).
  int max_size = 0;
  // With max_size 0 the photos share this many depth-map pixels: 48 photos of 400 x 300, the
  // capture the dense stage's time is set on, so fewer photos get larger maps in that time.
  double pixel_budget = 48 * 400 * 300;
  int min_auto_size = 400;        // ... and never less than this largest side
  int num_neighbors = 4;          // source photos per reference photo
  int num_depths = 96;            // sweep: planes, uniform in inverse depth
  int window_radius = 3;          // sweep: NCC window (2r+1)^2
  float min_ncc = 0.55f;          // sweep: aggregated NCC needed to keep a depth
  float consistency = 0.01f;      // relative depth agreement for geometric consistency
  int min_consistent = 2;         // other depth maps that must agree with a depth
  float max_normal_error = 30.f;  // degrees between agreeing plane normals (PatchMatch)
  int threads = 0;                // 0: hardware concurrency
  // A depth whose NCC (the map's score) reaches this needs only one agreeing map: surfaces that
  // few photos frame rarely have two, and a depth matched that well is rarely wrong (> 1: off).
  float single_agreement_ncc = 0.9f;
  PatchMatchOptions patch_match;
};

// A depth map of one photo (camera-space z, 0 where invalid) at reduced resolution.
struct DepthMap {
  int image_id = -1;
  Camera camera;  // PINHOLE, scaled to the depth map size
  Rigid3d cam_from_world;
  cv::Mat depth;               // CV_32F
  cv::Mat score;               // CV_32F, aggregated NCC
  cv::Mat normal;              // CV_32FC3 unit plane normals in camera space (PatchMatch only)
  cv::Mat color;               // CV_8UC3 BGR at the same size
  cv::Mat gray;                // CV_32F in [0, 1] at the same size
  std::vector<int> neighbors;  // image ids of its source photos
};

struct DenseResult {
  PointCloud cloud;                        // positions, colours, normals (PatchMatch)
  std::vector<Eigen::Vector3f> view_dirs;  // per point: unit sum of directions to its cameras
  int num_depth_maps = 0;
  int depth_map_size = 0;  // largest side of the depth maps (pixels), from DepthMapSize
};

// Source photos of each photo: the ones sharing the most sparse points at a triangulation angle
// of at least 2 degrees. Returns image id -> neighbour ids (best first).
std::map<int, std::vector<int>> SelectNeighbors(const ColmapModel& model, int k);

// Depth range (camera z) of a photo from the depths of the sparse points it sees: the 2nd
// percentile to the farthest point (unless beyond 4 times the 98th percentile), widened by 25 %.
std::pair<double, double> SparseDepthRange(std::vector<double> depths);

// Largest side of the depth maps: options.max_size, or when 0 the side at which the model's photos
// (each at its own aspect) share options.pixel_budget, at least options.min_auto_size. Photos
// smaller than the result keep their size.
int DepthMapSize(const ColmapModel& model, const DenseOptions& options);

// Depth map of one reference photo from its source photos (images already loaded and scaled).
// `depth_min`, `depth_max` bound the sweep (camera z).
DepthMap ComputeDepthMap(const DepthMap& ref_in, const std::vector<const DepthMap*>& sources,
                         double depth_min, double depth_max, const DenseOptions& options);

// Geometric consistency and fusion of depth maps (each with its image_id, camera,
// cam_from_world, depth, score, colour, neighbours and, from PatchMatch, normals) into points.
DenseResult FuseDepthMaps(const std::vector<DepthMap>& maps, const DenseOptions& options);

// Whole pipeline on an undistorted (PINHOLE) model and its images folder. `progress(done, total)`
// is called after each depth map.
DenseResult DensifyCpu(const ColmapModel& model, const std::filesystem::path& images_dir,
                       const DenseOptions& options,
                       const std::function<void(int, int)>& progress = {});

}  // namespace hdribr
