// Wavelet-threshold denoising (VisuShrink by default, as ../golden/wavelet/wavedec.json).
#include "gyrocomp/denoise/wavelet_denoise.h"

#include "normalising_scale.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>

namespace gyrocomp {
namespace {

// numpy.median: the mean of the two middle values for an even count.
double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  const double upper = v[mid];
  if (v.size() % 2 == 1) return upper;
  const double lower = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid));
  return 0.5 * (lower + upper);
}

// SureShrink threshold (Donoho & Johnstone 1995) for coefficients already divided by their noise
// SD: minimises SURE(t) = n - 2 #{|x_i| <= t} + sum_i min(x_i^2, t^2) over t in {|x_i|}, capped at
// the universal sqrt(2 ln n); the hybrid rule falls back to the universal threshold when the
// level is sparse (sum(x^2 - 1)/n <= (log2 n)^1.5 / sqrt(n)).
double SureThreshold(const std::vector<double>& x) {
  const std::size_t n = x.size();
  if (n == 0) return 0.0;
  const double universal = std::sqrt(2.0 * std::log(static_cast<double>(n)));
  double energy = 0.0;
  for (double v : x) energy += v * v;
  const double sparsity = (energy - static_cast<double>(n)) / static_cast<double>(n);
  const double critical = std::pow(std::log2(static_cast<double>(n)), 1.5) / std::sqrt(static_cast<double>(n));
  if (sparsity <= critical) return universal;
  std::vector<double> sq(n);
  for (std::size_t i = 0; i < n; ++i) sq[i] = x[i] * x[i];
  std::sort(sq.begin(), sq.end());
  // With t^2 = sq[k]: #{x^2 <= t^2} = k + 1, sum min(x^2, t^2) = prefix(k) + (n - k - 1) sq[k].
  double best_risk = std::numeric_limits<double>::infinity();
  double best_t = universal;
  double prefix = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    prefix += sq[k];
    const double risk = static_cast<double>(n) - 2.0 * static_cast<double>(k + 1) + prefix +
                        static_cast<double>(n - k - 1) * sq[k];
    if (risk < best_risk) {
      best_risk = risk;
      best_t = std::sqrt(sq[k]);
    }
  }
  return std::min(best_t, universal);
}

}  // namespace

std::optional<ThresholdMode> ParseThresholdMode(std::string_view name) {
  if (name == "soft") return ThresholdMode::kSoft;
  if (name == "hard") return ThresholdMode::kHard;
  return std::nullopt;
}

const char* ThresholdModeName(ThresholdMode mode) {
  return mode == ThresholdMode::kSoft ? "soft" : "hard";
}

std::optional<ThresholdRule> ParseThresholdRule(std::string_view name) {
  if (name == "universal") return ThresholdRule::kUniversal;
  if (name == "universal-level") return ThresholdRule::kUniversalLevelDependent;
  if (name == "sure") return ThresholdRule::kSure;
  return std::nullopt;
}

const char* ThresholdRuleName(ThresholdRule rule) {
  switch (rule) {
    case ThresholdRule::kUniversal: return "universal";
    case ThresholdRule::kUniversalLevelDependent: return "universal-level";
    case ThresholdRule::kSure: return "sure";
  }
  return "?";
}

void ApplyThreshold(std::span<double> coefficients, double threshold, ThresholdMode mode) {
  for (double& c : coefficients) {
    const double magnitude = std::abs(c);
    if (mode == ThresholdMode::kHard) {
      if (magnitude < threshold) c = 0.0;
    } else if (magnitude == 0.0) {
      c = 0.0;
    } else {
      // pywt.threshold(mode='soft'): x * max(1 - thr/|x|, 0).
      c = c * std::max(1.0 - threshold / magnitude, 0.0);
    }
  }
}

double MadSigma(std::span<const double> detail) {
  std::vector<double> a(detail.size());
  for (std::size_t i = 0; i < detail.size(); ++i) a[i] = std::abs(detail[i]);
  return Median(std::move(a)) / 0.6745;
}

bool WaveletDenoiseOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = "WaveletDenoiseOptions::" + message;
    return false;
  };
  if (!MakeWavelet(wavelet).ok()) return fail("wavelet = '" + wavelet + "': unknown wavelet name");
  if (level && *level < 0) return fail("level = " + std::to_string(*level) + ": must be >= 0");
  if (noise_sigma && !(*noise_sigma >= 0.0 && std::isfinite(*noise_sigma))) {
    return fail("noise_sigma = " + std::to_string(*noise_sigma) + ": must be finite and >= 0");
  }
  return true;
}

std::string WaveletDenoiseSummary::BriefReport() const {
  std::ostringstream out;
  out << "wavelet " << wavelet << "/" << ExtensionModeName(extension) << " level " << level << ", "
      << ThresholdRuleName(rule) << " " << ThresholdModeName(mode) << " threshold, " << num_samples
      << " samples";
  for (std::size_t l = 0; l < threshold.size(); ++l) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "; D%zu sigma %.4g thr %.4g zeroed %.0f%%", l + 1, sigma[l], threshold[l],
                  100.0 * fraction_zeroed[l]);
    out << buf;
  }
  return out.str();
}

Status ThresholdDetails(WaveletDecomposition* d, ThresholdRule rule, ThresholdMode mode,
                        std::optional<double> noise_sigma, WaveletDenoiseSummary* summary) {
  const int levels = d->level();
  if (levels == 0) return Status::Ok();
  const double log_term = std::sqrt(2.0 * std::log(static_cast<double>(std::max<std::size_t>(d->signal_length, 1))));
  // sigma = median(|cD1|) / 0.6745, thr = sigma sqrt(2 ln N): the golden "denoise_rule".
  const double sigma_finest = noise_sigma.value_or(MadSigma(d->details[0]));
  std::vector<double> sigmas(levels), thresholds(levels), zeroed(levels);
  for (int l = 0; l < levels; ++l) {
    std::vector<double>& detail = d->details[static_cast<std::size_t>(l)];
    double sigma = sigma_finest;
    double thr = 0.0;
    switch (rule) {
      case ThresholdRule::kUniversal:
        thr = sigma * log_term;
        break;
      case ThresholdRule::kUniversalLevelDependent:
        sigma = noise_sigma.value_or(MadSigma(detail));
        thr = sigma * log_term;
        break;
      case ThresholdRule::kSure: {
        sigma = noise_sigma.value_or(MadSigma(detail));
        if (sigma > 0.0) {
          std::vector<double> scaled(detail.size());
          for (std::size_t i = 0; i < detail.size(); ++i) scaled[i] = detail[i] / sigma;
          thr = sigma * SureThreshold(scaled);
        }
        break;
      }
    }
    ApplyThreshold(detail, thr, mode);
    std::size_t zeros = 0;
    for (double c : detail) zeros += (c == 0.0);
    sigmas[l] = sigma;
    thresholds[l] = thr;
    zeroed[l] = detail.empty() ? 0.0 : static_cast<double>(zeros) / static_cast<double>(detail.size());
  }
  if (summary) {
    summary->rule = rule;
    summary->mode = mode;
    summary->sigma = std::move(sigmas);
    summary->threshold = std::move(thresholds);
    summary->fraction_zeroed = std::move(zeroed);
  }
  return Status::Ok();
}

Result<WaveletDenoiseResult> RunWaveletDenoise(std::span<const double> x, const WaveletDenoiseOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (std::optional<Error> bad = denoise_internal::SignalError(x, "wavelet denoising")) return *bad;
  if (const double scale = denoise_internal::NormalisingScale(x); scale != 1.0) {
    WaveletDenoiseOptions o = options;
    if (o.noise_sigma) *o.noise_sigma *= scale;
    Result<WaveletDenoiseResult> r = RunWaveletDenoise(denoise_internal::Scaled(x, scale), o);
    if (!r.ok()) return r.error();
    if (!denoise_internal::Unscale(&r->denoised, scale)) {
      return InvalidInput("wavelet denoising: the reconstruction exceeds the range of a double (the signal is "
                          "within a factor 2 of the largest double)");
    }
    for (double& v : r->summary.sigma) v /= scale;
    for (double& v : r->summary.threshold) v /= scale;
    return r;
  }
  Result<Wavelet> wavelet = MakeWavelet(options.wavelet);
  if (!wavelet.ok()) return wavelet.error();
  Result<WaveletDecomposition> d = WaveDec(x, *wavelet, options.extension, options.level);
  if (!d.ok()) return d.error();
  WaveletDenoiseResult result;
  result.summary.wavelet = options.wavelet;
  result.summary.extension = options.extension;
  result.summary.level = d->level();
  result.summary.num_samples = x.size();
  Status s = ThresholdDetails(&*d, options.threshold, options.threshold_mode, options.noise_sigma, &result.summary);
  if (!s.ok()) return s.error();
  Result<std::vector<double>> rec = WaveRec(*d, *wavelet);
  if (!rec.ok()) return rec.error();
  result.denoised = std::move(*rec);
  return result;
}

Result<std::vector<double>> WaveletDenoise(std::span<const double> x, const WaveletDenoiseOptions& options) {
  Result<WaveletDenoiseResult> r = RunWaveletDenoise(x, options);
  if (!r.ok()) return r.error();
  return std::move(r->denoised);
}

}  // namespace gyrocomp
