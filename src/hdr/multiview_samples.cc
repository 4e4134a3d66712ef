#include "hdr/multiview_samples.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>

#include "core/error.h"

namespace hdribr {
namespace {

// A photo prepared for projection: camera at the image's size, rotation and translation, and
// the mask of flat pixels (CV_8UC1, 255 where every channel's 3x3 range <= max_local_range).
struct PreparedPhoto {
  Camera camera;
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  cv::Mat flat;
};

// Throws OptionError or UsageError on options or photos the gathering cannot use.
void ValidateGather(const std::vector<MultiViewPhoto>& photos, const GatherOptions& o) {
  if (o.samples < 1) throw OptionError("samples", "must be >= 1");
  if (!(o.depth_tolerance > 0) || !std::isfinite(o.depth_tolerance)) {
    throw OptionError("depth_tolerance", "must be a positive number");
  }
  if (o.max_local_range < 0) throw OptionError("max_local_range", "must be >= 0");
  if (o.clip_margin < 0 || o.clip_margin > 126) {
    throw OptionError("clip_margin", "must be in 0..126");
  }
  if (o.min_photos < 2) throw OptionError("min_photos", "must be >= 2");
  if (o.candidates < 0) throw OptionError("candidates", "must be >= 0");
  if (o.bins < 1 || o.bins > 256) throw OptionError("bins", "must be in 1..256");
  for (size_t i = 0; i < photos.size(); ++i) {
    const MultiViewPhoto& p = photos[i];
    const std::string name = "sample gathering: photo " + std::to_string(i);
    if (p.image.empty() || p.image.type() != CV_8UC3) {
      throw UsageError(name + ": the image must be 8-bit BGR (CV_8UC3)");
    }
    if (p.depth.empty() || p.depth.type() != CV_32FC1) {
      throw UsageError(name + ": the depth map must be CV_32FC1");
    }
    if (!p.camera.IsPinhole() && !p.camera.HasZeroDistortion()) {
      throw UsageError(name + ": the camera must be pinhole (undistort the photos first)");
    }
    if (!p.camera.FitsImage(p.image.cols, p.image.rows) ||
        !p.camera.FitsImage(p.depth.cols, p.depth.rows)) {
      throw UsageError(name + ": the image and the depth map must have the camera's aspect");
    }
  }
}

// The photo's camera at its image size, its pose as a matrix, and its flat-pixel mask.
PreparedPhoto Prepare(const MultiViewPhoto& p, int max_local_range) {
  PreparedPhoto out;
  out.camera = p.camera.width == p.image.cols && p.camera.height == p.image.rows
                   ? p.camera
                   : p.camera.Scaled(p.image.cols, p.image.rows);
  out.rotation = p.cam_from_world.rotation.toRotationMatrix();
  out.translation = p.cam_from_world.translation;
  cv::Mat range;
  cv::morphologyEx(p.image, range, cv::MORPH_GRADIENT,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  std::vector<cv::Mat> channels;
  cv::split(range, channels);
  cv::Mat largest = cv::max(cv::max(channels[0], channels[1]), channels[2]);
  out.flat = largest <= max_local_range;
  return out;
}

// The observations of world point `point` (visible, flat, not clipped in every channel).
MultiViewSample Observe(const Eigen::Vector3d& point, const std::vector<MultiViewPhoto>& photos,
                        const std::vector<PreparedPhoto>& prepared, const GatherOptions& o) {
  MultiViewSample sample;
  for (size_t i = 0; i < photos.size(); ++i) {
    const PreparedPhoto& p = prepared[i];
    const Eigen::Vector3d cam = p.rotation * point + p.translation;
    if (!(cam.z() > 0)) continue;
    const Eigen::Vector2d px = p.camera.PixelFromCam(cam);
    const cv::Mat& image = photos[i].image;
    const cv::Mat& depth = photos[i].depth;
    if (!(px.x() >= 0 && px.y() >= 0 && px.x() < image.cols && px.y() < image.rows)) continue;
    const int x = static_cast<int>(px.x());
    const int y = static_cast<int>(px.y());
    const int dx = std::min(depth.cols - 1, static_cast<int>(px.x() * depth.cols / image.cols));
    const int dy = std::min(depth.rows - 1, static_cast<int>(px.y() * depth.rows / image.rows));
    const float d = depth.at<float>(dy, dx);
    if (!(d > 0) || std::abs(cam.z() - d) > o.depth_tolerance * cam.z()) continue;
    if (!p.flat.at<uint8_t>(y, x)) continue;
    const cv::Vec3b v = image.at<cv::Vec3b>(y, x);
    bool usable = false;
    for (int c = 0; c < 3; ++c) {
      usable = usable || (v[c] > o.clip_margin && v[c] < 255 - o.clip_margin);
    }
    if (!usable) continue;
    sample.observations.push_back({static_cast<int>(i), {v[0], v[1], v[2]}});
  }
  return sample;
}

// Median over the observations of the mean channel value, in [0, 255].
double MedianValue(const MultiViewSample& sample) {
  std::vector<double> v;
  for (const MultiViewObservation& o : sample.observations) {
    v.push_back((o.bgr[0] + o.bgr[1] + o.bgr[2]) / 3.0);
  }
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Uniform index in [0, n) from a 64-bit generator (its raw output is the same everywhere).
size_t Pick(std::mt19937_64& rng, size_t n) { return static_cast<size_t>(rng() % n); }

// The first `count` entries of a fixed-seed random permutation of 0..n-1.
std::vector<int> RandomSubset(int n, int count, std::mt19937_64& rng) {
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  count = std::min(count, n);
  for (int k = 0; k < count; ++k) {
    std::swap(order[k], order[k + Pick(rng, static_cast<size_t>(n - k))]);
  }
  order.resize(count);
  return order;
}

}  // namespace

std::vector<MultiViewSample> GatherMultiViewSamples(const std::vector<MultiViewPhoto>& photos,
                                                    const std::vector<Eigen::Vector3f>& points,
                                                    const GatherOptions& options) {
  ValidateGather(photos, options);
  std::vector<PreparedPhoto> prepared(photos.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(photos.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      prepared[i] = Prepare(photos[i], options.max_local_range);
    }
  });
  std::mt19937_64 rng(options.seed);
  const int cap = options.candidates > 0 ? options.candidates : 20 * options.samples;
  std::vector<int> candidates = RandomSubset(static_cast<int>(points.size()), cap, rng);
  std::sort(candidates.begin(), candidates.end());
  std::vector<MultiViewSample> observed(candidates.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(candidates.size())), [&](const cv::Range& r) {
    for (int k = r.start; k < r.end; ++k) {
      observed[k] = Observe(points[candidates[k]].cast<double>(), photos, prepared, options);
      observed[k].point = candidates[k];
    }
  });
  // Bins of the median value, each in a random order, picked from in turn.
  std::vector<std::vector<int>> bins(options.bins);
  for (int k = 0; k < static_cast<int>(observed.size()); ++k) {
    if (static_cast<int>(observed[k].observations.size()) < options.min_photos) continue;
    const int b = std::min(options.bins - 1,
                           static_cast<int>(MedianValue(observed[k]) * options.bins / 256.0));
    bins[b].push_back(k);
  }
  for (auto& bin : bins) {
    for (size_t k = bin.size(); k > 1; --k) std::swap(bin[k - 1], bin[Pick(rng, k)]);
  }
  std::vector<int> picked;
  for (size_t depth = 0; static_cast<int>(picked.size()) < options.samples; ++depth) {
    bool any = false;
    for (const auto& bin : bins) {
      if (depth >= bin.size() || static_cast<int>(picked.size()) >= options.samples) continue;
      picked.push_back(bin[depth]);
      any = true;
    }
    if (!any) break;
  }
  std::sort(picked.begin(), picked.end());
  std::vector<MultiViewSample> samples;
  samples.reserve(picked.size());
  for (int k : picked) samples.push_back(std::move(observed[k]));
  return samples;
}

}  // namespace hdribr
