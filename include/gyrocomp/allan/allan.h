// Allan variance analysis of gyro rate data: the measurement stage (paper Section 4.3.1; method.md
// section 6).
//
// The overlapping Allan deviation (IEEE Std 952 / 1554; NIST SP 1065 Eq. (11)) of a rate series
// y_i (deg/s) sampled at fs_hz, computed exactly as allantools' oadev(data_type='freq'):
//   - phase x_0 = 0, x_{i+1} = x_i + (y_i - mean(y)) / fs        (angle in deg, mean removed);
//   - for each averaging factor m (tau = m / fs):
//       n(m)        = (N + 1) - 2m                  second differences ("n_clusters")
//       sigma^2(m)  = sum_{i<n} (x_{i+2m} - 2 x_{i+m} + x_i)^2 / (2 n tau^2)
//     so each tau costs O(N) whatever m is (cumulative sums, no re-averaging);
//   - taus with n <= 1 are dropped (allantools' remove_small_ns).
// Error bars: allantools' adev / sqrt(n), plus chi-square confidence intervals from equivalent
// degrees of freedom (see AllanOptions::confidence and EdfOverlappingAdevSimple below).
// Noise terms (method.md 6), each with its convention stated in AllanNoiseTerms.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/core/cancel.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp {

// How the averaging times are chosen (m = tau * fs, integer >= 1).
enum class TauGrid {
  kOctave,     // m = 1, 2, 4, ..., 2^k for k <= floor(log2(N + 1)) (allantools "octave")
  kDecade,     // m = 1, 2, 4, 10, 20, 40, 100, ... up to 10^floor(log10(N + 1)) (allantools "decade")
  kAll,        // m = 1, 2, 3, ..., N (allantools "all"; O(N^2) in total: at most
               // kMaxSamplesForAllTaus samples)
  kPerDecade,  // m = unique(round(10^(j / points_per_decade))), j = 0, 1, ... (log-spaced)
};

// TauGrid::kAll costs O(N^2): ComputeAllan refuses it (kInvalidArgument) above this many samples.
inline constexpr std::size_t kMaxSamplesForAllTaus = 100000;

// "octave" | "decade" | "all" | a positive integer N (N per decade). nullopt otherwise;
// *points_per_decade is set for the integer form.
std::optional<TauGrid> ParseTauGrid(const std::string& text, int* points_per_decade);

// The dominant power-law noise at one tau, named by the exponent alpha of the *rate* ("frequency")
// PSD S(f) ~ f^alpha, as in NIST SP 1065. ADEV slope in log-log: alpha = 2 -> -1, 0 -> -1/2,
// -1 -> 0, -2 -> +1/2 (alpha = 1 also gives about -1; ADEV cannot tell it from alpha = 2).
enum class PowerLawNoise {
  kWhitePhase = 2,         // angle (quantization-like) noise
  kFlickerPhase = 1,
  kWhiteRate = 0,          // angle random walk
  kFlickerRate = -1,       // bias instability (flicker floor)
  kRandomWalkRate = -2,    // rate random walk
};
// Name for reports, e.g. "white rate (angle random walk)".
const char* PowerLawNoiseName(PowerLawNoise noise);

// Settings of ComputeAllan: the tau grid, the confidence level, how the noise terms are read.
struct AllanOptions {
  // Tau grid (cli.md: --taus octave (default) | decade | all | N).
  TauGrid grid = TauGrid::kOctave;
  // Points per decade for TauGrid::kPerDecade. Must be >= 1.
  int points_per_decade = 10;
  // Two-sided confidence level of the chi-square intervals (0 < c < 1). 0.683 = "1 sigma".
  double confidence = 0.683;
  // Noise terms. ARW is read at this tau (s): sigma(1 s) (method.md 6; IEEE 952 N = sigma(1 s)).
  double arw_tau_s = 1.0;
  // RRW is read at this tau (s) on the fitted +1/2 line: K = sigma(3 s) (IEEE 952).
  double rrw_tau_s = 3.0;
  // Slope band (log-log) for classifying a segment as white rate (-1/2 +- tol), flicker (0 +- tol)
  // or random walk (+1/2 +- tol). Must be in (0, 0.25].
  double slope_tolerance = 0.2;
  // The EDF-qualified minimum (AllanNoiseTerms::adev_min_usable_deg_per_h) and the -1/2 / +1/2
  // fits use only taus with at least this many equivalent degrees of freedom (10: ~22% one-sigma
  // relative error of sigma). The curve and the default minimum keep every tau. CLI: --min-edf.
  double min_edf_for_terms = 10.0;
  // Polled before every tau (a curve over 1e9 samples takes seconds per tau); once
  // cancelled, ComputeAllan throws Cancelled. nullptr: not polled. Not owned.
  const CancellationToken* cancel = nullptr;
  // False with the field and the rule in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// The curve: one entry per tau, all vectors the same length.
struct AllanCurve {
  std::vector<std::int64_t> m;            // averaging factor, tau = m / fs
  std::vector<double> tau_s;  // averaging time, s
  std::vector<double> adev_dps;           // overlapping Allan deviation, deg/s
  std::vector<double> adev_error_dps;     // allantools' error: adev / sqrt(n_clusters)
  std::vector<std::int64_t> n_clusters;   // n = N + 1 - 2m (overlapping second differences)
  std::vector<double> slope;              // local log-log slope d ln(adev) / d ln(tau)
  std::vector<PowerLawNoise> noise;       // dominant noise assumed for the EDF (IdentifyNoiseLag1)
  std::vector<double> edf;                // equivalent degrees of freedom (chi-square)
  std::vector<double> adev_lo_dps;        // chi-square confidence interval at `confidence`
  std::vector<double> adev_hi_dps;  // upper end of that interval, deg/s
  // Number of taus.
  std::size_t size() const { return tau_s.size(); }
};

// Noise terms read off the curve, each with its convention (method.md section 6).
struct AllanNoiseTerms {
  // Angle random walk N = sigma(tau = arw_tau_s) * sqrt(arw_tau_s) in deg/s*sqrt(s), shown in
  // deg/sqrt(h) (x 60). sigma(1 s) is taken from the curve: exact when 1 s is on the grid,
  // otherwise interpolated linearly in log-log between the two bracketing taus; if 1 s is below
  // the smallest tau, extrapolated from the first point along slope -1/2. nullopt when 1 s is
  // beyond the largest tau.
  std::optional<double> arw_deg_per_sqrt_h;
  std::string arw_method;  // "on grid" | "log-log interpolation" | "extrapolated along -1/2" | ""
  // Second ARW estimate: least-squares fit of ln sigma = ln N - ln(tau)/2 (weights 2 EDF, the
  // inverse variance of ln sigma) over the usable taus up to the minimum whose local slope is within tol
  // of -1/2 (IEEE 952 -1/2 line), evaluated at tau = 1 s. nullopt if no such region; 0 when every
  // ADEV is exactly 0 (a constant record: no noise).
  std::optional<double> arw_fit_deg_per_sqrt_h;
  // Minimum of the whole ADEV curve, deg/h, and its tau: the "bias stability" as the paper,
  // allantools users, MATLAB's examples and allan_variance_ros read it. The last taus carry few
  // degrees of freedom and a random dip there can set it: compare adev_min_usable_deg_per_h.
  double adev_min_deg_per_h = 0.0;
  double tau_at_min_s = 0.0;  // tau of that minimum, s
  // True when that minimum is at the longest tau of the curve: the floor was not reached and the
  // minimum is an upper bound ("adev_min_at_longest_tau" in JSON).
  bool min_at_longest_tau = false;
  // The EDF-qualified minimum: over the taus with EDF >= min_edf ("usable"; all taus when none
  // qualifies or the curve has no EDFs), deg/h, and its tau. The -1/2 and +1/2 fits are anchored
  // on this one.
  double adev_min_usable_deg_per_h = 0.0;
  double tau_at_min_usable_s = 0.0;  // tau of the usable minimum, s
  // True when the usable minimum is at the largest usable tau.
  bool min_usable_at_longest_usable_tau = false;
  // The threshold used (AllanOptions::min_edf_for_terms) and the number of usable taus.
  double min_edf = 0.0;
  std::size_t num_taus_used = 0;  // taus with EDF >= min_edf
  // Bias instability B = adev_min_deg_per_h / 0.664 (IEEE 952 flicker floor sigma = 0.664 B), deg/h.
  double bias_instability_deg_per_h = 0.0;
  // Rate random walk K from the +1/2 region: least-squares fit of sigma = K sqrt(tau / 3) (slope
  // fixed at +1/2, weights 2 EDF) over the usable taus after the minimum whose local slope is within tol
  // of +1/2,
  // K = fitted sigma(3 s), shown in deg/h/sqrt(h). nullopt when the curve has no +1/2 region;
  // 0 when every ADEV is exactly 0 (a constant record).
  std::optional<double> rrw_deg_per_h_per_sqrt_h;
  std::optional<double> rrw_fit_tau_min_s;  // lower end of the +1/2 region fitted, s
  std::optional<double> rrw_fit_tau_max_s;  // upper end of the region, s

  // Support: the figures the curve cannot carry, by JSON key ("adev_min_deg_per_h",
  // "adev_min_usable_deg_per_h", "bias_instability_deg_per_h", "arw_deg_per_sqrt_h",
  // "arw_fit_deg_per_sqrt_h", "rrw_deg_per_h_per_sqrt_h"), each with its reason. Such a figure is
  // null in JSON (with "<key>_reason") and "n/a (reason)" on the console; its value above is not
  // to be read. The minimums each figure needs:
  //   the curve's minimum and B: kMinTausForMinimum taus (a minimum needs points on both sides);
  //   the EDF-qualified minimum, both ARW figures and RRW: at least one tau with EDF >= min_edf;
  //   ARW sigma(1 s): 1 s within the curve or below its first tau (read along -1/2 there);
  //   the -1/2 and +1/2 fits: kMinTausForFit taus in their region;
  //   RRW sigma(rrw_tau_s): rrw_tau_s within the curve (never projected past the record).
  struct Unsupported {
    std::string reason;                    // key: "fewer_than_3_taus", "no_tau_with_edf_ge_min_edf", ...
    std::string text;                      // for a person: what is missing
    std::optional<double> needs_record_s;  // the record length that would carry it, when that is what is missing
  };
  std::map<std::string, Unsupported> unsupported;  // the figures not supported, by JSON key
  // True when the figure `key` is supported (not in `unsupported`).
  bool Supported(const std::string& key) const { return unsupported.count(key) == 0; }
};
inline constexpr std::size_t kMinTausForMinimum = 3;  // taus a curve needs for its minimum and B
inline constexpr std::size_t kMinTausForFit = 2;  // taus a -1/2 or +1/2 fit needs in its region

// The Allan analysis of one rate series: the curve, the noise terms, how they were computed.
struct AllanResult {
  std::string axis;             // rate column name ("" when unnamed)
  double fs_hz = 0.0;  // sample rate, Hz
  std::size_t n_samples = 0;  // samples of the series
  AllanCurve curve;  // ADEV per tau with its intervals
  AllanNoiseTerms terms;  // ARW, bias instability, RRW read off the curve
  double confidence = 0.0;  // two-sided level of the curve's intervals
  // Names of the methods used, for reports and JSON.
  std::string deviation_method;  // "overlapping ADEV (IEEE 1554 / NIST SP 1065 Eq. 11), allantools oadev"
  std::string edf_method;        // see EdfOverlappingAdevSimple
  double seconds = 0.0;          // wall time of the computation
  // The most bandwidth the record can carry, Hz: fs/2 (Nyquist). A low-pass upstream of the
  // record (the sensor's own, a denoiser) leaves less, which the samples do not say; an ARW is
  // comparable only with one of the same bandwidth.
  double BandwidthMaxHz() const { return fs_hz / 2; }
  // One line for logs: samples, rate, taus, ARW with the bandwidth bound fs/2 it was read over,
  // the ADEV minimums, B, RRW ("n/a (reason)" for a figure not supported).
  std::string BriefReport() const;
};

// Averaging factors for `n_samples` rate samples, sorted, unique, those with n = N + 1 - 2m <= 1
// already dropped (as allantools does after computing). Empty when n_samples < 3.
Result<std::vector<std::int64_t>> AllanAveragingFactors(std::size_t n_samples,
                                                        const AllanOptions& options);

// Every m in (0, n_samples + 1) of the grid, sorted and unique, before any deviation drops the
// taus with too few terms (each kind has its own count; deviations.h).
Result<std::vector<std::int64_t>> CandidateAveragingFactors(std::size_t n_samples,
                                                            const AllanOptions& options);

// Phase (angle) record of a rate series as allantools' frequency2phase, of y / s with
// s = max |y| (*scale, 1 for an all-zero record): x_0 = 0, x_{i+1} = x_i + (y_i / s - mean) / fs.
// Deviations computed on it are multiplied back by s (they are scale-equivariant; this keeps
// squares of |y| near 1e+-300 in range). Error (kInvalidInput) naming the first non-finite sample.
Result<std::vector<double>> PhaseFromRate(std::span<const double> rate_dps, double fs_hz, double* scale);

// Overlapping ADEV of one rate series (deg/s) at fs_hz, with confidence intervals and noise
// terms. Errors: fs_hz <= 0 or non-finite, fewer than 3 samples, non-finite values
// (kInvalidInput), invalid options (kInvalidArgument).
Result<AllanResult> ComputeAllan(std::span<const double> rate_dps, double fs_hz,
                                 const AllanOptions& options = {});

// One axis of a multi-axis analysis: its name (AllanResult::axis), samples and rate.
struct AllanAxisInput {
  std::string name;  // axis name (AllanResult::axis)
  std::span<const double> rate;  // rate samples, deg/s
  double fs_hz = 0.0;  // sample rate, Hz
};

// One AllanResult per axis, in order, each computed as ComputeAllan(rate, fs_hz, options) alone
// would (the same bits), the axes spread over `threads` threads (0: DefaultItemThreads(), the
// machine's threads up to 2: the six axes of an IMU on both cores). An error names
// `source` and the axis: "<source>: column '<name>': <what>" (the lowest failing axis).
Result<std::vector<AllanResult>> ComputeAllan(std::span<const AllanAxisInput> axes, const std::string& source,
                                              const AllanOptions& options = {}, int threads = 0);

// One AllanResult per axis of a log, in axis order, each named after its rate column (the axes
// in parallel, as above).
Result<std::vector<AllanResult>> ComputeAllan(const GyroLog& log, const AllanOptions& options = {});

// Noise terms from an already computed curve (used by ComputeAllan; exposed for reuse/tests).
AllanNoiseTerms ExtractNoiseTerms(const AllanCurve& curve, const AllanOptions& options = {});

// Dominant power-law noise of rate data at averaging factor m by the lag-1 autocorrelation
// method of Riley & Greenhall (2004): the m-averages are differenced d = 0, 1, 2 times until
// rho = r1 / (1 + r1) < 0.25; alpha = round(-2 (rho + d)). nullopt when fewer than 32 averages
// remain (ComputeAllan then carries the previous tau's type over, or uses the local slope).
std::optional<PowerLawNoise> IdentifyNoiseLag1(std::span<const double> rate_dps, std::int64_t m);

// Equivalent degrees of freedom of the overlapping Allan variance, "simple" empirical formulas
// of Howe, Allan & Barnes (1981) as tabulated in NIST SP 1065 Table 5 (this is NOT Greenhall &
// Riley's exact algorithm). num_phase = N + 1 phase points, m = averaging factor.
double EdfOverlappingAdevSimple(PowerLawNoise noise, double num_phase, double m);

// Quantile of the chi-square distribution with `dof` > 0 degrees of freedom: x with
// P(X <= x) = p, 0 < p < 1 (regularized incomplete gamma, inverted by safeguarded Newton).
double ChiSquareQuantile(double p, double dof);

}  // namespace gyrocomp
