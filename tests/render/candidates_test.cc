// Candidate photos in the renderer (RendererOptions::max_candidates): the same render when the
// cap keeps every photo that sees the view, and with 200 photos and a small cap the same pixels
// and nearly the same colours, far closer than an arbitrary subset of the same size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

#include "analytic_scene.h"
#include "gl_test_util.h"
#include "render/renderer.h"

namespace hdribr::render {
namespace {

const Eigen::Vector3d kCentre(0.0, 0.05, 2.8);  // between the two spheres
const Eigen::Vector3d kUp(0, -1, 0);

// Texture of the analytic surfaces at world point p (BGR in [0, 1]), tinted by the photo's
// viewing direction d: view-dependent, so blending photos from far-off directions shows.
cv::Vec3f Shade(const Eigen::Vector3d& p, const Eigen::Vector3d& d) {
  const double tint = 0.8 + 0.2 * d.x();
  return {static_cast<float>(tint * (0.5 + 0.4 * std::sin(9.0 * p.x() + 3.0 * p.z()))),
          static_cast<float>(tint * (0.5 + 0.4 * std::sin(7.0 * p.y() - 5.0 * p.z()))),
          static_cast<float>(tint * (0.5 + 0.4 * std::sin(6.0 * (p.x() + p.y()))))};
}

// The analytic spheres and plane, 40k points, and one 96 x 96 8-bit photo per pose, ray-cast.
Scene MakeScene(const std::vector<Rigid3d>& poses, std::vector<cv::Mat>& images) {
  const auto shade = [](const Eigen::Vector3d& p, const Photo& photo) {
    return cv::Vec3b(Shade(p, photo.ViewDirection()) * 255.0f);
  };
  return test::PhotographScene(test::AnalyticScene::SpheresAndPlane(), test::TestCamera(96), poses,
                               40000, shade, images);
}

std::vector<Rigid3d> Dome(int count, double distance) {
  return test::DomePoses(count, distance, kCentre, kUp);
}

const Rigid3d kView = LookAt(kCentre + Eigen::Vector3d(0.4, -0.3, -2.4), kCentre, kUp);

class CandidatesTest : public test::GlSuite {
 protected:
  static double Psnr(const RenderImages& a, const RenderImages& b) {
    const cv::Mat both = a.valid & b.valid;
    cv::Mat diff = (a.color - b.color) * 255.0;
    diff = diff.mul(diff);
    const cv::Scalar m = cv::mean(diff, both);
    const double mse = (m[0] + m[1] + m[2]) / 3.0;
    return 10.0 * std::log10(255.0 * 255.0 / std::max(mse, 1e-12));
  }
  // Pixels valid in `reference` but not in `im`, as a share of the reference's valid pixels.
  static double Lost(const RenderImages& im, const RenderImages& reference) {
    return static_cast<double>(cv::countNonZero(reference.valid & ~im.valid)) /
           std::max(1, cv::countNonZero(reference.valid));
  }
  static bool Same(const cv::Mat& a, const cv::Mat& b) {
    return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
  }
};

// 24 photos of the dome and 8 far off to the side looking away: a cap of at least the photos
// that see the view leaves the render exactly as with every photo, with both weightings.
TEST_F(CandidatesTest, CapAboveThePhotosSeeingTheViewChangesNothing) {
  std::vector<Rigid3d> poses = Dome(24, 2.5);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d eye(20.0 + i, 0.0, 2.8);
    poses.push_back(LookAt(eye, eye + Eigen::Vector3d(1, 0, 0.2 * i - 0.7), kUp));
  }
  std::vector<cv::Mat> images;
  const Scene scene = MakeScene(poses, images);
  RendererOptions ro;
  ro.photo_images = images;
  Renderer r(*shaders_, scene, ro);
  const Camera cam = test::TestCamera(128);
  for (BlendWeights weights : {BlendWeights::kUnstructured, BlendWeights::kPaper}) {
    r.blend_options().weights = weights;
    r.SetMaxCandidates(0);
    const RenderImages all = r.RenderToImages(cam, kView, 128, 128);
    EXPECT_EQ(r.last_candidates().photos.size(), 32u);
    EXPECT_GT(cv::countNonZero(all.valid), 128 * 128 / 2);
    for (int cap : {32, 28}) {
      r.SetMaxCandidates(cap);
      const RenderImages capped = r.RenderToImages(cam, kView, 128, 128);
      const std::vector<int>& used = r.last_candidates().photos;
      std::printf("%s, cap %d: %zu candidates\n", BlendWeightsName(weights).c_str(), cap,
                  used.size());
      // Every photo of the dome, none of those looking away.
      ASSERT_EQ(used.size(), 24u);
      for (int k : used) EXPECT_LT(k, 24);
      EXPECT_TRUE(Same(capped.color, all.color)) << "cap " << cap;
      EXPECT_TRUE(Same(capped.valid, all.valid)) << "cap " << cap;
      EXPECT_TRUE(Same(capped.count, all.count)) << "cap " << cap;
    }
    // Below the photos that see the view, the render changes (the comparison can fail).
    r.SetMaxCandidates(8);
    EXPECT_FALSE(Same(r.RenderToImages(cam, kView, 128, 128).color, all.color));
  }
}

// 200 photos: a cap of 16 covers the same pixels as every photo, with nearly the same colours;
// 17 photos picked regardless of the view do much worse.
TEST_F(CandidatesTest, TwoHundredPhotosCappedKeepTheRender) {
  std::vector<cv::Mat> images;
  const Scene scene = MakeScene(Dome(200, 2.5), images);
  RendererOptions ro;
  ro.photo_images = images;
  Renderer r(*shaders_, scene, ro);
  const Camera cam = test::TestCamera(128);
  r.SetMaxCandidates(0);
  const RenderImages all = r.RenderToImages(cam, kView, 128, 128);
  r.SetMaxCandidates(16);
  const RenderImages capped = r.RenderToImages(cam, kView, 128, 128);
  EXPECT_EQ(r.last_candidates().photos.size(), 16u);
  EXPECT_EQ(r.last_candidates().active, 200);
  std::vector<int> arbitrary;
  for (int k = 0; k < 200; k += 12) arbitrary.push_back(k);
  r.SetActivePhotos(arbitrary);
  r.SetMaxCandidates(0);
  const RenderImages subset = r.RenderToImages(cam, kView, 128, 128);
  const double psnr = Psnr(capped, all), psnr_subset = Psnr(subset, all);
  std::printf(
      "200 photos, cap 16: PSNR %.2f dB against every photo, %.3f%% of its pixels lost; 17 "
      "arbitrary photos: %.2f dB, %.3f%% lost\n",
      psnr, 100 * Lost(capped, all), psnr_subset, 100 * Lost(subset, all));
  // Measured (llvmpipe): 55.4 dB and 0.15% lost; the arbitrary subset 31.4 dB.
  EXPECT_LT(Lost(capped, all), 0.005);
  EXPECT_GT(psnr, 45.0);
  EXPECT_GT(psnr, psnr_subset + 10.0);
}

}  // namespace
}  // namespace hdribr::render
