#include "io/io_test_util.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace hdribr::test {
namespace fs = std::filesystem;

ColmapModel MakeColmapModel() {
  ColmapModel m;
  m.cameras[4] = Camera::Pinhole(4, 640, 480, 500.125, 501.5, 320.25, 239.75);
  Camera simple;
  simple.id = 9;
  simple.model = CameraModel::kSimpleRadial;
  simple.width = 800;
  simple.height = 600;
  simple.params = {700.0 / 3.0, 400, 300, -0.0123456789012345};
  m.cameras[9] = simple;
  const int ids[] = {3, 8, 20};
  for (int k = 0; k < 3; ++k) {
    ColmapImage im;
    im.id = ids[k];
    im.camera_id = k == 1 ? 9 : 4;
    im.name = "img_" + std::to_string(k) + ".jpg";
    im.cam_from_world = LookAt(Eigen::Vector3d(2.0 * k - 2.0, 0.3 * k, -4.0 + 0.1 / 3.0),
                               Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0, -1, 0));
    for (int j = 0; j < 6; ++j) {
      ColmapPoint2D p;
      p.xy = Eigen::Vector2d(10.5 + 37.25 * j + k / 7.0, 20.125 + 11.0 * j);
      im.points2d.push_back(p);  // point3d_id filled below or left -1
    }
    m.images[im.id] = im;
  }
  for (int i = 0; i < 5; ++i) {
    ColmapPoint3D p;
    p.id = 7 + 3 * i;  // non-contiguous
    p.xyz = Eigen::Vector3d(0.1 * i - 0.2, std::sin(i) / 3.0, 1.0 / (i + 3.0));
    p.color = {static_cast<std::uint8_t>(40 * i), 200, static_cast<std::uint8_t>(255 - i)};
    p.error = 0.5 + i / 9.0;
    for (int k = 0; k < 3; ++k) {
      if ((i + k) % 2 == 1 && i > 0) continue;
      const int image_id = ids[k];
      const int idx = i;  // 2D point i of the image observes point i
      m.images[image_id].points2d[idx].point3d_id = p.id;
      p.track.push_back({image_id, idx});
    }
    m.points3d[p.id] = p;
  }
  return m;
}

void ExpectModelsEqual(const ColmapModel& a, const ColmapModel& b, double rot_tol) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (const auto& [id, ca] : a.cameras) {
    ASSERT_TRUE(b.cameras.count(id)) << "camera " << id;
    const Camera& cb = b.cameras.at(id);
    EXPECT_EQ(ca.id, cb.id);
    EXPECT_EQ(ca.model, cb.model);
    EXPECT_EQ(ca.width, cb.width);
    EXPECT_EQ(ca.height, cb.height);
    EXPECT_EQ(ca.params, cb.params) << "camera " << id;
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (const auto& [id, ia] : a.images) {
    ASSERT_TRUE(b.images.count(id)) << "image " << id;
    const ColmapImage& ib = b.images.at(id);
    EXPECT_EQ(ia.id, ib.id);
    EXPECT_EQ(ia.camera_id, ib.camera_id);
    EXPECT_EQ(ia.name, ib.name);
    if (rot_tol == 0.0) {
      EXPECT_EQ(ia.cam_from_world.rotation.coeffs(), ib.cam_from_world.rotation.coeffs());
    } else {
      EXPECT_LE((ia.cam_from_world.rotation.coeffs() - ib.cam_from_world.rotation.coeffs())
                    .cwiseAbs()
                    .maxCoeff(),
                rot_tol);
    }
    EXPECT_EQ(ia.cam_from_world.translation, ib.cam_from_world.translation);
    ASSERT_EQ(ia.points2d.size(), ib.points2d.size());
    for (size_t k = 0; k < ia.points2d.size(); ++k) {
      EXPECT_EQ(ia.points2d[k].xy, ib.points2d[k].xy);
      EXPECT_EQ(ia.points2d[k].point3d_id, ib.points2d[k].point3d_id);
    }
  }
  ASSERT_EQ(a.points3d.size(), b.points3d.size());
  for (const auto& [id, pa] : a.points3d) {
    ASSERT_TRUE(b.points3d.count(id)) << "point " << id;
    const ColmapPoint3D& pb = b.points3d.at(id);
    EXPECT_EQ(pa.xyz, pb.xyz);
    EXPECT_EQ(pa.color, pb.color);
    EXPECT_EQ(pa.error, pb.error);
    ASSERT_EQ(pa.track.size(), pb.track.size());
    for (size_t k = 0; k < pa.track.size(); ++k) {
      EXPECT_EQ(pa.track[k].image_id, pb.track[k].image_id);
      EXPECT_EQ(pa.track[k].point2d_idx, pb.track[k].point2d_idx);
    }
  }
}

std::map<std::string, std::string> Snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) {
      files[fs::relative(e.path(), dir).string() + "/"] = "";
      continue;
    }
    std::ifstream in(e.path(), std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    files[fs::relative(e.path(), dir).string()] = ss.str();
  }
  return files;
}

}  // namespace hdribr::test
