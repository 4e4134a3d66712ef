// Colours for a point cloud from the photos that see each point, so that colour-per-point
// splatting can be compared with image-based blending on clouds without colours and, in
// leave-one-out, without the held-out photo. OpenGL-free: visibility comes from depth maps.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "core/camera.h"
#include "core/point_cloud.h"
#include "core/rigid3.h"

namespace hdribr::eval {

class PointColorSampler {
 public:
  explicit PointColorSampler(const PointCloud& cloud) : cloud_(&cloud) {}

  // Samples `image` (8-bit BGR, any size: the camera is rescaled to it) at every point in
  // front of the camera whose depth agrees with `depth` (camera z, CV_32FC1, any size,
  // 0 = none) within tolerance x depth; bilinear. `key` identifies the photo for Colors().
  // Returns the number of points seen.
  size_t AddPhoto(int key, const cv::Mat& image, const cv::Mat& depth, const Camera& camera,
                  const Rigid3d& cam_from_world, float tolerance = 0.01f);

  // Mean colour (BGR, 0..1) of each point over the added photos except the one with key
  // `exclude` (-1: none); (-1, -1, -1) for points no remaining photo sees.
  std::vector<Eigen::Vector3f> Colors(int exclude = -1) const;

 private:
  struct Sample {
    unsigned index;
    Eigen::Vector3f bgr;
  };
  const PointCloud* cloud_;
  std::vector<Eigen::Vector3f> sum_;
  std::vector<int> count_;
  std::vector<int> keys_;
  std::vector<std::vector<Sample>> samples_;  // per added photo, for exclusion
};

}  // namespace hdribr::eval
