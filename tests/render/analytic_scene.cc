#include "analytic_scene.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

namespace hdribr::test {

AnalyticScene AnalyticScene::SpheresAndPlane() {
  AnalyticScene s = SpheresOnly();
  s.has_plane = true;
  s.plane_z = 4.2;
  s.plane_half = 3.0;
  return s;
}

AnalyticScene AnalyticScene::SpheresOnly() {
  AnalyticScene s;
  s.spheres = {{Eigen::Vector3d(-0.35, 0.0, 3.0), 0.55}, {Eigen::Vector3d(0.35, 0.15, 2.5), 0.4}};
  return s;
}

double AnalyticScene::Area() const {
  double a = 0;
  for (const auto& s : spheres) a += 4.0 * M_PI * s.radius * s.radius;
  if (has_plane) a += 4.0 * plane_half * plane_half;
  return a;
}

PointCloud AnalyticScene::Sample(int count, double radius_factor, unsigned seed) const {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const double area = Area();
  const double spacing = std::sqrt(area / count);
  const float radius = static_cast<float>(radius_factor * spacing);
  PointCloud pc;
  auto add = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
    pc.positions.push_back(p.cast<float>());
    pc.normals.push_back(n.cast<float>());
    pc.radii.push_back(radius);
  };
  for (const auto& s : spheres) {
    const int n = static_cast<int>(std::lround(count * 4.0 * M_PI * s.radius * s.radius / area));
    for (int i = 0; i < n; ++i) {
      Eigen::Vector3d d(normal(rng), normal(rng), normal(rng));
      d.normalize();
      add(s.centre + s.radius * d, d);
    }
  }
  if (has_plane) {
    const int n = static_cast<int>(std::lround(count * 4.0 * plane_half * plane_half / area));
    for (int i = 0; i < n; ++i) {
      add(Eigen::Vector3d(plane_half * uniform(rng), plane_half * uniform(rng), plane_z),
          Eigen::Vector3d(0, 0, -1));
    }
  }
  return pc;
}

cv::Mat AnalyticScene::GroundTruthDepth(const Camera& camera, const Rigid3d& cam_from_world) const {
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const Eigen::Vector3d origin = world_from_cam.translation;
  cv::Mat gt(camera.height, camera.width, CV_32FC1, cv::Scalar(0));
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const Eigen::Vector3d ray_cam = camera.CamFromPixel({x + 0.5, y + 0.5});  // z = 1
      const Eigen::Vector3d dir = world_from_cam.rotation * ray_cam;
      double best = std::numeric_limits<double>::infinity();  // t along dir: camera z
      for (const auto& s : spheres) {
        const Eigen::Vector3d oc = origin - s.centre;
        const double a = dir.squaredNorm();
        const double b = 2.0 * oc.dot(dir);
        const double c = oc.squaredNorm() - s.radius * s.radius;
        const double disc = b * b - 4 * a * c;
        if (disc < 0) continue;
        const double sq = std::sqrt(disc);
        for (double t : {(-b - sq) / (2 * a), (-b + sq) / (2 * a)}) {
          if (t > 1e-6) {
            best = std::min(best, t);
            break;
          }
        }
      }
      if (has_plane && std::abs(dir.z()) > 1e-12) {
        const double t = (plane_z - origin.z()) / dir.z();
        const Eigen::Vector3d hit = origin + t * dir;
        if (t > 1e-6 && std::abs(hit.x()) <= plane_half && std::abs(hit.y()) <= plane_half) {
          best = std::min(best, t);
        }
      }
      if (std::isfinite(best)) gt.at<float>(y, x) = static_cast<float>(best);
    }
  }
  return gt;
}

std::vector<Rigid3d> DomePoses(int count, double distance, const Eigen::Vector3d& centre,
                               const Eigen::Vector3d& up) {
  std::vector<Rigid3d> poses;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = -0.15 - 0.85 * (i + 0.5) / count;
    const double r = std::sqrt(1.0 - z * z);
    const Eigen::Vector3d dir(r * std::cos(golden * i), r * std::sin(golden * i), z);
    poses.push_back(LookAt(centre + distance * dir, centre, up));
  }
  return poses;
}

Scene PhotographScene(const AnalyticScene& analytic, const Camera& camera,
                      const std::vector<Rigid3d>& poses, int points, const SurfaceShade& shade,
                      std::vector<cv::Mat>& images) {
  Scene scene;
  scene.cameras[1] = camera;
  scene.points = analytic.Sample(points);
  images.clear();
  for (size_t i = 0; i < poses.size(); ++i) {
    Photo photo;
    photo.id = static_cast<int>(i) + 1;
    photo.name = "p" + std::to_string(i) + ".png";
    photo.image_path = photo.name;
    photo.camera_id = 1;
    photo.cam_from_world = poses[i];
    const cv::Mat depth = analytic.GroundTruthDepth(camera, poses[i]);
    const Rigid3d world_from_cam = poses[i].Inverse();
    cv::Mat img(camera.height, camera.width, CV_8UC3, cv::Scalar(0, 0, 0));
    for (int y = 0; y < camera.height; ++y) {
      for (int x = 0; x < camera.width; ++x) {
        const float z = depth.at<float>(y, x);
        if (z <= 0) continue;
        const Eigen::Vector3d p = world_from_cam * (camera.CamFromPixel({x + 0.5, y + 0.5}) * z);
        img.at<cv::Vec3b>(y, x) = shade(p, photo);
      }
    }
    scene.photos.push_back(photo);
    images.push_back(img);
  }
  scene.UpdateDerived();
  return scene;
}

Camera TestCamera(int size) {
  const double f = 0.5 * size / std::tan(0.5 * 58.0 * M_PI / 180.0);
  return Camera::Pinhole(1, size, size, f, f, 0.5 * size, 0.5 * size);
}

cv::Mat SilhouetteBand(const cv::Mat& gt, int radius) {
  cv::Mat mask = gt > 0;
  cv::Mat kernel =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
  cv::Mat dil, ero;
  cv::dilate(mask, dil, kernel);
  cv::erode(mask, ero, kernel);
  return dil & ~ero;
}

}  // namespace hdribr::test
