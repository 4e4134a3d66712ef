#include "eval/camera_accuracy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "core/error.h"
#include "core/point_cloud.h"

namespace hdribr::eval {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

CameraAccuracy CompareCameras(const ColmapModel& reconstruction, const ColmapModel& gt) {
  std::map<std::string, const ColmapImage*> rec;
  for (const auto& [id, im] : reconstruction.images) rec[im.name] = &im;
  CameraAccuracy a;
  std::vector<Eigen::Vector3d> src, dst;
  std::vector<Eigen::Quaterniond> rec_rot, gt_rot;
  Bounds bounds;
  for (const auto& [id, im] : gt.images) {
    ++a.gt_images;
    const Eigen::Vector3d c = im.cam_from_world.Inverse().translation;
    bounds.Extend(c);
    const auto it = rec.find(im.name);
    if (it == rec.end()) {
      a.missing.push_back(im.name);
      continue;
    }
    src.push_back(it->second->cam_from_world.Inverse().translation);
    dst.push_back(c);
    rec_rot.push_back(it->second->cam_from_world.rotation);
    gt_rot.push_back(im.cam_from_world.rotation);
  }
  a.matched = static_cast<int>(src.size());
  if (a.matched < 3) {
    throw UsageError("only " + std::to_string(a.matched) +
                     " photos have both a reconstructed and a ground-truth camera (need 3)");
  }
  try {
    a.alignment = AlignSimilarity(src, dst);
  } catch (const std::invalid_argument&) {
    throw UsageError("the ground-truth camera centres are collinear: no similarity to fit");
  }
  a.extent = bounds.Diagonal();
  const double unit = a.extent > 0 ? 100.0 / a.extent : 0.0;
  a.centre_median_pct = a.alignment.median * unit;
  a.centre_max_pct = a.alignment.max * unit;
  // A camera's cam_from_world rotation in the GT frame: R_rec * R_align^T.
  const Eigen::Quaterniond align(a.alignment.dst_from_src.rotation);
  std::vector<double> angles;
  for (size_t i = 0; i < rec_rot.size(); ++i) {
    const Eigen::Quaterniond aligned = rec_rot[i] * align.inverse();
    angles.push_back(gt_rot[i].angularDistance(aligned) * 180.0 / M_PI);
  }
  a.rotation_median_deg = Median(angles);
  a.rotation_max_deg = *std::max_element(angles.begin(), angles.end());
  return a;
}

std::string FormatCameraAccuracy(const CameraAccuracy& a) {
  char buf[512];
  std::snprintf(buf, sizeof(buf),
                "cameras: %d/%d ground-truth photos registered\n"
                "centres after similarity alignment: median %.4g (%.3f%%), max %.4g (%.3f%%) of "
                "the GT camera extent %.4g\n"
                "rotations: median %.3f deg, max %.3f deg\n",
                a.matched, a.gt_images, a.alignment.median, a.centre_median_pct, a.alignment.max,
                a.centre_max_pct, a.extent, a.rotation_median_deg, a.rotation_max_deg);
  std::string s = buf;
  for (const std::string& name : a.missing) s += "not registered: " + name + "\n";
  return s;
}

}  // namespace hdribr::eval
