// The renderer (depth pass + blend pass, Lechelek et al. 2019 sec. 4) on a small ground-truth
// synthetic capture: leave-one-out fidelity, debug maps, K best, active subsets, photo sizes,
// float photos and radiance blending.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "core/error.h"
#include "gl/context.h"
#include "hdr/response_curve.h"
#include "io/image.h"
#include "io/workspace.h"
#include "render/blend_pass.h"
#include "render/renderer.h"
#include "support/test_capture.h"
#include "test_util.h"

namespace hdribr::render {
namespace {

// The suite's capture, 2 series x 6 views, 160 x 120, in dir/capture.
void WriteSuiteCapture(const std::filesystem::path& dir) {
  test::WriteTestCapture(dir / "capture", {2, 6, 160, 120, 1});
}
constexpr char kCaptureFixture[] = "BlendPassCapture";

// The setup of the shared fixture (tests/render/CMakeLists.txt): the capture, once per CTest
// run, which every test of BlendPassTest reads.
TEST(Fixture, BlendPassCapture) { test::RemakeSharedFixture(kCaptureFixture, WriteSuiteCapture); }

class BlendPassTest : public ::testing::Test {
 protected:
  // One capture for the whole suite (read-only), made by the fixture's setup.
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(test::SharedFixture(kCaptureFixture, WriteSuiteCapture) /
                                     "capture");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    scene_ = LoadWorkspace(*dir_ / "workspace");
    ASSERT_EQ(scene_.photos.size(), 12u);
    ASSERT_EQ(scene_.series.size(), 2u);
  }

  // Photos of the series of `photo`, except `photo` itself.
  std::vector<int> SameSeriesExcept(int photo) const {
    std::vector<int> out;
    const int series = scene_.photos[static_cast<size_t>(photo)].series_id;
    for (size_t i = 0; i < scene_.photos.size(); ++i) {
      if (scene_.photos[i].series_id == series && static_cast<int>(i) != photo) {
        out.push_back(static_cast<int>(i));
      }
    }
    return out;
  }

  RenderImages RenderPhotoView(Renderer& r, int photo) const {
    const Photo& p = scene_.photos[static_cast<size_t>(photo)];
    const Camera& cam = scene_.CameraOf(p);
    return r.RenderToImages(cam, p.cam_from_world, cam.width, cam.height);
  }

  // PSNR (8-bit scale) of the render against photo `photo` over the valid pixels.
  double Psnr(const RenderImages& im, int photo) const { return Psnr(im, photo, im.valid); }
  // ... over the pixels of `mask`.
  double Psnr(const RenderImages& im, int photo, const cv::Mat& mask) const {
    cv::Mat ref;
    ReadImage(scene_.photos[static_cast<size_t>(photo)].image_path).convertTo(ref, CV_32FC3);
    cv::Mat diff = im.color * 255.0 - ref;
    diff = diff.mul(diff);
    const cv::Scalar m = cv::mean(diff, mask);
    const double mse = m[0] / 3 + m[1] / 3 + m[2] / 3;
    return 10.0 * std::log10(255.0 * 255.0 / std::max(mse, 1e-12));
  }

  // The points of the scene farther than 0.1 scene scales from the back wall's point seen at
  // the pixel a quarter across and a fifth down the view of `photo` (the sky behind it, top left
  // in the view), whose depth `depth` (the view's, from every point) holds.
  PointCloud WithoutBackWallPatch(int photo, const cv::Mat& depth) const {
    const cv::Point wall_px(depth.cols / 4, depth.rows / 5);
    EXPECT_GT(depth.at<float>(wall_px), 0.0f);
    const Photo& p = scene_.photos[static_cast<size_t>(photo)];
    const Camera& cam = scene_.CameraOf(p);
    const Eigen::Vector3d ray = cam.CamFromPixel({wall_px.x + 0.5, wall_px.y + 0.5});
    const Eigen::Vector3d hole_centre =
        p.cam_from_world.Inverse() * (ray * depth.at<float>(wall_px));
    PointCloud holed;
    for (size_t i = 0; i < scene_.points.size(); ++i) {
      if ((scene_.points.positions[i].cast<double>() - hole_centre).norm() <
          0.1 * scene_.scene_scale) {
        continue;
      }
      holed.positions.push_back(scene_.points.positions[i]);
      if (scene_.points.HasNormals()) holed.normals.push_back(scene_.points.normals[i]);
      if (scene_.points.HasColors()) holed.colors.push_back(scene_.points.colors[i]);
      if (scene_.points.HasRadii()) holed.radii.push_back(scene_.points.radii[i]);
    }
    return holed;
  }

  // A render's hole: the pixels where the render with every point has depth and it has none.
  struct HoleFill {
    double filled = 0.0;     // share of the hole that the render covers
    double psnr = 0.0;       // its PSNR against the photo there
    double psnr_full = 0.0;  // the render with every point's PSNR there
  };
  // Renders the view of `photo` with background `b` and measures its hole against `full`.
  HoleFill RenderHole(Renderer& r, int photo, const RenderImages& full, Background b) const {
    r.blend_options().background = b;
    const RenderImages im = RenderPhotoView(r, photo);
    ExpectSane(im, 5);
    const cv::Mat hole = (full.depth > 0) & (im.depth <= 0);
    const int hole_px = cv::countNonZero(hole);
    EXPECT_GT(hole_px, 100) << "no hole in the view's depth";
    if (hole_px == 0) return {};
    HoleFill f;
    f.filled = static_cast<double>(cv::countNonZero(hole & im.valid)) / hole_px;
    f.psnr = Psnr(im, photo, hole & im.valid);
    f.psnr_full = Psnr(full, photo, hole);
    std::printf(
        "background %s, hole of %d px: %.1f%% filled, %.2f dB there (%.2f dB with every "
        "point)\n",
        BackgroundName(b).c_str(), hole_px, 100.0 * f.filled, f.psnr, f.psnr_full);
    return f;
  }

  // Leave-one-out renders of `photo` (from the other photos of its series) by a renderer of
  // `scene` with options `a` and one with options `b`; the same pixels are valid in both.
  std::pair<RenderImages, RenderImages> LeaveOneOutPair(const gl::ShaderLibrary& shaders,
                                                        const Scene& scene,
                                                        const RendererOptions& a,
                                                        const RendererOptions& b, int photo) {
    Renderer ra(shaders, scene, a), rb(shaders, scene, b);
    ra.SetActivePhotos(SameSeriesExcept(photo));
    rb.SetActivePhotos(SameSeriesExcept(photo));
    std::pair<RenderImages, RenderImages> out(RenderPhotoView(ra, photo),
                                              RenderPhotoView(rb, photo));
    EXPECT_EQ(cv::countNonZero(out.first.valid != out.second.valid), 0);
    return out;
  }

  static double Coverage(const RenderImages& im) {
    return static_cast<double>(cv::countNonZero(im.valid)) / static_cast<double>(im.valid.total());
  }

  // Finite everywhere; invalid pixels exactly 0; count and weight consistent with validity.
  static void ExpectSane(const RenderImages& im, int active) {
    for (int y = 0; y < im.color.rows; ++y) {
      for (int x = 0; x < im.color.cols; ++x) {
        const cv::Vec3f c = im.color.at<cv::Vec3f>(y, x);
        const float n = im.count.at<float>(y, x), w = im.weight.at<float>(y, x);
        ASSERT_TRUE(std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]));
        ASSERT_TRUE(std::isfinite(n) && std::isfinite(w));
        ASSERT_GE(w, 0.0f);
        ASSERT_LE(w, 1.0f + 1e-5f);
        ASSERT_GE(n, 0.0f);
        ASSERT_LE(n, static_cast<float>(active));
        ASSERT_FALSE(im.valid.at<uint8_t>(y, x) && im.filled.at<uint8_t>(y, x));
        if (im.valid.at<uint8_t>(y, x)) {
          ASSERT_GE(n, 1.0f);
        } else {
          if (!im.filled.at<uint8_t>(y, x)) {
            ASSERT_EQ(c, cv::Vec3f(0, 0, 0));
          }
          ASSERT_EQ(n, 0.0f);
        }
      }
    }
  }

  static std::filesystem::path* dir_;
  Scene scene_;
};

std::filesystem::path* BlendPassTest::dir_ = nullptr;

TEST_F(BlendPassTest, LeaveOneOutResemblesThePhoto) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  Renderer r(shaders, scene_);
  EXPECT_GT(r.gpu_bytes(), 12u * 160 * 120 * 4);
  for (int photo : {1, 8}) {
    r.SetActivePhotos(SameSeriesExcept(photo));
    const RenderImages loo = RenderPhotoView(r, photo);
    ExpectSane(loo, 5);
    const double psnr = Psnr(loo, photo), cov = Coverage(loo);
    std::printf("photo %d: leave-one-out PSNR %.2f dB, coverage %.3f, mean count %.2f\n", photo,
                psnr, cov, cv::mean(loo.count, loo.valid)[0]);
    EXPECT_GT(psnr, 24.0);
    EXPECT_GT(cov, 0.8);
    // The photo itself among the inputs: closer still.
    std::vector<int> with = SameSeriesExcept(photo);
    with.push_back(photo);
    r.SetActivePhotos(with);
    const double psnr_self = Psnr(RenderPhotoView(r, photo), photo);
    std::printf("photo %d: with itself PSNR %.2f dB\n", photo, psnr_self);
    EXPECT_GT(psnr_self, psnr);
  }
}

TEST_F(BlendPassTest, DebugMapsAndViewLookingAway) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  RendererOptions ro;
  ro.blend.debug_photo = 2;
  Renderer r(shaders, scene_, ro);
  r.SetActivePhotos(SameSeriesExcept(0));  // photos 1..5
  const RenderImages im = RenderPhotoView(r, 0);
  ExpectSane(im, 5);
  EXPECT_GT(cv::mean(im.count, im.valid)[0], 1.5);      // several photos per pixel
  EXPECT_GT(cv::countNonZero(im.weight > 0.01f), 100);  // photo 2 contributes somewhere
  cv::Mat n2;
  cv::multiply(im.normal, im.normal, n2);
  const cv::Scalar nn = cv::mean(n2, im.valid & (im.depth > 0));  // the background has none
  EXPECT_NEAR(nn[0] + nn[1] + nn[2], 1.0, 0.05);                  // unit normals
  // Looking away from the scene (turned around at the first photo's centre).
  const Photo& p = scene_.photos[0];
  const Eigen::Vector3d c = p.Center();
  const Rigid3d away = LookAt(c, c - 5.0 * p.ViewDirection(), {0, -1, 0});
  const RenderImages none = r.RenderToImages(scene_.CameraOf(p), away, 96, 64);
  ExpectSane(none, 5);
  EXPECT_EQ(cv::countNonZero(none.valid), 0);
  // No active photo at all: all invalid, no NaN.
  r.SetActivePhotos({});
  const RenderImages empty = RenderPhotoView(r, 0);
  ExpectSane(empty, 0);
  EXPECT_EQ(cv::countNonZero(empty.valid), 0);
}

TEST_F(BlendPassTest, KBestAndSubsetSwitching) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  RendererOptions ro;
  ro.blend.weights = BlendWeights::kPaper;  // K best by the paper's weight
  Renderer r(shaders, scene_, ro);
  const std::vector<int> others = SameSeriesExcept(3);
  r.SetActivePhotos(others);
  const RenderImages all = RenderPhotoView(r, 3);
  r.blend_options().k_best = 1;
  const RenderImages one = RenderPhotoView(r, 3);
  r.blend_options().k_best = 2;
  const RenderImages two = RenderPhotoView(r, 3);
  r.blend_options().k_best = 5;  // >= active photos: the same as all
  const RenderImages five = RenderPhotoView(r, 3);
  ExpectSane(one, 1);
  ExpectSane(two, 2);
  double max_count_one = 0;
  cv::minMaxLoc(one.count, nullptr, &max_count_one);
  EXPECT_EQ(max_count_one, 1.0);
  EXPECT_EQ(cv::countNonZero(one.valid != all.valid), 0);  // K only drops weaker photos
  EXPECT_GT(cv::norm(one.color, all.color, cv::NORM_L1), 1.0);
  EXPECT_EQ(cv::norm(five.color, all.color, cv::NORM_INF), 0.0);
  const double p_all = Psnr(all, 3), p_one = Psnr(one, 3), p_two = Psnr(two, 3);
  std::printf("K best: all %.2f dB, K=2 %.2f dB, K=1 %.2f dB\n", p_all, p_two, p_one);
  EXPECT_GT(p_one, 20.0);
  // Subset of one photo: its normalised weight is 1 wherever valid.
  r.blend_options().k_best = 0;
  r.blend_options().debug_photo = others[0];
  r.SetActivePhotos({others[0]});
  const RenderImages single = RenderPhotoView(r, 3);
  ExpectSane(single, 1);
  EXPECT_GT(cv::countNonZero(single.valid), 1000);
  cv::Mat off = (single.weight < 0.999f) & (single.valid > 0);
  EXPECT_EQ(cv::countNonZero(off), 0);
  // Back to the first subset: the identical image.
  r.SetActivePhotos(others);
  r.blend_options().debug_photo = -1;
  EXPECT_EQ(cv::norm(RenderPhotoView(r, 3).color, all.color, cv::NORM_INF), 0.0);
  // Nearest-photo mode: exactly one photo per valid pixel.
  r.blend_options().mode = BlendMode::kNearestPhoto;
  const RenderImages nearest = RenderPhotoView(r, 3);
  ExpectSane(nearest, 1);
  std::printf("nearest photo: %.2f dB, coverage %.3f\n", Psnr(nearest, 3), Coverage(nearest));
  EXPECT_GT(Coverage(nearest), 0.5);
}

// Pixels without a point (the synthetic sky, which depends on the direction only, and the
// floor beyond the points): left empty by the paper, filled by the background, which never
// changes a pixel that has a point.
TEST_F(BlendPassTest, BackgroundFillsWhatNoPointCovers) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  Renderer r(shaders, scene_);
  EXPECT_EQ(r.blend_options().background, Background::kPlane);  // the default
  r.blend_options().fill = false;  // what the background itself leaves empty
  const int photo = 1;
  r.SetActivePhotos(SameSeriesExcept(photo));
  std::map<Background, RenderImages> im;
  for (Background b : kAllBackgrounds) {
    r.blend_options().background = b;
    im[b] = RenderPhotoView(r, photo);
    ExpectSane(im[b], 5);
  }
  const RenderImages& none = im[Background::kNone];
  const cv::Mat points = none.depth > 0;
  const cv::Mat no_point = none.depth <= 0;
  ASSERT_GT(cv::countNonZero(no_point), 500) << "the view shows no sky";
  // Without a background only the photos' surfaces along the ray fill them: not the sky.
  EXPECT_LT(cv::countNonZero(none.valid & no_point), cv::countNonZero(no_point) / 20);
  cv::Mat ref;
  ReadImage(scene_.photos[static_cast<size_t>(photo)].image_path).convertTo(ref, CV_32FC3);
  // Infinity fills the sky; the sphere also the floor beyond the points, which lies inside it;
  // the plane puts that floor at its depth.
  const std::map<Background, double> min_share = {
      {Background::kInfinity, 0.25}, {Background::kSphere, 0.85}, {Background::kPlane, 0.85}};
  for (Background b : {Background::kInfinity, Background::kSphere, Background::kPlane}) {
    const RenderImages& bg = im[b];
    EXPECT_EQ(cv::norm(bg.color, none.color, cv::NORM_INF, points), 0.0) << BackgroundName(b);
    EXPECT_EQ(cv::countNonZero((bg.valid != none.valid) & points), 0);
    const cv::Mat filled = bg.valid & no_point;
    const double share = static_cast<double>(cv::countNonZero(filled)) / cv::countNonZero(no_point);
    cv::Mat diff = bg.color * 255.0 - ref;
    diff = diff.mul(diff);
    const cv::Scalar m = cv::mean(diff, filled);
    const double psnr = 10.0 * std::log10(255.0 * 255.0 / ((m[0] + m[1] + m[2]) / 3));
    std::printf("background %s: %.1f%% of the pixels without a point filled, %.2f dB there\n",
                BackgroundName(b).c_str(), 100.0 * share, psnr);
    EXPECT_GT(share, min_share.at(b)) << BackgroundName(b);
    EXPECT_GT(psnr, 24.0) << BackgroundName(b);
  }
  // The plane (the scene's floor or back wall) takes some of the sphere's pixels, at its depth.
  const cv::Mat moved =
      (cv::abs(im[Background::kPlane].color - im[Background::kSphere].color) > 1.0 / 255.0);
  std::vector<cv::Mat> channels;
  cv::split(moved, channels);
  EXPECT_GT(cv::countNonZero((channels[0] | channels[1] | channels[2]) & no_point), 0);
  EXPECT_EQ(ParseBackground("infinity"), Background::kInfinity);
  EXPECT_THROW(ParseBackground("box"), UsageError);
  // The sphere lies beyond 99 % of the points and encloses every camera.
  const Eigen::Vector4d sphere = BackgroundSphere(scene_);
  int beyond = 0;
  for (const Eigen::Vector3f& p : scene_.points.positions) {
    beyond += (p.cast<double>() - sphere.head<3>()).norm() > sphere.w();
  }
  EXPECT_LE(beyond, static_cast<int>(scene_.points.size() / 100) + 1);
  for (const Photo& p : scene_.photos)
    EXPECT_LT((p.Center() - sphere.head<3>()).norm(), sphere.w());
}

// Pixels that no photo shows (here the sky, without a background) take the fill's colour,
// interpolated from what the photos show around them; the fill changes no pixel a photo shows.
TEST_F(BlendPassTest, FillColoursWhatNoPhotoShows) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  Renderer r(shaders, scene_);
  EXPECT_TRUE(r.blend_options().fill);  // the default
  const int photo = 1;
  r.SetActivePhotos(SameSeriesExcept(photo));
  r.blend_options().background = Background::kNone;
  const RenderImages filled = RenderPhotoView(r, photo);
  r.blend_options().fill = false;
  const RenderImages bare = RenderPhotoView(r, photo);
  ExpectSane(filled, 5);
  ExpectSane(bare, 5);
  EXPECT_EQ(cv::countNonZero(filled.valid != bare.valid), 0);
  EXPECT_EQ(cv::norm(filled.color, bare.color, cv::NORM_INF, bare.valid), 0.0);
  EXPECT_EQ(cv::countNonZero(bare.filled), 0);
  const cv::Mat empty = bare.valid == 0;
  ASSERT_GT(cv::countNonZero(empty), 500) << "the view shows no sky";
  EXPECT_EQ(cv::countNonZero(filled.filled != empty), 0);  // every empty pixel, only those
  // Against the held-out photo, the fill is closer than the mean colour of what photos show.
  RenderImages flat = bare;
  flat.color = bare.color.clone();
  flat.color.setTo(cv::mean(bare.color, bare.valid), empty);
  const double fill_psnr = Psnr(filled, photo, empty), flat_psnr = Psnr(flat, photo, empty);
  std::printf("fill of %d px: %.2f dB (the mean colour: %.2f dB)\n", cv::countNonZero(empty),
              fill_psnr, flat_psnr);
  EXPECT_GT(fill_psnr, flat_psnr + 3.0);
}

// A hole in the view's geometry that the photos' depth maps cover (points the view's depth pass
// lacks): its pixels take the photos' surface, found along the ray, instead of staying empty.
TEST_F(BlendPassTest, HolesInTheViewTakeThePhotosSurface) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  Renderer r(shaders, scene_);  // the photos' depth maps from every point
  const int photo = 1;
  r.SetActivePhotos(SameSeriesExcept(photo));
  const RenderImages full = RenderPhotoView(r, photo);
  r.depth_pass().SetPoints(WithoutBackWallPatch(photo, full.depth));
  // With the background sphere (the default) and without a background.
  for (Background b : {Background::kSphere, Background::kNone}) {
    const HoleFill f = RenderHole(r, photo, full, b);
    EXPECT_GT(f.filled, 0.9) << BackgroundName(b);
    EXPECT_GT(f.psnr, f.psnr_full - 3.0) << BackgroundName(b);
  }
}

// A hole that no depth map holds (points missing from the cloud, as multi-view stereo leaves
// untextured surfaces) inside a wall: with a background, its pixels take the plane of the wall
// around them and the photos' colours there, nearly as well as with every point; without, they
// stay empty.
TEST_F(BlendPassTest, HolesThatNoDepthMapHoldsTakeTheSurfaceAroundThem) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  const int photo = 1;
  RenderImages full;
  {
    Renderer r(shaders, scene_);
    r.SetActivePhotos(SameSeriesExcept(photo));
    full = RenderPhotoView(r, photo);
  }
  Scene holed = scene_;
  holed.points = WithoutBackWallPatch(photo, full.depth);
  Renderer r(shaders, holed);  // the photos' depth maps lack the patch too
  r.SetActivePhotos(SameSeriesExcept(photo));
  for (Background b : {Background::kSphere, Background::kNone}) {
    const HoleFill f = RenderHole(r, photo, full, b);
    // The sphere alone covers about a third of the hole, at about 23 dB.
    if (b == Background::kNone) {
      EXPECT_LT(f.filled, 0.1);
    } else {
      EXPECT_GT(f.filled, 0.99);
      EXPECT_GT(f.psnr, f.psnr_full - 1.0);
    }
  }
}

// One rule for every blend option, whatever the weights, checked before any upload.
// The C++ mirror of the uniform block BlendParams has the compiled block's size and every
// member's offset, in both programs of the pass.
TEST(BlendParams, MirrorMatchesTheCompiledBlock) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  const auto programs = BlendPass::ReachablePrograms();
  ASSERT_FALSE(programs.empty());
  for (const char* file : {"blend.comp", "blend_background.comp"}) {
    const auto it = std::find_if(programs.begin(), programs.end(),
                                 [&](const auto& p) { return p.first == file; });
    ASSERT_NE(it, programs.end()) << file;
    const gl::Program program = shaders.Build({file}, it->second);
    const GLuint block = glGetProgramResourceIndex(program.id(), GL_UNIFORM_BLOCK, "BlendParams");
    ASSERT_NE(block, GL_INVALID_INDEX) << file;
    const GLenum size_prop = GL_BUFFER_DATA_SIZE;
    GLint size = 0;
    glGetProgramResourceiv(program.id(), GL_UNIFORM_BLOCK, block, 1, &size_prop, 1, nullptr, &size);
    EXPECT_EQ(size, static_cast<GLint>(sizeof(BlendParamsGpu))) << file;
    for (const auto& [name, offset] : BlendParamsLayout()) {
      const GLuint index = glGetProgramResourceIndex(program.id(), GL_UNIFORM, name.c_str());
      ASSERT_NE(index, GL_INVALID_INDEX) << file << " " << name;
      const GLenum offset_prop = GL_OFFSET;
      GLint at = -1;
      glGetProgramResourceiv(program.id(), GL_UNIFORM, index, 1, &offset_prop, 1, nullptr, &at);
      EXPECT_EQ(at, static_cast<GLint>(offset)) << file << " " << name;
    }
  }
}

TEST(BlendOptions, OneRuleCheckedBeforeAnyWork) {
  BlendOptions ok;
  EXPECT_TRUE(BlendOptionProblems(ok).empty());
  for (BlendWeights w : kAllBlendWeights) {
    BlendOptions o;
    o.weights = w;
    o.k_best = kMaxKBest;
    EXPECT_TRUE(BlendOptionProblems(o).empty());
    o.k_best = kMaxKBest + 1;
    ASSERT_EQ(BlendOptionProblems(o).size(), 1u);
    EXPECT_EQ(BlendOptionProblems(o)[0].field, "k_best");
    o.k_best = -1;
    EXPECT_EQ(BlendOptionProblems(o).size(), 1u);
  }
  BlendOptions bad;
  bad.lambda = 1.0f;
  bad.occlusion_tolerance = 0.0f;
  bad.filter = kMaxFilter * 1.01f;
  const auto problems = BlendOptionProblems(bad);
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0].field, "lambda");
  EXPECT_EQ(problems[1].field, "occlusion_tolerance");
  EXPECT_EQ(problems[2].field, "filter");
  bad = BlendOptions();
  bad.outlier_scale = -0.1f;
  ASSERT_EQ(BlendOptionProblems(bad).size(), 1u);
  EXPECT_EQ(BlendOptionProblems(bad)[0].field, "outlier_scale");
  bad.outlier_scale = std::nanf("");
  EXPECT_EQ(BlendOptionProblems(bad).size(), 1u);
  bad = BlendOptions();
  bad.refine_depth = kMaxRefineDepth * 1.01f;
  ASSERT_EQ(BlendOptionProblems(bad).size(), 1u);
  EXPECT_EQ(BlendOptionProblems(bad)[0].field, "refine_depth");
  bad.refine_depth = -0.001f;
  EXPECT_EQ(BlendOptionProblems(bad).size(), 1u);
  bad = BlendOptions();
  bad.filter = -0.01f;
  EXPECT_EQ(BlendOptionProblems(bad).size(), 1u);
  bad.filter = kMaxFilter;
  EXPECT_TRUE(BlendOptionProblems(bad).empty());
  bad.lambda = 1.0f;
  bad.occlusion_tolerance = 0.0f;
  try {
    ValidateBlendOptions(bad);
    ADD_FAILURE() << "no OptionError";
  } catch (const OptionError& e) {
    EXPECT_EQ(e.field(), "lambda");
    EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
  }
  // The renderer refuses them before it reads a photo: a scene whose photos do not exist.
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  Scene missing;
  missing.cameras[1] = Camera::Pinhole(1, 64, 48, 50, 50, 32, 24);
  Photo p;
  p.camera_id = 1;
  p.image_path = "/nonexistent/photo.png";
  missing.photos.push_back(p);
  RendererOptions ro;
  ro.blend.k_best = 40;
  ro.blend.weights = BlendWeights::kPaper;
  EXPECT_THROW(Renderer(shaders, missing, ro), OptionError);
  ro.blend.k_best = 4;
  EXPECT_THROW(Renderer(shaders, missing, ro), InputError);  // the photo, read after the check
}

// Mean |Laplacian| of a render's grey image over its valid pixels: its fine detail.
double Detail(const RenderImages& im) {
  cv::Mat grey, lap;
  cv::cvtColor(im.color, grey, cv::COLOR_BGR2GRAY);
  cv::Laplacian(grey, lap, CV_32F);
  return cv::mean(cv::abs(lap), im.valid)[0];
}

// Filtered blending (Eisemann et al. 2007): a photo at the view's own viewpoint has a line of
// disparity of length 0 and keeps every detail; photos elsewhere are low-passed (here over
// +-5 % of the depth), so a leave-one-out render loses high frequencies but keeps its pixels.
TEST_F(BlendPassTest, FilteredBlending) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  RendererOptions sharp_options, filtered_options;
  // The filter's taps are trilinear: compared with trilinear sampling, on the depth pass's depth.
  sharp_options.blend.sampling = filtered_options.blend.sampling = PhotoSampling::kLinear;
  sharp_options.blend.refine_depth = filtered_options.blend.refine_depth = 0.0f;
  filtered_options.blend.filter = 0.05f;
  Renderer sharp(shaders, scene_, sharp_options), filtered(shaders, scene_, filtered_options);
  for (int photo : {1, 8}) {
    std::vector<int> with = SameSeriesExcept(photo);
    with.push_back(photo);
    sharp.SetActivePhotos(with);
    filtered.SetActivePhotos(with);
    const RenderImages a = RenderPhotoView(sharp, photo), b = RenderPhotoView(filtered, photo);
    EXPECT_EQ(cv::countNonZero(a.valid != b.valid), 0);
    const cv::Mat diff = cv::abs(a.color - b.color);
    double max_diff = 0.0;
    cv::minMaxLoc(diff.reshape(1), nullptr, &max_diff, nullptr, nullptr, cv::repeat(a.valid, 1, 3));
    EXPECT_LT(max_diff, 0.02) << "photo " << photo << " at its own viewpoint";

    sharp.SetActivePhotos(SameSeriesExcept(photo));
    filtered.SetActivePhotos(SameSeriesExcept(photo));
    const RenderImages s = RenderPhotoView(sharp, photo), f = RenderPhotoView(filtered, photo);
    ExpectSane(f, 5);
    EXPECT_EQ(cv::countNonZero(s.valid != f.valid), 0);
    const double psnr_s = Psnr(s, photo), psnr_f = Psnr(f, photo);
    std::printf("photo %d: detail %.4f -> %.4f, PSNR %.2f -> %.2f dB\n", photo, Detail(s),
                Detail(f), psnr_s, psnr_f);
    EXPECT_LT(Detail(f), 0.9 * Detail(s));
    EXPECT_GT(psnr_f, 20.0);  // a blurred picture of the scene, not noise
  }
}

// Catmull-Rom sampling interpolates: at a photo's own viewpoint (its texel centres) it returns
// the photo's values as trilinear sampling does; between texels it keeps more detail, and the
// leave-one-out render is closer to the held-out photo.
TEST_F(BlendPassTest, CubicSampling) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  RendererOptions linear_options, cubic_options;
  EXPECT_EQ(cubic_options.blend.sampling, PhotoSampling::kCubic);  // the default
  linear_options.blend.sampling = PhotoSampling::kLinear;
  Renderer linear(shaders, scene_, linear_options), cubic(shaders, scene_, cubic_options);
  for (int photo : {1, 8}) {
    linear.SetActivePhotos({photo});
    cubic.SetActivePhotos({photo});
    const RenderImages a = RenderPhotoView(linear, photo), b = RenderPhotoView(cubic, photo);
    EXPECT_EQ(cv::countNonZero(a.valid != b.valid), 0);
    EXPECT_LT(cv::norm(a.color, b.color, cv::NORM_INF, a.valid), 2e-3) << "photo " << photo;

    linear.SetActivePhotos(SameSeriesExcept(photo));
    cubic.SetActivePhotos(SameSeriesExcept(photo));
    const RenderImages l = RenderPhotoView(linear, photo), c = RenderPhotoView(cubic, photo);
    ExpectSane(c, 5);
    EXPECT_EQ(cv::countNonZero(l.valid != c.valid), 0);
    const double psnr_l = Psnr(l, photo), psnr_c = Psnr(c, photo);
    std::printf("photo %d: linear %.2f dB detail %.4f, cubic %.2f dB detail %.4f\n", photo, psnr_l,
                Detail(l), psnr_c, Detail(c));
    EXPECT_GT(Detail(c), 1.05 * Detail(l));
    EXPECT_GT(psnr_c, psnr_l);
  }
  EXPECT_EQ(ParsePhotoSampling("cubic"), PhotoSampling::kCubic);
  EXPECT_THROW(ParsePhotoSampling("lanczos"), UsageError);
}

// Photometric outlier rejection: one input photo replaced by a white picture pulls the plain
// blend towards white wherever it ranks among the K best; the reweighting discards it. With a
// huge scale the reweighting changes nothing.
TEST_F(BlendPassTest, OutlierRejection) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  const int photo = 2, bad = 3;
  const std::filesystem::path white = test::TempDir("blend_outlier") / "white.png";
  const cv::Mat original = ReadImage(scene_.photos[bad].image_path);
  WriteImage(white, cv::Mat(original.size(), CV_8UC3, cv::Scalar(255, 255, 255)));
  Scene corrupt = scene_;
  corrupt.photos[bad].image_path = white;
  RendererOptions plain_options, robust_options;
  EXPECT_EQ(robust_options.blend.outlier_scale, 0.08f);  // the default
  plain_options.blend.outlier_scale = 0.0f;
  Renderer plain(shaders, corrupt, plain_options), robust(shaders, corrupt, robust_options);
  plain.SetActivePhotos(SameSeriesExcept(photo));
  robust.SetActivePhotos(SameSeriesExcept(photo));
  const RenderImages p = RenderPhotoView(plain, photo), r = RenderPhotoView(robust, photo);
  ExpectSane(r, kDefaultUnstructuredK);
  EXPECT_EQ(cv::countNonZero(p.valid != r.valid), 0);
  const double psnr_p = Psnr(p, photo), psnr_r = Psnr(r, photo);
  std::printf("photo %d with photo %d white: plain %.2f dB, outliers rejected %.2f dB\n", photo,
              bad, psnr_p, psnr_r);
  EXPECT_GT(psnr_r, psnr_p + 1.0);
  robust.blend_options().outlier_scale = 1e6f;
  EXPECT_LT(cv::norm(RenderPhotoView(robust, photo).color, p.color, cv::NORM_INF, p.valid), 1e-4);
}

// Photo-consistent depth: with the cloud pushed 2 % away from the held-out view along its rays
// (the view's depth 2 % too far, its silhouettes unchanged), the photos' pixels of a surface
// point land apart and the blend blurs; a search over +-2 % of the depth realigns them. On the
// exact cloud the default search keeps the render as close to the photo. Pixel validity never
// changes.
TEST_F(BlendPassTest, PhotoConsistentDepth) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  EXPECT_EQ(BlendOptions().refine_depth, 0.003f);  // the default
  RendererOptions off, on_wide, on_default;
  off.blend.refine_depth = 0.0f;
  on_wide.blend.refine_depth = 0.02f;
  for (int photo : {1, 8}) {
    Scene pushed = scene_;
    const Eigen::Vector3f c = scene_.photos[static_cast<size_t>(photo)].Center().cast<float>();
    for (Eigen::Vector3f& p : pushed.points.positions) p = c + 1.02f * (p - c);
    const auto [a, b] = LeaveOneOutPair(shaders, pushed, off, on_wide, photo);
    ExpectSane(b, kDefaultUnstructuredK);
    const auto [e, d] = LeaveOneOutPair(shaders, scene_, off, on_default, photo);
    const double psnr_off = Psnr(a, photo), psnr_on = Psnr(b, photo);
    const double exact_off = Psnr(e, photo), exact_default = Psnr(d, photo);
    std::printf(
        "photo %d: depth 2 %% off: %.2f dB, refined over +-2 %% %.2f dB; exact: %.2f dB, "
        "refined (default) %.2f dB\n",
        photo, psnr_off, psnr_on, exact_off, exact_default);
    EXPECT_GT(psnr_on, psnr_off + 1.0);
    EXPECT_GT(exact_default, exact_off - 0.1);
  }
}

TEST_F(BlendPassTest, UnstructuredLumigraphWeights) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  RendererOptions ro;
  EXPECT_EQ(ro.blend.weights, BlendWeights::kUnstructured);  // the default
  ro.blend.k_best = 2;
  Renderer r(shaders, scene_, ro);
  // Photo 3 among the inputs, seen from its own viewpoint: its penalty is ~0, so its normalised
  // weight is ~1 wherever it sees the surface (the paper's eq. 5 spreads it over every photo).
  std::vector<int> with = SameSeriesExcept(3);
  with.push_back(3);
  r.SetActivePhotos(with);
  r.blend_options().debug_photo = 3;
  const RenderImages self = RenderPhotoView(r, 3);
  ExpectSane(self, 2);
  double max_count = 0;
  cv::minMaxLoc(self.count, nullptr, &max_count);
  EXPECT_LE(max_count, 2.0);  // at most K photos per pixel
  const cv::Mat seen = (self.weight > 0.0f) & (self.valid > 0);
  ASSERT_GT(cv::countNonZero(seen), 1000);
  EXPECT_GT(cv::mean(self.weight, seen)[0], 0.97);
  r.blend_options().weights = BlendWeights::kPaper;
  r.blend_options().k_best = 0;  // all photos
  const RenderImages paper = RenderPhotoView(r, 3);
  EXPECT_LT(cv::mean(paper.weight, seen)[0], 0.6);
  // Leave-one-out: the same coverage as the paper's weights (same visibility tests) and a
  // closer image (docs/decisions/0004 has the figures of the default capture).
  r.SetActivePhotos(SameSeriesExcept(3));
  r.blend_options().debug_photo = -1;
  const RenderImages paper_loo = RenderPhotoView(r, 3);
  r.blend_options().weights = BlendWeights::kUnstructured;
  r.blend_options().k_best = 0;  // the default K
  const RenderImages ulr_loo = RenderPhotoView(r, 3);
  ExpectSane(ulr_loo, kDefaultUnstructuredK);
  EXPECT_EQ(cv::countNonZero(ulr_loo.valid != paper_loo.valid), 0);
  const double p_paper = Psnr(paper_loo, 3), p_ulr = Psnr(ulr_loo, 3);
  std::printf("leave-one-out photo 3: paper weights %.2f dB, ULR K=%d %.2f dB\n", p_paper,
              kDefaultUnstructuredK, p_ulr);
  EXPECT_GT(p_ulr, p_paper);
  EXPECT_EQ(ParseBlendWeights(BlendWeightsName(BlendWeights::kUnstructured)),
            BlendWeights::kUnstructured);
  EXPECT_THROW(ParseBlendWeights("cosine"), UsageError);
}

TEST_F(BlendPassTest, PhotoSizesFloatPhotosAndMaxPhotoSize) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  const std::vector<int> others = SameSeriesExcept(4);
  // The paper's weights spread the weight over every photo, so the loss from the half-size
  // photos below stays bounded whichever photo is the nearest (ULR lets it dominate).
  RendererOptions paper;
  paper.blend.weights = BlendWeights::kPaper;
  Renderer base(shaders, scene_, paper);
  base.SetActivePhotos(others);
  const RenderImages ref = RenderPhotoView(base, 4);
  const size_t base_bytes = base.gpu_bytes();

  // Different sizes: every other photo at half size (the array keeps the largest).
  RendererOptions mixed = paper;
  for (size_t i = 0; i < scene_.photos.size(); ++i) {
    cv::Mat img = ReadImage(scene_.photos[i].image_path);
    if (i % 2 == 1) cv::resize(img, img, cv::Size(80, 60), 0, 0, cv::INTER_AREA);
    mixed.photo_images.push_back(img);
  }
  Renderer r_mixed(shaders, scene_, mixed);
  r_mixed.SetActivePhotos(others);
  const RenderImages im_mixed = RenderPhotoView(r_mixed, 4);
  ExpectSane(im_mixed, 5);
  const double p_ref = Psnr(ref, 4), p_mixed = Psnr(im_mixed, 4);
  std::printf("sizes: full %.2f dB, half-size odd photos %.2f dB\n", p_ref, p_mixed);
  EXPECT_GT(p_mixed, p_ref - 3.0);
  EXPECT_EQ(cv::countNonZero(im_mixed.valid != ref.valid), 0);

  // Float photos (an HDR photo set path): RGBA16F, same values as the 8-bit photos / 255.
  RendererOptions fl = paper;
  for (size_t i = 0; i < scene_.photos.size(); ++i) {
    cv::Mat f;
    ReadImage(scene_.photos[i].image_path).convertTo(f, CV_32FC3, 1.0 / 255.0);
    fl.photo_images.push_back(f);
  }
  Renderer r_float(shaders, scene_, fl);
  r_float.SetActivePhotos(others);
  EXPECT_GT(r_float.gpu_bytes(), base_bytes);  // RGBA16F: twice the photo bytes
  const RenderImages im_float = RenderPhotoView(r_float, 4);
  EXPECT_LT(cv::norm(im_float.color, ref.color, cv::NORM_INF), 2.0 / 255.0);

  // --max-photo-size: smaller textures, a blurrier but still close render.
  RendererOptions small = paper;
  small.max_photo_size = 64;
  Renderer r_small(shaders, scene_, small);
  r_small.SetActivePhotos(others);
  EXPECT_LT(r_small.gpu_bytes(), base_bytes);
  const RenderImages im_small = RenderPhotoView(r_small, 4);
  ExpectSane(im_small, 5);
  const double p_small = Psnr(im_small, 4);
  std::printf("max-photo-size 64: %.2f dB, %zu vs %zu bytes\n", p_small, r_small.gpu_bytes(),
              base_bytes);
  EXPECT_LT(p_small, p_ref);
  EXPECT_GT(p_small, 18.0);
}

TEST_F(BlendPassTest, RadianceEncodingMatchesAcrossSeries) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  RendererOptions ro;
  ro.blend.encoding = PhotoEncoding::kRadiance;
  ro.response = ReadResponseCurve(*dir_ / "calib" / "response.json");
  Renderer r(shaders, scene_, ro);
  // The same viewpoint from each series alone, in radiance: exposure divided out, so the two
  // agree where both are well exposed (mid-range values).
  std::vector<int> s0, s1;
  for (size_t i = 0; i < scene_.photos.size(); ++i) {
    if (i == 0 || i == 6) continue;  // photos 0 and 6 share view 0
    (scene_.photos[i].series_id == 0 ? s0 : s1).push_back(static_cast<int>(i));
  }
  r.SetActivePhotos(s0);
  const RenderImages a = RenderPhotoView(r, 0);
  r.SetActivePhotos(s1);
  const RenderImages b = RenderPhotoView(r, 0);
  ExpectSane(a, 5);
  ExpectSane(b, 5);
  const cv::Mat dark = ReadImage(scene_.photos[0].image_path);
  const cv::Mat bright = ReadImage(scene_.photos[6].image_path);
  double log_ratio_sum = 0;
  long n = 0;
  for (int y = 0; y < a.color.rows; ++y) {
    for (int x = 0; x < a.color.cols; ++x) {
      if (!a.valid.at<uint8_t>(y, x) || !b.valid.at<uint8_t>(y, x)) continue;
      const int zd = dark.at<cv::Vec3b>(y, x)[1], zb = bright.at<cv::Vec3b>(y, x)[1];
      if (zd < 40 || zb > 215) continue;
      log_ratio_sum +=
          std::abs(std::log(a.color.at<cv::Vec3f>(y, x)[1] / b.color.at<cv::Vec3f>(y, x)[1]));
      ++n;
    }
  }
  ASSERT_GT(n, 500);
  const double mean_abs_log = log_ratio_sum / static_cast<double>(n);
  std::printf("radiance series agreement: mean |ln ratio| %.4f over %ld pixels\n", mean_abs_log, n);
  EXPECT_LT(mean_abs_log, 0.15);
  // Without a response curve, radiance blending is refused.
  RendererOptions bad;
  bad.blend.encoding = PhotoEncoding::kRadiance;
  Renderer r_bad(shaders, scene_, bad);
  EXPECT_THROW(RenderPhotoView(r_bad, 0), UsageError);
}

}  // namespace
}  // namespace hdribr::render
