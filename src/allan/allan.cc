// Overlapping Allan deviation, confidence intervals and noise terms (paper Section 4.3.1,
// method.md section 6). See include/gyrocomp/allan.h for the conventions.
#include "gyrocomp/allan/allan.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "blocked_sum.h"
#include "gyrocomp/core/parallel.h"
#include "gyrocomp/core/units.h"

namespace gyrocomp {
namespace {

using allan_internal::BlockedSum;

// Fewest m-averages for the lag-1 autocorrelation noise identification (Riley & Greenhall ask
// for about 30).
constexpr std::int64_t kMinBlocksForLag1 = 32;

constexpr const char* kDeviationMethod =
    "overlapping Allan deviation (IEEE Std 1554 / NIST SP 1065 Eq. 11), as allantools oadev";
constexpr const char* kEdfMethod =
    "equivalent degrees of freedom from the simple formulas of Howe, Allan & Barnes (1981) "
    "(NIST SP 1065 Table 5), noise type per tau by lag-1 autocorrelation (Riley & Greenhall 2004; "
    "carried over from the previous tau when fewer than 32 averages remain); chi-square interval";

// Lag-1 autocorrelation of v (mean removed); NaN when v is constant.
double Lag1Autocorrelation(const std::vector<double>& v) {
  double mean = 0.0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double a = v[i] - mean;
    den += a * a;
    if (i + 1 < v.size()) num += a * (v[i + 1] - mean);
  }
  return den > 0.0 ? num / den : std::numeric_limits<double>::quiet_NaN();
}

// Riley & Greenhall (2004) on m-averages of rate ("frequency") data given as the phase record x
// (the m-average k is proportional to x[(k+1)m] - x[km]). dmax = 2 differences (Allan variance).
std::optional<PowerLawNoise> Lag1NoiseFromPhase(const std::vector<double>& x, std::int64_t m) {
  const auto num_blocks = static_cast<std::int64_t>(x.size() - 1) / m;
  if (num_blocks < kMinBlocksForLag1) return std::nullopt;
  std::vector<double> z(static_cast<std::size_t>(num_blocks));
  for (std::int64_t k = 0; k < num_blocks; ++k) z[k] = x[(k + 1) * m] - x[k * m];
  for (int d = 0;; ++d) {
    const double r1 = Lag1Autocorrelation(z);
    if (!std::isfinite(r1)) return std::nullopt;
    const double rho = r1 <= -1.0 ? -1.0 : r1 / (1.0 + r1);
    if (rho < 0.25 || d == 2) {
      const double alpha = std::clamp(std::round(-2.0 * (rho + d)), -2.0, 2.0);  // frequency data: alpha = p
      return static_cast<PowerLawNoise>(static_cast<int>(alpha));
    }
    for (std::size_t i = 0; i + 1 < z.size(); ++i) z[i] = z[i + 1] - z[i];
    z.pop_back();
  }
}

// Regularized lower incomplete gamma P(a, x) (Numerical Recipes 6.2: series for x < a + 1,
// Lentz continued fraction otherwise).
double GammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefactor = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double ap = a, del = 1.0 / a, sum = del;
    for (int n = 0; n < 10000; ++n) {
      ap += 1.0;
      del *= x / ap;
      sum += del;
      if (std::abs(del) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(log_prefactor);
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefactor) * h;
}

PowerLawNoise NoiseFromSlope(double slope, bool leading) {
  // ADEV slopes: white phase -1, white rate -1/2, flicker rate 0, random-walk rate +1/2 (and
  // steeper, e.g. a ramp's +1, is treated as random walk: its EDF is the smallest, conservative).
  // Phase (angle) noise is accepted only in the leading run of taus (quantization dominates the
  // shortest taus of a gyro); a steep fall in the noisy tail is not phase noise, and the
  // white-phase EDF (~N/2 at any m) would be absurd there.
  if (!std::isfinite(slope)) return PowerLawNoise::kWhiteRate;
  if (slope < -0.75 && leading) return PowerLawNoise::kWhitePhase;
  if (slope < -0.25) return PowerLawNoise::kWhiteRate;
  if (slope < 0.25) return PowerLawNoise::kFlickerRate;
  return PowerLawNoise::kRandomWalkRate;
}

}  // namespace

const char* PowerLawNoiseName(PowerLawNoise noise) {
  switch (noise) {
    case PowerLawNoise::kWhitePhase: return "white phase (angle)";
    case PowerLawNoise::kFlickerPhase: return "flicker phase (angle)";
    case PowerLawNoise::kWhiteRate: return "white rate (angle random walk)";
    case PowerLawNoise::kFlickerRate: return "flicker rate (bias instability)";
    case PowerLawNoise::kRandomWalkRate: return "random walk rate";
  }
  return "?";
}

std::optional<TauGrid> ParseTauGrid(const std::string& text, int* points_per_decade) {
  if (text == "octave") return TauGrid::kOctave;
  if (text == "decade") return TauGrid::kDecade;
  if (text == "all") return TauGrid::kAll;
  if (text.empty() || text.size() > 4) return std::nullopt;
  int v = 0;
  for (char ch : text) {
    if (ch < '0' || ch > '9') return std::nullopt;
    v = v * 10 + (ch - '0');
  }
  if (v < 1 || v > 1000) return std::nullopt;
  if (points_per_decade != nullptr) *points_per_decade = v;
  return TauGrid::kPerDecade;
}

bool AllanOptions::IsValid(std::string* error) const {
  std::ostringstream os;
  if (grid == TauGrid::kPerDecade && (points_per_decade < 1 || points_per_decade > 1000)) {
    os << "AllanOptions::points_per_decade = " << points_per_decade << ": must be in [1, 1000]";
  } else if (!(confidence > 0.0 && confidence < 1.0)) {
    os << "AllanOptions::confidence = " << confidence << ": must be in (0, 1)";
  } else if (!(arw_tau_s > 0.0) || !std::isfinite(arw_tau_s)) {
    os << "AllanOptions::arw_tau_s = " << arw_tau_s << ": must be > 0";
  } else if (!(rrw_tau_s > 0.0) || !std::isfinite(rrw_tau_s)) {
    os << "AllanOptions::rrw_tau_s = " << rrw_tau_s << ": must be > 0";
  } else if (!(min_edf_for_terms >= 0.0) || !std::isfinite(min_edf_for_terms)) {
    os << "AllanOptions::min_edf_for_terms = " << min_edf_for_terms << ": must be >= 0";
  } else if (!(slope_tolerance > 0.0 && slope_tolerance <= 0.25)) {
    os << "AllanOptions::slope_tolerance = " << slope_tolerance << ": must be in (0, 0.25]";
  } else {
    return true;
  }
  if (error != nullptr) *error = os.str();
  return false;
}

Result<std::vector<std::int64_t>> CandidateAveragingFactors(std::size_t n_samples,
                                                            const AllanOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  // allantools works on the phase record, one point longer than the rate record, and keeps
  // 0 < m < len(phase); each deviation then drops the taus with n <= 1 terms.
  const auto num_phase = static_cast<std::int64_t>(n_samples) + 1;
  std::vector<std::int64_t> m;
  switch (options.grid) {
    case TauGrid::kOctave: {
      const int maxn = std::bit_width(static_cast<std::uint64_t>(num_phase)) - 1;  // floor(log2)
      for (int k = 0; k <= maxn; ++k) m.push_back(std::int64_t{1} << k);
      break;
    }
    case TauGrid::kDecade: {
      for (std::int64_t p = 1; p <= num_phase; p *= 10) {  // 10^k for k <= floor(log10(len))
        for (std::int64_t f : {1, 2, 4}) m.push_back(f * p);
        if (p > std::numeric_limits<std::int64_t>::max() / 10) break;
      }
      break;
    }
    case TauGrid::kAll: {
      for (std::int64_t k = 1; k <= num_phase; ++k) m.push_back(k);
      break;
    }
    case TauGrid::kPerDecade: {
      for (int j = 0;; ++j) {
        const double v = std::round(std::pow(10.0, static_cast<double>(j) / options.points_per_decade));
        if (v >= static_cast<double>(num_phase)) break;
        m.push_back(static_cast<std::int64_t>(v));
      }
      break;
    }
  }
  std::vector<std::int64_t> out;
  for (std::int64_t v : m) {
    if (v > 0 && v < num_phase) out.push_back(v);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

Result<std::vector<std::int64_t>> AllanAveragingFactors(std::size_t n_samples,
                                                        const AllanOptions& options) {
  Result<std::vector<std::int64_t>> m = CandidateAveragingFactors(n_samples, options);
  if (!m.ok()) return m;
  const auto num_phase = static_cast<std::int64_t>(n_samples) + 1;
  std::erase_if(*m, [&](std::int64_t v) { return num_phase - 2 * v <= 1; });  // n = N_p - 2m
  return m;
}

Result<std::vector<double>> PhaseFromRate(std::span<const double> y, double fs_hz, double* scale) {
  const std::size_t n = y.size();
  // Scale first: every deviation is scale-equivariant, dev(s y) = |s| dev(y), so the record is
  // built from y / s with s = max |y| and the caller multiplies back by s. Squares then neither
  // overflow (|y| near 1e300) nor underflow (|y| near 1e-300); for ordinary data s only rounds
  // the last bit.
  double s = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(y[i])) {
      return InvalidInput("Allan deviation: sample " + std::to_string(i) + " is not finite");
    }
    s = std::max(s, std::abs(y[i]));
  }
  if (s == 0.0) s = 1.0;
  if (scale != nullptr) *scale = s;
  BlockedSum sum;
  for (std::size_t i = 0; i < n; ++i) sum.Add(y[i] / s);
  const double mean = n > 0 ? sum.Total() / static_cast<double>(n) : 0.0;
  // x_0 = 0, x_{i+1} = dt * cumsum(y / s - mean), as allantools frequency2phase.
  const double dt = 1.0 / fs_hz;
  std::vector<double> x(n + 1);
  x[0] = 0.0;
  double acc = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    acc += y[i] / s - mean;
    x[i + 1] = acc * dt;
  }
  return x;
}

std::optional<PowerLawNoise> IdentifyNoiseLag1(std::span<const double> rate, std::int64_t m) {
  if (m < 1 || rate.empty()) return std::nullopt;
  std::vector<double> x(rate.size() + 1, 0.0);
  for (std::size_t i = 0; i < rate.size(); ++i) x[i + 1] = x[i] + rate[i];
  return Lag1NoiseFromPhase(x, m);
}

double EdfOverlappingAdevSimple(PowerLawNoise noise, double N, double m) {
  // NIST SP 1065 Table 5 (Howe, Allan & Barnes 1981), N = number of phase points.
  switch (noise) {
    case PowerLawNoise::kWhitePhase:
      return (N + 1.0) * (N - 2.0 * m) / (2.0 * (N - m));
    case PowerLawNoise::kFlickerPhase:
      return std::exp(std::sqrt(std::log((N - 1.0) / (2.0 * m)) * std::log((2.0 * m + 1.0) * (N - 1.0) / 4.0)));
    case PowerLawNoise::kWhiteRate:
      return (3.0 * (N - 1.0) / (2.0 * m) - 2.0 * (N - 2.0) / N) * (4.0 * m * m) / (4.0 * m * m + 5.0);
    case PowerLawNoise::kFlickerRate:
      // m = 1: 2(N-2)^2 / (2.3N - 4.9) as printed in SP 1065 (allantools omits the square).
      if (m == 1.0) return 2.0 * (N - 2.0) * (N - 2.0) / (2.3 * N - 4.9);
      return 5.0 * N * N / (4.0 * m * (N + 3.0 * m));
    case PowerLawNoise::kRandomWalkRate:
      return (N - 2.0) / m * ((N - 1.0) * (N - 1.0) - 3.0 * m * (N - 1.0) + 4.0 * m * m) /
             ((N - 3.0) * (N - 3.0));
  }
  return N / m - 1.0;
}

double ChiSquareQuantile(double p, double dof) {
  assert(p > 0.0 && p < 1.0 && dof > 0.0);
  const double a = 0.5 * dof;
  // Bracket, then safeguarded Newton on F(x) = P(a, x/2) - p (F' = chi-square density).
  double lo = 0.0, hi = std::max(1.0, dof);
  while (GammaP(a, 0.5 * hi) < p) {
    lo = hi;
    hi *= 2.0;
  }
  double x = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double f = GammaP(a, 0.5 * x) - p;
    if (f < 0.0) lo = x; else hi = x;
    const double log_density = (a - 1.0) * std::log(0.5 * x) - 0.5 * x - std::lgamma(a) - std::log(2.0);
    const double density = std::exp(log_density);
    double next = density > 0.0 ? x - f / density : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 1e-14 * std::max(1.0, x) || hi - lo <= 1e-15 * std::max(1.0, x)) {
      return next;
    }
    x = next;
  }
  return x;
}


namespace {

// A curve near the largest double (rates within a factor ~3600 of it) is finite in deg/s, but its
// confidence bounds or its noise terms in deg/h (x 3600) are not: refused rather than returned
// as infinities (found by fuzz_numeric_stages).
Status CheckRepresentable(const AllanResult& r) {
  const AllanNoiseTerms& t = r.terms;
  bool ok = std::all_of(r.curve.adev_hi_dps.begin(), r.curve.adev_hi_dps.end(), [](double v) { return std::isfinite(v); });
  for (double v : {t.adev_min_deg_per_h, t.bias_instability_deg_per_h, t.adev_min_usable_deg_per_h}) {
    ok = ok && std::isfinite(v);
  }
  for (const std::optional<double>& v : {t.arw_deg_per_sqrt_h, t.arw_fit_deg_per_sqrt_h, t.rrw_deg_per_h_per_sqrt_h}) {
    ok = ok && (!v || std::isfinite(*v));
  }
  if (ok) return Status::Ok();
  const double top = r.curve.adev_dps.empty() ? 0.0 : *std::max_element(r.curve.adev_dps.begin(), r.curve.adev_dps.end());
  std::ostringstream os;
  os << "Allan deviation: the curve reaches " << top
     << " deg/s: its confidence bound or its noise terms in deg/h (x 3600) exceed the range of a double";
  return InvalidInput(os.str());
}

}  // namespace

Result<AllanResult> ComputeAllan(std::span<const double> y, double fs_hz, const AllanOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (!std::isfinite(fs_hz) || fs_hz <= 0.0) {
    return InvalidInput("Allan deviation: sample rate " + std::to_string(fs_hz) + " Hz: must be > 0");
  }
  if (y.size() < 3) {
    return InvalidInput("Allan deviation: " + std::to_string(y.size()) +
                        " samples: at least 3 are needed for one tau");
  }
  if (options.grid == TauGrid::kAll && y.size() > kMaxSamplesForAllTaus) {
    return InvalidArgument("AllanOptions::grid = all with " + std::to_string(y.size()) +
                           " samples: every tau costs O(N), all taus O(N^2); at most " +
                           std::to_string(kMaxSamplesForAllTaus) + " samples (use N taus per decade instead)");
  }
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t n = y.size();
  double scale = 1.0;
  Result<std::vector<double>> phase = PhaseFromRate(y, fs_hz, &scale);
  if (!phase.ok()) return phase.error();
  const std::vector<double>& x = *phase;

  Result<std::vector<std::int64_t>> ms = AllanAveragingFactors(n, options);
  if (!ms.ok()) return ms.error();
  AllanResult r;
  r.fs_hz = fs_hz;
  r.n_samples = n;
  r.confidence = options.confidence;
  r.deviation_method = kDeviationMethod;
  r.edf_method = kEdfMethod;
  AllanCurve& c = r.curve;
  const auto num_phase = static_cast<std::int64_t>(n) + 1;
  for (std::int64_t m : *ms) {
    if (options.cancel != nullptr && options.cancel->cancelled()) throw Cancelled();  // AllanOptions::cancel
    // NIST SP 1065 Eq. (11) in phase form: sigma^2 = sum (x_{i+2m} - 2x_{i+m} + x_i)^2 / (2 n tau^2).
    const std::int64_t count = num_phase - 2 * m;
    const double* x0 = x.data();
    const double* x1 = x.data() + m;
    const double* x2 = x.data() + 2 * m;
    BlockedSum s;
    for (std::int64_t i = 0; i < count; ++i) {
      const double d = (x2[i] - 2.0 * x1[i]) + x0[i];
      s.Add(d * d);
    }
    const double adev =
        std::sqrt(s.Total() / (2.0 * static_cast<double>(count))) / static_cast<double>(m) * fs_hz * scale;
    if (!std::isfinite(adev)) {
      return InvalidInput("Allan deviation: rate values up to " + std::to_string(scale) +
                          " deg/s give a deviation beyond the range of a double at tau = " +
                          std::to_string(static_cast<double>(m) / fs_hz) + " s");
    }
    c.m.push_back(m);
    c.tau_s.push_back(static_cast<double>(m) / fs_hz);
    c.adev_dps.push_back(adev);
    c.adev_error_dps.push_back(adev / std::sqrt(static_cast<double>(count)));
    c.n_clusters.push_back(count);
  }

  // Local log-log slopes (central differences; one-sided at the ends), noise type, EDF, interval.
  const std::size_t k = c.size();
  c.slope.assign(k, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t j = 0; j < k && k > 1; ++j) {
    const std::size_t a = j == 0 ? 0 : j - 1;
    const std::size_t b = j + 1 == k ? j : j + 1;
    if (c.adev_dps[a] > 0.0 && c.adev_dps[b] > 0.0) {
      c.slope[j] = std::log(c.adev_dps[b] / c.adev_dps[a]) / std::log(c.tau_s[b] / c.tau_s[a]);
    }
  }
  const double p_lo = 0.5 * (1.0 - options.confidence);
  bool leading = true;
  std::optional<PowerLawNoise> previous;
  for (std::size_t j = 0; j < k; ++j) {
    // Noise type: lag-1 autocorrelation while enough averages remain; then the last identified
    // type (Stable32 practice); the local slope only when nothing could be identified.
    std::optional<PowerLawNoise> identified = Lag1NoiseFromPhase(x, c.m[j]);
    if (!identified) identified = previous;
    const PowerLawNoise noise = identified ? *identified : NoiseFromSlope(c.slope[j], leading);
    leading = leading && noise == PowerLawNoise::kWhitePhase;
    previous = identified;
    double edf = EdfOverlappingAdevSimple(noise, static_cast<double>(num_phase), static_cast<double>(c.m[j]));
    // The empirical formulas can fall below 1 (or go wrong) at the largest taus; at least one
    // degree of freedom remains with n > 1 second differences.
    if (!std::isfinite(edf) || edf < 1.0) edf = 1.0;
    c.noise.push_back(noise);
    c.edf.push_back(edf);
    c.adev_lo_dps.push_back(c.adev_dps[j] * std::sqrt(edf / ChiSquareQuantile(1.0 - p_lo, edf)));
    c.adev_hi_dps.push_back(c.adev_dps[j] * std::sqrt(edf / ChiSquareQuantile(p_lo, edf)));
  }
  r.terms = ExtractNoiseTerms(c, options);
  if (Status s = CheckRepresentable(r); !s) return s.error();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

Result<std::vector<AllanResult>> ComputeAllan(std::span<const AllanAxisInput> axes, const std::string& source,
                                              const AllanOptions& options, int threads) {
  std::vector<std::optional<Result<AllanResult>>> results(axes.size());
  ParallelFor(axes.size(), threads > 0 ? threads : DefaultItemThreads(),
              [&](std::size_t a) { results[a] = ComputeAllan(axes[a].rate, axes[a].fs_hz, options); });
  std::vector<AllanResult> out;
  out.reserve(axes.size());
  for (std::size_t a = 0; a < axes.size(); ++a) {
    Result<AllanResult>& r = *results[a];
    if (!r.ok()) {
      Error e = r.error();
      e.message = source + ": column '" + axes[a].name + "': " + e.message;
      return e;
    }
    r->axis = axes[a].name;
    out.push_back(std::move(*r));
  }
  return out;
}

Result<std::vector<AllanResult>> ComputeAllan(const GyroLog& log, const AllanOptions& options) {
  std::vector<AllanAxisInput> axes;
  for (std::size_t a = 0; a < log.rate_dps.size(); ++a) {
    axes.push_back({a < log.axis_names.size() ? log.axis_names[a] : std::to_string(a), log.rate_dps[a], log.fs_hz});
  }
  Result<std::vector<AllanResult>> out = ComputeAllan(axes, log.source, options);
  if (out.ok()) {
    // An axis without a name keeps an empty AllanResult::axis (its error above names its index).
    for (std::size_t a = log.axis_names.size(); a < out->size(); ++a) (*out)[a].axis.clear();
  }
  return out;
}

std::string AllanResult::BriefReport() const {
  std::ostringstream os;
  os.precision(4);
  // A figure the curve cannot carry: "n/a (reason[; needs a record of at least X s])".
  auto na = [&](const std::string& key) -> bool {
    const auto it = terms.unsupported.find(key);
    if (it == terms.unsupported.end()) return false;
    os << "n/a (" << it->second.text;
    if (it->second.needs_record_s) os << "; needs a record of at least " << *it->second.needs_record_s << " s";
    os << ")";
    return true;
  };
  os << (axis.empty() ? std::string("rate") : axis) << ": " << n_samples << " samples at " << fs_hz
     << " Hz, " << curve.size() << " taus; ARW ";
  if (!na("arw_deg_per_sqrt_h")) {
    if (terms.arw_deg_per_sqrt_h) {
      // An ARW is comparable only beside its bandwidth (docs/explanation/pipeline.md, the
      // not-applicable rule): a sampled record carries at most fs/2; a filter upstream (the
      // sensor's low-pass, a denoiser) leaves less, which the record itself does not say.
      os << *terms.arw_deg_per_sqrt_h << " deg/sqrt(h) (sigma(1 s), " << terms.arw_method
         << "; bandwidth <= fs/2 = " << BandwidthMaxHz() << " Hz)";
    } else {
      os << "n/a";
    }
  }
  os << "; ADEV min ";
  if (!na("adev_min_deg_per_h")) {
    os << terms.adev_min_deg_per_h << " deg/h at tau " << terms.tau_at_min_s << " s"
       << (terms.min_at_longest_tau ? " (longest tau: floor not reached)" : "");
  }
  os << " (EDF >= " << terms.min_edf << ": ";
  if (!na("adev_min_usable_deg_per_h")) {
    os << terms.adev_min_usable_deg_per_h << " deg/h at " << terms.tau_at_min_usable_s << " s"
       << (terms.min_usable_at_longest_usable_tau ? ", longest usable tau" : "");
  }
  os << "); B = min/0.664 = ";
  if (!na("bias_instability_deg_per_h")) os << terms.bias_instability_deg_per_h << " deg/h";
  os << "; RRW ";
  if (!na("rrw_deg_per_h_per_sqrt_h")) {
    if (terms.rrw_deg_per_h_per_sqrt_h) {
      os << *terms.rrw_deg_per_h_per_sqrt_h << " deg/h/sqrt(h) (+1/2 fit, sigma(3 s))";
    } else {
      os << "n/a (no +1/2 region)";
    }
  }
  return os.str();  // the computing time is in the JSON ("seconds"), not in a line a person reads
}

}  // namespace gyrocomp
