// The photo cache (render/photo_cache.h): a capture whose photos need four times the GPU
// memory budget renders its first frame with the pixels of the all-resident render (coarse
// copies, no hole), exactly the all-resident render once the cache has settled, evicts when
// the view turns to other photos, caches the depth maps too when they do not fit, and refuses
// budgets it cannot work with.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <set>
#include <vector>

#include "analytic_scene.h"
#include "core/error.h"
#include "gl_test_util.h"
#include "render/renderer.h"

namespace hdribr::render {
namespace {

const Eigen::Vector3d kCentre(0.0, 0.05, 2.8);
const Eigen::Vector3d kUp(0, -1, 0);
constexpr int kPhotoSize = 128;
constexpr int kCandidates = 4;

// The analytic spheres and plane, 40k points, and one 8-bit photo per pose, ray-cast with a
// texture of the surface (fine detail, so that a coarse copy shows).
Scene MakeScene(const std::vector<Rigid3d>& poses, std::vector<cv::Mat>& images) {
  const auto texture = [](const Eigen::Vector3d& p, const Photo&) {
    const double a = 0.5 + 0.45 * std::sin(23.0 * p.x() + 11.0 * p.z());
    const double b = 0.5 + 0.45 * std::sin(19.0 * p.y() - 13.0 * p.z());
    return cv::Vec3b(static_cast<uchar>(255 * a), static_cast<uchar>(255 * b),
                     static_cast<uchar>(255 * 0.5 * (a + b)));
  };
  return test::PhotographScene(test::AnalyticScene::SpheresAndPlane(), test::TestCamera(kPhotoSize),
                               poses, 40000, texture, images);
}

std::vector<Rigid3d> Dome(int count, double distance) {
  return test::DomePoses(count, distance, kCentre, kUp);
}

const Rigid3d kView = LookAt(kCentre + Eigen::Vector3d(0.9, -0.5, -2.2), kCentre, kUp);
const Rigid3d kOtherView = LookAt(kCentre + Eigen::Vector3d(-1.0, 0.6, -2.1), kCentre, kUp);

bool Same(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

class PhotoCacheTest : public test::GlSuite {
 protected:
  static void SetUpTestSuite() {
    GlSuite::SetUpTestSuite();
    scene_ = new Scene(MakeScene(Dome(24, 2.5), images_));
  }
  static void TearDownTestSuite() {
    delete scene_;
    scene_ = nullptr;
    images_.clear();
    GlSuite::TearDownTestSuite();
  }
  // Depth maps at a quarter of the photos' size by default: small enough to stay resident.
  static RendererOptions Options(double depth_scale = 0.25) {
    RendererOptions ro;
    ro.photo_images = images_;
    ro.max_candidates = kCandidates;
    ro.photo_depth_scale = depth_scale;
    return ro;
  }
  // A quarter of what the photos need at full size with their mipmaps, MiB.
  static double QuarterOfPhotosMb() {
    const Renderer all(*shaders_, *scene_, Options());
    const PhotoResidency r = all.residency();
    return static_cast<double>(r.total_bytes - r.depth_bytes) / 4.0 / 1048576.0;
  }

  static inline Scene* scene_ = nullptr;
  static inline std::vector<cv::Mat> images_;
};

// First frame: coarse copies, the same valid pixels; settled: the all-resident render.
TEST_F(PhotoCacheTest, QuarterBudgetRendersWithoutHoleAndSettlesToTheAllResidentRender) {
  const Camera cam = test::TestCamera(160);
  Renderer all(*shaders_, *scene_, Options());
  EXPECT_FALSE(all.residency().cached);
  const RenderImages reference = all.RenderToImages(cam, kView, 160, 160);
  ASSERT_GT(cv::countNonZero(reference.valid), 160 * 160 / 2);

  RendererOptions ro = Options();
  ro.gpu_memory_mb = QuarterOfPhotosMb();
  ro.wait_for_photos = false;
  Renderer cached(*shaders_, *scene_, ro);
  const PhotoResidency r0 = cached.residency();
  std::printf("budget %.3f MiB: resident %.3f of %.3f MiB, %d slots, coarse 1/%d\n",
              ro.gpu_memory_mb, r0.resident_bytes / 1048576.0, r0.total_bytes / 1048576.0, r0.slots,
              r0.fallback_divisor);
  ASSERT_TRUE(r0.cached);
  EXPECT_LE(r0.resident_bytes, r0.budget_bytes);
  EXPECT_GE(r0.total_bytes - r0.depth_bytes, 4 * r0.budget_bytes - 4);  // photos need 4x
  ASSERT_GE(r0.slots, kCandidates);
  EXPECT_EQ(r0.full_size, 0);

  const RenderImages first = cached.RenderToImages(cam, kView, 160, 160);
  EXPECT_EQ(cached.last_candidates().photos, all.last_candidates().photos);
  EXPECT_TRUE(Same(first.valid, reference.valid));
  EXPECT_TRUE(Same(first.count, reference.count));
  EXPECT_EQ(cached.residency().full_size, 0);        // loads are uploaded at the next frame
  EXPECT_FALSE(Same(first.color, reference.color));  // coarse copies
  const double coarse_error = cv::norm(first.color, reference.color, cv::NORM_L1, reference.valid) /
                              cv::countNonZero(reference.valid) / 3.0;
  std::printf("first frame: mean |difference| %.4f per channel\n", coarse_error);

  cached.SettleCache();
  EXPECT_EQ(cached.residency().pending, 0);
  EXPECT_EQ(cached.residency().full_size, kCandidates);
  const RenderImages settled = cached.RenderToImages(cam, kView, 160, 160);
  // Exactly: the slots hold the texels of the all-resident array (same size, same mipmaps).
  EXPECT_TRUE(Same(settled.color, reference.color));
  EXPECT_TRUE(Same(settled.valid, reference.valid));
  EXPECT_TRUE(Same(settled.count, reference.count));
}

// Turning to other photos evicts the least recently used ones; offline (waiting) renders are
// the all-resident render at every view.
TEST_F(PhotoCacheTest, OtherPhotosEvictAndWaitingRendersEqualTheAllResidentRender) {
  const Camera cam = test::TestCamera(160);
  Renderer all(*shaders_, *scene_, Options());
  RendererOptions ro = Options();
  ro.gpu_memory_mb = QuarterOfPhotosMb();
  Renderer cached(*shaders_, *scene_, ro);
  ASSERT_TRUE(cached.residency().cached);
  std::set<int> seen;
  for (const Rigid3d& view : {kView, kOtherView, kView}) {
    const RenderImages reference = all.RenderToImages(cam, view, 160, 160);
    const RenderImages im = cached.RenderToImages(cam, view, 160, 160);
    const PhotoResidency r = cached.residency();
    EXPECT_EQ(r.pending, 0);
    EXPECT_LE(r.resident_bytes, r.budget_bytes);
    EXPECT_TRUE(Same(im.color, reference.color));
    EXPECT_TRUE(Same(im.valid, reference.valid));
    for (int p : cached.last_candidates().photos) seen.insert(p);
  }
  const PhotoResidency r = cached.residency();
  std::printf("%zu photos used, %zu loads, %zu evictions, %d slots\n", seen.size(), r.loads,
              r.evictions, r.slots);
  ASSERT_GT(static_cast<int>(seen.size()), r.slots);  // the views need more than the slots
  EXPECT_GT(r.evictions, 0u);
  EXPECT_EQ(r.loads, r.evictions + static_cast<size_t>(r.full_size + r.reduced));
}

// Depth maps of the photos' size and a quarter of what photos and depth maps need: the depth
// maps get a slot per candidate (uploaded with the frame), the first frame still has the
// all-resident valid pixels where the view has a point (and nearly all elsewhere), the settled
// one its colours.
TEST_F(PhotoCacheTest, DepthMapsBeyondTheBudgetAreCachedToo) {
  const Camera cam = test::TestCamera(160);
  Renderer all(*shaders_, *scene_, Options(1.0));
  const PhotoResidency everything = all.residency();
  EXPECT_FALSE(everything.cached);
  RendererOptions ro = Options(1.0);
  ro.gpu_memory_mb = static_cast<double>(everything.total_bytes) / 4.0 / 1048576.0;
  ro.wait_for_photos = false;
  Renderer cached(*shaders_, *scene_, ro);
  const PhotoResidency r = cached.residency();
  std::printf("budget %.3f MiB: resident %.3f of %.3f MiB (depth %.3f), %d slots, %d depth slots\n",
              ro.gpu_memory_mb, r.resident_bytes / 1048576.0, r.total_bytes / 1048576.0,
              r.depth_bytes / 1048576.0, r.slots, r.depth_slots);
  ASSERT_TRUE(r.cached);
  EXPECT_EQ(r.depth_slots, kCandidates);
  EXPECT_LT(r.depth_bytes, everything.depth_bytes);
  EXPECT_LE(r.resident_bytes, r.budget_bytes);
  ASSERT_GE(r.slots, kCandidates);
  for (const Rigid3d& view : {kView, kOtherView}) {
    const RenderImages reference = all.RenderToImages(cam, view, 160, 160);
    const RenderImages first = cached.RenderToImages(cam, view, 160, 160);
    // Where the view has a point, the first frame has the reference's pixels; elsewhere the
    // plane sweep of the background's holes compares the photos' colours, coarser in it.
    const cv::Mat point = reference.depth > 0;
    const auto at_points = [&](const cv::Mat& m) {
      cv::Mat out = cv::Mat::zeros(m.size(), m.type());
      m.copyTo(out, point);
      return out;
    };
    EXPECT_TRUE(Same(at_points(first.valid), at_points(reference.valid)));
    EXPECT_TRUE(Same(at_points(first.count), at_points(reference.count)));
    const double kept = static_cast<double>(cv::countNonZero(first.valid & reference.valid)) /
                        cv::countNonZero(reference.valid);
    std::printf("first frame: %.4f of the reference's valid pixels, %d more\n", kept,
                cv::countNonZero(first.valid & ~reference.valid));
    EXPECT_GT(kept, 0.99);
    EXPECT_FALSE(Same(first.color, reference.color));
    cached.SettleCache();
    const RenderImages settled = cached.RenderToImages(cam, view, 160, 160);
    EXPECT_TRUE(Same(settled.color, reference.color));
    EXPECT_TRUE(Same(settled.valid, reference.valid));
  }
  EXPECT_GT(cached.residency().evictions, 0u);
}

// A small view of the whole scene samples the photos from mip level 2 on: with a budget that
// holds fewer full-size photos than a frame's candidates, the slots are split between sizes
// from the levels the blend reports, the candidates go to reduced slots, and the settled render
// is the all-resident one.
TEST_F(PhotoCacheTest, CandidatesAreResidentAtTheLevelTheViewNeeds) {
  constexpr int kSize = 16;
  constexpr int kMany = 8;
  const Camera cam = test::TestCamera(kSize);
  RendererOptions ro = Options();
  ro.max_candidates = kMany;
  Renderer all(*shaders_, *scene_, ro);
  ro.gpu_memory_mb = QuarterOfPhotosMb();
  ro.wait_for_photos = false;
  Renderer cached(*shaders_, *scene_, ro);
  const PhotoResidency r0 = cached.residency();
  std::printf("budget %.3f MiB: %d full-size slots, %d reduced, coarse 1/%d\n", ro.gpu_memory_mb,
              r0.slots, r0.reduced_slots, r0.fallback_divisor);
  ASSERT_TRUE(r0.cached);
  EXPECT_LE(r0.resident_bytes, r0.budget_bytes);
  // The budget less the depth maps holds fewer full-size photos than a frame's candidates.
  const size_t layer = (r0.total_bytes - r0.depth_bytes) / scene_->photos.size();
  ASSERT_LT((r0.budget_bytes - r0.depth_bytes) / layer, static_cast<size_t>(kMany));
  for (const Rigid3d& view : {kView, kOtherView}) {
    const RenderImages reference = all.RenderToImages(cam, view, kSize, kSize);
    ASSERT_GT(cv::countNonZero(reference.valid), kSize * kSize / 2);
    const RenderImages first = cached.RenderToImages(cam, view, kSize, kSize);
    EXPECT_TRUE(Same(first.valid, reference.valid));  // never a hole
    // The first frame's levels place the photos; the next settles to the all-resident render.
    for (int frame = 0; frame < 2; ++frame) {
      cached.SettleCache();
      cached.RenderToImages(cam, view, kSize, kSize);
    }
    cached.SettleCache();
    const RenderImages settled = cached.RenderToImages(cam, view, kSize, kSize);
    const PhotoResidency r = cached.residency();
    std::printf(
        "settled: %d full-size slots, %d reduced; %d photos at full size, %d at a reduced "
        "level, %zu loads\n",
        r.slots, r.reduced_slots, r.full_size, r.reduced, r.loads);
    EXPECT_LE(r.resident_bytes, r.budget_bytes);
    EXPECT_GT(r.reduced, 0);
    EXPECT_TRUE(Same(settled.color, reference.color));
    EXPECT_TRUE(Same(settled.valid, reference.valid));
  }
}

TEST_F(PhotoCacheTest, BadBudgetsAreOptionErrors) {
  for (double mb : {-1.0, std::numeric_limits<double>::quiet_NaN(),
                    std::numeric_limits<double>::infinity(), 0.01}) {
    RendererOptions ro = Options();
    ro.gpu_memory_mb = mb;
    try {
      const Renderer r(*shaders_, *scene_, ro);
      ADD_FAILURE() << "gpu_memory_mb " << mb << " accepted";
    } catch (const OptionError& e) {
      EXPECT_EQ(e.field(), "gpu_memory_mb") << e.what();
      std::printf("%g: %s\n", mb, e.what());
    }
  }
}

}  // namespace
}  // namespace hdribr::render
