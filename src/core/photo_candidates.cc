#include "core/photo_candidates.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>

#include "core/error.h"

namespace hdribr {
namespace {

// Penalty of a photo that does not see the point (finite: it is multiplied by 0).
constexpr float kNotSeen = 1e30f;
constexpr float kHalfPi = 1.5707963f;
// Gain of merely seeing a visible sample point: orders the photos that get no vote.
constexpr double kSeenScore = 1e-4;
// Weight of the votes of a point that already has per_point chosen photos: more photos there
// only stand in for occluded ones.
constexpr double kSaturatedVote = 1e-3;

}  // namespace

PhotoCandidates::PhotoCandidates(const Scene& scene)
    : scene_(scene), scores_(scene.photos.size(), 0.0), selected_(scene.photos.size(), 0) {
  const PointCloud& cloud = scene.points;
  const size_t n = cloud.size();
  const size_t m = std::min(n, static_cast<size_t>(kMaxSamples));
  // A fixed random order (partial Fisher-Yates, fixed seed): the same sample on every run.
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::mt19937 rng(0x68647269u);
  for (size_t i = 0; i < m; ++i) {
    const size_t j = i + static_cast<size_t>(rng()) % (n - i);
    std::swap(order[i], order[j]);
  }
  positions_.reserve(m);
  for (size_t i = 0; i < m; ++i) positions_.push_back(cloud.positions[order[i]]);
  if (cloud.HasNormals()) {
    normals_.reserve(m);
    for (size_t i = 0; i < m; ++i) normals_.push_back(cloud.normals[order[i]]);
  }
  grids_.reserve(scene.photos.size());
  for (const Photo& photo : scene.photos) {
    const Camera& cam = scene.CameraOf(photo);
    OcclusionGrid g;
    g.cells_per_pixel = static_cast<float>(kGridCells) / std::max({cam.width, cam.height, 1});
    g.width = std::max(1, static_cast<int>(std::ceil(cam.width * g.cells_per_pixel)));
    g.height = std::max(1, static_cast<int>(std::ceil(cam.height * g.cells_per_pixel)));
    g.nearest_z.assign(static_cast<size_t>(g.width) * static_cast<size_t>(g.height),
                       std::numeric_limits<float>::infinity());
    const Eigen::Matrix3f r = photo.cam_from_world.rotation.toRotationMatrix().cast<float>();
    const Eigen::Vector3f t = photo.cam_from_world.translation.cast<float>();
    const float fx = static_cast<float>(cam.fx()), fy = static_cast<float>(cam.fy());
    const float cx = static_cast<float>(cam.cx()), cy = static_cast<float>(cam.cy());
    for (const Eigen::Vector3f& x : positions_) {
      const Eigen::Vector3f q = r * x + t;
      if (!(q.z() > 0)) continue;
      const float u = fx * q.x() / q.z() + cx, v = fy * q.y() / q.z() + cy;
      if (!(u >= 0 && u < cam.width && v >= 0 && v < cam.height)) continue;
      float& z = g.nearest_z[g.Cell(u, v)];
      z = std::min(z, q.z());
    }
    grids_.push_back(std::move(g));
  }
}

void PhotoCandidates::Reset() {
  has_previous_ = false;
  std::fill(selected_.begin(), selected_.end(), 0);
}

// The allowed photos, one row each (nearest the view first), one column per quantity: Eigen
// arrays, so that the per-point work runs on SIMD packets.
struct PhotoCandidates::Rows {
  static constexpr int kRotation = 0;     // 9 columns, row-major R of cam_from_world
  static constexpr int kTranslation = 9;  // 3
  static constexpr int kFocal = 12;       // fx, fy
  static constexpr int kPrincipal = 14;   // cx, cy
  static constexpr int kSize = 16;        // width, height in pixels
  static constexpr int kCentre = 18;      // 3, world
  static constexpr int kColumns = 21;
  Eigen::ArrayXXf columns;
  std::vector<int> photo;                  // row -> scene photo index
  std::vector<const OcclusionGrid*> grid;  // row -> its occlusion grid

  int count() const { return static_cast<int>(photo.size()); }
  auto col(int c) const { return columns.col(c); }
};

// Each visible sample point's votes: entries [begin[v], begin[v + 1]) of (row, vote).
struct PhotoCandidates::Votes {
  std::vector<int> begin = {0};
  std::vector<int> row;
  std::vector<float> value;
  Eigen::ArrayXf seen;  // per row: visible points in front of it, inside it, facing it

  int points() const { return static_cast<int>(begin.size()) - 1; }
};

PhotoCandidates::Rows PhotoCandidates::GatherRows(const std::vector<int>& allowed,
                                                  const Eigen::Vector3d& centre,
                                                  const Eigen::Vector3d& direction) const {
  // Nearest the view first (Scene::NearestPhoto's measure): each point's best photos then come
  // early, and the ranking in CollectVotes rarely reorders.
  const int count = static_cast<int>(allowed.size());
  const double inv_scale = 1.0 / std::max(scene_.scene_scale, 1e-12);
  std::vector<double> nearness(static_cast<size_t>(count));
  for (int a = 0; a < count; ++a) {
    const int k = allowed[static_cast<size_t>(a)];
    HDRIBR_CHECK(k >= 0 && k < static_cast<int>(scene_.photos.size()));
    const Photo& photo = scene_.photos[static_cast<size_t>(k)];
    nearness[static_cast<size_t>(a)] =
        (photo.Center() - centre).norm() * inv_scale + (1.0 - direction.dot(photo.ViewDirection()));
  }
  std::vector<int> order(static_cast<size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) {
    return nearness[static_cast<size_t>(i)] < nearness[static_cast<size_t>(j)];
  });
  Rows rows;
  rows.columns.resize(count, Rows::kColumns);
  for (int r = 0; r < count; ++r) {
    const int k = allowed[static_cast<size_t>(order[static_cast<size_t>(r)])];
    rows.photo.push_back(k);
    rows.grid.push_back(&grids_[static_cast<size_t>(k)]);
    const Photo& photo = scene_.photos[static_cast<size_t>(k)];
    const Camera& cam = scene_.CameraOf(photo);
    const Eigen::Matrix3d rot = photo.cam_from_world.rotation.toRotationMatrix();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        rows.columns(r, Rows::kRotation + 3 * i + j) = static_cast<float>(rot(i, j));
      }
      rows.columns(r, Rows::kTranslation + i) =
          static_cast<float>(photo.cam_from_world.translation(i));
      rows.columns(r, Rows::kCentre + i) = static_cast<float>(photo.Center()(i));
    }
    rows.columns(r, Rows::kFocal) = static_cast<float>(cam.fx());
    rows.columns(r, Rows::kFocal + 1) = static_cast<float>(cam.fy());
    rows.columns(r, Rows::kPrincipal) = static_cast<float>(cam.cx());
    rows.columns(r, Rows::kPrincipal + 1) = static_cast<float>(cam.cy());
    rows.columns(r, Rows::kSize) = static_cast<float>(cam.width);
    rows.columns(r, Rows::kSize + 1) = static_cast<float>(cam.height);
  }
  return rows;
}

// Visible sample points (in front of the view, inside its image, facing it), each ranking the
// photos that see it (in front, inside the photo, facing it, not hidden in its occlusion grid)
// by the Unstructured Lumigraph penalty of the blend: angle(V, V_k) + kUlrDistanceWeight
// | |C - P| - |C_k - P| | / scene_scale. Each point votes for its 2 x `demand` best photos (the
// second half stands in where a better photo is occluded at a finer scale than the grid's) with the
// Unstructured Lumigraph's weight 1 - p / t, t = the next penalty (pi / 2 when no other photo sees
// the point), and 1 for the best when every weight is 0, as in the blend: votes vary continuously
// with the view.
PhotoCandidates::Votes PhotoCandidates::CollectVotes(const Camera& camera,
                                                     const Rigid3d& cam_from_world,
                                                     const Rows& rows, int demand) const {
  const int count = rows.count();
  const int voters = 2 * demand;
  const int ranked = std::min(voters + 1, std::max(count, 1));
  const Eigen::Matrix3f view_r = cam_from_world.rotation.toRotationMatrix().cast<float>();
  const Eigen::Vector3f view_t = cam_from_world.translation.cast<float>();
  const Eigen::Vector3f view_c = cam_from_world.Inverse().translation.cast<float>();
  const float vfx = static_cast<float>(camera.fx()), vfy = static_cast<float>(camera.fy());
  const float vcx = static_cast<float>(camera.cx()), vcy = static_cast<float>(camera.cy());
  const float vw = static_cast<float>(camera.width), vh = static_cast<float>(camera.height);
  const float inv_scale = static_cast<float>(1.0 / std::max(scene_.scene_scale, 1e-12));
  const float tolerance = static_cast<float>(kOcclusionTolerance);
  const bool normals = !normals_.empty();
  // Without normals every photo faces every point: n = 0 passes n . V_k > -1.
  const float facing_min = normals ? 0.0f : -1.0f;
  Eigen::ArrayXf qz(count), pu(count), pv(count), dx(count), dy(count), dz(count), dist_k(count),
      cos_k(count), seen_by(count), penalty(count);
  std::vector<float> best_p(static_cast<size_t>(ranked));
  std::vector<int> best_r(static_cast<size_t>(ranked));
  Votes votes;
  votes.seen = Eigen::ArrayXf::Zero(count);
  for (size_t s = 0; s < positions_.size() && votes.points() < kTargetVisible; ++s) {
    const Eigen::Vector3f& x = positions_[s];
    const Eigen::Vector3f pc = view_r * x + view_t;
    if (!(pc.z() > 0)) continue;
    const float u = vfx * pc.x() / pc.z() + vcx, v = vfy * pc.y() / pc.z() + vcy;
    if (!(u >= 0 && u < vw && v >= 0 && v < vh)) continue;
    const Eigen::Vector3f to_view = view_c - x;
    const Eigen::Vector3f n = normals ? normals_[s] : Eigen::Vector3f::Zero();
    if (normals && n.dot(to_view) <= 0) continue;  // its back faces the view
    const float dist_c = to_view.norm();
    const Eigen::Vector3f vdir = to_view / dist_c;
    const float px = x.x(), py = x.y(), pz = x.z();
    const auto r = [&](int i, int j) { return rows.col(Rows::kRotation + 3 * i + j); };
    const auto qx = r(0, 0) * px + r(0, 1) * py + r(0, 2) * pz + rows.col(Rows::kTranslation);
    const auto qy = r(1, 0) * px + r(1, 1) * py + r(1, 2) * pz + rows.col(Rows::kTranslation + 1);
    qz = r(2, 0) * px + r(2, 1) * py + r(2, 2) * pz + rows.col(Rows::kTranslation + 2);
    pu = rows.col(Rows::kFocal) * qx / qz.max(1e-30f) + rows.col(Rows::kPrincipal);
    pv = rows.col(Rows::kFocal + 1) * qy / qz.max(1e-30f) + rows.col(Rows::kPrincipal + 1);
    dx = rows.col(Rows::kCentre) - px;
    dy = rows.col(Rows::kCentre + 1) - py;
    dz = rows.col(Rows::kCentre + 2) - pz;
    dist_k = (dx.square() + dy.square() + dz.square()).sqrt();
    cos_k =
        ((vdir.x() * dx + vdir.y() * dy + vdir.z() * dz) / dist_k.max(1e-30f)).max(0.0f).min(1.0f);
    // Seen (1) or not (0): in front, inside the image, facing the photo. Arithmetic masks keep
    // the loop on SIMD packets (Eigen does not vectorise select).
    seen_by = qz.min(pu)
                  .min(rows.col(Rows::kSize) - pu)
                  .min(pv)
                  .min(rows.col(Rows::kSize + 1) - pv)
                  .min(n.x() * dx + n.y() * dy + n.z() * dz - facing_min)
                  .max(0.0f)
                  .min(1e-30f) *
              1e30f;
    // acos on [0, 1] (Abramowitz & Stegun 4.4.45, error below 7e-5 rad), plus weighted delta_k.
    penalty = (1.0f - cos_k).sqrt() *
                  (1.5707288f + cos_k * (-0.2121144f + cos_k * (0.0742610f - 0.0187293f * cos_k))) +
              (dist_c - dist_k).abs() * (kUlrDistanceWeight * inv_scale) +
              (1.0f - seen_by) * kNotSeen;
    votes.seen += seen_by;
    // The `ranked` smallest penalties of the photos that see the point and do not hide it,
    // sorted by insertion (ties: the earlier row first).
    int filled = 0;
    for (int a = 0; a < count; ++a) {
      const float p = penalty(a);
      if (p >= 0.5f * kNotSeen) continue;
      if (filled == ranked && p >= best_p[static_cast<size_t>(ranked - 1)]) continue;
      // Hidden? (Tested only for photos that would rank: the grids' lookups are memory-bound.)
      const OcclusionGrid& g = *rows.grid[static_cast<size_t>(a)];
      if (qz(a) > g.nearest_z[g.Cell(pu(a), pv(a))] * (1.0f + tolerance)) continue;
      int j = std::min(filled, ranked - 1);
      for (; j > 0 && best_p[static_cast<size_t>(j - 1)] > p; --j) {
        best_p[static_cast<size_t>(j)] = best_p[static_cast<size_t>(j - 1)];
        best_r[static_cast<size_t>(j)] = best_r[static_cast<size_t>(j - 1)];
      }
      best_p[static_cast<size_t>(j)] = p;
      best_r[static_cast<size_t>(j)] = a;
      filled = std::min(filled + 1, ranked);
    }
    const float t = filled > voters ? best_p[static_cast<size_t>(voters)] : kHalfPi;
    for (int j = 0; j < std::min(filled, voters); ++j) {
      float vote = 1.0f - best_p[static_cast<size_t>(j)] / std::max(t, 1e-6f);
      if (j == 0 && vote <= 0) vote = 1.0f;  // every photo beyond the horizon: the best (blend)
      if (vote <= 0) continue;
      votes.row.push_back(best_r[static_cast<size_t>(j)]);
      votes.value.push_back(vote);
    }
    votes.begin.push_back(static_cast<int>(votes.row.size()));
  }
  return votes;
}

// Greedy coverage: each round takes the photo of largest gain = its votes from the points that
// still lack `demand` picked photos, plus kSaturatedVote of its votes from the others, plus
// kSeenScore per visible point it sees. Without the saturation the photos nearest the view,
// each seeing most of it, would fill the cap while parts of the view that only other photos
// see went uncovered. Photos of the previous selection gain more (hysteresis).
std::vector<int> PhotoCandidates::PickGreedy(const Rows& rows, const Votes& votes, int max_count,
                                             int demand) {
  const int count = rows.count(), points = votes.points();
  const auto at = [](const auto& v, int i) -> decltype(auto) { return v[static_cast<size_t>(i)]; };
  // The votes by row: (point, vote) of row r in [row_begin[r], row_begin[r + 1]).
  std::vector<int> row_begin(static_cast<size_t>(count) + 1, 0), row_point(votes.row.size());
  std::vector<float> row_vote(votes.row.size());
  for (int r : votes.row) ++row_begin[static_cast<size_t>(r) + 1];
  for (int r = 0; r < count; ++r) row_begin[static_cast<size_t>(r) + 1] += at(row_begin, r);
  std::vector<int> fill(row_begin.begin(), row_begin.end() - 1);
  for (int v = 0; v < points; ++v) {
    for (int e = at(votes.begin, v); e < at(votes.begin, v + 1); ++e) {
      const int slot = fill[static_cast<size_t>(at(votes.row, e))]++;
      row_point[static_cast<size_t>(slot)] = v;
      row_vote[static_cast<size_t>(slot)] = at(votes.value, e);
    }
  }
  std::vector<double> gain(static_cast<size_t>(count));
  double first_gain = 0;
  for (int r = 0; r < count; ++r) {
    double g = kSeenScore * votes.seen(r);
    for (int e = at(row_begin, r); e < at(row_begin, r + 1); ++e) g += at(row_vote, e);
    gain[static_cast<size_t>(r)] = g;
    first_gain = std::max(first_gain, g);
    scores_[static_cast<size_t>(at(rows.photo, r))] = g / points;
  }
  std::vector<int> covered(static_cast<size_t>(points), 0), picked;
  std::vector<char> chosen(static_cast<size_t>(count), 0);
  while (static_cast<int>(picked.size()) < max_count) {
    int best = -1;
    double best_gain = 0;
    for (int r = 0; r < count; ++r) {
      const double g = at(gain, r);
      if (at(chosen, r) || g <= 0) continue;
      const double held = at(selected_, at(rows.photo, r))
                              ? g * (1.0 + kHysteresisGain) + kHysteresisFloor * first_gain
                              : g;
      if (held > best_gain) {  // ties: the earlier row, nearer the view
        best = r;
        best_gain = held;
      }
    }
    if (best < 0) break;  // no other photo sees a visible point
    chosen[static_cast<size_t>(best)] = 1;
    picked.push_back(at(rows.photo, best));
    // Points that now have `demand` picked photos: their other votes drop to kSaturatedVote.
    for (int e = at(row_begin, best); e < at(row_begin, best + 1); ++e) {
      const int v = at(row_point, e);
      if (++covered[static_cast<size_t>(v)] != demand) continue;
      for (int f = at(votes.begin, v); f < at(votes.begin, v + 1); ++f) {
        gain[static_cast<size_t>(at(votes.row, f))] -= (1.0 - kSaturatedVote) * at(votes.value, f);
      }
    }
  }
  return picked;
}

const std::vector<int>& PhotoCandidates::Select(const Camera& camera, const Rigid3d& cam_from_world,
                                                const std::vector<int>& allowed, int max_count,
                                                int per_point) {
  HDRIBR_CHECK(max_count > 0);
  std::fill(scores_.begin(), scores_.end(), 0.0);
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const Eigen::Vector3d centre = world_from_cam.translation;
  const Eigen::Vector3d direction = world_from_cam.rotation * Eigen::Vector3d::UnitZ();
  const bool continuous =
      has_previous_ &&
      (centre - previous_centre_).norm() <= kContinuityDistance * scene_.scene_scale &&
      direction.dot(previous_direction_) >= std::cos(kContinuityDegrees * M_PI / 180.0);
  if (!continuous) std::fill(selected_.begin(), selected_.end(), 0);

  const int demand = std::max(per_point, 1);
  const Rows rows = GatherRows(allowed, centre, direction);
  const Votes votes = CollectVotes(camera, cam_from_world, rows, demand);
  visible_count_ = votes.points();
  result_.clear();
  if (visible_count_ == 0) {  // nothing to choose by: every allowed photo
    result_ = allowed;
    Reset();
    return result_;
  }
  const std::vector<int> picked = PickGreedy(rows, votes, max_count, demand);
  for (int k : allowed) selected_[static_cast<size_t>(k)] = 0;
  for (int k : picked) selected_[static_cast<size_t>(k)] = 1;
  for (int k : allowed) {
    if (selected_[static_cast<size_t>(k)]) result_.push_back(k);
  }
  has_previous_ = true;
  previous_centre_ = centre;
  previous_direction_ = direction;
  return result_;
}

}  // namespace hdribr
