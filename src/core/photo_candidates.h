// Candidate photos of a view: the few photos, among the allowed ones, that can matter for the
// pixels the view sees, so that the per-pixel blend loops over those only. Chosen on the CPU
// from a fixed random sample of the point cloud, with a coarse occlusion test per photo
// (docs/algorithms/blend.md, "Candidate photos"; docs/decisions/0010).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"
#include "core/scene.h"

namespace hdribr {

// Weight of delta_k (LEC19 eq. 4, scene-scale units) against the angle (radians) in the
// Unstructured Lumigraph penalty angle(V, V_k) + kUlrDistanceWeight delta_k: of the blend
// (shaders/blend_visibility.glsl) and of the candidate photos' votes. Below 1 so that a photo at a
// different distance from the point but from the view's direction keeps a share of the blend
// (docs/decisions/0033).
inline constexpr float kUlrDistanceWeight = 0.3f;

class PhotoCandidates {
 public:
  // Largest number of sample points drawn from the cloud, once, in a fixed random order.
  static constexpr int kMaxSamples = 65536;
  // Sample points in front of the view scanned per frame (fewer when the sample runs out).
  static constexpr int kTargetVisible = 1024;
  // Hysteresis: a photo chosen in the previous frame counts its gain x (1 + kHysteresisGain)
  // + kHysteresisFloor x the frame's largest gain when the photos are picked (the floor keeps
  // marginal photos, whose small gains vary the most, from swapping back and forth).
  static constexpr double kHysteresisGain = 0.25;
  static constexpr double kHysteresisFloor = 0.005;
  // Hysteresis holds between frames whose view centres are within this many scene scales and
  // whose viewing directions are within kContinuityDegrees; a larger move selects afresh.
  static constexpr double kContinuityDistance = 0.1;
  static constexpr double kContinuityDegrees = 5.0;
  // Occlusion: a photo's nearest sample point per cell of a grid kGridCells wide (along the
  // photo's longer side); a point farther than that by kOcclusionTolerance x its z is hidden.
  static constexpr int kGridCells = 64;
  static constexpr double kOcclusionTolerance = 0.1;

  // Draws the sample from scene.points and the photos' occlusion grids; keeps a reference to
  // `scene`, which must outlive it.
  explicit PhotoCandidates(const Scene& scene);

  // The photos of `allowed` (indices into scene.photos) that can matter for the view (pinhole
  // `camera`, any size), at most `max_count` (> 0), in the order of `allowed`. `per_point`:
  // photos the blend ranks per pixel (K + 1 for the Unstructured Lumigraph, K for K best, the
  // cap for all). Each visible sample point votes for its 2 x `per_point` photos of smallest
  // blending penalty, weighted like the Unstructured Lumigraph; photos are then picked greedily
  // for the votes of the points that still lack `per_point` picked photos. A photo that sees
  // no visible sample point is never selected. When no sample point is visible, returns
  // `allowed`. Remembers the selection for the next call (hysteresis).
  const std::vector<int>& Select(const Camera& camera, const Rigid3d& cam_from_world,
                                 const std::vector<int>& allowed, int max_count, int per_point);
  // Forgets the previous selections: the next Select chooses afresh.
  void Reset();

  // Score of a photo in the newest Select: its votes and seen points per visible sample point,
  // before any photo was picked (0 when not allowed or seeing no visible sample point).
  double score(int photo) const { return scores_[static_cast<size_t>(photo)]; }
  // Sample points that were visible in the newest Select.
  int visible_samples() const { return visible_count_; }
  // Size of the fixed sample.
  int sample_size() const { return static_cast<int>(positions_.size()); }

 private:
  // The camera z of the nearest sample point per grid cell of one photo.
  struct OcclusionGrid {
    int width = 0, height = 0;  // cells
    float cells_per_pixel = 0;
    std::vector<float> nearest_z;  // row-major; infinity where no sample point falls

    // The cell of pixel position (u, v) of the photo, inside the image.
    size_t Cell(float u, float v) const {
      const int x = std::min(static_cast<int>(u * cells_per_pixel), width - 1);
      const int y = std::min(static_cast<int>(v * cells_per_pixel), height - 1);
      return static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
    }
  };

  struct Rows;
  struct Votes;
  // The allowed photos as rows of SIMD columns, nearest the view first.
  Rows GatherRows(const std::vector<int>& allowed, const Eigen::Vector3d& centre,
                  const Eigen::Vector3d& direction) const;
  // The visible sample points' votes for the rows that see them.
  Votes CollectVotes(const Camera& camera, const Rigid3d& cam_from_world, const Rows& rows,
                     int demand) const;
  // At most max_count photos (scene indices), picked for coverage; fills scores_.
  std::vector<int> PickGreedy(const Rows& rows, const Votes& votes, int max_count, int demand);

  const Scene& scene_;
  std::vector<Eigen::Vector3f> positions_;  // the sample, world
  std::vector<Eigen::Vector3f> normals_;    // empty when the cloud has none
  std::vector<OcclusionGrid> grids_;        // per scene photo
  std::vector<double> scores_;              // per scene photo
  std::vector<char> selected_;              // per scene photo: in its newest selection
  std::vector<int> result_;
  int visible_count_ = 0;
  bool has_previous_ = false;  // selected_ and the previous view are meaningful
  Eigen::Vector3d previous_centre_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d previous_direction_ = Eigen::Vector3d::UnitZ();
};

}  // namespace hdribr
