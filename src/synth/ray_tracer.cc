#include "synth/ray_tracer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

#include "core/error.h"

namespace hdribr::synth {

Ray PixelRay(const Camera& camera, const Rigid3d& world_from_cam, double x, double y) {
  const Eigen::Vector3d d_cam = camera.CamFromPixel({x, y});
  return {world_from_cam.translation, (world_from_cam.rotation * d_cam).normalized()};
}

void ParallelRows(int rows, int threads, const std::function<void(int)>& body) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, std::max(rows, 1));
  std::atomic<int> next{0};
  auto worker = [&] {
    for (int r = next++; r < rows; r = next++) body(r);
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
}

RenderedView RenderView(const SynthScene& scene, const Camera& camera,
                        const Rigid3d& cam_from_world, const RenderOptions& options) {
  HDRIBR_CHECK(camera.IsPinhole());
  const int w = camera.width, h = camera.height;
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const Eigen::Vector3d view_dir = world_from_cam.rotation * Eigen::Vector3d::UnitZ();
  RenderedView out;
  out.radiance.create(h, w, CV_32FC3);
  out.depth.create(h, w, CV_32FC1);
  out.normal.create(h, w, CV_32FC3);
  out.shape.create(h, w, CV_32SC1);

  // Pass 1: one ray through every pixel centre.
  ParallelRows(h, options.threads, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const Ray ray = PixelRay(camera, world_from_cam, x + 0.5, y + 0.5);
      Hit hit;
      const Eigen::Vector3d rgb = scene.Trace(ray, &hit);
      out.radiance.at<cv::Vec3f>(y, x) = cv::Vec3f(float(rgb.z()), float(rgb.y()), float(rgb.x()));
      out.shape.at<int>(y, x) = hit.shape;
      if (hit.shape >= 0) {
        // Camera-space z = distance along the ray times the cosine to the optical axis.
        out.depth.at<float>(y, x) = float(hit.t * ray.direction.dot(view_dir));
        out.normal.at<cv::Vec3f>(y, x) =
            cv::Vec3f(float(hit.normal.x()), float(hit.normal.y()), float(hit.normal.z()));
      } else {
        out.depth.at<float>(y, x) = 0.f;
        out.normal.at<cv::Vec3f>(y, x) = cv::Vec3f(0, 0, 0);
      }
    }
  });
  if (!options.antialias) return out;

  // Pass 2: supersample pixels on edges (geometry or texture), reading only pass-1 values.
  const cv::Mat centre = out.radiance.clone();
  auto differs = [&](int y0, int x0, int y1, int x1) {
    if (x1 < 0 || y1 < 0 || x1 >= w || y1 >= h) return false;
    if (out.shape.at<int>(y0, x0) != out.shape.at<int>(y1, x1)) return true;
    const cv::Vec3f a = centre.at<cv::Vec3f>(y0, x0), b = centre.at<cv::Vec3f>(y1, x1);
    for (int c = 0; c < 3; ++c) {
      const double lo = std::min(a[c], b[c]) + 1e-6, hi = std::max(a[c], b[c]) + 1e-6;
      if (hi / lo > options.edge_ratio) return true;
    }
    return false;
  };
  ParallelRows(h, options.threads, [&](int y) {
    for (int x = 0; x < w; ++x) {
      if (!(differs(y, x, y, x - 1) || differs(y, x, y, x + 1) || differs(y, x, y - 1, x) ||
            differs(y, x, y + 1, x)))
        continue;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      constexpr int kN = 3;
      for (int j = 0; j < kN; ++j) {
        for (int i = 0; i < kN; ++i) {
          sum +=
              scene.Trace(PixelRay(camera, world_from_cam, x + (i + 0.5) / kN, y + (j + 0.5) / kN));
        }
      }
      sum /= kN * kN;
      out.radiance.at<cv::Vec3f>(y, x) = cv::Vec3f(float(sum.z()), float(sum.y()), float(sum.x()));
    }
  });
  return out;
}

}  // namespace hdribr::synth
