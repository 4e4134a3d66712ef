#include "synth/camera_response.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "synth/ray_tracer.h"

namespace hdribr::synth {

std::uint64_t SplitMix64::Next() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double SplitMix64::Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

double SplitMix64::Gaussian() {
  const double u1 = 1.0 - Uniform();  // (0, 1]
  const double u2 = Uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

namespace {

// s(x) of one channel: its gamma, the toe's end, and the offset a and slope phi for which
// phi x and (1 + a) x^(1/gamma) - a meet with equal value and slope at x = end
// (a = c / (1 - c), c = end^(1/gamma) (1 - 1/gamma)).
struct Toe {
  double gamma = 1.0;
  double end = 0.0;
  double offset = 0.0;
  double slope = 0.0;
};

Toe ToeOf(double gamma, double end) {
  if (end <= 0.0) return {gamma, 0.0, 0.0, 0.0};
  const double root = std::pow(end, 1.0 / gamma);
  const double c = root * (1.0 - 1.0 / gamma);
  const double offset = c / (1.0 - c);
  return {gamma, end, offset, (1.0 + offset) * root / (end * gamma)};
}

// s_c(x) with the channel's toe constants computed once (Expose's per-pixel loop).
double EncodeWith(const Toe& t, double x) {
  if (x < t.end) return t.slope * x;
  return (1.0 + t.offset) * std::pow(x, 1.0 / t.gamma) - t.offset;
}

// 255 f_c(x) for x = X / x_sat >= 0 (ValueFromExposure).
double ValueWith(const SyntheticResponse& r, const Toe& t, int c, double x) {
  if (x >= 1.0) return 255.0;
  const double y = EncodeWith(t, x);
  return 255.0 * y * (1.0 + r.knee[c]) / (y + r.knee[c]);
}

}  // namespace

double SyntheticResponse::Encode(int c, double x) const {
  return EncodeWith(ToeOf(gamma[c], toe), x);
}

double SyntheticResponse::Decode(int c, double y) const {
  const Toe t = ToeOf(gamma[c], toe);
  if (y < t.slope * t.end) return y / t.slope;
  return std::pow((y + t.offset) / (1.0 + t.offset), t.gamma);
}

double SyntheticResponse::ValueFromExposure(int c, double exposure) const {
  return ValueWith(*this, ToeOf(gamma[c], toe), c, std::clamp(exposure / x_sat, 0.0, 1.0));
}

double SyntheticResponse::ExposureFromValue(int c, double z) const {
  const double f = std::clamp(z / 255.0, 0.0, 1.0);
  return x_sat * Decode(c, f * knee[c] / (1.0 + knee[c] - f));
}

ResponseCurve SyntheticResponse::Curve() const {
  ResponseCurve curve;
  curve.source = "synthetic-truth";
  for (int c = 0; c < 3; ++c) {
    curve.log_inverse[c].resize(256);
    for (int z = 0; z < 256; ++z) {
      curve.log_inverse[c][z] = std::log(ExposureFromValue(c, z == 0 ? 0.5 : z));
    }
  }
  return curve;
}

cv::Mat SyntheticResponse::Expose(const cv::Mat& radiance, double time_s, std::uint64_t noise_seed,
                                  int threads) const {
  CV_Assert(radiance.type() == CV_32FC3);
  cv::Mat out(radiance.size(), CV_8UC3);
  const std::array<Toe, 3> toes = {ToeOf(gamma[0], toe), ToeOf(gamma[1], toe),
                                   ToeOf(gamma[2], toe)};
  // One generator per row, seeded from (noise_seed, row): the same bytes for any thread count.
  ParallelRows(radiance.rows, threads, [&](int y) {
    SplitMix64 rng(noise_seed ^ (0xD1B54A32D192ED03ull * static_cast<std::uint64_t>(y + 1)));
    for (int x = 0; x < radiance.cols; ++x) {
      const cv::Vec3f l = radiance.at<cv::Vec3f>(y, x);
      cv::Vec3b& z = out.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) {
        const double xn = std::max(0.0, double(l[c]) * time_s / x_sat);
        const double sigma = std::sqrt(shot * xn + read * read);
        const double noisy = std::max(0.0, xn + sigma * rng.Gaussian());
        z[c] = static_cast<std::uint8_t>(
            std::lround(ValueWith(*this, toes[c], c, std::min(noisy, 1.0))));
      }
    }
  });
  return out;
}

}  // namespace hdribr::synth
