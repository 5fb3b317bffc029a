// MDEV, HDEV, OHDEV and TOTDEV as allantools computes them (include/gyrocomp/allan/deviations.h).
// Every tau costs O(N): running sums for MDEV, one pass of differences for the others.
#include "gyrocomp/allan/deviations.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "blocked_sum.h"

namespace gyrocomp {
namespace {

using allan_internal::BlockedSum;

constexpr const char* kMdevMethod =
    "modified Allan deviation (NIST SP 1065 Eq. 14), as allantools mdev";
constexpr const char* kHdevMethod =
    "Hadamard deviation, non-overlapping (NIST SP 1065 Eq. 17), as allantools hdev";
constexpr const char* kOhdevMethod =
    "overlapping Hadamard deviation (NIST SP 1065 Eq. 18), as allantools ohdev";
constexpr const char* kTotdevMethod =
    "total deviation, phase reflected at both ends (NIST SP 1065 Eq. 25), as allantools totdev";
constexpr const char* kCountEdfMethod =
    "approximate: EDF = number of non-overlapping m-averages minus 2 (floor(N/m) - 2, at least 1); "
    "Greenhall & Riley's exact EDF is not implemented; chi-square interval";
constexpr const char* kTotdevEdfMethod =
    "EDF = b (T / tau) - c of NIST SP 1065 Table 11 (white rate b = 1.50, c = 0; flicker rate "
    "1.17, 0.22; random-walk rate 0.93, 0.36; phase noises use white rate), noise type per tau by "
    "lag-1 autocorrelation (carried over when fewer than 32 averages remain); chi-square interval";

// One tau's value: the deviation and the number of terms n (0 when the tau is dropped).
struct TauValue {
  double dev_dps = 0.0;
  std::int64_t n = 0;
};

// MDEV, allantools' loop: v_0 = sum_{j<m} (x_{j+2m} - 2x_{j+m} + x_j), then
// v_{i+1} = v_i + (x_{i+3m} - 3x_{i+2m} + 3x_{i+m} - x_i); mvar = sum v_i^2 / (2 m^2 tau^2 n).
TauValue Mdev(const std::vector<double>& x, std::int64_t m, double tau_s) {
  const auto np = static_cast<std::int64_t>(x.size());
  const std::int64_t e = np - 3 * m;  // increments; n = e + 1 terms
  if (e < 1) return {};
  double v = 0.0;
  for (std::int64_t j = 0; j < m; ++j) v += (x[j + 2 * m] - 2.0 * x[j + m]) + x[j];
  BlockedSum s;
  s.Add(v * v);
  for (std::int64_t i = 0; i < e; ++i) {
    v += ((x[i + 3 * m] - 3.0 * x[i + 2 * m]) + 3.0 * x[i + m]) - x[i];
    s.Add(v * v);
  }
  const std::int64_t n = e + 1;
  const double md = static_cast<double>(m);
  return {std::sqrt(s.Total() / (2.0 * md * md * tau_s * tau_s * static_cast<double>(n))), n};
}

// HDEV (stride m) and OHDEV (stride 1): hvar = sum (x_{i+3m} - 3x_{i+2m} + 3x_{i+m} - x_i)^2 / (6 tau^2 n).
TauValue Hadamard(const std::vector<double>& x, std::int64_t m, std::int64_t stride, double tau_s) {
  const auto np = static_cast<std::int64_t>(x.size());
  if (np <= 3 * m) return {};
  const std::int64_t n = (np - 3 * m + stride - 1) / stride;  // len(x[3m::stride])
  BlockedSum s;
  for (std::int64_t k = 0; k < n; ++k) {
    const std::int64_t i = k * stride;
    const double d = ((x[i + 3 * m] - 3.0 * x[i + 2 * m]) + 3.0 * x[i + m]) - x[i];
    s.Add(d * d);
  }
  return {std::sqrt(s.Total() / 6.0 / static_cast<double>(n)) / tau_s, n};
}

// TOTDEV on the record reflected at both ends (ext holds x_{-(N_p-2)} .. x_{2N_p-3}, offset mid).
TauValue Totdev(const std::vector<double>& ext, std::int64_t num_phase, std::int64_t m, double tau_s) {
  const std::int64_t mid = num_phase - 2;
  if (mid <= 1 || m > num_phase - 1) return {};
  BlockedSum s;
  for (std::int64_t i = 1; i <= mid; ++i) {
    const std::int64_t c = mid + i;
    const double d = (ext[c - m] - 2.0 * ext[c]) + ext[c + m];
    s.Add(d * d);
  }
  return {std::sqrt(s.Total() / (2.0 * tau_s * tau_s * static_cast<double>(mid))), mid};
}

// x extended by reflection: ext[mid + j] = x_j for j in [-(N_p - 2), 2N_p - 3].
std::vector<double> ReflectPhase(const std::vector<double>& x) {
  const auto np = static_cast<std::int64_t>(x.size());
  const std::int64_t mid = np - 2;
  std::vector<double> ext(static_cast<std::size_t>(3 * np - 4));
  for (std::int64_t j = -mid; j < 0; ++j) ext[mid + j] = 2.0 * x[0] - x[-j];
  for (std::int64_t j = 0; j < np; ++j) ext[mid + j] = x[j];
  for (std::int64_t j = np; j <= 2 * np - 3; ++j) ext[mid + j] = 2.0 * x[np - 1] - x[2 * np - 2 - j];
  return ext;
}

// SP 1065 Table 11: TOTVAR EDF = b (T / tau) - c, T = N / fs (so T / tau = N / m).
double TotdevEdf(PowerLawNoise noise, double num_samples, double m) {
  double b = 1.50, c = 0.0;  // white rate (and the phase noises)
  if (noise == PowerLawNoise::kFlickerRate) {
    b = 1.17;
    c = 0.22;
  } else if (noise == PowerLawNoise::kRandomWalkRate) {
    b = 0.93;
    c = 0.36;
  }
  return b * num_samples / m - c;
}

// EDF per tau and the chi-square interval at options.confidence.
void AddIntervals(std::span<const double> rate, const AllanOptions& options, DeviationCurve* c) {
  const double p_lo = 0.5 * (1.0 - options.confidence);
  std::optional<PowerLawNoise> previous;
  for (std::size_t j = 0; j < c->size(); ++j) {
    const double m = static_cast<double>(c->m[j]);
    double edf = std::floor(static_cast<double>(rate.size()) / m) - 2.0;
    if (c->kind == DeviationKind::kTotdev) {
      std::optional<PowerLawNoise> noise = IdentifyNoiseLag1(rate, c->m[j]);
      if (!noise) noise = previous;
      previous = noise;
      edf = TotdevEdf(noise.value_or(PowerLawNoise::kWhiteRate), static_cast<double>(rate.size()), m);
    }
    if (!std::isfinite(edf) || edf < 1.0) edf = 1.0;
    c->edf.push_back(edf);
    c->lo_dps.push_back(c->dev_dps[j] * std::sqrt(edf / ChiSquareQuantile(1.0 - p_lo, edf)));
    c->hi_dps.push_back(c->dev_dps[j] * std::sqrt(edf / ChiSquareQuantile(p_lo, edf)));
  }
}

DeviationCurve FromAllan(const AllanResult& r) {
  DeviationCurve d;
  const AllanCurve& c = r.curve;
  d.kind = DeviationKind::kAdev;
  d.m = c.m;
  d.tau_s = c.tau_s;
  d.dev_dps = c.adev_dps;
  d.error_dps = c.adev_error_dps;
  d.n = c.n_clusters;
  d.edf = c.edf;
  d.lo_dps = c.adev_lo_dps;
  d.hi_dps = c.adev_hi_dps;
  d.confidence = r.confidence;
  d.method = r.deviation_method;
  d.edf_method = r.edf_method;
  d.seconds = r.seconds;
  return d;
}

}  // namespace

std::optional<DeviationKind> ParseDeviationKind(const std::string& text) {
  for (DeviationKind k : {DeviationKind::kAdev, DeviationKind::kMdev, DeviationKind::kHdev,
                          DeviationKind::kOhdev, DeviationKind::kTotdev}) {
    if (text == DeviationKindName(k)) return k;
  }
  return std::nullopt;
}

const char* DeviationKindName(DeviationKind kind) {
  switch (kind) {
    case DeviationKind::kAdev: return "adev";
    case DeviationKind::kMdev: return "mdev";
    case DeviationKind::kHdev: return "hdev";
    case DeviationKind::kOhdev: return "ohdev";
    case DeviationKind::kTotdev: return "totdev";
  }
  return "?";
}

Result<DeviationCurve> ComputeDeviation(std::span<const double> rate, double fs_hz, DeviationKind kind,
                                        const AllanOptions& options) {
  if (kind == DeviationKind::kAdev) {
    Result<AllanResult> r = ComputeAllan(rate, fs_hz, options);
    if (!r.ok()) return r.error();
    return FromAllan(*r);
  }
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  const char* name = DeviationKindName(kind);
  if (!std::isfinite(fs_hz) || fs_hz <= 0.0) {
    return InvalidInput(std::string(name) + ": sample rate " + std::to_string(fs_hz) + " Hz: must be > 0");
  }
  if (rate.size() < 4) {
    return InvalidInput(std::string(name) + ": " + std::to_string(rate.size()) +
                        " samples: at least 4 are needed for one tau");
  }
  if (options.grid == TauGrid::kAll && rate.size() > kMaxSamplesForAllTaus) {
    return InvalidArgument("AllanOptions::grid = all with " + std::to_string(rate.size()) +
                           " samples: at most " + std::to_string(kMaxSamplesForAllTaus) +
                           " (every tau costs O(N); use N taus per decade instead)");
  }
  const auto t0 = std::chrono::steady_clock::now();
  double scale = 1.0;
  Result<std::vector<double>> phase = PhaseFromRate(rate, fs_hz, &scale);
  if (!phase.ok()) return phase.error();
  Result<std::vector<std::int64_t>> ms = CandidateAveragingFactors(rate.size(), options);
  if (!ms.ok()) return ms.error();
  const std::vector<double>& x = *phase;
  const auto num_phase = static_cast<std::int64_t>(x.size());
  const std::vector<double> ext = kind == DeviationKind::kTotdev ? ReflectPhase(x) : std::vector<double>{};

  DeviationCurve d;
  d.kind = kind;
  d.confidence = options.confidence;
  for (std::int64_t m : *ms) {
    const double tau_s = static_cast<double>(m) / fs_hz;
    TauValue v;
    switch (kind) {
      case DeviationKind::kMdev: v = Mdev(x, m, tau_s); break;
      case DeviationKind::kHdev: v = Hadamard(x, m, m, tau_s); break;
      case DeviationKind::kOhdev: v = Hadamard(x, m, 1, tau_s); break;
      case DeviationKind::kTotdev: v = Totdev(ext, num_phase, m, tau_s); break;
      case DeviationKind::kAdev: break;
    }
    if (v.n <= 1) continue;  // allantools' remove_small_ns
    v.dev_dps *= scale;
    if (!std::isfinite(v.dev_dps)) {
      return InvalidInput(std::string(name) + ": rate values up to " + std::to_string(scale) +
                          " deg/s give a deviation beyond the range of a double at tau = " +
                          std::to_string(tau_s) + " s");
    }
    d.m.push_back(m);
    d.tau_s.push_back(tau_s);
    d.dev_dps.push_back(v.dev_dps);
    d.error_dps.push_back(v.dev_dps / std::sqrt(static_cast<double>(v.n)));
    d.n.push_back(v.n);
  }
  switch (kind) {
    case DeviationKind::kMdev: d.method = kMdevMethod; break;
    case DeviationKind::kHdev: d.method = kHdevMethod; break;
    case DeviationKind::kOhdev: d.method = kOhdevMethod; break;
    case DeviationKind::kTotdev: d.method = kTotdevMethod; break;
    case DeviationKind::kAdev: break;
  }
  d.edf_method = kind == DeviationKind::kTotdev ? kTotdevEdfMethod : kCountEdfMethod;
  AddIntervals(rate, options, &d);
  // The curve is finite; a confidence bound above it can still overflow near the largest double
  // (fuzz_numeric_stages: hdev hi = inf at +-1.8e308). Refused, not returned as inf.
  for (std::size_t j = 0; j < d.size(); ++j) {
    if (!std::isfinite(d.hi_dps[j]) || !std::isfinite(d.lo_dps[j])) {
      return InvalidInput(std::string(name) + ": the confidence bound at tau = " + std::to_string(d.tau_s[j]) +
                          " s exceeds the range of a double (rates within a few times the largest double)");
    }
  }
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return d;
}

}  // namespace gyrocomp
