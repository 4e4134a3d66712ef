// The workspace "HDR photo set" (LEC19 sec. 5): for each reference viewpoint, one render per
// exposure series from that series' photos only (the aligned LDR stack), a Debevec-Malik
// response calibrated from those stacks (or given), and the merged radiance (eq. 7) stored as
// EXR. This is what `hdribr hdr` does; the format is in docs/formats.md ("HDR photo set").
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/scene.h"
#include "gl/shader_library.h"
#include "hdr/debevec.h"
#include "hdr/exposure_stack.h"
#include "hdr/response_curve.h"
#include "io/camera_spec.h"
#include "render/renderer.h"

namespace hdribr::render {

// Folder of the HDR photo set inside a workspace, and its index file.
inline constexpr const char* kHdrSetFolder = "hdr";
inline constexpr const char* kHdrSetIndex = "hdr_set.json";

struct HdrPhotoSetOptions {
  // Series whose photos are the reference viewpoints; -1 = the middle series (the paper).
  // Ignored when `views` is not empty.
  int reference_series = -1;
  // Explicit reference views instead (photo names, camera specs or path frames: any View).
  std::vector<View> views;
  // Response file to use instead of calibrating (e.g. a synthetic capture's
  // calib/response.json).
  std::optional<std::filesystem::path> response_file;
  CalibrationOptions calibration;  // --lambda, --samples
  // Output folder; empty = <workspace>/hdr.
  std::filesystem::path output;
  // Size of the renders relative to each view's camera (1 = full size).
  double scale = 1.0;
  // Write the aligned LDR renders (PNG per series + mask PNG) as well.
  bool export_aligned = true;
  // Depth/blend settings for the per-series renders (the renderer's defaults: Unstructured
  // Lumigraph weights). Blending happens on 8-bit values, so the blur of averaging many photos
  // biases dark pixels next to bright ones upward (+7-11 DN at 2-20 DN on a 200x150 capture)
  // and with it the calibrated dark end; the few nearest photos blur less (response RMS over
  // 10-245 DN, B/G/R, 200x150 capture: 0.022/0.015/0.023 vs 0.032/0.019/0.034 with the paper's
  // weights; docs/decisions/0008). The paper's weights averaged away more noise, which helped
  // only on the synthetic camera before its linear toe (read noise over its lowest ~25 codes).
  RendererOptions renderer;
  // Called after each view (index, count), for progress lines.
  std::function<void(int, int)> progress;
};

// One reference viewpoint of the set.
struct HdrSetView {
  View view;                  // name, intrinsics (of the stored image size) and pose
  int photo_index = -1;       // scene photo it was taken from, -1 for other views
  std::string radiance_file;  // relative to the set folder: EXR, half RGB + "valid" channel
  std::vector<std::string> aligned_files;  // per series: relative PNG (empty if not exported)
  std::vector<std::string> mask_files;     // per series: relative PNG mask, 255 = valid
  double valid_fraction = 0;               // pixels valid in the merged image
};

// The set as indexed by hdr_set.json.
struct HdrPhotoSet {
  std::filesystem::path folder;                 // absolute folder holding the index
  std::vector<std::string> series_names;        // darkest first, as in the scene
  std::vector<double> series_exposures;         // relative exposure of each series (merge times)
  int reference_series = -1;                    // -1 when explicit views were given
  std::string response_file = "response.json";  // relative; the curve used for the merge
  // Stored EXR values = radiance (merge units: exp(g) per relative exposure) x radiance_scale,
  // the geometric mean of the series' exposures, so that they sit in half's range.
  double radiance_scale = 1.0;
  std::vector<HdrSetView> views;
};

// Builds the set for `scene` and writes it (atomically, file by file; the index last). Needs a
// current GL 4.5 context. Throws UsageError for one-series scenes, an unknown reference series,
// or when the stacks cannot constrain a response (no overlap between series: the message
// says so); InputError for unreadable files.
HdrPhotoSet BuildHdrPhotoSet(const gl::ShaderLibrary& shaders, const Scene& scene,
                             const HdrPhotoSetOptions& options = {});

// The two halves of BuildHdrPhotoSet, usable without a renderer (tests, other renderers):
// the reference views (sized by options.scale) and series of the set, after checking the scene
// (>= 2 series of distinct positive exposures; UsageError otherwise). No files, no GL.
HdrPhotoSet PlanHdrPhotoSet(const Scene& scene, const HdrPhotoSetOptions& options = {});
// Calibrates (unless options.response_file) from the aligned stacks, stacks[i] = the per-series
// 8-bit renders of plan.views[i] with their masks (times = plan.series_exposures), merges
// (eq. 7) and writes the set to plan.folder. Throws UsageError when no pixel is valid in all
// series (and no response file is given). sample_masks[i][s], when given, restrict the
// calibration samples of view i and series s (e.g. to the pixels rendered from points: the
// background's parallax makes its pixels poor samples); the merge uses the stacks' masks.
HdrPhotoSet WriteHdrPhotoSet(HdrPhotoSet plan, const std::vector<ExposureStack>& stacks,
                             const HdrPhotoSetOptions& options = {},
                             const std::vector<std::vector<cv::Mat>>& sample_masks = {});

// Reads <folder>/hdr_set.json (folder = a workspace, whose hdr/ is used, or the set folder
// itself). Throws InputError naming the file when missing or malformed.
HdrPhotoSet ReadHdrPhotoSet(const std::filesystem::path& folder);

// The set ready for the renderer: a scene whose photos are the set's views (same cameras and
// points as `scene`, one series "hdr"), the images in that scene's photo order (CV_32FC3 BGR,
// for RendererOptions::photo_images; stored units, i.e. radiance x index.radiance_scale), their
// validity (CV_8UC1) and the response.
struct LoadedHdrPhotoSet {
  Scene scene;
  std::vector<cv::Mat> images;
  std::vector<cv::Mat> valid;
  ResponseCurve response;
  HdrPhotoSet index;
};
// Throws InputError naming the file when an image is missing or of the wrong size.
LoadedHdrPhotoSet LoadHdrPhotoSet(const Scene& scene, const std::filesystem::path& folder);
// Same, loading the scene from `workspace` and the set from <workspace>/hdr.
LoadedHdrPhotoSet LoadHdrPhotoSet(const std::filesystem::path& workspace);

}  // namespace hdribr::render
