// BuildHdrPhotoSet: the GPU half of the HDR photo set (aligned per-series renders); the rest
// is in hdr_photo_set.cc.
#include "render/hdr_photo_set.h"

#include <vector>

namespace hdribr::render {

HdrPhotoSet BuildHdrPhotoSet(const gl::ShaderLibrary& shaders, const Scene& scene,
                             const HdrPhotoSetOptions& options) {
  HdrPhotoSet plan = PlanHdrPhotoSet(scene, options);
  // Aligned LDR renders: one per series and view, from that series' photos only; the blended
  // display value rounded back to 8 bits, the render's validity as the mask; calibration
  // samples only where a point was rendered. Nothing is filled: the set holds photo pixels only.
  RendererOptions ropt = options.renderer;
  ropt.blend.encoding = PhotoEncoding::kDisplay;
  ropt.blend.fill = false;
  ropt.photo_images.clear();
  Renderer renderer(shaders, scene, ropt);
  std::vector<ExposureStack> stacks(plan.views.size());
  std::vector<std::vector<cv::Mat>> from_points(plan.views.size());  // calibration samples
  for (size_t i = 0; i < plan.views.size(); ++i) {
    const View& v = plan.views[i].view;
    stacks[i].times = plan.series_exposures;
    for (const ExposureSeries& series : scene.series) {
      renderer.SetActivePhotos(series.photo_indices);
      RenderImages r =
          renderer.RenderToImages(v.camera, v.cam_from_world, v.camera.width, v.camera.height);
      cv::Mat bgr8;
      r.color.convertTo(bgr8, CV_8UC3, 255.0);
      stacks[i].images.push_back(bgr8);
      stacks[i].masks.push_back(r.valid.clone());
      from_points[i].push_back(r.valid & (r.depth > 0));
    }
    if (options.progress) {
      options.progress(static_cast<int>(i) + 1, static_cast<int>(plan.views.size()));
    }
  }
  renderer.SetAllPhotosActive();
  return WriteHdrPhotoSet(std::move(plan), stacks, options, from_points);
}

}  // namespace hdribr::render
