// Bandwidth and delay of a processing, measured with test tones on a background record.
#include "gyrocomp/denoise/bandwidth.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>

namespace gyrocomp {
namespace {

std::string Str(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// The background record b: the one given, else num_samples of zeros or of white noise.
std::vector<double> MakeBackground(std::span<const double> background, const BandwidthOptions& options) {
  std::vector<double> base;
  if (background.empty()) {
    base.assign(options.num_samples, 0.0);
    if (options.white_noise_sd > 0.0) {
      std::mt19937_64 rng(options.seed);
      std::normal_distribution<double> gauss(0.0, options.white_noise_sd);
      for (double& v : base) v = gauss(rng);
    }
  } else {
    base.assign(background.begin(), background.end());
  }
  return base;
}

// Test amplitude A: as given, else the background's population SD (1 for a zero background).
double TestAmplitude(const BandwidthOptions& options, const std::vector<double>& base) {
  double amplitude = 1.0;
  if (options.amplitude) {
    amplitude = *options.amplitude;
  } else {
    const std::size_t n = base.size();
    double mean = 0.0, var = 0.0;
    for (double v : base) mean += v;
    mean /= static_cast<double>(n);
    for (double v : base) var += (v - mean) * (v - mean);
    const double sd = std::sqrt(var / static_cast<double>(n));
    if (sd > 0.0) amplitude = sd;
  }
  return amplitude;
}

// Test frequencies: whole numbers of cycles m in the window, log-spaced, strictly increasing.
std::vector<long> TestCycles(const BandwidthOptions& options, std::size_t window) {
  const double fs = options.fs_hz;
  const double wl = static_cast<double>(window);
  const double f_min = options.min_frequency_hz.value_or(20.0 * fs / wl);
  const double f_max = options.max_frequency_hz.value_or(0.45 * fs);
  std::vector<long> cycles;
  for (int k = 0; k < options.num_frequencies; ++k) {
    const double t = static_cast<double>(k) / static_cast<double>(options.num_frequencies - 1);
    const double f = f_min * std::pow(f_max / f_min, t);
    const long m = std::clamp(std::lround(f * wl / fs), 1L, static_cast<long>(window / 2) - 1);
    if (cycles.empty() || m > cycles.back()) cycles.push_back(m);
  }
  return cycles;
}

// One call of the processing, counted in result.num_runs; the output must keep the length.
Result<std::vector<double>> RunProcessing(const SignalProcessing& processing, const std::vector<double>& in,
                                          BandwidthResult& result) {
  ++result.num_runs;
  Result<std::vector<double>> out = processing(in);
  if (!out.ok()) return out.error();
  if (out->size() != in.size()) {
    return InternalError("bandwidth measurement: the processing returned " + std::to_string(out->size()) +
                         " samples for " + std::to_string(in.size()));
  }
  return out;
}

// Gain and phase of the response to each test tone b + A sin(omega i), m cycles in the window
// [margin, margin + window), appended to result.frequency_hz / gain / phase_rad (wrapped).
Status MeasureTones(const SignalProcessing& processing, const std::vector<double>& base,
                    const std::vector<double>& base_out, const std::vector<long>& cycles, double amplitude,
                    double fs, std::size_t margin, std::size_t window, BandwidthResult& result) {
  const std::size_t n = base.size();
  const double wl = static_cast<double>(window);
  std::vector<double> in(n);
  for (long m : cycles) {
    const double omega = 2.0 * std::numbers::pi * static_cast<double>(m) / wl;  // rad/sample
    for (std::size_t i = 0; i < n; ++i) in[i] = base[i] + amplitude * std::sin(omega * static_cast<double>(i));
    Result<std::vector<double>> out = RunProcessing(processing, in, result);
    if (!out.ok()) return out.error();
    // Least-squares amplitude of sin / cos over a whole number of cycles (they are orthogonal
    // there): response = a sin(omega i) + b cos(omega i) = R sin(omega i + phi).
    double a = 0.0, b = 0.0;
    for (std::size_t i = margin; i < margin + window; ++i) {
      const double diff = (*out)[i] - base_out[i];
      a += diff * std::sin(omega * static_cast<double>(i));
      b += diff * std::cos(omega * static_cast<double>(i));
    }
    a *= 2.0 / wl;
    b *= 2.0 / wl;
    result.frequency_hz.push_back(static_cast<double>(m) * fs / wl);
    result.gain.push_back(std::hypot(a, b) / amplitude);
    result.phase_rad.push_back(std::atan2(b, a));
  }
  return Status::Ok();
}

// Unwraps the phase over increasing frequency, predictively: each phase is moved by whole turns
// to the branch closest to -2 pi f tau, tau fitted (least squares through the origin) to the
// phases already unwrapped. Plain neighbour unwrapping fails as soon as a delay turns the phase
// by more than pi between two log-spaced tones; this does not, as long as the delay is smooth.
void UnwrapPhase(BandwidthResult& result) {
  double num = 0.0, den = 0.0;
  for (std::size_t k = 0; k < result.phase_rad.size(); ++k) {
    const double w = 2.0 * std::numbers::pi * result.frequency_hz[k];
    if (k > 0) {
      const double predicted = den > 0.0 ? (num / den) * w : 0.0;  // num/den = -tau
      result.phase_rad[k] += 2.0 * std::numbers::pi *
                             std::round((predicted - result.phase_rad[k]) / (2.0 * std::numbers::pi));
    }
    num += result.phase_rad[k] * w;
    den += w * w;
  }
}

// -3 dB crossing, interpolated in (log f, dB), into result.bandwidth_hz. Returns the end of the
// passband: the first test frequency whose gain is below 1/sqrt(2) (the size when none is).
std::size_t FindMinus3dB(BandwidthResult& result) {
  const double target_db = 20.0 * std::log10(1.0 / std::sqrt(2.0));
  std::size_t passband_end = result.gain.size();
  for (std::size_t k = 0; k < result.gain.size(); ++k) {
    if (result.gain[k] < 1.0 / std::sqrt(2.0)) {
      passband_end = k;
      break;
    }
  }
  if (passband_end == 0) {
    result.bandwidth_hz = result.frequency_hz.front();
    result.bandwidth_below_range = true;
  } else if (passband_end < result.gain.size()) {
    const std::size_t k = passband_end;
    const double g1 = 20.0 * std::log10(result.gain[k - 1]);
    const double g2 = 20.0 * std::log10(std::max(result.gain[k], 1e-300));
    const double t = (g1 - target_db) / (g1 - g2);
    const double l1 = std::log(result.frequency_hz[k - 1]), l2 = std::log(result.frequency_hz[k]);
    result.bandwidth_hz = std::exp(l1 + t * (l2 - l1));
  }
  return passband_end;
}

// Group delay: phase = -2 pi f tau over the passband (at least the first tone), least squares
// through the origin.
double FitGroupDelay(const BandwidthResult& result, std::size_t passband_end) {
  const std::size_t use = std::max<std::size_t>(passband_end, 1);
  double num = 0.0, den = 0.0;
  for (std::size_t k = 0; k < use; ++k) {
    const double w = 2.0 * std::numbers::pi * result.frequency_hz[k];
    num += result.phase_rad[k] * w;
    den += w * w;
  }
  return den > 0.0 ? -num / den : 0.0;
}

}  // namespace

bool BandwidthOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = "BandwidthOptions::" + message;
    return false;
  };
  if (!(fs_hz > 0.0 && std::isfinite(fs_hz))) return fail("fs_hz = " + Str(fs_hz) + ": must be > 0");
  if (num_samples < 256) return fail("num_samples = " + std::to_string(num_samples) + ": must be >= 256");
  if (num_frequencies < 2) return fail("num_frequencies = " + std::to_string(num_frequencies) + ": must be >= 2");
  if (min_frequency_hz && !(*min_frequency_hz > 0.0)) {
    return fail("min_frequency_hz = " + Str(*min_frequency_hz) + ": must be > 0");
  }
  if (max_frequency_hz && !(*max_frequency_hz > 0.0 && *max_frequency_hz < 0.5 * fs_hz)) {
    return fail("max_frequency_hz = " + Str(*max_frequency_hz) + ": must be in (0, fs/2)");
  }
  if (min_frequency_hz && max_frequency_hz && !(*min_frequency_hz < *max_frequency_hz)) {
    return fail("min_frequency_hz = " + Str(*min_frequency_hz) + ": must be below max_frequency_hz");
  }
  if (amplitude && !(*amplitude > 0.0 && std::isfinite(*amplitude))) {
    return fail("amplitude = " + Str(*amplitude) + ": must be > 0");
  }
  if (!(edge_fraction >= 0.0 && edge_fraction < 0.45)) {
    return fail("edge_fraction = " + Str(edge_fraction) + ": must be in [0, 0.45)");
  }
  if (!(white_noise_sd >= 0.0 && std::isfinite(white_noise_sd))) {
    return fail("white_noise_sd = " + Str(white_noise_sd) + ": must be >= 0");
  }
  return true;
}

std::string BandwidthResult::BriefReport() const {
  char buf[256];
  if (bandwidth_hz) {
    std::snprintf(buf, sizeof buf, "-3 dB bandwidth %.4g Hz%s, delay %.4g s, gain %.3f at %.3g Hz (%zu runs)",
                  *bandwidth_hz, bandwidth_below_range ? " (below the lowest test frequency)" : "", delay_s,
                  dc_gain, frequency_hz.empty() ? 0.0 : frequency_hz.front(), num_runs);
  } else {
    std::snprintf(buf, sizeof buf,
                  "-3 dB bandwidth above %.4g Hz (gain never fell below -3 dB), delay %.4g s, gain %.3f at %.3g Hz "
                  "(%zu runs)",
                  max_frequency_hz, delay_s, dc_gain, frequency_hz.empty() ? 0.0 : frequency_hz.front(), num_runs);
  }
  return buf;
}

Result<BandwidthResult> MeasureBandwidth(const SignalProcessing& processing, std::span<const double> background,
                                         const BandwidthOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  const std::vector<double> base = MakeBackground(background, options);
  const std::size_t n = base.size();
  const std::size_t margin = static_cast<std::size_t>(options.edge_fraction * static_cast<double>(n));
  const std::size_t window = n - 2 * margin;
  if (window < 128) {
    return InvalidArgument("bandwidth measurement: the analysis window has " + std::to_string(window) +
                           " samples (record " + std::to_string(n) + ", edge_fraction " + Str(options.edge_fraction) +
                           "); at least 128 are needed");
  }
  for (double v : base) {
    if (!std::isfinite(v)) return InvalidInput("bandwidth measurement: the background has a non-finite sample");
  }

  BandwidthResult result;
  result.amplitude = TestAmplitude(options, base);
  Result<std::vector<double>> base_out = RunProcessing(processing, base, result);
  if (!base_out.ok()) return base_out.error();
  const Status tones = MeasureTones(processing, base, *base_out, TestCycles(options, window), result.amplitude,
                                    options.fs_hz, margin, window, result);
  if (!tones.ok()) return tones.error();
  UnwrapPhase(result);
  result.max_frequency_hz = result.frequency_hz.back();
  result.dc_gain = result.gain.front();
  const std::size_t passband_end = FindMinus3dB(result);
  result.delay_s = FitGroupDelay(result, passband_end);
  return result;
}

}  // namespace gyrocomp
