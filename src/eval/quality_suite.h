// The quality suite (`hdribr bench quality`): its manifest of captures, the figures measured on
// each, and the table that compares them per split (mean and worst). OpenGL-free.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "synth/capture.h"

namespace hdribr::eval {

// One capture of the suite: a synthetic capture made by `synth`, or a folder of real photos.
struct SuiteCapture {
  std::string name;    // unique, a folder name ([A-Za-z0-9_-]+)
  std::string split;   // "tune" (looked at while choosing) or "check" (only to report)
  bool quick = false;  // part of the --quick subset
  std::optional<synth::CaptureOptions> synth;  // synthetic: how to make it
  std::filesystem::path photos;        // real: the photo folder, relative to the datasets folder
  std::vector<std::string> eval_args;  // `eval --leave-one-out` arguments (e.g. --series all)
  std::string note;                    // what the capture stresses
};

// Reads the manifest (JSON, format "hdribr-quality-suite", version 1; docs/formats.md).
// Throws InputError naming the file and the problem (bad JSON, unknown split or scene, a
// duplicate or unsafe name, neither or both of `synth` and `photos`).
std::vector<SuiteCapture> ReadSuiteManifest(const std::filesystem::path& path);

// Figures of one capture; a figure that does not apply or was not measured is absent.
struct CaptureFigures {
  std::string name, split;
  bool synthetic = false;
  std::optional<double> reconstruct_s;  // wall time of `reconstruct` (its first full run)
  std::optional<double> registered;     // share of the photos with a camera
  // Leave-one-out on the reconstructed workspace: hdribr and the nearest photo on the pixels
  // both cover, hdribr on its own pixels.
  std::optional<double> psnr, ssim, nearest_psnr, nearest_ssim, own_psnr, own_coverage;
  // Synthetic: hdribr's own-pixel PSNR with the capture's GT points and cameras (the same
  // held-out photos), GT novel views (PSNR, depth pass within 1 %), HDR in direct radiance mode
  // (median per-channel |log ratio|, mu-law PSNR), calibrated exposures against the truth.
  std::optional<double> gt_own_psnr, novel_psnr, depth_accuracy, hdr_log_ratio, hdr_mulaw_psnr;
  std::optional<double> exposure_median, exposure_max;  // relative errors (0.01 = 1 %)
  std::optional<double> frame_ms;  // the default render at 512x512, median wall ms a frame

  std::optional<double> margin() const;  // psnr - nearest_psnr
  std::optional<double> gap() const;     // gt_own_psnr - own_psnr (full pipeline vs GT)
};

nlohmann::json FiguresToJson(const CaptureFigures& f);
CaptureFigures FiguresFromJson(const nlohmann::json& j);

// Reads a capture's figures from `eval --out` folders and `calibrate --truth` output:
// leave-one-out of the reconstructed workspace (required), of the GT workspace and the GT novel
// views (absent folders leave their figures absent). Throws InputError on a malformed file.
void ReadLeaveOneOut(const std::filesystem::path& eval_dir, CaptureFigures& f);
void ReadGtLeaveOneOut(const std::filesystem::path& eval_dir, CaptureFigures& f);
void ReadGtNovel(const std::filesystem::path& eval_dir, CaptureFigures& f);
// Parses the "exposures vs truth" line of `calibrate --truth`; false when it is not there.
bool ParseExposureTruth(const std::string& text, CaptureFigures& f);

// The suite's table: one row per capture, then the mean and the worst capture of each split.
std::string FormatSuiteTable(const std::vector<CaptureFigures>& rows);
// The same as markdown, under a line naming the date, commit and machine.
std::string FormatSuiteMarkdown(const std::vector<CaptureFigures>& rows,
                                const std::string& provenance);
// JSON: {format "hdribr-bench-quality", version, provenance, captures: [...], splits: {...}}.
std::string FormatSuiteJson(const std::vector<CaptureFigures>& rows, const std::string& provenance);

}  // namespace hdribr::eval
