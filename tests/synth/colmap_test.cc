// The real colmap executable (CPU) calibrates a small synthetic capture: every photo is
// registered and the camera centres match the ground truth after a similarity alignment.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <map>

#include "eval/alignment.h"
#include "io/colmap_model.h"
#include "synth/capture.h"
#include "test_util.h"

namespace hdribr::synth {
namespace {
namespace fs = std::filesystem;

TEST(SynthColmap, ColmapRegistersAllPhotosAtTheTruePoses) {
  if (test::RunCommand("colmap help").exit_code != 0) GTEST_SKIP() << "colmap is not installed";
  const fs::path tmp = test::TempDir();
  CaptureOptions o;
  o.series = 3;
  o.views = 8;
  o.width = 640;
  o.height = 480;
  o.novel_views = 0;
  o.seed = 3;
  WriteCapture(o, tmp / "capture");

  const auto t0 = std::chrono::steady_clock::now();
  const std::string db = (tmp / "db.db").string();
  const std::string images = (tmp / "capture/photos").string();
  const std::string env = "QT_QPA_PLATFORM=offscreen ";
  auto run = [&](const std::string& args) {
    const auto r = test::RunCommand(env + "colmap " + args);
    EXPECT_EQ(r.exit_code, 0) << "colmap " << args << "\n" << r.output.substr(0, 4000);
    return r.exit_code == 0;
  };
  ASSERT_TRUE(run("feature_extractor --database_path " + db + " --image_path " + images +
                  " --ImageReader.single_camera 1 --ImageReader.camera_model SIMPLE_RADIAL"
                  " --SiftExtraction.use_gpu 0 --SiftExtraction.num_threads 2"
                  " --SiftExtraction.max_num_features 1024"));
  ASSERT_TRUE(run("exhaustive_matcher --database_path " + db +
                  " --SiftMatching.use_gpu 0 --SiftMatching.num_threads 2"));
  fs::create_directories(tmp / "sparse");
  ASSERT_TRUE(run("mapper --database_path " + db + " --image_path " + images + " --output_path " +
                  (tmp / "sparse").string() + " --Mapper.num_threads 2"));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  RecordProperty("colmap_seconds", std::to_string(seconds));
  std::printf("colmap took %.1f s\n", seconds);

  // The largest reconstruction.
  ColmapModel sfm;
  for (const auto& e : fs::directory_iterator(tmp / "sparse")) {
    ColmapModel m = ReadColmapModel(e.path());
    if (m.images.size() > sfm.images.size()) sfm = std::move(m);
  }
  const ColmapModel gt = ReadColmapModelText(tmp / "capture/gt");
  std::map<std::string, Eigen::Vector3d> gt_centres;
  for (const auto& [id, im] : gt.images)
    gt_centres[im.name] = im.cam_from_world.Inverse().translation;
  EXPECT_EQ(sfm.images.size(), gt.images.size()) << "not every photo was registered";
  std::vector<Eigen::Vector3d> src, dst;
  for (const auto& [id, im] : sfm.images) {
    ASSERT_TRUE(gt_centres.count(im.name)) << im.name;
    src.push_back(im.cam_from_world.Inverse().translation);
    dst.push_back(gt_centres[im.name]);
  }
  ASSERT_GE(src.size(), 3u);
  const SimilarityAlignment a = AlignSimilarity(src, dst);
  const double scene_size = 1.0;  // CapturePlan::scene.size of the default scene
  RecordProperty("median_centre_error", std::to_string(a.median));
  std::printf("registered %zu/%zu, centre error after Umeyama: median %.5f max %.5f (scene %.1f)\n",
              sfm.images.size(), gt.images.size(), a.median, a.max, scene_size);
  EXPECT_LT(a.median, 0.01 * scene_size);
}

}  // namespace
}  // namespace hdribr::synth
