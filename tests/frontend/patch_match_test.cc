#include "frontend/patch_match.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <opencv2/imgproc.hpp>

namespace hdribr {
namespace {

// Slanted plane z = 4 + 0.3 x seen by four cameras looking down +z at different gains; its
// texture maps [-3, 3]^2 to a 600 x 600 image.
constexpr double kSlope = 0.3;
const Eigen::Vector3d kNormal = Eigen::Vector3d(kSlope, 0, -1).normalized();  // faces the cameras

double PlaneDepth(const Eigen::Vector3d& center, const Eigen::Vector3d& ray) {
  return (4.0 + kSlope * center.x() - center.z()) / (ray.z() - kSlope * ray.x());
}

// Smooth random texture in [0, 1]; `weak` scales the contrast inside |x|, |y| < 0.5 around 0.5.
cv::Mat Texture(float weak) {
  cv::Mat small(60, 60, CV_32F), texture;
  cv::RNG rng(7);
  rng.fill(small, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::resize(small, texture, cv::Size(600, 600), 0, 0, cv::INTER_CUBIC);
  const cv::Rect weak_area(250, 250, 100, 100);
  texture(weak_area) = 0.5f + weak * (texture(weak_area) - 0.5f);
  return texture;
}

std::vector<DepthMap> RenderViews(const cv::Mat& texture, const Camera& cam) {
  const std::vector<Eigen::Vector3d> centers = {{-0.3, 0, 0}, {0, 0, 0}, {0.3, 0, 0}, {0, 0.3, 0}};
  const std::vector<double> gains = {1.0, 0.5, 0.8, 1.0};  // different exposures
  std::vector<DepthMap> maps(centers.size());
  for (size_t i = 0; i < centers.size(); ++i) {
    DepthMap& m = maps[i];
    m.image_id = static_cast<int>(i) + 1;
    m.camera = cam;
    m.cam_from_world = Rigid3d(Eigen::Quaterniond::Identity(), -centers[i]);
    cv::Mat img(cam.height, cam.width, CV_8U);
    for (int v = 0; v < cam.height; ++v) {
      for (int u = 0; u < cam.width; ++u) {
        const Eigen::Vector3d ray = cam.CamFromPixel({u + 0.5, v + 0.5});
        const Eigen::Vector3d p = centers[i] + PlaneDepth(centers[i], ray) * ray;
        cv::Mat px;
        cv::getRectSubPix(texture, cv::Size(1, 1),
                          cv::Point2f(float((p.x() + 3) / 6 * 599), float((p.y() + 3) / 6 * 599)),
                          px);
        img.at<uchar>(v, u) =
            cv::saturate_cast<uchar>(255.0 * gains[i] * (0.1 + 0.8 * px.at<float>(0, 0)));
      }
    }
    img.convertTo(m.gray, CV_32F, 1.0 / 255.0);
    cv::cvtColor(img, m.color, cv::COLOR_GRAY2BGR);
  }
  return maps;
}

std::vector<PatchMatchTask> Tasks(const std::vector<DepthMap>& maps, int num_seeds) {
  std::vector<PatchMatchTask> tasks(maps.size());
  cv::RNG rng(3);
  for (size_t i = 0; i < maps.size(); ++i) {
    for (size_t s = 0; s < maps.size(); ++s) {
      if (s != i) tasks[i].sources.push_back(static_cast<int>(s));
    }
    tasks[i].depth_min = 2.5;
    tasks[i].depth_max = 6.0;
    for (int k = 0; k < num_seeds; ++k) {
      const double x = rng.uniform(-0.8, 0.8), y = rng.uniform(-0.6, 0.6);
      tasks[i].seeds.push_back(maps[i].cam_from_world * Eigen::Vector3d(x, y, 4.0 + kSlope * x));
    }
  }
  return tasks;
}

struct Figures {
  int pixels = 0, valid = 0, accurate = 0, normal_ok = 0, normal_ok10 = 0, within5 = 0;
};

// Depth within 1 % (5 %) and normal within 5 (10) degrees of the truth, over pixels inside `area`
// (pixels of photo 1, the centre camera).
Figures Measure(const DepthMap& m, const cv::Rect& area) {
  Figures f;
  const Eigen::Vector3d center = m.cam_from_world.Inverse().translation;
  for (int y = area.y; y < area.y + area.height; ++y) {
    for (int x = area.x; x < area.x + area.width; ++x) {
      ++f.pixels;
      const float z = m.depth.at<float>(y, x);
      if (z <= 0) continue;
      ++f.valid;
      const double truth = PlaneDepth(center, m.camera.CamFromPixel({x + 0.5, y + 0.5}));
      if (std::abs(z - truth) < 0.01 * truth) ++f.accurate;
      if (std::abs(z - truth) < 0.05 * truth) ++f.within5;
      const cv::Vec3f n = m.normal.at<cv::Vec3f>(y, x);
      const double cosine = Eigen::Vector3d(n[0], n[1], n[2]).dot(kNormal);
      f.normal_ok += cosine > std::cos(5.0 * M_PI / 180);
      f.normal_ok10 += cosine > std::cos(10.0 * M_PI / 180);
    }
  }
  return f;
}

const Camera kCamera = Camera::Pinhole(1, 160, 120, 150, 150, 80, 60);

// Figures in the weak square seen by the centre camera (photo 1; x, y in [-0.5, 0.5] at z ~ 4)
// after PatchMatch on views of `texture` with the options that `configure` sets.
Figures WeakSquareFigures(const cv::Mat& texture,
                          const std::function<void(PatchMatchOptions&)>& configure) {
  std::vector<DepthMap> maps = RenderViews(texture, kCamera);
  DenseOptions o;
  o.threads = 2;
  configure(o.patch_match);
  PatchMatchDepthMaps(maps, Tasks(maps, 0), o);
  return Measure(maps[1], cv::Rect(68, 48, 24, 24));
}

TEST(PatchMatch, RecoversASlantedPlaneAcrossExposures) {
  std::vector<DepthMap> maps = RenderViews(Texture(1.f), kCamera);
  DenseOptions o;
  o.threads = 2;
  int calls = 0;
  PatchMatchDepthMaps(maps, Tasks(maps, 30), o, [&](int done, int total) {
    ++calls;
    EXPECT_LE(done, total);
  });
  EXPECT_EQ(calls, 12);  // 4 photos x (2 levels + the geometric pass)
  for (const DepthMap& m : maps) {
    ASSERT_EQ(m.depth.size(), m.gray.size());
    ASSERT_EQ(m.normal.type(), CV_32FC3);
    // Away from the borders, where the sources see the same part of the plane.
    const Figures f = Measure(m, cv::Rect(24, 20, 112, 80));
    std::cout << "photo " << m.image_id << ": valid " << 100.0 * f.valid / f.pixels
              << "%, depth within 1% " << 100.0 * f.accurate / f.valid << "%, normal within 5 deg "
              << 100.0 * f.normal_ok / f.valid << "%, within 10 deg "
              << 100.0 * f.normal_ok10 / f.valid << "%\n";
    EXPECT_GT(f.valid, 0.9 * f.pixels) << "photo " << m.image_id;
    EXPECT_GE(f.accurate, 0.95 * f.valid) << "photo " << m.image_id;
    EXPECT_GE(f.normal_ok, 0.75 * f.valid) << "photo " << m.image_id;
    EXPECT_GE(f.normal_ok10, 0.95 * f.valid) << "photo " << m.image_id;
  }
}

TEST(PatchMatch, CoarseLevelsFillWeakTexture) {
  // Texture at 2 % contrast in the centre: a few grey levels, mostly lost in quantisation at full
  // resolution but spread over enough pixels at the coarse levels.
  const cv::Mat texture = Texture(0.02f);
  auto accurate_in_weak_area = [&](int levels) {
    const Figures f = WeakSquareFigures(texture, [&](PatchMatchOptions& o) {
      o.num_levels = levels;
      o.min_ncc = -1.f;  // the estimates themselves, not the output filter
      o.min_texture = 0.f;
    });
    return double(f.accurate) / f.pixels;
  };
  const double single = accurate_in_weak_area(1), multi = accurate_in_weak_area(3);
  std::cout << "weak texture: accurate " << single * 100 << "% with 1 level, " << multi * 100
            << "% with 3\n";
  EXPECT_GT(multi, 0.85);
  EXPECT_GT(multi, single + 0.1);
}

TEST(PatchMatch, CoarsePlanesFillWhatFailsAtFullSize) {
  // At 3 % contrast the weak square's windows fail the output filter's NCC or texture test at
  // full size; the half-size level, whose windows span twice the texture, passes it there.
  const cv::Mat texture = Texture(0.03f);
  auto figures_in_weak_area = [&](bool fill) {
    return WeakSquareFigures(texture, [&](PatchMatchOptions& o) { o.coarse_fill = fill; });
  };
  const Figures off = figures_in_weak_area(false), on = figures_in_weak_area(true);
  std::cout << "weak texture, 2 levels: valid " << 100.0 * off.valid / off.pixels
            << "% without the fill, " << 100.0 * on.valid / on.pixels << "% with it ("
            << 100.0 * on.accurate / on.valid << "% within 1 % of the depth, "
            << 100.0 * on.within5 / on.valid << "% within 5 %)\n";
  EXPECT_LT(off.valid, off.pixels / 20);
  EXPECT_GT(on.valid, on.pixels / 2);
  // Coarser, so less accurate than full-size depths; the fusion's consistency test sorts them.
  EXPECT_GE(on.within5, 0.8 * on.valid);
}

TEST(PatchMatch, PixelsThatOneSourceFramesGetTheirDepth) {
  // Photos 0-2 only (centres x = -0.3, 0, 0.3): the left border of photo 1 is framed by photo 0
  // alone. Two best views per pixel: a source that does not frame the patch must not vote, or
  // every plane there costs the mean of one NCC and the worst cost, and the depth is lost.
  std::vector<DepthMap> maps = RenderViews(Texture(1.f), kCamera);
  maps.pop_back();
  DenseOptions o;
  o.threads = 2;
  o.patch_match.best_views = 2;
  PatchMatchDepthMaps(maps, Tasks(maps, 30), o);
  // Photo 2 frames world x >= 0.3 - 0.53 z, from pixel 14 of photo 1 on, and its whole patch
  // from pixel 19 on; the first 5 pixels' windows are clamped at the border.
  const Figures one = Measure(maps[1], cv::Rect(5, 20, 8, 80));
  const Figures edge = Measure(maps[1], cv::Rect(13, 20, 8, 80));
  std::cout << "framed by one source: valid " << 100.0 * one.valid / one.pixels
            << "%, depth within 1% " << 100.0 * one.accurate / std::max(1, one.valid)
            << "%, within 5% " << 100.0 * one.within5 / std::max(1, one.valid)
            << "%; at the second source's frame edge: valid " << 100.0 * edge.valid / edge.pixels
            << "%, within 1% " << 100.0 * edge.accurate / std::max(1, edge.valid) << "%\n";
  EXPECT_GT(one.valid, 0.9 * one.pixels);
  // One source of baseline 0.3 at z ~ 3.5: 1 % of depth is 0.13 pixel of disparity.
  EXPECT_GE(one.within5, 0.95 * one.valid);
  // A source whose patch leaves its frame does not pull the plane there.
  EXPECT_GT(edge.valid, 0.9 * edge.pixels);
  EXPECT_GE(edge.accurate, 0.95 * edge.valid);
}

}  // namespace
}  // namespace hdribr
