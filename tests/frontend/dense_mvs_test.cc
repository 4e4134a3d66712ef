#include "frontend/dense_mvs.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "test_util.h"

namespace hdribr {
namespace {

// Slanted textured plane z = 4 + 0.3 x, seen by four cameras looking down +z.
double PlaneZ(double x) { return 4.0 + 0.3 * x; }

struct Fixture {
  ColmapModel model;
  std::filesystem::path images;
};

Fixture MakeScene() {
  Fixture f;
  f.images = test::TempDir("dense_mvs");
  const Camera cam = Camera::Pinhole(1, 160, 120, 150, 150, 80, 60);
  f.model.cameras[1] = cam;
  // Texture over [-3, 3]^2: smooth random pattern.
  cv::Mat small(60, 60, CV_32F), texture;
  cv::RNG rng(7);
  rng.fill(small, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::resize(small, texture, cv::Size(600, 600), 0, 0, cv::INTER_CUBIC);
  const std::vector<Eigen::Vector3d> centers = {{-0.3, 0, 0}, {0, 0, 0}, {0.3, 0, 0}, {0, 0.3, 0}};
  const std::vector<double> gains = {1.0, 0.5, 0.8, 1.0};  // different exposures
  for (int i = 0; i < 4; ++i) {
    ColmapImage im;
    im.id = i + 1;
    im.camera_id = 1;
    im.name = "v" + std::to_string(i) + ".png";
    im.cam_from_world = Rigid3d(Eigen::Quaterniond::Identity(), -centers[i]);
    cv::Mat img(cam.height, cam.width, CV_8UC3);
    for (int v = 0; v < cam.height; ++v) {
      for (int u = 0; u < cam.width; ++u) {
        const Eigen::Vector3d d = cam.CamFromPixel({u + 0.5, v + 0.5});
        const Eigen::Vector3d& c = centers[i];
        const double t = (4.0 + 0.3 * c.x() - c.z()) / (d.z() - 0.3 * d.x());
        const Eigen::Vector3d p = c + t * d;
        const float tx = static_cast<float>((p.x() + 3) / 6 * 599);
        const float ty = static_cast<float>((p.y() + 3) / 6 * 599);
        cv::Mat px;
        cv::getRectSubPix(texture, cv::Size(1, 1), cv::Point2f(tx, ty), px);
        const double val =
            std::clamp(255.0 * gains[i] * (0.1 + 0.8 * px.at<float>(0, 0)), 0.0, 255.0);
        img.at<cv::Vec3b>(v, u) =
            cv::Vec3b(cv::saturate_cast<uchar>(val), cv::saturate_cast<uchar>(val * 0.9),
                      cv::saturate_cast<uchar>(val * 0.8));
      }
    }
    cv::imwrite((f.images / im.name).string(), img);
    f.model.images[im.id] = im;
  }
  // Sparse points on the plane, seen by all photos.
  for (int k = 0; k < 60; ++k) {
    ColmapPoint3D pt;
    pt.id = k + 1;
    const double x = rng.uniform(-0.8, 0.8), y = rng.uniform(-0.6, 0.6);
    pt.xyz = {x, y, PlaneZ(x)};
    for (auto& [id, im] : f.model.images) {
      ColmapPoint2D p2;
      p2.xy = cam.PixelFromCam(im.cam_from_world * pt.xyz);
      p2.point3d_id = pt.id;
      im.points2d.push_back(p2);
      pt.track.push_back({id, static_cast<int>(im.points2d.size()) - 1});
    }
    f.model.points3d[pt.id] = pt;
  }
  return f;
}

TEST(DenseMvs, NeighboursShareSparsePoints) {
  const Fixture f = MakeScene();
  const auto nb = SelectNeighbors(f.model, 2);
  ASSERT_EQ(nb.size(), 4u);
  for (const auto& [id, list] : nb) {
    EXPECT_EQ(list.size(), 2u);
    for (int n : list) EXPECT_NE(n, id);
  }
}

// Both CPU methods; PatchMatch also fuses its plane normals, facing the cameras.
TEST(DenseMvs, RecoversASlantedPlaneAcrossExposures) {
  const Fixture f = MakeScene();
  for (const DenseMethod method : {DenseMethod::kSweep, DenseMethod::kPatchMatch}) {
    SCOPED_TRACE(method == DenseMethod::kSweep ? "sweep" : "patch match");
    DenseOptions o;
    o.method = method;
    o.max_size = 160;
    o.num_neighbors = 3;
    o.num_depths = 64;
    o.min_consistent = 2;
    o.threads = 2;
    const DenseResult r = DensifyCpu(f.model, f.images, o);
    EXPECT_EQ(r.num_depth_maps, 4);
    EXPECT_EQ(r.depth_map_size, 160);
    ASSERT_EQ(r.view_dirs.size(), r.cloud.size());
    ASSERT_EQ(r.cloud.colors.size(), r.cloud.size());
    ASSERT_EQ(r.cloud.normals.size(), method == DenseMethod::kSweep ? 0u : r.cloud.size());
    // Each photo's 160 x 120 pixels see most of the plane, and its points merge those of the
    // others: about one point per pixel of one photo, not one per pixel of every photo.
    EXPECT_GT(r.cloud.size(), 160u * 120u / 2u);
    EXPECT_LT(r.cloud.size(), 2u * 160u * 120u);
    size_t accurate = 0, normal_ok = 0;
    const Eigen::Vector3f truth = Eigen::Vector3f(0.3f, 0.f, -1.f).normalized();
    for (size_t i = 0; i < r.cloud.size(); ++i) {
      const Eigen::Vector3f& p = r.cloud.positions[i];
      if (std::abs(p.z() - PlaneZ(p.x())) < 0.01 * 4.0) ++accurate;  // 1% of the distance
      EXPECT_LT(r.view_dirs[i].z(), -0.8f);  // toward the cameras (FOV 56 deg)
      if (r.cloud.HasNormals() && r.cloud.normals[i].dot(truth) > std::cos(10 * M_PI / 180)) {
        ++normal_ok;
      }
    }
    EXPECT_GT(double(accurate) / r.cloud.size(), 0.95) << accurate << " of " << r.cloud.size();
    if (r.cloud.HasNormals()) {
      EXPECT_GT(double(normal_ok) / r.cloud.size(), 0.95);
    }
  }
}

// Three depth maps of the plane z = 4 from cameras at x = -0.2, 0, 0.2; the third map holds a
// wrong depth over |x| < 0.5, |y| < 0.3, so that there only one other map agrees with the
// first. The first map's NCC is 0.95 left of x = 0, 0.5 elsewhere; the others' 0.5.
std::vector<DepthMap> PlaneMapsWithOneWrong() {
  const Camera cam = Camera::Pinhole(1, 40, 30, 40, 40, 20, 15);
  std::vector<DepthMap> maps(3);
  for (int i = 0; i < 3; ++i) {
    DepthMap& m = maps[i];
    m.image_id = i + 1;
    m.camera = cam;
    m.cam_from_world =
        Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.2 - 0.2 * i, 0, 0));
    m.depth = cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(4.0));
    m.score = cv::Mat(cam.height, cam.width, CV_32F, cv::Scalar(0.5));
    m.color = cv::Mat::zeros(cam.height, cam.width, CV_8UC3);
    for (int j = 0; j < 3; ++j) {
      if (j != i) m.neighbors.push_back(j + 1);
    }
    const Rigid3d world_from_cam = m.cam_from_world.Inverse();
    for (int y = 0; y < cam.height; ++y) {
      for (int x = 0; x < cam.width; ++x) {
        const Eigen::Vector3d p = world_from_cam * (cam.CamFromPixel({x + 0.5, y + 0.5}) * 4.0);
        if (i == 0 && p.x() < 0) m.score.at<float>(y, x) = 0.95f;
        if (i == 2 && std::abs(p.x()) < 0.5 && std::abs(p.y()) < 0.3) m.depth.at<float>(y, x) = 3.f;
      }
    }
  }
  return maps;
}

// Points fused inside the wrong map's region, left and right of x = 0 (margins of 0.05).
std::pair<int, int> PointsInRegion(const DenseResult& r) {
  int left = 0, right = 0;
  for (const Eigen::Vector3f& p : r.cloud.positions) {
    if (std::abs(p.y()) > 0.25 || std::abs(p.x()) > 0.45 || std::abs(p.x()) < 0.05) continue;
    EXPECT_NEAR(p.z(), 4.f, 1e-3f);
    ++(p.x() < 0 ? left : right);
  }
  return {left, right};
}

// n photos of w x h (one camera), for the depth-map size rule.
ColmapModel PhotosOfSize(int n, int w, int h) {
  ColmapModel model;
  model.cameras[1] = Camera::Pinhole(1, w, h, w, w, w / 2.0, h / 2.0);
  for (int i = 0; i < n; ++i) {
    ColmapImage im;
    im.id = i + 1;
    im.camera_id = 1;
    model.images[im.id] = im;
  }
  return model;
}

// Auto size: the photos share 48 x 400 x 300 pixels whatever their aspect, never below 400;
// a size given explicitly is kept.
TEST(DenseMvs, DepthMapSizeSharesThePixelBudget) {
  const DenseOptions o;
  ASSERT_EQ(o.max_size, 0);
  EXPECT_EQ(DepthMapSize(PhotosOfSize(48, 800, 600), o), 400);
  EXPECT_EQ(DepthMapSize(PhotosOfSize(12, 800, 600), o), 800);
  EXPECT_EQ(DepthMapSize(PhotosOfSize(12, 600, 800), o), 800);  // portrait: same pixels
  EXPECT_EQ(DepthMapSize(PhotosOfSize(23, 1600, 1200), o), 578);
  EXPECT_EQ(DepthMapSize(PhotosOfSize(11, 1536, 1024), o), 886);  // 886 x 591 each
  EXPECT_EQ(DepthMapSize(PhotosOfSize(300, 800, 600), o), 400);
  EXPECT_EQ(DepthMapSize(ColmapModel{}, o), 400);
  DenseOptions fixed;
  fixed.max_size = 300;
  EXPECT_EQ(DepthMapSize(PhotosOfSize(4, 800, 600), fixed), 300);
}

TEST(DenseMvs, SparseDepthRangeReachesFewFarPoints) {
  // 200 points on a wall 4-6 m away and 3 on a building at 20 m (1.5 %, above the 98th
  // percentile): the range reaches the building.
  std::vector<double> z;
  for (int i = 0; i < 200; ++i) z.push_back(4.0 + 2.0 * i / 199);
  for (double far : {19.0, 20.0, 21.0}) z.push_back(far);
  auto [near, far] = SparseDepthRange(z);
  EXPECT_NEAR(near, 0.75 * z[4], 1e-9);
  EXPECT_NEAR(far, 1.25 * 21.0, 1e-9);
  // One point at 500 m lies beyond 4 times the 98th percentile (6 m): an outlier.
  z.push_back(500.0);
  std::tie(near, far) = SparseDepthRange(z);
  EXPECT_NEAR(far, 1.25 * 4.0 * 6.0, 1e-9);
  EXPECT_EQ(SparseDepthRange({}), std::make_pair(0.0, 0.0));
}

// Where one map disagrees, a depth with one agreeing map is kept only when its NCC reaches
// single_agreement_ncc; elsewhere two maps agree and every depth is kept.
TEST(DenseMvs, FusionKeepsWellMatchedDepthsThatOneMapConfirms) {
  const std::vector<DepthMap> maps = PlaneMapsWithOneWrong();
  DenseOptions o;
  o.single_agreement_ncc = 0.9f;
  const DenseResult r = FuseDepthMaps(maps, o);
  const auto [left, right] = PointsInRegion(r);
  EXPECT_GT(left, 20);
  EXPECT_EQ(right, 0);
  EXPECT_GT(r.cloud.size(), 500u);  // the plane outside the region: 40 x 30 pixels a map

  o.single_agreement_ncc = 2.f;  // off: two agreeing maps everywhere
  const DenseResult strict = FuseDepthMaps(maps, o);
  EXPECT_EQ(PointsInRegion(strict), std::make_pair(0, 0));
  EXPECT_GE(r.cloud.size(), strict.cloud.size() + left);
}

}  // namespace
}  // namespace hdribr
