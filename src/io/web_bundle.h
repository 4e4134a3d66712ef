// `hdribr export-web`: a workspace as a static folder that a WebGL2 viewer in any browser opens
// (web/, embedded at build time). Bundle format in docs/usage/web.md.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "core/scene.h"

namespace hdribr {

// Version of the bundle's capture/scene.json; the viewer refuses a newer one.
inline constexpr int kWebBundleVersion = 1;
// Bytes per point of capture/points.bin once inflated: 3 x uint16 position in the bounds,
// 2 x int8 octahedral normal, uint16 radius (layout in docs/usage/web.md).
inline constexpr int kWebPointBytes = 10;

struct WebBundleOptions {
  int max_photo_size = 1600;  // longest side of the photos in the bundle (0 = as they are)
  int jpeg_quality = 90;      // for the photos that are re-encoded
  // Called after each photo is written: (photos done, photos in all).
  std::function<void(int, int)> progress;
};

// What the export wrote, in bytes.
struct WebBundleReport {
  std::uintmax_t photos = 0;  // the photos' JPEG files
  std::uintmax_t points = 0;  // capture/points.bin
  std::uintmax_t viewer = 0;  // index.html and the viewer's scripts
  std::uintmax_t other = 0;   // scene.json, the response
  int photo_count = 0;
  size_t point_count = 0;
  std::uintmax_t total() const { return photos + points + viewer + other; }
};

// The viewer's files (path inside the bundle -> contents), embedded from web/ at build time.
const std::map<std::string, std::string>& EmbeddedWebFiles();

// Writes the bundle of `scene` into `out` (which must not exist or be empty); the folder
// appears complete or not at all (written to a sibling, then renamed). Throws InputError.
WebBundleReport WriteWebBundle(const Scene& scene, const std::filesystem::path& out,
                               const WebBundleOptions& options);

}  // namespace hdribr
