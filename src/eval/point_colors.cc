#include "eval/point_colors.h"

#include <cmath>

#include "core/error.h"

namespace hdribr::eval {
namespace {

Eigen::Vector3f Bilinear(const cv::Mat& image, double u, double v) {
  // Pixel centres at (x + 0.5, y + 0.5) (COLMAP convention).
  const double fx = std::clamp(u - 0.5, 0.0, image.cols - 1.0);
  const double fy = std::clamp(v - 0.5, 0.0, image.rows - 1.0);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const int x1 = std::min(x0 + 1, image.cols - 1), y1 = std::min(y0 + 1, image.rows - 1);
  const double ax = fx - x0, ay = fy - y0;
  Eigen::Vector3f out;
  for (int c = 0; c < 3; ++c) {
    const double top =
        (1 - ax) * image.at<cv::Vec3b>(y0, x0)[c] + ax * image.at<cv::Vec3b>(y0, x1)[c];
    const double bot =
        (1 - ax) * image.at<cv::Vec3b>(y1, x0)[c] + ax * image.at<cv::Vec3b>(y1, x1)[c];
    out[c] = static_cast<float>(((1 - ay) * top + ay * bot) / 255.0);
  }
  return out;
}

}  // namespace

size_t PointColorSampler::AddPhoto(int key, const cv::Mat& image, const cv::Mat& depth,
                                   const Camera& camera, const Rigid3d& cam_from_world,
                                   float tolerance) {
  HDRIBR_CHECK(image.type() == CV_8UC3 && depth.type() == CV_32FC1);
  const PointCloud& cloud = *cloud_;
  if (sum_.empty()) {
    sum_.assign(cloud.size(), Eigen::Vector3f::Zero());
    count_.assign(cloud.size(), 0);
  }
  const Camera cam_i = camera.Scaled(image.cols, image.rows);
  const Camera cam_d = camera.Scaled(depth.cols, depth.rows);
  std::vector<Sample> samples;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = cam_from_world * cloud.positions[i].cast<double>();
    if (p.z() <= 0) continue;
    const Eigen::Vector2d pd = cam_d.PixelFromCam(p);
    const int dx = static_cast<int>(std::floor(pd.x()));
    const int dy = static_cast<int>(std::floor(pd.y()));
    if (dx < 0 || dy < 0 || dx >= depth.cols || dy >= depth.rows) continue;
    const float d = depth.at<float>(dy, dx);
    if (!(d > 0) || std::abs(static_cast<float>(p.z()) - d) > tolerance * d) continue;
    const Eigen::Vector2d pi = cam_i.PixelFromCam(p);
    if (pi.x() < 0 || pi.y() < 0 || pi.x() >= image.cols || pi.y() >= image.rows) continue;
    const Eigen::Vector3f c = Bilinear(image, pi.x(), pi.y());
    samples.push_back({static_cast<unsigned>(i), c});
    sum_[i] += c;
    ++count_[i];
  }
  keys_.push_back(key);
  const size_t seen = samples.size();
  samples_.push_back(std::move(samples));
  return seen;
}

std::vector<Eigen::Vector3f> PointColorSampler::Colors(int exclude) const {
  const size_t n = cloud_->size();
  std::vector<Eigen::Vector3f> sum =
      sum_.empty() ? std::vector<Eigen::Vector3f>(n, Eigen::Vector3f::Zero()) : sum_;
  std::vector<int> count = count_.empty() ? std::vector<int>(n, 0) : count_;
  for (size_t k = 0; k < keys_.size(); ++k) {
    if (keys_[k] != exclude) continue;
    for (const Sample& s : samples_[k]) {
      sum[s.index] -= s.bgr;
      --count[s.index];
    }
  }
  std::vector<Eigen::Vector3f> out(n, Eigen::Vector3f::Constant(-1.0f));
  for (size_t i = 0; i < n; ++i) {
    if (count[i] > 0) out[i] = (sum[i] / static_cast<float>(count[i])).cwiseMax(0.0f);
  }
  return out;
}

}  // namespace hdribr::eval
