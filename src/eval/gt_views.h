// Ground truth of synthetic captures (`hdribr synth`): the novel test views and the
// conversion of their radiance to the 8-bit values the capture's camera would record.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/rigid3.h"
#include "core/scene.h"
#include "synth/camera_response.h"

namespace hdribr::eval {

// One ground-truth novel view: pose, camera and linear radiance file (CV_32FC3 BGR EXR).
struct GtView {
  std::string name;  // "novel_03" (the image name without extension)
  Camera camera;
  Rigid3d cam_from_world;
  std::filesystem::path radiance_path;
  std::filesystem::path depth_path;  // camera z (EXR `Z`, 0 = sky); may be absent
};

// The novel views of a capture folder (CAPTURE/gt/novel: COLMAP TEXT model, radiance/*.exr),
// in image-id order. Throws InputError naming the folder or file when something is missing.
std::vector<GtView> ReadGtNovelViews(const std::filesystem::path& capture_dir);

// The capture's true response (gamma, knee, toe, x_sat from CAPTURE/gt/capture.json), noise
// parameters included (not used by RadianceToLdr). Throws InputError on a bad file.
synth::SyntheticResponse ReadCaptureResponse(const std::filesystem::path& capture_dir);

// Camera-space unit normals (CV_32FC3 x, y, z) of a depth map (CV_32FC1 camera z, 0 = none)
// seen by `camera` (of the map's size): the cross product of the back-projected neighbours on
// the side whose depth is closer, so that normals do not bend across silhouettes; facing the
// camera; the reversed ray where no neighbour has depth, 0 where the pixel has none.
cv::Mat NormalsFromDepth(const cv::Mat& depth, const Camera& camera);

// The capture folder whose ground truth holds this workspace's cameras (a synthetic capture's
// own workspace): `capture_dir` when given (--gt), else the workspace's parent folder. Empty
// when there is none or its cameras differ from the workspace's (e.g. after `reconstruct`).
std::filesystem::path FindGtCapture(const Scene& scene, const std::filesystem::path& capture_dir);

// GT depth (CV_32FC1 camera z, 0 = sky) of every scene photo, from CAPTURE/gt/depth/STEM.exr.
// Throws InputError naming a missing or unreadable file.
std::vector<cv::Mat> ReadGtPhotoDepths(const Scene& scene, const std::filesystem::path& capture);

// 8-bit BGR image of linear BGR radiance exposed for `time_s` seconds through the response,
// without noise: z = round(ValueFromExposure(c, L t)), exactly as the capture's photos were
// made (synth/capture.cc) minus noise and JPEG.
cv::Mat RadianceToLdr(const cv::Mat& radiance, const synth::SyntheticResponse& response,
                      double time_s);

}  // namespace hdribr::eval
