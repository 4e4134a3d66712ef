// WriteWebBundle (io/web_bundle.h) on a scene made in code: the files, scene.json's fields,
// the points as the viewer decodes them, resized photos, and a refused output folder.
#include "io/web_bundle.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <array>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "core/error.h"
#include "io/atomic_file.h"
#include "test_util.h"

namespace hdribr {
namespace {

namespace fs = std::filesystem;

// Two photos of one 64x48 camera looking down +z at a grid of points on z = 2.
Scene TinyScene(const fs::path& dir) {
  Scene scene;
  scene.workspace = dir;
  scene.cameras[1] = Camera::Pinhole(1, 64, 48, 50, 50, 32, 24);
  for (int i = 0; i < 2; ++i) {
    Photo p;
    p.id = i + 1;
    p.name = "p" + std::to_string(i) + ".png";
    p.image_path = dir / p.name;
    p.camera_id = 1;
    p.cam_from_world.translation = Eigen::Vector3d(0.1 * i, 0, 0);
    cv::imwrite(p.image_path.string(), cv::Mat(48, 64, CV_8UC3, cv::Scalar(10, 20 * i, 30)));
    scene.photos.push_back(p);
  }
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 30; ++x) {
      scene.points.positions.emplace_back(0.05f * x - 0.7f, 0.05f * y - 0.5f, 2.0f + 0.01f * x);
      scene.points.normals.emplace_back(0.0f, 0.0f, -1.0f);
      scene.points.radii.push_back(0.02f + 0.001f * y);
    }
  }
  scene.UpdateDerived();
  return scene;
}

// points.bin inflated and decoded as web/viewer/bundle.js does: positions in the bounds.
std::vector<Eigen::Vector3f> DecodePoints(const fs::path& file, const nlohmann::json& desc) {
  const std::string z = ReadFileToString(file);
  const size_t n = desc["count"].get<size_t>();
  std::vector<unsigned char> planes(n * kWebPointBytes);
  uLongf size = planes.size();
  EXPECT_EQ(uncompress(planes.data(), &size, reinterpret_cast<const Bytef*>(z.data()), z.size()),
            Z_OK);
  EXPECT_EQ(size, planes.size());
  std::vector<Eigen::Vector3f> out;
  std::array<int, 3> prev = {0, 0, 0};
  for (size_t k = 0; k < n; ++k) {
    Eigen::Vector3f p;
    for (int a = 0; a < 3; ++a) {
      const int d = planes[2 * a * n + k] | (planes[(2 * a + 1) * n + k] << 8);
      prev[a] = (prev[a] + d) & 0xffff;
      const float lo = desc["min"][a], hi = desc["max"][a];
      p[a] = lo + prev[a] / 65535.0f * (hi - lo);
    }
    out.push_back(p);
  }
  return out;
}

TEST(WebBundle, WritesTheViewerTheSceneAndThePoints) {
  const fs::path dir = test::TempDir("web_bundle");
  const Scene scene = TinyScene(dir);
  WebBundleOptions opt;
  opt.max_photo_size = 32;  // the 64x48 photos are reduced to 32x24
  const fs::path out = dir / "bundle";
  const WebBundleReport r = WriteWebBundle(scene, out, opt);
  EXPECT_TRUE(fs::exists(out / "index.html"));
  EXPECT_TRUE(fs::exists(out / "viewer" / "main.js"));
  EXPECT_FALSE(fs::exists(dir / "bundle.partial"));
  EXPECT_EQ(r.photo_count, 2);
  EXPECT_EQ(r.point_count, scene.points.size());
  const nlohmann::json j = nlohmann::json::parse(ReadFileToString(out / "capture/scene.json"));
  EXPECT_EQ(j["format"], "hdribr-web");
  EXPECT_EQ(j["version"], kWebBundleVersion);
  ASSERT_EQ(j["photos"].size(), 2u);
  EXPECT_EQ(j["photos"][1]["name"], "p1.png");
  EXPECT_EQ(j["photos"][1]["image_size"], nlohmann::json({32, 24}));
  EXPECT_EQ(cv::imread((out / "capture" / j["photos"][1]["file"].get<std::string>()).string()).cols,
            32);
  EXPECT_DOUBLE_EQ(j["photos"][1]["tvec"][0].get<double>(), 0.1);
  EXPECT_EQ(j["cameras"]["1"]["fx"], 50.0);
  EXPECT_TRUE(j["response"].is_null());  // an uncalibrated workspace
  // Every point comes back within the quantisation step, in some order.
  const std::vector<Eigen::Vector3f> decoded =
      DecodePoints(out / "capture/points.bin", j["points"]);
  ASSERT_EQ(decoded.size(), scene.points.size());
  for (const Eigen::Vector3f& p : scene.points.positions) {
    float best = 1e9f;
    for (const Eigen::Vector3f& d : decoded) best = std::min(best, (d - p).norm());
    EXPECT_LT(best, 1e-4f);
  }
}

TEST(WebBundle, RefusesAFolderThatIsNotEmpty) {
  const fs::path dir = test::TempDir("web_bundle_refuse");
  const Scene scene = TinyScene(dir);
  const fs::path out = dir / "taken";
  fs::create_directories(out);
  std::ofstream(out / "keep.txt") << "mine";
  EXPECT_THROW(WriteWebBundle(scene, out, {}), InputError);
  EXPECT_EQ(ReadFileToString(out / "keep.txt"), "mine");
  EXPECT_FALSE(fs::exists(dir / "taken.partial"));
}

}  // namespace
}  // namespace hdribr
