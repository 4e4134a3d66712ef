#include "hdr/multiview_calibration.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include "core/error.h"
#include "hdr/debevec.h"
#include "hdr/response_curve.h"
#include "synth/camera_response.h"

namespace hdribr {
namespace {

using synth::SplitMix64;
using synth::SyntheticResponse;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// 8-bit value of linear exposure x (in units of the saturation exposure) in channel c, with
// the synthetic camera's shot and read noise.
uint8_t Value(const SyntheticResponse& camera, int c, double x, SplitMix64& rng) {
  const double sigma = std::sqrt(camera.shot * std::max(0.0, x) + camera.read * camera.read);
  const double noisy = std::max(0.0, x + sigma * rng.Gaussian());
  const double z = camera.ValueFromExposure(c, noisy * camera.x_sat);
  return static_cast<uint8_t>(std::clamp(std::lround(z), 0L, 255L));
}

// Scene points with known radiance seen by random subsets of photos with known exposures.
struct SyntheticViews {
  std::vector<MultiViewSample> samples;
  std::vector<std::array<double, 3>> radiance;  // per sample, x units at ln t = 0
  std::vector<double> log_t;                    // true, mean 0
  std::vector<double> prior;                    // log_t perturbed (log-normal)
  // True ln t per photo and channel (BGR): log_t plus the photo's white-balance gains.
  std::vector<std::array<double, 3>> channel_log_t;
};

struct ViewsSpec {
  int photos = 48;
  int samples = 3000;
  double stops = 4.0;         // exposures spread evenly over this many stops
  double prior_sigma = 0.05;  // log-normal perturbation of the prior
  double outliers = 0.03;     // share of observations replaced (misregistered, highlight)
  int min_views = 4;          // views per sample, uniform in [min_views, max_views]
  int max_views = 12;
  // Standard deviation (natural log) of per-photo, per-channel gains (a white balance per
  // shot); 0 = one white balance for every photo.
  double channel_sigma = 0.0;
  // Standard deviation (natural log) of a per-observation factor on the radiance: a pixel or
  // two of misregistration on texture, JPEG; 0 = none.
  double value_sigma = 0.0;
  std::uint64_t seed = 7;
};

ViewsSpec Spec(int photos, int samples, double stops = 4.0) {
  ViewsSpec spec;
  spec.photos = photos;
  spec.samples = samples;
  spec.stops = stops;
  return spec;
}

SyntheticViews MakeViews(const ViewsSpec& spec, const SyntheticResponse& camera = {}) {
  SplitMix64 rng(spec.seed);
  SyntheticViews v;
  for (int i = 0; i < spec.photos; ++i) {
    v.log_t.push_back(std::log(2.0) * spec.stops * (i / (spec.photos - 1.0) - 0.5));
    v.prior.push_back(v.log_t.back() + spec.prior_sigma * rng.Gaussian());
  }
  for (int i = 0; i < spec.photos; ++i) {
    std::array<double, 3> t;
    for (int c = 0; c < 3; ++c) {
      t[c] = v.log_t[i] + (spec.channel_sigma > 0 ? spec.channel_sigma * rng.Gaussian() : 0.0);
    }
    v.channel_log_t.push_back(t);
  }
  std::vector<int> order(spec.photos);
  for (int j = 0; j < spec.samples; ++j) {
    // Radiance: mid-exposure x log-uniform over 1e-4 .. 2, tinted per channel.
    const double base = std::exp(rng.Uniform(std::log(1e-4), std::log(2.0)));
    std::array<double, 3> e;
    for (int c = 0; c < 3; ++c) e[c] = base * rng.Uniform(0.7, 1.3);
    v.radiance.push_back(e);
    std::iota(order.begin(), order.end(), 0);
    const int spread = spec.max_views - spec.min_views + 1;
    const int views = std::min(spec.photos, spec.min_views + static_cast<int>(rng.Next() % spread));
    MultiViewSample sample;
    for (int k = 0; k < views; ++k) {
      std::swap(order[k], order[k + rng.Next() % (spec.photos - k)]);
      const int i = order[k];
      MultiViewObservation o;
      o.photo = i;
      std::array<double, 3> t;
      const double jitter = spec.value_sigma > 0 ? spec.value_sigma * rng.Gaussian() : 0.0;
      for (int c = 0; c < 3; ++c) t[c] = std::exp(v.channel_log_t[i][c] + jitter);
      const double u = rng.Uniform();
      for (int c = 0; c < 3; ++c) o.bgr[c] = Value(camera, c, e[c] * t[c], rng);
      if (u < spec.outliers / 2) {  // misregistered: another surface's values
        for (int c = 0; c < 3; ++c) o.bgr[c] = static_cast<uint8_t>(rng.Next() % 256);
      } else if (u < spec.outliers) {  // view-dependent highlight: 2-4 x brighter
        const double gain = rng.Uniform(2.0, 4.0);
        for (int c = 0; c < 3; ++c) o.bgr[c] = Value(camera, c, gain * e[c] * t[c], rng);
      }
      sample.observations.push_back(o);
    }
    v.samples.push_back(std::move(sample));
  }
  return v;
}

// Largest relative exposure error |exp(d_i - mean d) - 1|, d = got - truth over `photos`.
double MaxExposureError(const std::vector<double>& got, const std::vector<double>& truth) {
  double mean = 0;
  for (size_t i = 0; i < got.size(); ++i) mean += (got[i] - truth[i]) / got.size();
  double worst = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    worst = std::max(worst, std::abs(std::exp(got[i] - truth[i] - mean) - 1.0));
  }
  return worst;
}

void ExpectFinite(const MultiViewCalibration& r) {
  for (int c = 0; c < 3; ++c) {
    for (double g : r.response.log_inverse[c]) EXPECT_TRUE(std::isfinite(g));
  }
  for (double t : r.log_exposure) EXPECT_TRUE(std::isfinite(t));
  for (double t : r.relative_exposure) EXPECT_TRUE(std::isfinite(t) && t > 0);
}

// Options for the generated observations: noise and 8-bit rounding only, without the JPEG and
// resampling errors of photos, so they want less smoothing than the default (which is set on
// rendered captures: docs/decisions/0018). The plain solve: no response prior.
MultiViewOptions CleanData() {
  MultiViewOptions o;
  o.lambda = 60.0;
  o.response_prior_candidates.clear();
  return o;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

TEST(CalibrateMultiView, RecoversResponseAndExposuresWithPerturbedPrior) {
  const SyntheticResponse camera;
  const SyntheticViews views = MakeViews({});
  const auto start = std::chrono::steady_clock::now();
  const MultiViewCalibration got = CalibrateMultiView(views.samples, views.prior, CleanData());
  const double seconds = Seconds(start);
  ASSERT_TRUE(got.response.IsValid());
  ExpectFinite(got);
  EXPECT_EQ(got.response.source, "multiview");
  EXPECT_TRUE(got.stats.exponent_from_prior);
  const ResponseCurve truth = camera.Curve();
  for (int c = 0; c < 3; ++c) {
    const double rms = RmsLinearError(got.response, truth, c);
    std::printf("channel %d: RMS linear error %.4f\n", c, rms);
    EXPECT_LE(rms, 0.03) << c;
    EXPECT_DOUBLE_EQ(got.response.log_inverse[c][128], 0.0);
  }
  const double exposure_error = MaxExposureError(got.log_exposure, views.log_t);
  const double prior_error = MaxExposureError(views.prior, views.log_t);
  std::printf(
      "48 photos, %d samples, %d observations (%d rejected): max exposure error %.4f (prior "
      "%.4f), residual RMS %.4f, %d solves, %.3f s\n",
      got.stats.samples_used, got.stats.observations_used, got.stats.observations_rejected,
      exposure_error, prior_error, got.stats.residual_rms, got.stats.iterations, seconds);
  EXPECT_LE(exposure_error, 0.02);
  EXPECT_GT(got.stats.samples_used, 2900);  // the rest are clipped in every view
  EXPECT_GT(got.stats.observations_rejected, 0);
  for (bool calibrated : got.calibrated) EXPECT_TRUE(calibrated);
  // The prior's scale: the mean log exposure matches the prior's.
  double mean_got = 0, mean_prior = 0;
  for (size_t i = 0; i < views.prior.size(); ++i) {
    mean_got += got.log_exposure[i];
    mean_prior += views.prior[i];
  }
  EXPECT_NEAR(mean_got, mean_prior, 1e-3 * views.prior.size());
  for (size_t i = 0; i < views.prior.size(); ++i) {
    EXPECT_NEAR(got.relative_exposure[i], std::exp(got.log_exposure[i]), 1e-12);
  }
}

TEST(CalibrateMultiView, WithinTheAlignedStackCalibrationsError) {
  // The same radiances as an aligned stack (each sample a flat 4x4 block) with 9 exposures over
  // the same 4 stops: CalibrateDebevec's error is the reference. Equivalent data: exact
  // exposures (a prior without error) and no outliers for the multi-view calibration too.
  const SyntheticResponse camera;
  ViewsSpec spec;
  spec.prior_sigma = 0.0;
  spec.outliers = 0.0;
  const SyntheticViews views = MakeViews(spec);
  const MultiViewCalibration got = CalibrateMultiView(views.samples, views.prior, CleanData());
  ExposureStack stack;
  constexpr int kBlocks = 60, kBlock = 4;
  SplitMix64 rng(11);
  for (int k = 0; k <= 8; ++k) {
    const double log_t = std::log(2.0) * (k / 2.0 - 2.0);
    stack.times.push_back(std::exp(log_t));
    cv::Mat image(kBlocks / 2 * kBlock, kBlocks * kBlock, CV_8UC3);
    for (int y = 0; y < image.rows; ++y) {
      for (int x = 0; x < image.cols; ++x) {
        const auto& e = views.radiance[(y / kBlock) * kBlocks + x / kBlock];
        for (int c = 0; c < 3; ++c) {
          image.at<cv::Vec3b>(y, x)[c] = Value(camera, c, e[c] * std::exp(log_t), rng);
        }
      }
    }
    stack.images.push_back(image);
  }
  const ResponseCurve aligned = CalibrateDebevec(stack);
  const ResponseCurve truth = camera.Curve();
  double multi_mean = 0, reference_mean = 0;
  for (int c = 0; c < 3; ++c) {
    const double multi = RmsLinearError(got.response, truth, c);
    const double reference = RmsLinearError(aligned, truth, c);
    std::printf("channel %d: multi-view %.4f, aligned stack (CalibrateDebevec) %.4f\n", c, multi,
                reference);
    EXPECT_LE(multi, 1.5 * reference) << c;
    multi_mean += multi / 3;
    reference_mean += reference / 3;
  }
  EXPECT_LE(multi_mean, 1.2 * reference_mean);
}

// Largest error of the photos' channel log exposures relative to their mean over the channels,
// each channel's mean over the photos removed (the data leave one factor per channel free).
double MaxChannelError(const MultiViewCalibration& got, const SyntheticViews& views) {
  const size_t n = views.log_t.size();
  std::array<double, 3> mean{};
  std::vector<std::array<double, 3>> d(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& t = views.channel_log_t[i];
    const double truth_mean = (t[0] + t[1] + t[2]) / 3;
    for (int c = 0; c < 3; ++c) {
      d[i][c] = (got.channel_log_exposure[i][c] - got.log_exposure[i]) - (t[c] - truth_mean);
      mean[c] += d[i][c] / n;
    }
  }
  double worst = 0;
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(d[i][c] - mean[c]));
  }
  return worst;
}

TEST(CalibrateMultiView, PerChannelExposureRecoversPerShotWhiteBalance) {
  // Each photo's channels get their own gain (5 % RMS): one exposure per photo cannot fit it,
  // one per photo and channel recovers the gains.
  const SyntheticResponse camera;
  ViewsSpec spec;
  spec.channel_sigma = 0.05;
  const SyntheticViews views = MakeViews(spec);
  const MultiViewCalibration scalar = CalibrateMultiView(views.samples, views.prior, CleanData());
  MultiViewOptions options = CleanData();
  options.per_channel_exposure = true;
  const MultiViewCalibration got = CalibrateMultiView(views.samples, views.prior, options);
  ExpectFinite(got);
  const double channel_error = MaxChannelError(got, views);
  std::vector<double> mean_log_t;  // the true exposure: the mean over the channels
  for (const auto& t : views.channel_log_t) mean_log_t.push_back((t[0] + t[1] + t[2]) / 3);
  const double exposure_error = MaxExposureError(got.log_exposure, mean_log_t);
  std::printf(
      "white balance per shot (5 %%): residual %.4f (one exposure per photo %.4f), max channel "
      "error %.4f, max exposure error %.4f\n",
      got.stats.residual_rms, scalar.stats.residual_rms, channel_error, exposure_error);
  EXPECT_LE(got.stats.residual_rms, 0.7 * scalar.stats.residual_rms);
  EXPECT_LE(channel_error, 0.01);
  EXPECT_LE(exposure_error, 0.02);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(RmsLinearError(got.response, camera.Curve(), c), 0.03) << c;
  }
  for (size_t i = 0; i < got.log_exposure.size(); ++i) {
    const auto& t = got.channel_log_exposure[i];
    EXPECT_NEAR((t[0] + t[1] + t[2]) / 3, got.log_exposure[i], 1e-9);
  }
}

TEST(CalibrateMultiView, PerChannelExposureKeepsOneWhiteBalance) {
  // One white balance for every photo: the per-channel exposures come out equal, and the
  // response as good as with one exposure per photo.
  const SyntheticResponse camera;
  const SyntheticViews views = MakeViews({});
  MultiViewOptions options = CleanData();
  options.per_channel_exposure = true;
  const MultiViewCalibration got = CalibrateMultiView(views.samples, views.prior, options);
  ExpectFinite(got);
  const double channel_error = MaxChannelError(got, views);
  std::printf("one white balance: max channel error %.4f, residual %.4f\n", channel_error,
              got.stats.residual_rms);
  EXPECT_LE(channel_error, 0.005);
  EXPECT_LE(MaxExposureError(got.log_exposure, views.log_t), 0.02);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(RmsLinearError(got.response, camera.Curve(), c), 0.03) << c;
  }
}

TEST(CalibrateMultiView, CrossValidationKeepsTheDataWhereTheyFixTheResponse) {
  // Exposures over 4 stops fix the response: the cross-validation picks no prior (or one too
  // weak to matter) and the response is as good as the plain solve's.
  const SyntheticResponse camera;
  const SyntheticViews views = MakeViews({});
  MultiViewOptions options = CleanData();
  options.response_prior_candidates = MultiViewOptions().response_prior_candidates;
  const MultiViewCalibration got = CalibrateMultiView(views.samples, views.prior, options);
  ExpectFinite(got);
  ASSERT_EQ(got.stats.prior_code_error.size(), options.response_prior_candidates.size());
  std::printf("4 stops: response prior %g; cross-validated error (DN):", got.stats.response_prior);
  for (double e : got.stats.prior_code_error) std::printf(" %.3f", e);
  std::printf("\n");
  EXPECT_LE(got.stats.response_prior, 100.0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(RmsLinearError(got.response, camera.Curve(), c), 0.03) << c;
  }
  EXPECT_LE(MaxExposureError(got.log_exposure, views.log_t), 0.02);
}

TEST(CalibrateMultiView, ResponsePriorWhereExposuresBarelyDiffer) {
  // Exposures over 0.4 stops and 5 % of misregistration noise per observation: without a
  // prior, g flattens where the noise is (a flat g explains values that differ at one
  // exposure), so re-exposing one photo's values from the others' errs; the cross-validation
  // picks a prior, which lowers that error and brings the response nearer the truth.
  const SyntheticResponse camera;
  ViewsSpec spec;
  spec.stops = 0.4;
  spec.prior_sigma = 0.02;
  spec.value_sigma = 0.2;
  const SyntheticViews views = MakeViews(spec);
  MultiViewOptions options;  // the defaults, as on photos
  const MultiViewCalibration got = CalibrateMultiView(views.samples, views.prior, options);
  options.response_prior_candidates.clear();
  const MultiViewCalibration plain = CalibrateMultiView(views.samples, views.prior, options);
  ExpectFinite(got);
  ASSERT_FALSE(got.stats.prior_code_error.empty());
  std::printf("0.4 stops: response prior %g; cross-validated error (DN):",
              got.stats.response_prior);
  for (double e : got.stats.prior_code_error) std::printf(" %.3f", e);
  std::printf("\n");
  EXPECT_GT(got.stats.response_prior, 0.0);
  size_t chosen = 0;
  while (MultiViewOptions().response_prior_candidates[chosen] != got.stats.response_prior) ++chosen;
  EXPECT_LT(got.stats.prior_code_error[chosen], 0.8 * got.stats.prior_code_error[0]);
  double got_mean = 0, plain_mean = 0;
  for (int c = 0; c < 3; ++c) {
    const double a = RmsLinearError(got.response, camera.Curve(), c);
    const double b = RmsLinearError(plain.response, camera.Curve(), c);
    std::printf("channel %d: RMS linear error %.4f with the prior, %.4f without\n", c, a, b);
    got_mean += a / 3;
    plain_mean += b / 3;
  }
  EXPECT_LT(got_mean, plain_mean);
}

TEST(CalibrateMultiView, PartialPriorFixesTheRest) {
  // EXIF for one photo in four (spread over the exposures); the data gives the others. The
  // exponent shared by g and ln t comes from the priors alone, so fewer priors must be better:
  // 1 % here (12 priors of 5 % leave it about 2 % off).
  const SyntheticResponse camera;
  ViewsSpec spec;
  spec.prior_sigma = 0.01;
  const SyntheticViews views = MakeViews(spec);
  std::vector<double> prior(views.prior.size(), kNaN);
  for (size_t i = 0; i < prior.size(); i += 4) prior[i] = views.prior[i];
  const MultiViewCalibration got = CalibrateMultiView(views.samples, prior, CleanData());
  ExpectFinite(got);
  EXPECT_TRUE(got.stats.exponent_from_prior);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(RmsLinearError(got.response, camera.Curve(), c), 0.03) << c;
  }
  const double error = MaxExposureError(got.log_exposure, views.log_t);
  std::printf("prior for 12 of 48 photos: max exposure error %.4f\n", error);
  EXPECT_LE(error, 0.02);
}

// Exponent k and offset m of the least-squares fit got ~ k truth + m.
std::pair<double, double> FitExponent(const std::vector<double>& got,
                                      const std::vector<double>& truth) {
  const double n = static_cast<double>(got.size());
  const double mg = std::accumulate(got.begin(), got.end(), 0.0) / n;
  const double mt = std::accumulate(truth.begin(), truth.end(), 0.0) / n;
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    sxy += (got[i] - mg) * (truth[i] - mt);
    sxx += (truth[i] - mt) * (truth[i] - mt);
  }
  const double k = sxy / sxx;
  return {k, mg - k * mt};
}

TEST(CalibrateMultiView, WithoutPriorRecoversExposuresUpToFactorAndExponent) {
  // Without any exposure ratio the data determine g and ln t only up to g -> k g, ln t -> k ln t
  // (and a common factor); the solve fixes k by sRGB's g(192) - g(64). Up to k, the curve and
  // the exposures are recovered.
  const SyntheticResponse camera;
  const SyntheticViews views = MakeViews({});
  const MultiViewCalibration got = CalibrateMultiView(views.samples, {}, CleanData());
  ExpectFinite(got);
  EXPECT_FALSE(got.stats.exponent_from_prior);
  EXPECT_NEAR(std::accumulate(got.log_exposure.begin(), got.log_exposure.end(), 0.0), 0.0, 1e-3);
  const auto [k, m] = FitExponent(got.log_exposure, views.log_t);
  std::vector<double> rescaled(got.log_exposure.size());
  for (size_t i = 0; i < rescaled.size(); ++i) rescaled[i] = got.log_exposure[i] / k;
  ResponseCurve curve = got.response;
  for (auto& g : curve.log_inverse) {
    for (double& v : g) v /= k;
  }
  std::printf("no prior: exponent %.4f, max exposure error %.4f (%.4f after the exponent)\n", k,
              MaxExposureError(got.log_exposure, views.log_t),
              MaxExposureError(rescaled, views.log_t));
  EXPECT_NEAR(k, 1.0, 0.3);  // sRGB's span against the synthetic camera's: measured 0.78
  EXPECT_LE(MaxExposureError(rescaled, views.log_t), 0.02);
  for (int c = 0; c < 3; ++c) {
    const double rms = RmsLinearError(curve, camera.Curve(), c);
    std::printf("channel %d: RMS linear error %.4f after the exponent\n", c, rms);
    EXPECT_LE(rms, 0.03) << c;
  }
}

TEST(CalibrateMultiView, PhotoWithoutObservationsKeepsItsPrior) {
  SyntheticViews views = MakeViews(Spec(16, 800));
  views.prior.push_back(0.3);   // photo 16: in the prior, in no sample
  views.prior.push_back(kNaN);  // photo 17: neither
  const MultiViewCalibration got = CalibrateMultiView(views.samples, views.prior, CleanData());
  ExpectFinite(got);
  ASSERT_EQ(got.log_exposure.size(), 18u);
  EXPECT_FALSE(got.calibrated[16]);
  EXPECT_FALSE(got.calibrated[17]);
  EXPECT_TRUE(got.calibrated[0]);
  EXPECT_EQ(got.photo_observations[16], 0);
  EXPECT_DOUBLE_EQ(got.log_exposure[16], 0.3);
}

MultiViewSample Sample(std::initializer_list<std::pair<int, int>> photo_value) {
  MultiViewSample s;
  for (const auto& [photo, z] : photo_value) {
    s.observations.push_back(
        {photo, {static_cast<uint8_t>(z), static_cast<uint8_t>(z), static_cast<uint8_t>(z)}});
  }
  return s;
}

TEST(CalibrateMultiView, RejectsObservationsThatCannotConstrainACurve) {
  // A single photo.
  EXPECT_THROW(CalibrateMultiView({Sample({{0, 100}}), Sample({{0, 50}})}, {0.0}), UsageError);
  // Each point seen by one photo only: no overlap.
  EXPECT_THROW(CalibrateMultiView({Sample({{0, 100}}), Sample({{1, 50}})}, {0.0, 1.0}), UsageError);
  // Everything clipped.
  EXPECT_THROW(
      CalibrateMultiView({Sample({{0, 255}, {1, 255}}), Sample({{0, 0}, {1, 255}})}, {0.0, 1.0}),
      UsageError);
  // No samples at all, and an index outside the prior.
  EXPECT_THROW(CalibrateMultiView({}, {0.0, 1.0}), UsageError);
  EXPECT_THROW(CalibrateMultiView({Sample({{0, 100}, {2, 120}})}, {0.0, 1.0}), UsageError);
  // Photos exposed alike and no prior to tell them apart.
  SyntheticViews same = MakeViews(Spec(8, 500, 0.0));
  EXPECT_THROW(CalibrateMultiView(same.samples, {}), UsageError);
  // Bad options.
  MultiViewOptions bad;
  bad.prior_sigma = 0;
  EXPECT_THROW(CalibrateMultiView(MakeViews(Spec(8, 100)).samples, {}, bad), OptionError);
}

TEST(CalibrateMultiView, DisconnectedPhotosWithoutPriorAreNotCalibrated) {
  // Photos 0-7 share samples; photos 8 and 9 see only each other's points, with no prior:
  // their exposure relative to the rest is unknown, so they keep the others' mean.
  SyntheticViews views = MakeViews(Spec(8, 600));
  for (int j = 0; j < 20; ++j) views.samples.push_back(Sample({{8, 60 + j}, {9, 120 + j}}));
  std::vector<double> prior = views.prior;
  prior.push_back(kNaN);
  prior.push_back(kNaN);
  const MultiViewCalibration got = CalibrateMultiView(views.samples, prior, CleanData());
  ExpectFinite(got);
  EXPECT_FALSE(got.calibrated[8]);
  EXPECT_FALSE(got.calibrated[9]);
  for (int i = 0; i < 8; ++i) EXPECT_TRUE(got.calibrated[i]);
}

// --- Sample gathering -------------------------------------------------------------------

// A scene of a textured plane z = 0 (world) and, optionally, a small square occluder at
// z = -occluder_depth, cast by rays from each camera.
struct PlaneScene {
  double cell = 0.25;          // texture cell size (world units), flat inside
  double occluder_half = 0.0;  // half size of the occluder square (0 = none)
  Eigen::Vector2d occluder_xy{0.0, 0.0};
  double occluder_z = -1.0;

  // Radiance (x units at ln t = 0) of a plane point: one log-uniform value per cell.
  std::array<double, 3> Radiance(double x, double y) const {
    const auto ix = static_cast<long>(std::floor(x / cell));
    const auto iy = static_cast<long>(std::floor(y / cell));
    SplitMix64 rng(static_cast<std::uint64_t>((ix + 1000) * 7919 + (iy + 1000)));
    const double base = std::exp(rng.Uniform(std::log(2e-3), std::log(2.0)));
    return {base * rng.Uniform(0.7, 1.3), base * rng.Uniform(0.7, 1.3),
            base * rng.Uniform(0.7, 1.3)};
  }

  // Depth (camera z) and radiance along the ray through pixel (u, v) of `camera`.
  std::pair<double, std::array<double, 3>> Cast(const Camera& camera, const Rigid3d& cam_from_world,
                                                double u, double v) const {
    const Rigid3d world_from_cam = cam_from_world.Inverse();
    const Eigen::Vector3d origin = world_from_cam.translation;
    const Eigen::Vector3d dir = world_from_cam.rotation * camera.CamFromPixel({u, v});  // z = 1
    if (occluder_half > 0 && std::abs(dir.z()) > 1e-12) {
      const double s = (occluder_z - origin.z()) / dir.z();
      const Eigen::Vector3d hit = origin + s * dir;
      if (s > 0 && std::abs(hit.x() - occluder_xy.x()) < occluder_half &&
          std::abs(hit.y() - occluder_xy.y()) < occluder_half) {
        return {s, {0.02, 0.5, 0.02}};  // a green occluder
      }
    }
    const double s = -origin.z() / dir.z();
    if (!(s > 0)) return {0.0, {0.0, 0.0, 0.0}};
    const Eigen::Vector3d hit = origin + s * dir;
    return {s, Radiance(hit.x(), hit.y())};
  }
};

// Image (exposure log_t, noisy) and depth map (at depth_scale of the image's size) of a view.
MultiViewPhoto Render(const PlaneScene& scene, const Camera& camera, const Rigid3d& pose,
                      double log_t, double depth_scale, std::uint64_t seed) {
  const SyntheticResponse response;
  SplitMix64 rng(seed);
  MultiViewPhoto photo;
  photo.camera = camera;
  photo.cam_from_world = pose;
  photo.image.create(camera.height, camera.width, CV_8UC3);
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const auto [depth, e] = scene.Cast(camera, pose, x + 0.5, y + 0.5);
      for (int c = 0; c < 3; ++c) {
        photo.image.at<cv::Vec3b>(y, x)[c] = Value(response, c, e[c] * std::exp(log_t), rng);
      }
    }
  }
  const Camera small = camera.Scaled(static_cast<int>(camera.width * depth_scale),
                                     static_cast<int>(camera.height * depth_scale));
  photo.depth.create(small.height, small.width, CV_32FC1);
  for (int y = 0; y < small.height; ++y) {
    for (int x = 0; x < small.width; ++x) {
      photo.depth.at<float>(y, x) =
          static_cast<float>(scene.Cast(small, pose, x + 0.5, y + 0.5).first);
    }
  }
  return photo;
}

// Points on the plane z = 0 over [-extent, extent]^2, `n` per side.
std::vector<Eigen::Vector3f> PlanePoints(double extent, int n) {
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      points.emplace_back(static_cast<float>(-extent + 2 * extent * (i + 0.5) / n),
                          static_cast<float>(-extent + 2 * extent * (j + 0.5) / n), 0.0f);
    }
  }
  return points;
}

TEST(GatherMultiViewSamples, RejectsPointsOccludedInOnePhoto) {
  PlaneScene scene;
  // An occluder 1 unit in front of camera 2 only (the others look from the sides).
  const Eigen::Vector3d eyes[3] = {{-1.2, 0.0, -3.0}, {1.2, 0.0, -3.0}, {0.0, 0.3, -3.0}};
  scene.occluder_half = 0.15;
  scene.occluder_xy = {0.0, 0.2};
  scene.occluder_z = -2.0;
  const Camera camera = Camera::Pinhole(1, 160, 120, 140, 140, 80, 60);
  std::vector<MultiViewPhoto> photos;
  for (int i = 0; i < 3; ++i) {
    const Rigid3d pose = LookAt(eyes[i], Eigen::Vector3d::Zero(), Eigen::Vector3d(0, -1, 0));
    photos.push_back(Render(scene, camera, pose, 0.5 * i - 0.5, i == 1 ? 0.5 : 1.0, 100 + i));
  }
  const std::vector<Eigen::Vector3f> points = PlanePoints(1.0, 60);
  GatherOptions options;
  options.samples = 100000;  // every candidate
  const std::vector<MultiViewSample> samples = GatherMultiViewSamples(photos, points, options);
  ASSERT_GT(samples.size(), 500u);
  int occluded = 0, seen_by_2 = 0;
  for (const MultiViewSample& s : samples) {
    ASSERT_GE(s.observations.size(), 2u);
    ASSERT_GE(s.point, 0);
    const Eigen::Vector3d p = points[s.point].cast<double>();
    // Is p behind the occluder from camera 2 (the segment eye -> p crosses the square)?
    const double f = (scene.occluder_z - eyes[2].z()) / (p.z() - eyes[2].z());
    const Eigen::Vector3d cross = eyes[2] + f * (p - eyes[2]);
    const bool hidden = std::abs(cross.x() - scene.occluder_xy.x()) < scene.occluder_half &&
                        std::abs(cross.y() - scene.occluder_xy.y()) < scene.occluder_half;
    bool in_2 = false;
    for (const MultiViewObservation& o : s.observations) {
      in_2 = in_2 || o.photo == 2;
      // Every observation is the plane's (never the green occluder).
      EXPECT_FALSE(o.bgr[1] > 3 * std::max(o.bgr[0], o.bgr[2]) + 20) << s.point;
    }
    if (hidden) {
      ++occluded;
      EXPECT_FALSE(in_2) << "point " << s.point << " is occluded in photo 2";
    }
    seen_by_2 += in_2;
  }
  std::printf("%zu samples, %d occluded in photo 2, %d seen by photo 2\n", samples.size(), occluded,
              seen_by_2);
  EXPECT_GT(occluded, 20);
  EXPECT_GT(seen_by_2, 300);
  // The cap and its spread over intensity.
  options.samples = 200;
  const std::vector<MultiViewSample> capped = GatherMultiViewSamples(photos, points, options);
  EXPECT_EQ(capped.size(), 200u);
  EXPECT_EQ(GatherMultiViewSamples(photos, points, options).front().point, capped.front().point);
}

TEST(GatherMultiViewSamples, RejectsInconsistentPhotos) {
  const Camera camera = Camera::Pinhole(1, 160, 120, 140, 140, 80, 60);
  MultiViewPhoto photo;
  photo.camera = camera;
  photo.image = cv::Mat(120, 160, CV_8UC3, cv::Scalar::all(100));
  photo.depth = cv::Mat(120, 160, CV_32FC1, cv::Scalar(1.0f));
  const std::vector<Eigen::Vector3f> points = {{0, 0, 1}};
  EXPECT_NO_THROW(GatherMultiViewSamples({photo, photo}, points));
  MultiViewPhoto gray = photo;
  gray.image = cv::Mat(120, 160, CV_8UC1);
  EXPECT_THROW(GatherMultiViewSamples({photo, gray}, points), UsageError);
  MultiViewPhoto squashed = photo;
  squashed.depth = cv::Mat(120, 120, CV_32FC1);
  EXPECT_THROW(GatherMultiViewSamples({photo, squashed}, points), UsageError);
}

// The whole pipeline on 48 views of a textured plane over 4 stops, 5 % prior: accuracy and
// timing. The exponent shared by g and ln t comes from the 48 priors: its error, about
// 0.05 sqrt(3 / 48) = 1.25 % in ln t at the ends of the series (one sigma), dominates here.
void GatherAndCalibrate48Photos(int width, int height) {
  const SyntheticResponse response;
  PlaneScene scene;
  scene.cell = 0.1;
  const double f = 0.875 * width;
  const Camera camera = Camera::Pinhole(1, width, height, f, f, width / 2.0, height / 2.0);
  std::vector<MultiViewPhoto> photos;
  std::vector<double> log_t, prior;
  SplitMix64 rng(5);
  for (int i = 0; i < 48; ++i) {
    const double angle = 2 * M_PI * i / 48;
    const Eigen::Vector3d eye(0.8 * std::cos(angle), 0.8 * std::sin(angle), -3.0);
    const Rigid3d pose = LookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, -1, 0));
    log_t.push_back(std::log(2.0) * 4.0 * (((i * 7) % 48) / 47.0 - 0.5));
    prior.push_back(log_t.back() + 0.05 * rng.Gaussian());
    photos.push_back(Render(scene, camera, pose, log_t.back(), 0.5, 200 + i));
  }
  const std::vector<Eigen::Vector3f> points = PlanePoints(1.5, 300);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<MultiViewSample> samples = GatherMultiViewSamples(photos, points);
  const double gather_s = Seconds(start);
  const auto solve_start = std::chrono::steady_clock::now();
  const MultiViewCalibration got = CalibrateMultiView(samples, prior);
  const double solve_s = Seconds(solve_start);
  std::printf("48 photos %dx%d: %zu samples, %d observations; gather %.3f s, solve %.3f s\n", width,
              height, samples.size(), got.stats.observations_used, gather_s, solve_s);
  ExpectFinite(got);
  for (int c = 0; c < 3; ++c) {
    const double rms = RmsLinearError(got.response, response.Curve(), c);
    std::printf("channel %d: RMS linear error %.4f\n", c, rms);
    EXPECT_LE(rms, 0.03) << c;
  }
  const double error = MaxExposureError(got.log_exposure, log_t);
  std::printf("max exposure error %.4f\n", error);
  EXPECT_LE(error, 0.02);
}

TEST(MultiView, GathersAndCalibrates48PhotosOf320x240) { GatherAndCalibrate48Photos(320, 240); }

// The timing at full size (about 8 s, mostly rendering the photos); run with
// --gtest_also_run_disabled_tests.
TEST(MultiView, DISABLED_GathersAndCalibrates48PhotosOf640x480) {
  GatherAndCalibrate48Photos(640, 480);
}

}  // namespace
}  // namespace hdribr
