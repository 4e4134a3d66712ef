#include "frontend/dense_mvs.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <tuple>

#include "core/error.h"
#include "frontend/ncc.h"
#include "frontend/parallel.h"
#include "frontend/patch_match.h"
#include "io/image.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

// A photo's farthest sparse point bounds its depth range unless it lies beyond this many times the
// 98th percentile of their depths (an outlier): far content (a building across a square) may
// hold only a few sparse points.
constexpr double kFarOutlier = 4.0;

// K for OpenCV's pixel convention (pixel centres at integer coordinates): COLMAP's cx - 0.5.
Eigen::Matrix3d OpenCvK(const Camera& c) {
  Eigen::Matrix3d k = c.K();
  k(0, 2) -= 0.5;
  k(1, 2) -= 0.5;
  return k;
}

// Unit plane normal of a depth map's pixel in world space, or zero when the map has none.
Eigen::Vector3d WorldNormal(const DepthMap& m, const Rigid3d& world_from_cam, int x, int y) {
  if (m.normal.empty()) return Eigen::Vector3d::Zero();
  const cv::Vec3f n = m.normal.at<cv::Vec3f>(y, x);
  return world_from_cam.rotation * Eigen::Vector3d(n[0], n[1], n[2]);
}

// Geometric consistency and fusion of one depth map: a depth survives when at least
// min_consistent of its source photos' depth maps see the same surface within `consistency`
// relative depth (and, with plane normals, max_normal_error), or one does and its NCC reaches
// single_agreement_ncc; the fused point averages the agreeing back-projections (and normals).
// The agreeing pixels of the other maps are marked in `used` (one CV_8U mask per map) and make
// no point of their own, and the pixels already marked in map i are skipped: one point per
// surface element rather than one per photo that sees it (as COLMAP's fusion), so that the
// depth pass does not keep the nearest of several noisy copies of a surface.
DenseResult FuseDepthMap(const std::vector<DepthMap>& maps, const std::map<int, int>& index, int i,
                         const DenseOptions& options, std::vector<cv::Mat>& used) {
  DenseResult out;
  const DepthMap& ref = maps[i];
  if (ref.depth.empty()) return out;
  const Rigid3d world_from_ref = ref.cam_from_world.Inverse();
  const Eigen::Vector3d ref_center = world_from_ref.translation;
  const bool with_normals = !ref.normal.empty();
  const double min_normal_cos = std::cos(options.max_normal_error * M_PI / 180.0);
  std::vector<std::pair<int, cv::Point>> merged;  // (map, pixel) of the agreeing depths
  for (int y = 0; y < ref.depth.rows; ++y) {
    for (int x = 0; x < ref.depth.cols; ++x) {
      const float z = ref.depth.at<float>(y, x);
      if (z <= 0) continue;
      if (used[i].at<uint8_t>(y, x)) continue;
      merged.clear();
      const Eigen::Vector3d xw =
          world_from_ref * (ref.camera.CamFromPixel({x + 0.5, y + 0.5}) * double(z));
      Eigen::Vector3d sum = xw;
      Eigen::Vector3d dir = (ref_center - xw).normalized();
      const Eigen::Vector3d ref_normal = WorldNormal(ref, world_from_ref, x, y);
      Eigen::Vector3d normal = ref_normal;
      int agree = 0;
      for (int nid : ref.neighbors) {
        const DepthMap& nb = maps[index.at(nid)];
        if (nb.depth.empty()) continue;
        const Eigen::Vector3d pc = nb.cam_from_world * xw;
        if (pc.z() <= 0) continue;
        const Eigen::Vector2d px = nb.camera.PixelFromCam(pc);
        const int u = static_cast<int>(std::floor(px.x())),
                  v = static_cast<int>(std::floor(px.y()));
        if (u < 0 || v < 0 || u >= nb.depth.cols || v >= nb.depth.rows) continue;
        const float zn = nb.depth.at<float>(v, u);
        if (zn <= 0 || std::abs(zn - pc.z()) > options.consistency * pc.z()) continue;
        const Rigid3d world_from_nb = nb.cam_from_world.Inverse();
        const Eigen::Vector3d nb_normal = WorldNormal(nb, world_from_nb, u, v);
        if (with_normals && nb_normal.dot(ref_normal) < min_normal_cos) continue;
        ++agree;
        merged.push_back({index.at(nid), cv::Point(u, v)});
        sum += world_from_nb * (nb.camera.CamFromPixel(px) * double(zn));
        dir += (world_from_nb.translation - xw).normalized();
        normal += nb_normal;
      }
      const bool well_matched =
          !ref.score.empty() && ref.score.at<float>(y, x) >= options.single_agreement_ncc;
      if (agree < (well_matched ? std::min(1, options.min_consistent) : options.min_consistent)) {
        continue;
      }
      for (const auto& [j, q] : merged) used[j].at<uint8_t>(q) = 1;
      const Eigen::Vector3d p = sum / (agree + 1);
      out.cloud.positions.push_back(p.cast<float>());
      const cv::Vec3b c = ref.color.at<cv::Vec3b>(y, x);
      out.cloud.colors.push_back({c[2], c[1], c[0]});
      out.view_dirs.push_back(dir.normalized().cast<float>());
      if (with_normals) {
        out.cloud.normals.push_back(
            (normal.norm() > 0 ? normal.normalized() : dir.normalized()).cast<float>());
      }
    }
  }
  return out;
}

}  // namespace

std::map<int, std::vector<int>> SelectNeighbors(const ColmapModel& model, int k) {
  std::map<int, Eigen::Vector3d> centers;
  for (const auto& [id, im] : model.images) centers[id] = im.cam_from_world.Inverse().translation;
  std::map<std::pair<int, int>, int> shared;
  const double min_angle = 2.0 * M_PI / 180.0;
  for (const auto& [pid, pt] : model.points3d) {
    std::vector<int> ids;
    for (const auto& el : pt.track) ids.push_back(el.image_id);
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    for (size_t a = 0; a < ids.size(); ++a) {
      for (size_t b = a + 1; b < ids.size(); ++b) {
        auto ca = centers.find(ids[a]), cb = centers.find(ids[b]);
        if (ca == centers.end() || cb == centers.end()) continue;
        const Eigen::Vector3d ra = (ca->second - pt.xyz).normalized();
        const Eigen::Vector3d rb = (cb->second - pt.xyz).normalized();
        const double angle = std::acos(std::clamp(ra.dot(rb), -1.0, 1.0));
        if (angle >= min_angle) ++shared[{ids[a], ids[b]}];
      }
    }
  }
  std::map<int, std::vector<std::pair<int, int>>> scored;
  for (const auto& [pair, count] : shared) {
    scored[pair.first].push_back({count, pair.second});
    scored[pair.second].push_back({count, pair.first});
  }
  std::map<int, std::vector<int>> out;
  for (const auto& [id, im] : model.images) {
    auto& list = scored[id];
    std::sort(list.begin(), list.end(), [](auto& x, auto& y) { return x.first > y.first; });
    for (size_t i = 0; i < list.size() && static_cast<int>(i) < k; ++i) {
      out[id].push_back(list[i].second);
    }
  }
  return out;
}

DepthMap ComputeDepthMap(const DepthMap& ref_in, const std::vector<const DepthMap*>& sources,
                         double depth_min, double depth_max, const DenseOptions& options) {
  DepthMap ref = ref_in;
  const int w = ref.gray.cols, h = ref.gray.rows;
  const int r = options.window_radius;
  const int nd = std::max(3, options.num_depths);
  cv::Mat ref_mean, ref_var;
  WindowStats(ref.gray, r, ref_mean, ref_var);

  const Eigen::Matrix3d kr_inv = OpenCvK(ref.camera).inverse();
  const Rigid3d world_from_ref = ref.cam_from_world.Inverse();
  const double inv_near = 1.0 / depth_min, inv_far = 1.0 / depth_max;
  std::vector<cv::Mat> volume(nd);
  const cv::Mat ones(ref.gray.size(), CV_8U, cv::Scalar(1));
  const size_t ns = sources.size();
  const int keep = std::max<int>(1, static_cast<int>((ns + 1) / 2));
  std::vector<cv::Mat> ncc(ns);
  for (int k = 0; k < nd; ++k) {
    const double depth = 1.0 / (inv_far + (inv_near - inv_far) * k / (nd - 1));
    for (size_t s = 0; s < ns; ++s) {
      const DepthMap& src = *sources[s];
      const Rigid3d src_from_ref = src.cam_from_world * world_from_ref;
      const Eigen::Matrix3d rot = src_from_ref.rotation.toRotationMatrix();
      // Plane z = depth in the reference frame: x_src ~ K_s (R + t e3^T / depth) K_r^-1 x_ref.
      Eigen::Matrix3d hm = rot;
      hm.col(2) += src_from_ref.translation / depth;
      const Eigen::Matrix3d src_from_ref_px = OpenCvK(src.camera) * hm * kr_inv;
      cv::Mat hcv(3, 3, CV_64F);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) hcv.at<double>(i, j) = src_from_ref_px(i, j);
      cv::Mat warped, mask;
      cv::warpPerspective(src.gray, warped, hcv, ref.gray.size(),
                          cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
      cv::warpPerspective(ones, mask, hcv, ref.gray.size(),
                          cv::INTER_NEAREST | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, 0);
      ncc[s] = NccMap(ref.gray, ref_mean, ref_var, warped, r, 1e-5f);
      ncc[s].setTo(-1.f, mask == 0);
    }
    // Aggregate: mean of the best half of the sources (robust to occlusion in some of them).
    cv::Mat agg(h, w, CV_32F);
    std::vector<float> vals(ns);
    for (int y = 0; y < h; ++y) {
      float* pa = agg.ptr<float>(y);
      for (int x = 0; x < w; ++x) {
        for (size_t s = 0; s < ns; ++s) vals[s] = ncc[s].at<float>(y, x);
        std::partial_sort(vals.begin(), vals.begin() + keep, vals.end(), std::greater<float>());
        float sum = 0;
        for (int i = 0; i < keep; ++i) sum += vals[i];
        pa[x] = ns ? sum / keep : -1.f;
      }
    }
    volume[k] = agg;
  }

  ref.depth = cv::Mat::zeros(h, w, CV_32F);
  ref.score = cv::Mat::zeros(h, w, CV_32F);
  const float min_texture = 1e-4f;  // window variance of [0,1] intensities (about 2.5/255 std)
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (ref_var.at<float>(y, x) < min_texture) continue;
      int best = 0;
      float best_score = -2.f;
      for (int k = 0; k < nd; ++k) {
        const float v = volume[k].at<float>(y, x);
        if (v > best_score) {
          best_score = v;
          best = k;
        }
      }
      if (best_score < options.min_ncc || best == 0 || best == nd - 1) continue;
      // Parabola through the three scores around the peak, in plane-index units.
      const float a = volume[best - 1].at<float>(y, x), c = volume[best + 1].at<float>(y, x);
      const float denom = a - 2 * best_score + c;
      const double offset = denom < 0 ? std::clamp(0.5 * (a - c) / denom, -0.5, 0.5) : 0.0;
      const double inv = inv_far + (inv_near - inv_far) * (best + offset) / (nd - 1);
      ref.depth.at<float>(y, x) = static_cast<float>(1.0 / inv);
      ref.score.at<float>(y, x) = best_score;
    }
  }
  return ref;
}

std::pair<double, double> SparseDepthRange(std::vector<double> depths) {
  if (depths.empty()) return {0.0, 0.0};
  std::sort(depths.begin(), depths.end());
  const double lo = depths[depths.size() * 2 / 100], z98 = depths[depths.size() * 98 / 100];
  const double hi = std::min(depths.back(), kFarOutlier * z98);
  return {0.75 * lo, 1.25 * hi};
}

int DepthMapSize(const ColmapModel& model, const DenseOptions& options) {
  if (options.max_size > 0) return options.max_size;
  if (model.images.empty()) return options.min_auto_size;
  // A photo of largest side L at largest side s has s^2 * (w h / L^2) pixels.
  double area_per_side2 = 0;
  for (const auto& [id, im] : model.images) {
    const Camera& cam = model.cameras.at(im.camera_id);
    const double l = std::max(cam.width, cam.height);
    area_per_side2 += double(cam.width) * cam.height / (l * l);
  }
  const double side = std::sqrt(options.pixel_budget / area_per_side2);
  return std::max(options.min_auto_size, static_cast<int>(std::lround(side)));
}

DenseResult DensifyCpu(const ColmapModel& model, const fs::path& images_dir,
                       const DenseOptions& options, const std::function<void(int, int)>& progress) {
  const int threads = ThreadCount(options.threads);
  const int max_size = DepthMapSize(model, options);
  const auto neighbors = SelectNeighbors(model, options.num_neighbors);

  // Load and scale every photo.
  std::vector<int> ids;
  for (const auto& [id, im] : model.images) ids.push_back(id);
  const int n = static_cast<int>(ids.size());
  std::vector<DepthMap> maps(n);
  std::map<int, int> index;
  for (int i = 0; i < n; ++i) index[ids[i]] = i;
  ParallelFor(n, threads, [&](int i) {
    const ColmapImage& im = model.images.at(ids[i]);
    const Camera& cam = model.cameras.at(im.camera_id);
    const cv::Mat bgr = ReadImage(images_dir / im.name);
    const double s = std::min(1.0, double(max_size) / std::max(bgr.cols, bgr.rows));
    const int w = std::max(1, static_cast<int>(std::lround(bgr.cols * s)));
    const int h = std::max(1, static_cast<int>(std::lround(bgr.rows * s)));
    DepthMap& m = maps[i];
    m.image_id = im.id;
    m.camera =
        Camera::Pinhole(cam.id, cam.width, cam.height, cam.fx(), cam.fy(), cam.cx(), cam.cy())
            .Scaled(w, h);
    m.cam_from_world = im.cam_from_world;
    cv::resize(bgr, m.color, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    cv::Mat g;
    cv::cvtColor(m.color, g, cv::COLOR_BGR2GRAY);
    g.convertTo(m.gray, CV_32F, 1.0 / 255.0);
    auto it = neighbors.find(im.id);
    if (it != neighbors.end()) m.neighbors = it->second;
  });

  // Depth range of each photo from the sparse points it sees; they also seed PatchMatch.
  std::vector<PatchMatchTask> tasks(n);
  for (int i = 0; i < n; ++i) {
    const ColmapImage& im = model.images.at(ids[i]);
    std::vector<double> z;
    for (const auto& p2 : im.points2d) {
      if (p2.point3d_id < 0) continue;
      auto it = model.points3d.find(p2.point3d_id);
      if (it == model.points3d.end()) continue;
      const Eigen::Vector3d pc = im.cam_from_world * it->second.xyz;
      if (pc.z() <= 0) continue;
      z.push_back(pc.z());
      tasks[i].seeds.push_back(pc);
    }
    for (int nid : maps[i].neighbors) tasks[i].sources.push_back(index.at(nid));
    if (z.size() < 10) continue;
    std::tie(tasks[i].depth_min, tasks[i].depth_max) = SparseDepthRange(std::move(z));
  }

  if (options.method == DenseMethod::kPatchMatch) {
    DenseOptions o = options;
    o.threads = threads;
    PatchMatchDepthMaps(maps, tasks, o, progress);
  } else {
    std::atomic<int> done{0};
    std::mutex progress_mutex;
    ParallelFor(n, threads, [&](int i) {
      std::vector<const DepthMap*> sources;
      for (int s : tasks[i].sources) sources.push_back(&maps[s]);
      if (!sources.empty() && tasks[i].depth_max > 0) {
        DepthMap out =
            ComputeDepthMap(maps[i], sources, tasks[i].depth_min, tasks[i].depth_max, options);
        maps[i].depth = out.depth;
        maps[i].score = out.score;
      }
      const int d = ++done;
      if (progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress(d, n);
      }
    });
  }

  DenseResult result = FuseDepthMaps(maps, options);
  result.depth_map_size = max_size;
  return result;
}

DenseResult FuseDepthMaps(const std::vector<DepthMap>& maps, const DenseOptions& options) {
  const int n = static_cast<int>(maps.size());
  std::map<int, int> index;
  for (int i = 0; i < n; ++i) index[maps[i].image_id] = i;
  // One map after the other: a map's pixels that an earlier map's points merged are used.
  std::vector<DenseResult> partial(n);
  std::vector<cv::Mat> used(n);
  for (int i = 0; i < n; ++i) used[i] = cv::Mat::zeros(maps[i].depth.size(), CV_8U);
  for (int i = 0; i < n; ++i) partial[i] = FuseDepthMap(maps, index, i, options, used);
  DenseResult result;
  for (auto& p : partial) {
    result.cloud.positions.insert(result.cloud.positions.end(), p.cloud.positions.begin(),
                                  p.cloud.positions.end());
    result.cloud.colors.insert(result.cloud.colors.end(), p.cloud.colors.begin(),
                               p.cloud.colors.end());
    result.cloud.normals.insert(result.cloud.normals.end(), p.cloud.normals.begin(),
                                p.cloud.normals.end());
    result.view_dirs.insert(result.view_dirs.end(), p.view_dirs.begin(), p.view_dirs.end());
  }
  for (const auto& m : maps) result.num_depth_maps += m.depth.empty() ? 0 : 1;
  return result;
}

}  // namespace hdribr
