// Everything loaded from a workspace: cameras, photos in exposure series, the point cloud.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/exposure_series.h"
#include "core/photo.h"
#include "core/point_cloud.h"
#include "core/rigid3.h"

namespace hdribr {

struct Scene {
  std::filesystem::path workspace;
  std::map<int, Camera> cameras;       // by COLMAP camera id
  std::vector<Photo> photos;           // in COLMAP image-id order
  std::vector<ExposureSeries> series;  // darkest first
  PointCloud points;

  // Derived by UpdateDerived().
  Bounds point_bounds;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // of the points (cameras if none)
  // Median camera-to-centroid distance: the unit for every scene-relative threshold
  // (occlusion tolerance, blending distance term), since SfM's scale is arbitrary.
  double scene_scale = 1.0;

  const Camera& CameraOf(const Photo& photo) const { return cameras.at(photo.camera_id); }
  // Index of the photo with this name, or -1.
  int FindPhoto(const std::string& name) const;
  // Relative exposure of a photo for radiance: its calibrated exposure when the workspace has
  // one, else its series' (shared by the series' photos), else the photo's own EXIF value.
  double RelativeExposureOf(const Photo& photo) const;
  // Relative exposure per second of exposure time: the median ISO / 100 / N^2 of the photos
  // with an exposure time (1 without any), to turn a time in seconds into a relative exposure.
  double ExposureGain() const;
  // Median of RelativeExposureOf over the photos (1 without photos): the exposure of a typical
  // photo, EV 0 of a re-exposure through the camera's response.
  double MedianRelativeExposure() const;
  // Index of the photo whose viewpoint is nearest a view, among `candidates` (indices into
  // photos) or all photos: the smallest |C - C_k| / scene_scale + (1 - d . d_k), with C, d the
  // centres and viewing directions. -1 when there is no candidate.
  int NearestPhoto(const Rigid3d& cam_from_world) const;
  int NearestPhoto(const Rigid3d& cam_from_world, const std::vector<int>& candidates) const;
  // Recomputes bounds, centroid and scene scale.
  void UpdateDerived();
};

}  // namespace hdribr
