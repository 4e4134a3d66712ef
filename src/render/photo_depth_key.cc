#include "render/photo_depth_key.h"

#include <algorithm>
#include <string_view>
#include <vector>

#include "core/hash.h"

namespace hdribr::render {
namespace {

// Changes when the key's inputs or the meaning of the depth maps change.
constexpr std::uint32_t kKeyVersion = 1;

std::string_view GlString(GLenum name) {
  const auto* text = reinterpret_cast<const char*>(glGetString(name));
  return text ? std::string_view(text) : std::string_view();
}

// The bytes of a GPU buffer, read back in chunks.
void AddBuffer(Fnv1a64& hash, const gl::Buffer& buffer) {
  constexpr size_t kChunk = size_t{4} << 20;
  std::vector<unsigned char> bytes(std::min(kChunk, buffer.size()));
  for (size_t offset = 0; offset < buffer.size(); offset += kChunk) {
    const size_t n = std::min(kChunk, buffer.size() - offset);
    glGetNamedBufferSubData(buffer.id(), static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(n),
                            bytes.data());
    hash.AddBytes(bytes.data(), n);
  }
}

}  // namespace

std::uint64_t PhotoDepthMapsKey(const Scene& scene, const DepthPass& pass, double scale) {
  Fnv1a64 hash;
  hash.Add(kKeyVersion);
  // Another driver or GPU may rasterise differently.
  hash.AddString(GlString(GL_VENDOR)).AddString(GlString(GL_RENDERER));
  hash.AddString(GlString(GL_VERSION));
  hash.Add(pass.program_hash());
  // The options that change the output (not profile, points_per_dispatch, layered_classify).
  const DepthPassOptions& options = pass.options();
  hash.Add(static_cast<int>(options.mode)).Add(static_cast<int>(options.raster));
  hash.Add(options.front_radii).Add(options.front_rel).Add(options.silhouette_trim);
  hash.Add(scale);
  // The points as the pass reads them (order, default radii included).
  hash.Add<std::uint64_t>(pass.points().size());
  if (pass.points().size() > 0) AddBuffer(hash, pass.points().buffer());
  hash.Add<std::uint64_t>(scene.photos.size());
  for (const Photo& photo : scene.photos) {
    const Camera& camera = scene.CameraOf(photo);
    hash.Add(static_cast<int>(camera.model)).Add(camera.width).Add(camera.height);
    hash.Add<std::uint64_t>(camera.params.size());
    for (double p : camera.params) hash.Add(p);
    const Eigen::Quaterniond& q = photo.cam_from_world.rotation;
    hash.Add(q.w()).Add(q.x()).Add(q.y()).Add(q.z());
    for (int i = 0; i < 3; ++i) hash.Add(photo.cam_from_world.translation[i]);
  }
  return hash.value();
}

}  // namespace hdribr::render
