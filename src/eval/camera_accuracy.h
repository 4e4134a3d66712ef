// Accuracy of a reconstruction's cameras against ground-truth cameras of the same photos:
// similarity-aligned centres and rotations. OpenGL-free.
#pragma once

#include <string>
#include <vector>

#include "eval/alignment.h"
#include "io/colmap_model.h"

namespace hdribr::eval {

struct CameraAccuracy {
  int gt_images = 0;                 // photos with a ground-truth camera
  int matched = 0;                   // of those, registered in the reconstruction (by name)
  std::vector<std::string> missing;  // ground-truth photos the reconstruction lacks
  // Reconstruction centres onto ground-truth centres; its residuals are the centre errors
  // after alignment, in GT units (median, max).
  SimilarityAlignment alignment;
  double extent = 0;  // diagonal of the GT centres' bounding box (GT units)
  // alignment.median and alignment.max in per cent of `extent`.
  double centre_median_pct = 0, centre_max_pct = 0;
  // Angle between each GT rotation and the aligned reconstructed one, degrees.
  double rotation_median_deg = 0, rotation_max_deg = 0;
};

// Matches images by name, aligns the reconstructed centres onto the GT centres (Umeyama) and
// measures centres and rotations in the GT frame. Throws UsageError when fewer than 3 photos
// match or their centres are degenerate (collinear).
CameraAccuracy CompareCameras(const ColmapModel& reconstruction, const ColmapModel& gt);

// Readable lines for the terminal.
std::string FormatCameraAccuracy(const CameraAccuracy& accuracy);

}  // namespace hdribr::eval
