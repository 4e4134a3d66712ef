// Options of the blend pass (Lechelek et al. 2019, sec. 4, eqs. 1-5, and the Unstructured
// Lumigraph weights), their names and their one validity rule.
#pragma once

#include <string>
#include <vector>

namespace hdribr::render {

// What the blend pass computes per pixel.
enum class BlendMode {
  kBlend,         // blend the photos that see the point (weights: BlendWeights)
  kNearestPhoto,  // baseline: projective texturing from the single photo nearest the view
};

// The blending weights of BlendMode::kBlend.
enum class BlendWeights {
  kPaper,         // LEC19 eq. 5: max(0, V . V_k) / (delta_k + 1) over all (or the K best)
  kUnstructured,  // Unstructured Lumigraph (Buehler et al. 2001): K smallest angle + delta
                  // penalties p_k, w_k = (1 - p_k / p_(K+1)) / p_k
};

// Every BlendWeights value, in declaration order.
inline constexpr BlendWeights kAllBlendWeights[] = {BlendWeights::kPaper,
                                                    BlendWeights::kUnstructured};

// "paper", "ulr"; ParseBlendWeights throws UsageError for anything else.
std::string BlendWeightsName(BlendWeights weights);
BlendWeights ParseBlendWeights(const std::string& name);

// K of BlendWeights::kUnstructured when BlendOptions::k_best is 0.
inline constexpr int kDefaultUnstructuredK = 4;
// Largest K of BlendOptions::k_best handled per pixel (KEEP - 1 in shaders/blend_common.glsl).
inline constexpr int kMaxKBest = 32;

// Largest BlendOptions::filter: a depth uncertainty of +-50 %.
inline constexpr float kMaxFilter = 0.5f;
// Largest BlendOptions::refine_depth: +-5 % of the view depth.
inline constexpr float kMaxRefineDepth = 0.05f;

// What the blend shows where the depth pass found no point (sky, distant ground, gaps).
// Either surface is seen by a photo where the photo's own depth map has no point either.
// The values are BACKGROUND of shaders/blend_holes.glsl.
enum class Background {
  kNone = 0,      // nothing: only the photos' surfaces along the ray, else the pixel stays invalid
  kInfinity = 1,  // a surface at infinity: each photo's pixel in the ray's direction
  kSphere = 2,    // a sphere around the points and the cameras (BackgroundSphere)
  kPlane = 3,     // the scene's dominant plane where it holds points (FindDominantPlane), else
                  // the sphere
};

// Every Background value, in declaration order.
inline constexpr Background kAllBackgrounds[] = {Background::kNone, Background::kInfinity,
                                                 Background::kSphere, Background::kPlane};

// "none", "infinity", "sphere", "plane"; ParseBackground throws UsageError for anything else.
std::string BackgroundName(Background background);
Background ParseBackground(const std::string& name);

// How photo pixels are turned into the blended value.
enum class PhotoEncoding {
  kDisplay,   // the photo's stored values (8-bit / 255, or float for an HDR photo set)
  kRadiance,  // direct radiance blending: exp(g(Z)) / relative exposure, blending weight
              // times Debevec's hat weight of Z; needs a response curve
};

// A point's visibility in a photo, from the 2x2 depth-map texels about its projection: kHard,
// visible when one agrees; kSoft, weighted by the share that agree (soft at the photo's depth
// discontinuities, where the test is a coin toss).
enum class Visibility { kHard = 0, kSoft = 1 };

// How a photo is sampled at a point's projection: kLinear, trilinear (bilinear in the mipmap
// level of the pixel's footprint); kCubic, Catmull-Rom bicubic where that level is about 0 (a
// sharper reconstruction of the photo's pixels), trilinear at coarser levels.
enum class PhotoSampling { kLinear = 0, kCubic = 1 };

// Every PhotoSampling value, in declaration order.
inline constexpr PhotoSampling kAllPhotoSamplings[] = {PhotoSampling::kLinear,
                                                       PhotoSampling::kCubic};

// "linear", "cubic"; ParsePhotoSampling throws UsageError for anything else.
std::string PhotoSamplingName(PhotoSampling sampling);
PhotoSampling ParsePhotoSampling(const std::string& name);

struct BlendOptions {
  BlendMode mode = BlendMode::kBlend;
  PhotoEncoding encoding = PhotoEncoding::kDisplay;
  // Unstructured Lumigraph by default (closer to held-out photos than eq. 5, see
  // docs/decisions/0004); kPaper is the paper's blending exactly.
  BlendWeights weights = BlendWeights::kUnstructured;
  int k_best = 0;        // 0 = all photos for kPaper (the paper), kDefaultUnstructuredK for ULR
  float lambda = 1e-4f;  // a photo counts when N_p . V_k > lambda (paper eq. 3)
  float occlusion_tolerance = 0.01f;  // |z_k(P) - depth_k| <= tolerance * depth_k passes
  int debug_photo = -1;               // photo index whose weight goes to RenderImages::weight
  // The plane by default (closer to held-out photos than the sphere alone, docs/decisions/0038).
  Background background = Background::kPlane;
  // Pixels that no photo shows (past every photo's frame, or a surface no photo sees) take the
  // pull-push interpolation of the pixels around them (FillPass), marked as filled; false
  // leaves them empty.
  bool fill = true;
  Visibility visibility = Visibility::kHard;
  // Filtered blending (Eisemann et al. 2007): relative depth uncertainty along the view's ray
  // over which each blended photo is low-passed; 0 = off.
  float filter = 0.0f;
  // Catmull-Rom by default (sharper than trilinear, docs/decisions/0019).
  PhotoSampling sampling = PhotoSampling::kCubic;
  // Photometric outlier rejection of the ranked photos of 8-bit photos (not with every photo
  // summed, nor for float photos): each weight divided by 1 + (|c_k - m| / outlier_scale)^2,
  // c_k the photo's value (RGB, 1 = white), m the weighted mean; 0 = off.
  float outlier_scale = 0.08f;
  // Photo-consistent depth: each pixel takes, of its view depth z and z (1 +- refine_depth), the
  // one where its ranked photos agree best over a 5-ray patch; 0 = off. On by default (closer
  // to held-out photos on reconstructed clouds, docs/decisions/0028).
  float refine_depth = 0.003f;
};

// One BlendOptions field that no blend can use.
struct BlendOptionProblem {
  std::string field;    // the BlendOptions member: "k_best", "lambda", "occlusion_tolerance",
                        // "filter", "outlier_scale", "refine_depth"
  std::string problem;  // e.g. "must be in [0, 32] (0 = the default), got 40"
};

// The fields of `options` outside their valid ranges: k_best in [0, kMaxKBest] whatever the
// weights, lambda in [0, 1), occlusion_tolerance in (0, 1), filter in [0, kMaxFilter],
// outlier_scale finite and >= 0, refine_depth in [0, kMaxRefineDepth]. Empty when the options are
// usable.
std::vector<BlendOptionProblem> BlendOptionProblems(const BlendOptions& options);

// Throws OptionError(field, problem) for the first of BlendOptionProblems.
void ValidateBlendOptions(const BlendOptions& options);

// Photos the blend ranks per pixel: K + 1 for the Unstructured Lumigraph (its threshold is the
// (K+1)-th penalty), K for the paper's weights with K best, 0 when every photo counts, 1 for
// the nearest photo.
int RankedPhotosPerPixel(const BlendOptions& options);
// True when the blend of `photos` photos keeps a per-pixel list of the best ones (the
// Unstructured Lumigraph, or the paper's K best with K < photos), whose result does not depend
// on the order the photos are visited in; false when it sums every photo in their order.
bool BlendRanksPhotos(const BlendOptions& options, int photos);

}  // namespace hdribr::render
