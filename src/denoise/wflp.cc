// WFLP: DWT, FLP on the approximation, thresholded details, reconstruction (paper Section 3.3).
#include "gyrocomp/denoise/wflp.h"

#include "normalising_scale.h"

#include <cmath>
#include <sstream>
#include <string>

namespace gyrocomp {

std::optional<DetailHandling> ParseDetailHandling(std::string_view name) {
  if (name == "threshold") return DetailHandling::kThreshold;
  if (name == "keep") return DetailHandling::kKeep;
  if (name == "zero") return DetailHandling::kZero;
  return std::nullopt;
}

const char* DetailHandlingName(DetailHandling handling) {
  switch (handling) {
    case DetailHandling::kThreshold: return "threshold";
    case DetailHandling::kKeep: return "keep";
    case DetailHandling::kZero: return "zero";
  }
  return "?";
}

bool WflpOptions::IsValid(std::string* error) const {
  WaveletDenoiseOptions w;
  w.wavelet = wavelet;
  w.level = level;
  w.noise_sigma = noise_sigma;
  std::string why;
  if (!w.IsValid(&why)) {
    if (error) *error = "WflpOptions::" + why.substr(why.find("::") + 2);
    return false;
  }
  if (!flp.IsValid(&why)) {
    if (error) *error = "WflpOptions::flp." + why.substr(why.find("::") + 2);
    return false;
  }
  return true;
}

std::string WflpSummary::BriefReport() const {
  std::ostringstream out;
  out << "WFLP " << wavelet << " level " << level << " (" << num_samples << " samples, approximation "
      << approximation_length << "), details " << DetailHandlingName(details) << "; " << flp.BriefReport();
  if (details == DetailHandling::kThreshold) out << "; " << thresholds.BriefReport();
  return out.str();
}

Result<WflpResult> RunWflp(std::span<const double> x, const WflpOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (std::optional<Error> bad = denoise_internal::SignalError(x, "WFLP")) return *bad;
  // Near the ends of the double range: a power-of-two scaled copy (normalising_scale.h).
  if (const double scale = denoise_internal::NormalisingScale(x); scale != 1.0) {
    WflpOptions o = options;
    if (o.noise_sigma) *o.noise_sigma *= scale;
    Result<WflpResult> r = RunWflp(denoise_internal::Scaled(x, scale), o);
    if (!r.ok()) return r.error();
    if (!denoise_internal::Unscale(&r->denoised, scale)) {
      return InvalidInput("WFLP: the denoised signal exceeds the range of a double (the signal is within a factor 2 "
                          "of the largest double)");
    }
    r->summary.flp.rms_error /= scale;
    r->summary.flp.rms_error_second_half /= scale;
    for (double& v : r->summary.thresholds.sigma) v /= scale;
    for (double& v : r->summary.thresholds.threshold) v /= scale;
    return r;
  }
  Result<Wavelet> wavelet = MakeWavelet(options.wavelet);
  if (!wavelet.ok()) return wavelet.error();
  // Step (1): wavelet decomposition of the (mixed) signal.
  Result<WaveletDecomposition> d = WaveDec(x, *wavelet, options.extension, options.level);
  if (!d.ok()) return d.error();
  WflpResult result;
  WflpSummary& s = result.summary;
  s.wavelet = options.wavelet;
  s.level = d->level();
  s.num_samples = x.size();
  s.approximation_length = d->approximation.size();
  s.details = options.details;
  // Step (2): the approximation coefficients are the FLP's input; its prediction (Eq. 14) replaces
  // them.
  Result<FlpResult> flp = RunFlp(d->approximation, options.flp);
  if (!flp.ok()) return flp.error();
  d->approximation = std::move(flp->filtered);
  s.flp = std::move(flp->summary);
  switch (options.details) {
    case DetailHandling::kThreshold: {
      s.thresholds.wavelet = options.wavelet;
      s.thresholds.extension = options.extension;
      s.thresholds.level = d->level();
      s.thresholds.num_samples = x.size();
      Status st = ThresholdDetails(&*d, options.threshold, options.threshold_mode, options.noise_sigma, &s.thresholds);
      if (!st.ok()) return st.error();
      break;
    }
    case DetailHandling::kKeep:
      break;
    case DetailHandling::kZero:
      for (auto& detail : d->details) std::fill(detail.begin(), detail.end(), 0.0);
      break;
  }
  // Step (3): reconstruction with the same wavelet.
  Result<std::vector<double>> rec = WaveRec(*d, *wavelet);
  if (!rec.ok()) return rec.error();
  result.denoised = std::move(*rec);
  return result;
}

Result<std::vector<double>> WflpDenoise(std::span<const double> x, const WflpOptions& options) {
  Result<WflpResult> r = RunWflp(x, options);
  if (!r.ok()) return r.error();
  return std::move(r->denoised);
}

}  // namespace gyrocomp
