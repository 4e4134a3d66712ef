// The cache of the photos' depth maps (render/photo_depth_maps.h with a cache folder): a warm
// start gives exactly the floats of a cold one, every input of the key changes it, and a bad
// file or an unwritable folder only costs a warning.
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "analytic_scene.h"
#include "core/error.h"
#include "gl_test_util.h"
#include "io/depth_map_cache.h"
#include "render/photo_depth_key.h"
#include "render/photo_depth_maps.h"
#include "render/readback.h"
#include "render/renderer.h"
#include "test_util.h"

namespace hdribr::render {
namespace {
namespace fs = std::filesystem;

// Everything spdlog logs while it lives.
class LogCapture {
 public:
  LogCapture() : sink_(std::make_shared<spdlog::sinks::ostream_sink_mt>(stream_)) {
    spdlog::default_logger()->sinks().push_back(sink_);
  }
  ~LogCapture() {
    auto& sinks = spdlog::default_logger()->sinks();
    sinks.erase(std::find(sinks.begin(), sinks.end(), sink_));
  }
  std::string text() const { return stream_.str(); }
  // Occurrences of `part` in the log.
  int Count(const std::string& part) const {
    const std::string t = text();
    int n = 0;
    for (size_t at = t.find(part); at != std::string::npos; at = t.find(part, at + 1)) ++n;
    return n;
  }

 private:
  std::ostringstream stream_;
  std::shared_ptr<spdlog::sinks::ostream_sink_mt> sink_;
};

bool SameBits(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && a.isContinuous() && b.isContinuous() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

class PhotoDepthCacheTest : public test::GlSuite {
 protected:
  // Three photos of two spheres and a plane (two 96x96 cameras' views, one 64x64).
  static Scene MakeScene() {
    Scene s;
    s.cameras[1] = test::TestCamera(96);
    s.cameras[2] = test::TestCamera(64);
    s.cameras[2].id = 2;
    const Eigen::Vector3d target(0, 0, 3.2), up(0, -1, 0);
    for (int i = 0; i < 3; ++i) {
      const double a = (-20.0 + 22.0 * i) * M_PI / 180.0;
      const Eigen::Vector3d eye = target + 3.2 * Eigen::Vector3d(std::sin(a), 0.1, -std::cos(a));
      Photo p;
      p.id = i + 1;
      p.name = "p" + std::to_string(i);
      p.camera_id = i == 2 ? 2 : 1;
      p.cam_from_world = LookAt(eye, target, up);
      s.photos.push_back(p);
    }
    s.points = test::AnalyticScene::SpheresAndPlane().Sample(6000);
    s.UpdateDerived();
    return s;
  }

  // Every layer of the maps' texture, whole (padding included).
  static std::vector<cv::Mat> Layers(const PhotoDepthMaps& maps) {
    std::vector<cv::Mat> layers;
    for (int i = 0; i < maps.depth().layers(); ++i) {
      layers.push_back(ReadTextureLayerR32F(maps.depth(), i));
    }
    return layers;
  }

  static void ExpectSameLayers(const PhotoDepthMaps& a, const PhotoDepthMaps& b) {
    const std::vector<cv::Mat> la = Layers(a), lb = Layers(b);
    ASSERT_EQ(la.size(), lb.size());
    for (size_t i = 0; i < la.size(); ++i) {
      EXPECT_TRUE(SameBits(la[i], lb[i])) << "layer " << i;
      EXPECT_EQ(a.layer_size(static_cast<int>(i)), b.layer_size(static_cast<int>(i)));
    }
  }

  // Renderer options with random pixels for every photo of `s`.
  static RendererOptions RandomPhotos(const Scene& s, int seed) {
    RendererOptions options;
    cv::RNG rng(static_cast<std::uint64_t>(seed));
    for (const Photo& p : s.photos) {
      const Camera& cam = s.CameraOf(p);
      cv::Mat img(cam.height, cam.width, CV_8UC3);
      rng.fill(img, cv::RNG::UNIFORM, 0, 256);
      options.photo_images.push_back(img);
    }
    return options;
  }

  // A view between the photos, looking at the scene.
  static Rigid3d ViewPose() {
    return LookAt(Eigen::Vector3d(0.3, 0.2, -0.1), Eigen::Vector3d(0, 0, 3.2),
                  Eigen::Vector3d(0, -1, 0));
  }

  static size_t FilesIn(const fs::path& dir) {
    return static_cast<size_t>(std::distance(fs::directory_iterator(dir), {}));
  }
};

TEST_F(PhotoDepthCacheTest, WarmStartReadsTheSameFloats) {
  const Scene s = MakeScene();
  DepthPass pass(*shaders_);
  pass.SetPoints(s.points);
  const fs::path dir = test::TempDir() / "cache";
  const PhotoDepthMaps reference(s, pass);
  EXPECT_FALSE(reference.from_cache());

  LogCapture log;
  const PhotoDepthMaps cold(s, pass, 1.0, dir);
  EXPECT_FALSE(cold.from_cache());
  const fs::path file = DepthMapCacheFile(dir, PhotoDepthMapsKey(s, pass, 1.0));
  ASSERT_TRUE(fs::exists(file));
  EXPECT_EQ(FilesIn(dir), 1u);
  EXPECT_EQ(log.Count("photo depth maps: 3 computed in"), 1) << log.text();
  EXPECT_EQ(log.Count("cached to " + file.string()), 1) << log.text();

  const PhotoDepthMaps warm(s, pass, 1.0, dir);
  EXPECT_TRUE(warm.from_cache());
  EXPECT_EQ(log.Count("photo depth maps: 3 from cache " + file.string()), 1) << log.text();
  EXPECT_EQ(log.Count("[warning]"), 0) << log.text();
  ExpectSameLayers(reference, cold);
  ExpectSameLayers(reference, warm);
  EXPECT_GT(cv::countNonZero(Layers(warm)[2]), 64 * 64 / 2);

  // The warm maps are the file's: other floats under the same key come back as they are.
  std::vector<cv::Mat> fake;
  for (int i = 0; i < 3; ++i) fake.emplace_back(warm.layer_size(i), CV_32FC1, cv::Scalar(i + 0.5));
  WriteDepthMapCache(file, PhotoDepthMapsKey(s, pass, 1.0), fake);
  const PhotoDepthMaps faked(s, pass, 1.0, dir);
  ASSERT_TRUE(faked.from_cache());
  const cv::Mat layer1 = Layers(faked)[1];
  EXPECT_EQ(layer1.at<float>(10, 10), 1.5f);
  EXPECT_EQ(Layers(faked)[2].at<float>(80, 80), 0.0f);  // outside the 64x64 photo: cleared
}

TEST_F(PhotoDepthCacheTest, EveryInputOfTheKeyChangesIt) {
  const Scene s = MakeScene();
  DepthPass pass(*shaders_);
  pass.SetPoints(s.points);
  const std::uint64_t base = PhotoDepthMapsKey(s, pass, 1.0);
  EXPECT_EQ(PhotoDepthMapsKey(s, pass, 1.0), base);

  // Options that do not change the output keep the key.
  pass.options().profile = true;
  pass.options().points_per_dispatch = 1000;
  pass.options().layered_classify = false;
  EXPECT_EQ(PhotoDepthMapsKey(s, pass, 1.0), base);
  pass.options() = DepthPassOptions();

  std::vector<std::uint64_t> keys = {base};
  const auto with_option = [&](auto change) {
    change(pass.options());
    keys.push_back(PhotoDepthMapsKey(s, pass, 1.0));
    pass.options() = DepthPassOptions();
  };
  with_option([](DepthPassOptions& o) { o.mode = DepthMode::kMarroquim; });
  with_option([](DepthPassOptions& o) { o.mode = DepthMode::kPlain; });
  with_option([](DepthPassOptions& o) { o.raster = PointRaster::kPipeline; });
  with_option([](DepthPassOptions& o) { o.front_radii *= 1.5f; });
  with_option([](DepthPassOptions& o) { o.front_rel *= 2.0f; });
  with_option([](DepthPassOptions& o) { o.silhouette_trim = 0; });
  keys.push_back(PhotoDepthMapsKey(s, pass, 0.5));

  const auto with_scene = [&](auto change) {
    Scene t = s;
    change(t);
    pass.SetPoints(t.points);
    keys.push_back(PhotoDepthMapsKey(t, pass, 1.0));
    pass.SetPoints(s.points);
  };
  with_scene([](Scene& t) { t.points.positions[17].x() += 1e-4f; });
  with_scene([](Scene& t) { t.points.normals[17].y() += 1e-3f; });
  with_scene([](Scene& t) { t.points.radii[17] *= 1.01f; });
  with_scene([](Scene& t) {
    t.points.positions.pop_back();
    t.points.normals.pop_back();
    t.points.radii.pop_back();
  });
  with_scene([](Scene& t) {  // no radii: the default radius the pass computes
    t.points.radii.clear();
  });
  with_scene([](Scene& t) { t.cameras[1].params[0] += 0.01; });
  with_scene([](Scene& t) { t.cameras[2] = t.cameras[2].Scaled(60, 60); });
  with_scene([](Scene& t) { t.photos[1].cam_from_world.translation.z() += 1e-6; });
  with_scene(
      [](Scene& t) { t.photos[0].cam_from_world.rotation = t.photos[1].cam_from_world.rotation; });
  with_scene([](Scene& t) { std::swap(t.photos[0], t.photos[1]); });  // layer order
  with_scene([](Scene& t) { t.photos.pop_back(); });
  EXPECT_EQ(PhotoDepthMapsKey(s, pass, 1.0), base);  // the scene itself is back

  // The pass's shaders: a changed depth-pass source changes the key, another one does not.
  std::map<std::string, std::string> sources = gl::EmbeddedShaders();
  sources["resolve.comp"] += "\n// changed\n";
  const gl::ShaderLibrary changed(sources);
  DepthPass changed_pass(changed);
  changed_pass.SetPoints(s.points);
  keys.push_back(PhotoDepthMapsKey(s, changed_pass, 1.0));
  sources = gl::EmbeddedShaders();
  sources["tonemap.comp"] += "\n// changed\n";
  const gl::ShaderLibrary unrelated(sources);
  DepthPass unrelated_pass(unrelated);
  unrelated_pass.SetPoints(s.points);
  EXPECT_EQ(PhotoDepthMapsKey(s, unrelated_pass, 1.0), base);

  std::vector<std::uint64_t> sorted = keys;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::unique(sorted.begin(), sorted.end()), sorted.end())
      << "two different inputs gave the same key";
  EXPECT_EQ(keys.size(), 20u);
}

TEST_F(PhotoDepthCacheTest, ChangedInputMissesAndComputes) {
  const Scene s = MakeScene();
  DepthPass pass(*shaders_);
  pass.SetPoints(s.points);
  const fs::path dir = test::TempDir() / "cache";
  ASSERT_FALSE(PhotoDepthMaps(s, pass, 1.0, dir).from_cache());

  Scene moved = s;
  for (auto& p : moved.points.positions) p.z() -= 0.3f;  // everything nearer
  pass.SetPoints(moved.points);
  const PhotoDepthMaps reference(moved, pass);
  const PhotoDepthMaps missed(moved, pass, 1.0, dir);
  EXPECT_FALSE(missed.from_cache());
  ExpectSameLayers(reference, missed);
  EXPECT_EQ(FilesIn(dir), 2u);

  pass.options().mode = DepthMode::kPlain;
  EXPECT_FALSE(PhotoDepthMaps(moved, pass, 1.0, dir).from_cache());
  pass.options().mode = DepthMode::kLechelek;
  EXPECT_FALSE(PhotoDepthMaps(moved, pass, 0.5, dir).from_cache());
  EXPECT_TRUE(PhotoDepthMaps(moved, pass, 1.0, dir).from_cache());
  // Four keys: the least recently used one, the first scene's, was removed.
  EXPECT_EQ(FilesIn(dir), kDepthMapCacheKeep);
  pass.SetPoints(s.points);
  EXPECT_FALSE(PhotoDepthMaps(s, pass, 1.0, dir).from_cache());
}

TEST_F(PhotoDepthCacheTest, BadFileIsIgnoredWithAWarningAndReplaced) {
  const Scene s = MakeScene();
  DepthPass pass(*shaders_);
  pass.SetPoints(s.points);
  const fs::path dir = test::TempDir() / "cache";
  const PhotoDepthMaps reference(s, pass, 1.0, dir);
  const fs::path file = DepthMapCacheFile(dir, PhotoDepthMapsKey(s, pass, 1.0));
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 0x40);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {bytes.substr(0, bytes.size() / 2), "truncated"},
      {flipped, "checksum mismatch"},
      {"garbage", "not a depth map cache file"},
      {"", "not a depth map cache file"}};
  for (const auto& [contents, problem] : bad) {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << contents;
    LogCapture log;
    const PhotoDepthMaps recomputed(s, pass, 1.0, dir);
    EXPECT_FALSE(recomputed.from_cache()) << problem;
    EXPECT_EQ(log.Count("[warning]"), 1) << log.text();
    EXPECT_EQ(log.Count("ignoring the cache (" + file.string() + ": " + problem), 1) << log.text();
    EXPECT_EQ(log.Count("cached to " + file.string()), 1) << log.text();
    ExpectSameLayers(reference, recomputed);
    // Replaced by a sound file.
    const PhotoDepthMaps warm(s, pass, 1.0, dir);
    EXPECT_TRUE(warm.from_cache()) << problem;
    ExpectSameLayers(reference, warm);
  }
}

TEST_F(PhotoDepthCacheTest, UnwritableFolderStillComputesAndWarnsOnce) {
  const Scene s = MakeScene();
  DepthPass pass(*shaders_);
  pass.SetPoints(s.points);
  const PhotoDepthMaps reference(s, pass);
  // A file where the cache folder's parent should be (permissions do not stop root).
  const fs::path blocker = test::TempDir() / "cache";
  std::ofstream(blocker) << "not a folder";
  LogCapture log;
  for (int i = 0; i < 2; ++i) {
    const PhotoDepthMaps maps(s, pass, 1.0, blocker / "depth_maps");
    EXPECT_FALSE(maps.from_cache());
    ExpectSameLayers(reference, maps);
  }
  EXPECT_EQ(log.Count("[warning]"), 1) << log.text();
  EXPECT_EQ(log.Count("photo depth maps: not cached ("), 1) << log.text();
  EXPECT_EQ(log.Count("photo depth maps: 3 computed in"), 2) << log.text();
  EXPECT_TRUE(fs::is_regular_file(blocker));
}

TEST_F(PhotoDepthCacheTest, OnlyTheMostRecentKeysAreKept) {
  const Scene s = MakeScene();
  DepthPass pass(*shaders_);
  pass.SetPoints(s.points);
  const fs::path dir = test::TempDir() / "cache";
  const std::vector<double> scales = {1.0, 0.9, 0.8, 0.7, 0.6};
  for (double scale : scales) {
    const PhotoDepthMaps maps(s, pass, scale, dir);
    EXPECT_FALSE(maps.from_cache());
  }
  EXPECT_EQ(FilesIn(dir), kDepthMapCacheKeep);
  for (size_t i = 0; i < scales.size(); ++i) {
    const bool kept = i + kDepthMapCacheKeep >= scales.size();
    EXPECT_EQ(fs::exists(DepthMapCacheFile(dir, PhotoDepthMapsKey(s, pass, scales[i]))), kept)
        << "scale " << scales[i];
  }
}

TEST_F(PhotoDepthCacheTest, RendererWithAWarmCacheRendersTheSameBytes) {
  const Scene s = MakeScene();
  const RendererOptions options = RandomPhotos(s, 3);
  const Camera view_cam = test::TestCamera(80);
  const Rigid3d view = ViewPose();
  const auto render = [&](const fs::path& cache, bool expect_cached) {
    RendererOptions o = options;
    o.depth_cache_dir = cache;
    Renderer r(*shaders_, s, o);
    EXPECT_EQ(r.depth_maps_from_cache(), expect_cached);
    return r.RenderToImages(view_cam, view, view_cam.width, view_cam.height);
  };
  const fs::path dir = test::TempDir() / "cache";
  const RenderImages none = render({}, false);
  const RenderImages cold = render(dir, false);
  const RenderImages warm = render(dir, true);
  EXPECT_GT(cv::countNonZero(none.valid), 80 * 80 / 3);
  for (const RenderImages* im : {&cold, &warm}) {
    EXPECT_TRUE(SameBits(im->color, none.color));
    EXPECT_TRUE(SameBits(im->valid, none.valid));
    EXPECT_TRUE(SameBits(im->depth, none.depth));
    EXPECT_TRUE(SameBits(im->count, none.count));
  }
}

// Depth given instead of computed (the perfect-depth reference of `eval`): the depth pass's own
// maps given back, for the photos and the view, render the same bytes.
TEST_F(PhotoDepthCacheTest, GivenDepthsRenderTheSameBytes) {
  const Scene s = MakeScene();
  const RendererOptions options = RandomPhotos(s, 5);
  DepthPass pass(*shaders_);
  pass.SetPoints(s.points);
  const PhotoDepthMaps computed(s, pass);
  std::vector<cv::Mat> given_maps;
  for (int i = 0; i < computed.count(); ++i) {
    const cv::Size size = computed.layer_size(i);
    given_maps.push_back(ReadTextureLayerR32F(computed.depth(), i)(cv::Rect({0, 0}, size)).clone());
  }
  const Camera view_cam = test::TestCamera(80);
  const Rigid3d view = ViewPose();
  Renderer splat(*shaders_, s, options);
  const RenderImages reference = splat.RenderToImages(view_cam, view, 80, 80);
  EXPECT_GT(cv::countNonZero(reference.valid), 80 * 80 / 3);

  RendererOptions with_maps = options;
  with_maps.photo_depths = given_maps;
  Renderer given(*shaders_, s, with_maps);
  const GivenDepth view_depth{reference.depth, reference.normal};
  const RenderImages out = given.RenderToImages(view_cam, view, 80, 80, &view_depth);
  EXPECT_TRUE(SameBits(out.color, reference.color));
  EXPECT_TRUE(SameBits(out.valid, reference.valid));
  EXPECT_TRUE(SameBits(out.depth, reference.depth));
  EXPECT_TRUE(SameBits(out.count, reference.count));

  // A wrong count of maps or a view depth of another size is refused.
  with_maps.photo_depths.pop_back();
  EXPECT_THROW(Renderer(*shaders_, s, with_maps), UsageError);
  const GivenDepth small{cv::Mat(40, 40, CV_32FC1, cv::Scalar(1)),
                         cv::Mat(40, 40, CV_32FC3, cv::Scalar(0, 0, -1))};
  EXPECT_THROW(given.RenderToImages(view_cam, view, 80, 80, &small), UsageError);
}

}  // namespace
}  // namespace hdribr::render
