#include "hdr/debevec.h"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace hdribr {
namespace {

constexpr int kLevels = 256;
constexpr int kMid = 128;  // g(kMid) = 0 fixes the curve's free additive constant
constexpr int kBins = 32;  // intensity bins of the reference exposure (sampling and trimming)

int BinOf(int z) { return z * kBins / kLevels; }

// Pixel indices for channel c, spread over the intensity range and over the image: candidate
// pixels (a grid of about 60k) are binned by their value in the reference (mid) exposure; a
// share of the samples is split evenly over the non-empty bins, so that rare intensities
// (windows, sky) constrain the curve, and the rest in proportion to the bins' pixel counts, so
// that the common radiances are fitted as well. Within a bin, picks are evenly spaced in scan
// order, i.e. spread over the image.
// With `contrast` (CV_16UC1, optional), only the flattest `flat_fraction` of each bin's
// candidates are kept before picking.
std::vector<int> SelectSamples(const cv::Mat& reference, const cv::Mat& all_valid, int channel,
                               int count, const cv::Mat& contrast, double flat_fraction) {
  const int w = reference.cols;
  const int h = reference.rows;
  const long total = static_cast<long>(w) * h;
  const int step = std::max(1, static_cast<int>(std::sqrt(total / 60000.0)));
  std::array<std::vector<int>, kBins> bins;
  long candidates = 0;
  for (int y = step / 2; y < h; y += step) {
    const uint8_t* row = reference.ptr<uint8_t>(y);
    const uint8_t* valid = all_valid.empty() ? nullptr : all_valid.ptr<uint8_t>(y);
    for (int x = step / 2; x < w; x += step) {
      if (valid && !valid[x]) continue;
      bins[BinOf(row[3 * x + channel])].push_back(y * w + x);
      ++candidates;
    }
  }
  if (candidates == 0) return {};
  if (!contrast.empty() && flat_fraction < 1.0) {
    candidates = 0;
    for (auto& bin : bins) {
      if (bin.empty()) continue;
      const size_t keep = std::max<size_t>(1, std::llround(flat_fraction * bin.size()));
      const uint16_t* flatness = contrast.ptr<uint16_t>();
      // Flattest first, ties by scan order (the same picks on every platform).
      std::nth_element(bin.begin(), bin.begin() + static_cast<long>(keep) - 1, bin.end(),
                       [&](int a, int b) {
                         return flatness[a] != flatness[b] ? flatness[a] < flatness[b] : a < b;
                       });
      bin.resize(keep);
      std::sort(bin.begin(), bin.end());  // back to scan order: spread over the image
      candidates += static_cast<long>(keep);
    }
  }
  int nonempty = 0;
  for (const auto& bin : bins) nonempty += !bin.empty();
  constexpr double kCover = 0.25;  // share of the samples split evenly over the bins
  const int even_share = static_cast<int>(std::ceil(kCover * count / nonempty));
  std::array<int, kBins> quota{};
  int assigned = 0;
  for (int b = 0; b < kBins; ++b) {
    quota[b] = std::min<int>(static_cast<int>(bins[b].size()), even_share);
    assigned += quota[b];
  }
  const int rest = std::max(0, count - assigned);
  for (int b = 0; b < kBins; ++b) {
    const int proportional =
        static_cast<int>(static_cast<double>(rest) * bins[b].size() / candidates);
    quota[b] = std::min<int>(static_cast<int>(bins[b].size()), quota[b] + proportional);
  }
  std::vector<int> samples;
  samples.reserve(count + kBins);
  for (int b = 0; b < kBins; ++b) {
    const size_t n = bins[b].size();
    for (int k = 0; k < quota[b]; ++k) {
      samples.push_back(bins[b][static_cast<size_t>((k + 0.5) * n / quota[b])]);
    }
  }
  return samples;
}

cv::Mat AllValid(const ExposureStack& stack) {
  if (stack.masks.empty()) return {};
  cv::Mat all(stack.images[0].size(), CV_8UC1, cv::Scalar(255));
  for (const auto& m : stack.masks) all.setTo(0, m == 0);
  return all;
}

// Local contrast per channel: the 3x3 range (max - min, in DN) summed over the images
// (CV_16UC3: at most 255 per image, so exact up to 257 images; saturates beyond).
cv::Mat LocalContrast(const ExposureStack& stack) {
  cv::Mat sum(stack.images[0].size(), CV_16UC3, cv::Scalar::all(0));
  const cv::Mat box = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
  cv::Mat range;
  for (const cv::Mat& image : stack.images) {
    cv::morphologyEx(image, range, cv::MORPH_GRADIENT, box);
    cv::add(sum, range, sum, cv::noArray(), CV_16U);
  }
  return sum;
}

// One channel's sample: its value in every image of the stack.
using SampleValues = std::vector<uint8_t>;

// Debevec's least squares for one channel with g(128) = 0, over the samples flagged in `use`.
// Returns false when the system cannot be solved.
bool SolveChannel(const std::vector<SampleValues>& samples, const std::vector<char>& use,
                  const std::vector<double>& log_t, const CalibrationOptions& options,
                  std::vector<double>& g) {
  const int p = static_cast<int>(log_t.size());
  // Normal equations of Debevec's system with the per-sample unknowns ln E_i eliminated
  // (Schur complement): for sample i with a_j = w(Z_ij)^2 and r_j = g(Z_ij) - ln t_j, the
  // minimum over ln E_i of sum_j a_j (r_j - ln E_i)^2 is sum a r^2 - (sum a r)^2 / sum a.
  // This leaves a dense 256 x 256 system whatever the number of samples.
  Eigen::MatrixXd hess = Eigen::MatrixXd::Zero(kLevels, kLevels);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(kLevels);
  std::vector<double> a(p);
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!use[i]) continue;
    const SampleValues& z = samples[i];
    double sum_a = 0;
    double sum_al = 0;
    for (int j = 0; j < p; ++j) {
      const double wj = HatWeight(z[j]);
      a[j] = wj * wj;
      sum_a += a[j];
      sum_al += a[j] * log_t[j];
    }
    for (int j = 0; j < p; ++j) {
      if (a[j] == 0) continue;
      hess(z[j], z[j]) += a[j];
      rhs(z[j]) += a[j] * log_t[j] - a[j] * sum_al / sum_a;
      for (int k = 0; k < p; ++k) {
        if (a[k] != 0) hess(z[j], z[k]) -= a[j] * a[k] / sum_a;
      }
    }
  }
  // Smoothness: lambda w(z) D(g)(z) = 0 for z = 1..254, D the second difference.
  for (int k = 1; k + 1 < kLevels; ++k) {
    const double s = options.lambda * options.lambda * HatWeight(k) * HatWeight(k);
    const int idx[3] = {k - 1, k, k + 1};
    const std::array<double, 3> d = SmoothnessStencil(k, options.smoothness);
    for (int u = 0; u < 3; ++u) {
      for (int v = 0; v < 3; ++v) hess(idx[u], idx[v]) += s * d[u] * d[v];
    }
  }
  // g(128) = 0: drop that unknown.
  Eigen::MatrixXd reduced(kLevels - 1, kLevels - 1);
  Eigen::VectorXd reduced_rhs(kLevels - 1);
  auto full = [](int r) { return r < kMid ? r : r + 1; };
  for (int r = 0; r < kLevels - 1; ++r) {
    reduced_rhs(r) = rhs(full(r));
    for (int col = 0; col < kLevels - 1; ++col) reduced(r, col) = hess(full(r), full(col));
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(reduced);
  const Eigen::VectorXd solution = ldlt.solve(reduced_rhs);
  if (ldlt.info() != Eigen::Success || !solution.allFinite()) return false;
  g.assign(kLevels, 0.0);
  for (int r = 0; r < kLevels - 1; ++r) g[full(r)] = solution(r);
  return true;
}

// Weighted RMS of g(Z_ij) - ln t_j - ln E_i over the images of sample i (ln E_i fitted).
double SampleResidual(const SampleValues& z, const std::vector<double>& log_t,
                      const std::vector<double>& g) {
  double sum_a = 0, sum_ar = 0, sum_arr = 0;
  for (size_t j = 0; j < z.size(); ++j) {
    const double wj = HatWeight(z[j]);
    const double r = g[z[j]] - log_t[j];
    sum_a += wj * wj;
    sum_ar += wj * wj * r;
    sum_arr += wj * wj * r * r;
  }
  const double mean = sum_ar / sum_a;
  return std::sqrt(std::max(0.0, sum_arr / sum_a - mean * mean));
}

// Clears use[i] for the share `trim` of the samples with the largest residual within each
// group (group[i] in [0, kBins)), and for every sample whose residual exceeds `gross`.
void TrimWorst(const std::vector<double>& residual, const std::vector<int>& group, double trim,
               double gross, std::vector<char>& use) {
  std::array<std::vector<std::pair<double, size_t>>, kBins> groups;
  for (size_t i = 0; i < residual.size(); ++i) groups[group[i]].push_back({residual[i], i});
  for (auto& members : groups) {
    const auto n = static_cast<long>(std::floor(trim * static_cast<double>(members.size())));
    std::nth_element(members.begin(), members.end() - n, members.end());
    for (auto it = members.begin(); it != members.end(); ++it) {
      if (it >= members.end() - n || it->first > gross) use[it->second] = 0;
    }
  }
}

}  // namespace

double HatWeight(int z) { return std::min(z, 255 - z); }

// The smoothness term's second difference at k as coefficients of g(k-1), g(k), g(k+1). In
// u = ln(k + 0.5) it is the difference of the slopes dg/du on either side times the mean step,
// so that it is (1, -2, 1) where the steps are equal (large k) and lambda keeps its scale.
std::array<double, 3> SmoothnessStencil(int k, CalibrationOptions::Smoothness axis) {
  if (axis == CalibrationOptions::Smoothness::kCode) return {1.0, -2.0, 1.0};
  const double h1 = std::log((k + 0.5) / (k - 0.5));
  const double h2 = std::log((k + 1.5) / (k + 0.5));
  const double mean = 0.5 * (h1 + h2);
  return {mean / h1, -mean / h1 - mean / h2, mean / h2};
}

CalibrationOptions PlainDebevec(CalibrationOptions options) {
  options.smoothness = CalibrationOptions::Smoothness::kCode;
  options.flat_fraction = 1.0;
  options.trim = 0.0;
  return options;
}

ResponseCurve CalibrateDebevec(const ExposureStack& stack, const CalibrationOptions& options,
                               CalibrationStats* stats) {
  stack.Validate();
  if (options.samples < 1) throw UsageError("the calibration needs at least 1 sample per channel");
  if (!std::isfinite(options.lambda) || options.lambda < 0) {
    throw UsageError("the smoothness weight lambda must be a non-negative number");
  }
  if (!(options.flat_fraction > 0 && options.flat_fraction <= 1)) {
    throw UsageError("the flat-sample fraction must be in (0, 1]");
  }
  if (!(options.trim >= 0 && options.trim < 1)) {
    throw UsageError("the trimmed-sample fraction must be in [0, 1)");
  }
  const int p = static_cast<int>(stack.images.size());
  const auto [tmin, tmax] = std::minmax_element(stack.times.begin(), stack.times.end());
  if (p < 2 || *tmax / *tmin < 1.0 + 1e-9) {
    throw UsageError(
        "calibration needs at least two images with different exposure times "
        "(pass a response file to merge without calibrating)");
  }
  const std::vector<int> order = stack.OrderByTime();
  const int reference_index = order[p / 2];
  const cv::Mat& reference = stack.images[reference_index];
  const cv::Mat all_valid = AllValid(stack);
  std::vector<double> log_t(p);
  for (int j = 0; j < p; ++j) log_t[j] = std::log(stack.times[j]);

  ResponseCurve curve;
  curve.source = "debevec";
  curve.lambda = options.lambda;
  CalibrationStats local_stats;
  cv::Mat contrast3;
  cv::Mat candidates_valid = all_valid;
  if (options.flat_fraction < 1.0) {
    contrast3 = LocalContrast(stack);
    // Flat also means not at the border of a mask (partly covered, resampled pixels).
    if (!all_valid.empty()) {
      cv::Mat eroded;  // a new buffer: candidates_valid shares all_valid's
      cv::erode(all_valid, eroded, cv::Mat());
      if (cv::countNonZero(eroded) > 0) candidates_valid = eroded;
    }
  }
  for (int c = 0; c < 3; ++c) {
    cv::Mat contrast;
    if (!contrast3.empty()) cv::extractChannel(contrast3, contrast, c);
    const std::vector<int> indices = SelectSamples(reference, candidates_valid, c, options.samples,
                                                   contrast, options.flat_fraction);
    std::vector<SampleValues> samples;
    samples.reserve(indices.size());
    for (int index : indices) {
      SampleValues z(p);
      int observed = 0;
      for (int j = 0; j < p; ++j) {
        z[j] = stack.images[j].ptr<uint8_t>()[3 * static_cast<size_t>(index) + c];
        observed += HatWeight(z[j]) > 0;
      }
      if (observed >= 2) samples.push_back(std::move(z));
    }
    const int used = static_cast<int>(samples.size());
    if (used == 0) {
      throw UsageError(
          "no pixel is well exposed (values 1-254) in two or more images: the "
          "stack cannot constrain a response curve (pass a response file instead)");
    }
    std::vector<char> use(samples.size(), 1);
    std::vector<double>& g = curve.log_inverse[c];
    bool solved = SolveChannel(samples, use, log_t, options, g);
    int drop = 0;
    if (solved && options.trim > 0) {
      // Robust refit in two rounds. First the samples the first fit explains worst over the
      // whole stack (series that disagree, corrupt or misregistered images) are dropped and g
      // solved again; then, with that cleaner g, the worst of each intensity bin of the
      // reference exposure (and any gross outlier). Per bin because the dark and bright ends
      // are noisier in ln E: the first round alone drops nearly all of their samples, leaving
      // those ends to the smoothness term.
      constexpr double kOutlier = 10.0;  // round 1: x the median residual, dropped in any bin
      std::vector<double> residual(samples.size());
      for (int round = 0; round < 2; ++round) {
        for (size_t i = 0; i < samples.size(); ++i) {
          residual[i] = SampleResidual(samples[i], log_t, g);
        }
        // Round 0: one group, no gross cut; round 1: the intensity bins and the gross cut
        // (none where the median residual is 0: exact data).
        std::vector<int> group(samples.size(), 0);
        double gross = std::numeric_limits<double>::infinity();
        if (round == 1) {
          for (size_t i = 0; i < samples.size(); ++i) group[i] = BinOf(samples[i][reference_index]);
          std::vector<double> sorted = residual;
          const auto mid = sorted.begin() + static_cast<long>(sorted.size() / 2);
          std::nth_element(sorted.begin(), mid, sorted.end());
          if (*mid > 0) gross = kOutlier * *mid;
        }
        std::fill(use.begin(), use.end(), 1);
        TrimWorst(residual, group, options.trim, gross, use);
        // Should a refit be singular, g keeps the previous fit (SolveChannel leaves it alone).
        if (!SolveChannel(samples, use, log_t, options, g)) break;
        drop = static_cast<int>(std::count(use.begin(), use.end(), 0));
      }
    }
    if (!solved) {
      throw UsageError(
          "the response calibration is ill-conditioned for this stack (too few "
          "well exposed pixels); try more samples or a larger smoothness weight lambda");
    }
    // A response is monotonic; noise at the barely constrained ends can bend g back. Clamp
    // outward from the fixed middle so that g stays non-decreasing.
    int fixes = 0;
    for (int k = kMid + 1; k < kLevels; ++k) {
      if (g[k] < g[k - 1]) g[k] = g[k - 1], ++fixes;
    }
    for (int k = kMid - 1; k >= 0; --k) {
      if (g[k] > g[k + 1]) g[k] = g[k + 1], ++fixes;
    }
    local_stats.samples_used[c] = used - drop;
    local_stats.monotone_fixes[c] = fixes;
  }
  if (stats) *stats = local_stats;
  return curve;
}

cv::Mat MergeDebevec(const ExposureStack& stack, const ResponseCurve& response, cv::Mat* valid,
                     MergeStats* stats) {
  stack.Validate();
  HDRIBR_CHECK_MSG(response.IsValid(), "invalid response curve");
  const int p = static_cast<int>(stack.images.size());
  const std::vector<int> order = stack.OrderByTime();
  const int w = stack.images[0].cols;
  const int h = stack.images[0].rows;
  const bool has_masks = !stack.masks.empty();

  // Look-up tables: weight(z) and w(z) (g_c(z) - ln t_j) per image and channel, in the order
  // of increasing exposure time.
  std::array<float, kLevels> weight{};
  for (int k = 0; k < kLevels; ++k) weight[k] = static_cast<float>(HatWeight(k));
  std::vector<float> term(static_cast<size_t>(p) * 3 * kLevels);   // [j][c][z]
  std::vector<float> plain(static_cast<size_t>(p) * 3 * kLevels);  // g_c(z) - ln t_j
  for (int jj = 0; jj < p; ++jj) {
    const double log_t = std::log(stack.times[order[jj]]);
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < kLevels; ++k) {
        const double value = response.log_inverse[c][k] - log_t;
        plain[(jj * 3 + c) * kLevels + k] = static_cast<float>(value);
        term[(jj * 3 + c) * kLevels + k] = static_cast<float>(HatWeight(k) * value);
      }
    }
  }

  cv::Mat radiance(h, w, CV_32FC3);
  cv::Mat validity(h, w, CV_8UC1);
  std::atomic<int> saturated{0}, dark{0}, invalid{0};
  // ln E is clamped to where exp() stays a finite float (and a normal one).
  constexpr float kMinLog = -87.0f;
  constexpr float kMaxLog = 88.0f;

  cv::parallel_for_(cv::Range(0, h), [&](const cv::Range& rows) {
    std::vector<float> num(3 * static_cast<size_t>(w));
    std::vector<float> den(3 * static_cast<size_t>(w));
    std::vector<int> first(w), last(w);  // shortest and longest valid exposure per pixel
    int local_saturated = 0, local_dark = 0, local_invalid = 0;
    for (int y = rows.start; y < rows.end; ++y) {
      std::fill(num.begin(), num.end(), 0.0f);
      std::fill(den.begin(), den.end(), 0.0f);
      std::fill(first.begin(), first.end(), -1);
      std::fill(last.begin(), last.end(), -1);
      for (int jj = 0; jj < p; ++jj) {
        const uint8_t* px = stack.images[order[jj]].ptr<uint8_t>(y);
        const float* t0 = &term[(jj * 3 + 0) * kLevels];
        const float* t1 = t0 + kLevels;
        const float* t2 = t1 + kLevels;
        // Equation 7's sums for pixel x (inlined into both loops below).
        const auto add = [&](int x) {
          const uint8_t b = px[3 * x], g = px[3 * x + 1], r = px[3 * x + 2];
          num[3 * x] += t0[b];
          num[3 * x + 1] += t1[g];
          num[3 * x + 2] += t2[r];
          den[3 * x] += weight[b];
          den[3 * x + 1] += weight[g];
          den[3 * x + 2] += weight[r];
        };
        if (!has_masks) {
          for (int x = 0; x < w; ++x) add(x);
        } else {
          const uint8_t* m = stack.masks[order[jj]].ptr<uint8_t>(y);
          for (int x = 0; x < w; ++x) {
            if (!m[x]) continue;
            if (first[x] < 0) first[x] = jj;
            last[x] = jj;
            add(x);
          }
        }
      }
      float* out = radiance.ptr<float>(y);
      uint8_t* out_valid = validity.ptr<uint8_t>(y);
      for (int x = 0; x < w; ++x) {
        const int shortest = has_masks ? first[x] : 0;
        const int longest = has_masks ? last[x] : p - 1;
        if (shortest < 0) {
          out[3 * x] = out[3 * x + 1] = out[3 * x + 2] = 0.0f;
          out_valid[x] = 0;
          ++local_invalid;
          continue;
        }
        out_valid[x] = 255;
        for (int c = 0; c < 3; ++c) {
          float log_e;
          if (den[3 * x + c] > 0) {
            log_e = num[3 * x + c] / den[3 * x + c];
          } else {
            // Every valid image is 0 or 255 here. Saturated in the shortest exposure: the
            // radiance is at least what that exposure's 255 means; else it is black in all,
            // and the longest exposure gives the tightest (smallest) estimate.
            const int zs = stack.images[order[shortest]].ptr<uint8_t>(y)[3 * x + c];
            if (zs > 127) {
              log_e = plain[(shortest * 3 + c) * kLevels + zs];
              ++local_saturated;
            } else {
              const int zl = stack.images[order[longest]].ptr<uint8_t>(y)[3 * x + c];
              log_e = plain[(longest * 3 + c) * kLevels + zl];
              ++local_dark;
            }
          }
          out[3 * x + c] = std::exp(std::clamp(log_e, kMinLog, kMaxLog));
        }
      }
    }
    saturated += local_saturated;
    dark += local_dark;
    invalid += local_invalid;
  });
  if (valid) *valid = validity;
  if (stats) *stats = MergeStats{saturated.load(), dark.load(), invalid.load()};
  return radiance;
}

}  // namespace hdribr
