#include "frontend/point_attributes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace hdribr {
namespace {

// A 40x40 grid on the plane z = 1 with spacing s, seen from a camera at z = 5.
PointCloud Grid(float s) {
  PointCloud c;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) c.positions.push_back({i * s, j * s, 1.f});
  return c;
}

TEST(PointAttributes, NormalsFaceTheCameras) {
  PointCloud c = Grid(0.01f);
  std::vector<Eigen::Vector3f> view(c.size(), Eigen::Vector3f(0.2f, 0.f, 1.f).normalized());
  EstimateNormals(c, view, {});
  ASSERT_EQ(c.normals.size(), c.size());
  for (const auto& n : c.normals) EXPECT_GT(n.z(), 0.999f);
  // Seen from below: all flipped.
  std::vector<Eigen::Vector3f> below(c.size(), Eigen::Vector3f(0.f, 0.f, -1.f));
  EstimateNormals(c, below, {});
  for (const auto& n : c.normals) EXPECT_LT(n.z(), -0.999f);
}

TEST(PointAttributes, NormalsAlreadyPresentAreKeptAndOriented) {
  PointCloud c = Grid(0.01f);
  const Eigen::Vector3f slanted = Eigen::Vector3f(0.f, 0.6f, -0.8f);
  c.normals.assign(c.size(), slanted);
  std::vector<Eigen::Vector3f> view(c.size(), Eigen::Vector3f(0.f, 0.f, 1.f));
  EstimateNormals(c, view, {});
  ASSERT_EQ(c.normals.size(), c.size());
  for (const auto& n : c.normals) EXPECT_TRUE(n.isApprox(-slanted, 1e-5f)) << n.transpose();
}

TEST(PointAttributes, ViewDirsFromCameraCentres) {
  PointCloud c = Grid(0.01f);
  const auto dirs = ViewDirsFromCameras(c, {Eigen::Vector3d(0.2, 0.2, 5.0)});
  for (const auto& d : dirs) EXPECT_GT(d.z(), 0.9f);
}

TEST(PointAttributes, RadiiMakeNeighbouringSplatsOverlap) {
  const float s = 0.02f;
  PointCloud c = Grid(s);
  EstimateRadii(c, {});
  ASSERT_EQ(c.radii.size(), c.size());
  for (float r : c.radii) {
    EXPECT_GT(r, 0.5f * s);  // discs of neighbours at distance s overlap
    EXPECT_LT(r, 2.0f * s);  // but not absurdly large
  }
}

TEST(PointAttributes, RemovesIsolatedOutliersKeepingAttributesInStep) {
  PointCloud c = Grid(0.01f);
  c.colors.assign(c.size(), {10, 20, 30});
  c.positions.push_back({5.f, 5.f, 5.f});  // far away
  c.colors.push_back({255, 0, 0});
  std::vector<Eigen::Vector3f> view(c.size(), Eigen::Vector3f::UnitZ());
  view.back() = -Eigen::Vector3f::UnitZ();
  const size_t removed = RemoveOutliers(c, view, {}, {});
  EXPECT_GE(removed, 1u);
  EXPECT_LT(removed, 20u);
  ASSERT_EQ(c.colors.size(), c.size());
  ASSERT_EQ(view.size(), c.size());
  for (size_t i = 0; i < c.size(); ++i) {
    EXPECT_LT(c.positions[i].norm(), 2.f);
    EXPECT_EQ(c.colors[i][0], 10);
    EXPECT_GT(view[i].z(), 0.f);
  }
}

// A depth map samples a far surface more sparsely: a 100x100 grid at distance 1 from the
// camera with spacing 0.002 and a 20x20 grid at distance 8 with spacing 0.016 (the same angular
// spacing; a far facade is a small part of a cloud). By plain distances the far grid goes; with
// the distance to the camera it stays (but for its rim, whose neighbours lie on one side: the
// exact grids' spread is tiny), and a point off both surfaces still goes.
TEST(PointAttributes, OutlierRemovalKeepsFarSurfacesSampledSparsely) {
  PointCloud c;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j) c.positions.push_back({i * 0.002f, j * 0.002f, 1.f});
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) c.positions.push_back({i * 0.016f - 0.06f, j * 0.016f, 8.f});
  const std::vector<Eigen::Vector3d> centers = {Eigen::Vector3d(0.05, 0.05, 0.0)};
  const auto far_points = [](const PointCloud& cloud) {
    return std::count_if(cloud.positions.begin(), cloud.positions.end(),
                         [](const Eigen::Vector3f& p) { return p.z() == 8.f; });
  };
  std::vector<Eigen::Vector3f> none;

  PointCloud plain = c;
  EXPECT_GE(RemoveOutliers(plain, none, {}, {}), 400u);
  EXPECT_EQ(far_points(plain), 0);

  PointCloud scaled = c;
  const size_t removed = RemoveOutliers(scaled, none, centers, {});
  EXPECT_GE(far_points(scaled), 18 * 18);
  EXPECT_LT(removed, 200u);

  PointCloud stray = c;
  stray.positions.push_back({0.5f, 0.5f, 4.f});
  RemoveOutliers(stray, none, centers, {});
  EXPECT_GE(far_points(stray), 18 * 18);
  for (const auto& p : stray.positions) EXPECT_NE(p.z(), 4.f);
}

}  // namespace
}  // namespace hdribr
