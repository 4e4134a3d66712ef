#include "workspace/workspace_fixture.h"

#include <opencv2/core.hpp>

#include "core/exposure_series.h"
#include "io/colmap_model.h"
#include "io/exif.h"
#include "io/image.h"
#include "io/ply.h"
#include "io/series_json.h"

namespace hdribr::test {
namespace fs = std::filesystem;

void MakeWorkspace(const fs::path& dir, const FixtureOptions& options) {
  fs::create_directories(dir / "images");
  ColmapModel model;
  model.cameras[3] = Camera::Pinhole(3, 64, 48, 60, 60, 32, 24);
  Camera second = Camera::Pinhole(7, 80, 60, 70, 70, 40, 30);
  if (options.distorted_camera) {
    second.model = CameraModel::kOpenCV;
    second.params = {70, 70, 40, 30, 0.1, 0.01, 0, 0};
  }
  model.cameras[7] = second;

  std::vector<Photo> photos;
  const int ids[] = {2, 5, 9, 11};  // non-contiguous on purpose
  for (int k = 0; k < 4; ++k) {
    ColmapImage image;
    image.id = ids[k];
    image.camera_id = k < 2 ? 3 : 7;
    image.name = "p" + std::to_string(k) + ".jpg";
    const double angle = 0.4 * k;
    image.cam_from_world = LookAt(Eigen::Vector3d(3 * std::sin(angle), 0.5, -3 * std::cos(angle)),
                                  Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0));
    model.images[image.id] = image;

    const Camera& cam = model.cameras.at(image.camera_id);
    cv::Mat pixels(cam.height, cam.width, CV_8UC3, cv::Scalar(40 * k, 100, 200 - 30 * k));
    WriteImage(dir / "images" / image.name, pixels);
    ExifInfo exif;
    exif.exposure.time_s = (k % 2 == 0) ? 1.0 / 100 : 1.0 / 25;  // two series, 2 EV apart
    exif.exposure.iso = 100;
    exif.exposure.f_number = 4;
    exif.exposure.focal_mm = 5;
    WriteExif(dir / "images" / image.name, exif);

    Photo p;
    p.name = image.name;
    p.exposure = exif.exposure;
    photos.push_back(p);
  }
  WriteColmapModel(model, dir / "sparse", ColmapFormat::kText);

  if (options.write_points_ply) {
    PointCloud cloud;
    for (int i = 0; i < 200; ++i) {
      const float t = static_cast<float>(i) / 200.0f;
      cloud.positions.emplace_back(std::cos(20 * t) * 0.5f, t - 0.5f, std::sin(20 * t) * 0.5f);
      cloud.normals.emplace_back(std::cos(20 * t), 0.0f, std::sin(20 * t));
      cloud.radii.push_back(0.02f);
    }
    WritePly(dir / "points.ply", cloud, true);
  }
  if (options.write_series_json) {
    const auto series = GroupByExposure(photos);
    WriteSeriesJson(dir / "series.json", series, photos);
  }
}

}  // namespace hdribr::test
