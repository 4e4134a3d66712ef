#include "core/photo_candidates.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace hdribr {
namespace {

const Eigen::Vector3d kUp(0, 1, 0);

// Two squares of points facing -z (normals toward the cameras): A, 2 x 2 around the origin,
// and B, the same around x = 10.
PointCloud TwoSquares(bool normals) {
  PointCloud cloud;
  for (double cx : {0.0, 10.0}) {
    for (int i = 0; i < 100; ++i) {
      for (int j = 0; j < 100; ++j) {
        cloud.positions.emplace_back(static_cast<float>(cx - 1 + i * 0.02),
                                     static_cast<float>(-1 + j * 0.02), 0.0f);
        if (normals) cloud.normals.emplace_back(0.0f, 0.0f, -1.0f);
      }
    }
  }
  return cloud;
}

// 64 x 48 pixels, 60 degrees wide.
Camera SmallCamera() {
  const double f = 32.0 / std::tan(M_PI / 6.0);
  return Camera::Pinhole(1, 64, 48, f, f, 32, 24);
}

Photo PhotoAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  Photo p;
  p.camera_id = 1;
  p.cam_from_world = LookAt(eye, target, kUp);
  return p;
}

// A view of square A from 3 units out on -z; a point on a cone around that direction.
Eigen::Vector3d OnCone(double angle_deg, double around_deg, double distance = 3.0) {
  const double a = angle_deg * M_PI / 180.0, b = around_deg * M_PI / 180.0;
  return distance *
         Eigen::Vector3d(std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), -std::cos(a));
}

Scene MakeScene(const std::vector<Photo>& photos, bool normals = true) {
  Scene scene;
  scene.cameras[1] = SmallCamera();
  scene.photos = photos;
  scene.points = TwoSquares(normals);
  scene.UpdateDerived();
  return scene;
}

std::vector<int> All(const Scene& scene) {
  std::vector<int> all(scene.photos.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  return all;
}

const Rigid3d kViewA = LookAt(Eigen::Vector3d(0, 0, -3), Eigen::Vector3d::Zero(), kUp);

TEST(PhotoCandidates, PhotosThatCannotSeeTheViewAreNeverCandidates) {
  for (bool normals : {true, false}) {
    const Scene scene = MakeScene(
        {
            PhotoAt({0.3, 0.2, -3}, {0, 0, 0}),  // 0: sees A like the view
            PhotoAt({0, 0, -3.5}, {0, 0, -10}),  // 1: behind the view, looking away
            PhotoAt({10, 0, -3}, {10, 0, 0}),    // 2: sees only B, outside the view
            PhotoAt({0, 0, 3}, {0, 0, 0}),       // 3: behind A, sees its back
            PhotoAt({-2, 0, -2.5}, {0, 0, 0}),   // 4: sees A obliquely
            PhotoAt({0, 0, -0.5}, {0, 0, -3}),   // 5: between A and the view, facing it
            PhotoAt({0, 0, -3}, {-30, 0, -3}),   // 6: the view's centre, looking aside
        },
        normals);
    PhotoCandidates candidates(scene);
    const std::vector<int> selected = candidates.Select(SmallCamera(), kViewA, All(scene), 32, 5);
    EXPECT_GT(candidates.visible_samples(), 100);
    // Photo 3 sees A's back: out with normals; without them nothing tells (nothing hides A).
    const std::vector<int> expected = normals ? std::vector<int>{0, 4} : std::vector<int>{0, 3, 4};
    EXPECT_EQ(selected, expected) << "normals " << normals;
    for (int k : {1, 2, 5, 6}) EXPECT_EQ(candidates.score(k), 0.0) << k;
    // Ranked by one photo per point: the view's own direction scores higher.
    candidates.Select(SmallCamera(), kViewA, All(scene), 32, 1);
    EXPECT_GT(candidates.score(0), 1.5 * candidates.score(4));
  }
}

// Two photos mirrored about the view's axis; a small square of points just in front of one,
// outside the view, hides most of square A from it: that photo loses most of its votes.
TEST(PhotoCandidates, HiddenPhotosLoseTheirVotes) {
  const Eigen::Vector3d left = OnCone(25, 180), right = OnCone(25, 0);
  Scene scene = MakeScene({PhotoAt(left, {0, 0, 0}), PhotoAt(right, {0, 0, 0})});
  PhotoCandidates open(scene);
  open.Select(SmallCamera(), kViewA, All(scene), 2, 1);
  const double left_open = open.score(0), right_open = open.score(1);
  const Eigen::Vector3d blocker = right + 0.15 * (Eigen::Vector3d::Zero() - right);
  for (int i = 0; i < 30; ++i) {
    for (int j = 0; j < 30; ++j) {
      scene.points.positions.emplace_back(static_cast<float>(blocker.x() - 0.15 + 0.01 * i),
                                          static_cast<float>(blocker.y() - 0.15 + 0.01 * j),
                                          static_cast<float>(blocker.z()));
      scene.points.normals.emplace_back(0.0f, 0.0f, -1.0f);
    }
  }
  scene.UpdateDerived();
  PhotoCandidates hidden(scene);
  hidden.Select(SmallCamera(), kViewA, All(scene), 2, 1);
  std::printf("scores without the blocker %.3f / %.3f, with it %.3f / %.3f\n", left_open,
              right_open, hidden.score(0), hidden.score(1));
  EXPECT_NEAR(left_open, right_open, 0.1 * left_open);
  EXPECT_LT(hidden.score(1), 0.4 * hidden.score(0));  // the blocker hides most of A
}

// A ring of 36 photos on cones of 10 to 60 degrees around the view direction.
Scene RingScene() {
  std::vector<Photo> photos;
  for (int i = 0; i < 36; ++i) {
    photos.push_back(PhotoAt(OnCone(10.0 + 10.0 * (i % 6), 10.0 * i), Eigen::Vector3d::Zero()));
  }
  return MakeScene(photos);
}

TEST(PhotoCandidates, CapKeepsTheBestAndOnlyAllowedPhotos) {
  const Scene scene = RingScene();
  PhotoCandidates candidates(scene);
  const std::vector<int> all = All(scene);
  for (int cap : {1, 4, 8, 16}) {
    candidates.Reset();
    const std::vector<int> selected = candidates.Select(SmallCamera(), kViewA, all, cap, 5);
    ASSERT_EQ(static_cast<int>(selected.size()), cap);
    EXPECT_TRUE(std::is_sorted(selected.begin(), selected.end()));  // the order of `allowed`
    // Every selected photo scores at least as high as every photo left out.
    double worst_in = 1e9, best_out = 0;
    for (int k : all) {
      const bool in = std::find(selected.begin(), selected.end(), k) != selected.end();
      (in ? worst_in : best_out) =
          in ? std::min(worst_in, candidates.score(k)) : std::max(best_out, candidates.score(k));
    }
    EXPECT_GE(worst_in, best_out) << "cap " << cap;
    // The photos nearest the view's direction (10 degrees) are the first chosen.
    if (cap == 4) {
      for (int k : selected) EXPECT_EQ(k % 6, 0) << k;
    }
  }
  // Only allowed photos, in their order.
  const std::vector<int> allowed = {35, 12, 7, 0, 1};
  candidates.Reset();
  const std::vector<int> selected = candidates.Select(SmallCamera(), kViewA, allowed, 3, 1);
  // 12 and 0 at 10 degrees, then 7 or 1 at 20 (in the order of `allowed`); 35, at 60, out.
  EXPECT_TRUE(selected == (std::vector<int>{12, 7, 0}) || selected == (std::vector<int>{12, 0, 1}))
      << ::testing::PrintToString(selected);
  EXPECT_EQ(candidates.score(6), 0.0);  // not allowed
}

// Twelve photos close to square A, all seeing its left part and none its right edge, and two
// from far to the right seeing the right part: the cap takes a far photo, whose score is below
// the cap's, before the twelfth redundant close one.
TEST(PhotoCandidates, CoverageBeforeRedundancy) {
  std::vector<Photo> photos;
  const Eigen::Vector3d left(-0.3, 0, 0);
  for (int i = 0; i < 12; ++i) {
    photos.push_back(PhotoAt(left + OnCone(3.0 + 2.0 * (i % 3), 30.0 * i, 1.8), left));
  }
  photos.push_back(PhotoAt({3.5, 0.3, -1.5}, {0.8, 0, 0}));  // 12, 13: far, on the right
  photos.push_back(PhotoAt({3.5, -0.3, -1.5}, {0.8, 0, 0}));
  const Scene scene = MakeScene(photos);
  PhotoCandidates candidates(scene);
  const std::vector<int> selected = candidates.Select(SmallCamera(), kViewA, All(scene), 8, 5);
  ASSERT_EQ(selected.size(), 8u);
  std::vector<double> scores;
  for (int k = 0; k < 14; ++k) scores.push_back(candidates.score(k));
  std::sort(scores.rbegin(), scores.rend());
  int far = -1;
  for (int k : selected) far = k >= 12 ? k : far;
  ASSERT_GE(far, 0) << ::testing::PrintToString(selected);
  std::printf("far photo %d: score %.4f, 8th best score %.4f\n", far, candidates.score(far),
              scores[7]);
  EXPECT_LT(candidates.score(far), scores[7]);  // not among the 8 best scores
}

TEST(PhotoCandidates, Deterministic) {
  const Scene scene = RingScene();
  PhotoCandidates a(scene), b(scene);
  const std::vector<int> first = a.Select(SmallCamera(), kViewA, All(scene), 8, 5);
  EXPECT_EQ(b.Select(SmallCamera(), kViewA, All(scene), 8, 5), first);
  a.Reset();
  EXPECT_EQ(a.Select(SmallCamera(), kViewA, All(scene), 8, 5), first);
  EXPECT_EQ(a.sample_size(), 20000);  // the whole cloud: below kMaxSamples
}

TEST(PhotoCandidates, TinyMovesKeepTheSet) {
  const Scene scene = RingScene();
  PhotoCandidates candidates(scene);
  const std::vector<int> first = candidates.Select(SmallCamera(), kViewA, All(scene), 8, 5);
  for (int step = 1; step <= 10; ++step) {
    const Eigen::Vector3d eye(0.002 * step, -0.001 * step, -3 + 0.001 * step);
    const Rigid3d view = LookAt(eye, Eigen::Vector3d(0.001 * step, 0, 0), kUp);
    EXPECT_EQ(candidates.Select(SmallCamera(), view, All(scene), 8, 5), first) << step;
  }
}

// Two photos at +-20 degrees and a view sweeping from one to the other, cap 1: the selection
// switches once, later than a fresh selection would (hysteresis), and a jump selects afresh.
TEST(PhotoCandidates, HysteresisSwitchesOnceAndLate) {
  const Scene scene =
      MakeScene({PhotoAt(OnCone(20, 180), {0, 0, 0}), PhotoAt(OnCone(20, 0), {0, 0, 0})});
  PhotoCandidates moving(scene);
  int switches = 0, moving_switch = -1, fresh_switch = -1;
  int last = -1;
  for (int i = 0; i <= 80; ++i) {
    const double angle = -20.0 + 0.5 * i;  // small steps: within the continuity limits
    const Rigid3d view =
        LookAt(OnCone(std::abs(angle), angle < 0 ? 180 : 0), Eigen::Vector3d::Zero(), kUp);
    const std::vector<int> m = moving.Select(SmallCamera(), view, All(scene), 1, 1);
    PhotoCandidates fresh(scene);
    const std::vector<int> f = fresh.Select(SmallCamera(), view, All(scene), 1, 1);
    ASSERT_EQ(m.size(), 1u);
    ASSERT_EQ(f.size(), 1u);
    if (last >= 0 && m[0] != last) {
      ++switches;
      moving_switch = i;
    }
    if (fresh_switch < 0 && f[0] == 1) fresh_switch = i;
    last = m[0];
  }
  EXPECT_EQ(switches, 1);
  EXPECT_EQ(last, 1);
  ASSERT_GE(fresh_switch, 0);
  EXPECT_GT(moving_switch, fresh_switch);
  std::printf("fresh selection switches at step %d, with hysteresis at %d\n", fresh_switch,
              moving_switch);
  // A jump back to the first photo's side selects afresh.
  const Rigid3d back = LookAt(OnCone(15, 180), Eigen::Vector3d::Zero(), kUp);
  EXPECT_EQ(moving.Select(SmallCamera(), back, All(scene), 1, 1), std::vector<int>{0});
}

TEST(PhotoCandidates, NoVisibleSampleKeepsEveryAllowedPhoto) {
  const Scene scene = RingScene();
  PhotoCandidates candidates(scene);
  const Rigid3d away = LookAt(Eigen::Vector3d(0, 0, -3), Eigen::Vector3d(0, 0, -10), kUp);
  const std::vector<int> allowed = {3, 1, 2};
  EXPECT_EQ(candidates.Select(SmallCamera(), away, allowed, 2, 5), allowed);
  EXPECT_EQ(candidates.visible_samples(), 0);
}

}  // namespace
}  // namespace hdribr
