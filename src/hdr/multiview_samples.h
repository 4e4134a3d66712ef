// Samples for the multi-view radiometric calibration: scene points and the 8-bit values of the
// photos that see them, gathered from photos with depth maps.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"

namespace hdribr {

// One photo's view of a scene point: its 8-bit values in BGR order.
struct MultiViewObservation {
  int photo = -1;                     // index into the photo list (and the prior)
  std::array<std::uint8_t, 3> bgr{};  // pixel values, BGR
};

// One scene point (one radiance per channel) and the photos that see it.
struct MultiViewSample {
  std::vector<MultiViewObservation> observations;
  int point = -1;  // index of its candidate point (GatherMultiViewSamples), -1 if none
};

// One photo for sample gathering.
struct MultiViewPhoto {
  cv::Mat image;  // CV_8UC3 BGR
  Camera camera;  // pinhole (or zero distortion), any size with the image's aspect
  Rigid3d cam_from_world;
  // CV_32FC1 camera-space z (world units) per pixel, 0 = nothing; any size with the image's
  // aspect (pixel coordinates are scaled to it).
  cv::Mat depth;
};

// Options of GatherMultiViewSamples.
struct GatherOptions {
  int samples = 3000;  // samples to return at most
  // Visible in a photo when |z - depth| <= depth_tolerance z at the point's pixel (z its
  // camera-space depth, depth the map's value there).
  double depth_tolerance = 0.01;
  // Kept observations lie where the 3x3 range (max - min, DN) of every channel is at most
  // this, so that a pixel or two of misregistration changes the value little.
  int max_local_range = 12;
  int clip_margin = 2;     // an observation counts when some channel is in (margin, 255 - margin)
  int min_photos = 2;      // samples need this many counted observations
  int candidates = 0;      // points projected at most (random subset); 0 = 20 x samples
  int bins = 32;           // intensity bins of the samples' median value, filled in turn
  std::uint64_t seed = 1;  // subset and picks (same on every platform)
};

// Gathers samples for CalibrateMultiView: each candidate point (world frame) is projected into
// every photo and observed where the depth map agrees and the image is flat; points seen by
// >= min_photos photos are binned by the median over their observations of the mean channel
// value and picked from the bins in turn (a fixed-seed random order within each bin).
// Throws UsageError on inconsistent photos (types, sizes, non-pinhole cameras).
std::vector<MultiViewSample> GatherMultiViewSamples(const std::vector<MultiViewPhoto>& photos,
                                                    const std::vector<Eigen::Vector3f>& points,
                                                    const GatherOptions& options = {});
}  // namespace hdribr
