// Accuracy and completeness of a reconstructed point cloud against a ground-truth cloud, with
// the camera-based alignment refined by ICP. OpenGL-free.
#pragma once

#include "core/point_cloud.h"
#include "eval/alignment.h"

namespace hdribr::eval {

// Shares of points within the tolerance of the other cloud's nearest point (Seitz et al. 2006,
// "A comparison and evaluation of multi-view stereo reconstruction algorithms").
struct CloudScore {
  double accuracy = 0;      // reconstructed points within tolerance of a GT point
  double completeness = 0;  // GT points within tolerance of a reconstructed point
};

struct CloudAccuracy {
  double tolerance = 0;  // GT units
  CloudScore cameras;    // aligned by the cameras alone
  // After the ICP refinement (similarity) of that alignment, as Tanks and Temples does
  // (Knapitsch et al. 2017): the cameras' alignment leaves a rotation that the centres do not
  // constrain (about the chord of an arc of views) in the figure; the refinement removes it.
  CloudScore refined;
  Sim3d refinement;           // GT-frame similarity applied after the cameras' alignment
  double refinement_deg = 0;  // its rotation angle, degrees
};

// Scores `reconstruction` mapped by `gt_from_reconstruction` (e.g. CompareCameras' alignment)
// against `gt`, `tolerance` in GT units. Throws UsageError when a cloud is empty.
CloudAccuracy CompareClouds(const PointCloud& reconstruction, const Sim3d& gt_from_reconstruction,
                            const PointCloud& gt, double tolerance);

// Readable lines for the terminal.
std::string FormatCloudAccuracy(const CloudAccuracy& accuracy);

}  // namespace hdribr::eval
