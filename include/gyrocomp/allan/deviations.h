// More stability deviations of a gyro rate series beside the overlapping ADEV of allan.h, each
// computed exactly as allantools (data_type='freq') does, on the same phase record
// x_0 = 0, x_{i+1} = x_i + (y_i - mean(y)) / fs, with N_p = N + 1 phase points and tau = m / fs:
//
//   MDEV  (modified; NIST SP 1065 Eq. 14), n = N_p - 3m + 1 terms:
//     mvar = sum_{i<n} v_i^2 / (2 m^2 tau^2 n),  v_i = sum_{j=i}^{i+m-1} (x_{j+2m} - 2x_{j+m} + x_j)
//     with v_{i+1} = v_i + (x_{i+3m} - 3x_{i+2m} + 3x_{i+m} - x_i) (O(N) per tau, allantools' loop);
//   OHDEV (overlapping Hadamard; SP 1065 Eq. 18), n = N_p - 3m:
//     hvar = sum_{i<n} (x_{i+3m} - 3x_{i+2m} + 3x_{i+m} - x_i)^2 / (6 tau^2 n);
//   HDEV  (non-overlapping Hadamard; SP 1065 Eq. 17): the same third differences at i = 0, m, 2m, ...
//     (n = ceil((N_p - 3m) / m) of them). Both Hadamard kinds are blind to a linear rate drift
//     (a temperature ramp), where ADEV rises as +1;
//   TOTDEV (total; SP 1065 Eq. 25), n = N_p - 2 terms i = 1 .. N_p - 2 on the phase record
//     extended by reflection about both end points (x_{-j} = 2x_0 - x_j, x_{N_p-1+j} =
//     2x_{N_p-1} - x_{N_p-1-j}): totvar = sum (x_{i-m} - 2x_i + x_{i+m})^2 / (2 tau^2 (N_p - 2)).
// Taus with n <= 1 are dropped (allantools' remove_small_ns). Error bars: dev / sqrt(n) as
// allantools, and a chi-square interval from an approximate EDF (see DeviationCurve::edf_method).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/allan/allan.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp {

// The deviation a curve holds.
enum class DeviationKind {
  kAdev,    // overlapping Allan (allan.h; ComputeAllan's curve)
  kMdev,    // modified Allan
  kHdev,    // Hadamard, non-overlapping
  kOhdev,   // Hadamard, overlapping
  kTotdev,  // total
};

// "adev" | "mdev" | "hdev" | "ohdev" | "totdev"; nullopt otherwise.
std::optional<DeviationKind> ParseDeviationKind(const std::string& text);
// The short name above (also the JSON key prefix: "<name>_dps").
const char* DeviationKindName(DeviationKind kind);

// One deviation curve; all vectors the same length.
struct DeviationCurve {
  DeviationKind kind = DeviationKind::kAdev;  // which deviation
  std::vector<std::int64_t> m;       // averaging factor, tau = m / fs
  std::vector<double> tau_s;  // averaging time, s
  std::vector<double> dev_dps;       // the deviation, deg/s
  std::vector<double> error_dps;     // allantools' error: dev / sqrt(n)
  std::vector<std::int64_t> n;       // number of terms summed (allantools' ns)
  std::vector<double> edf;           // approximate equivalent degrees of freedom
  std::vector<double> lo_dps;        // chi-square confidence interval at `confidence`
  std::vector<double> hi_dps;  // upper end of that interval, deg/s
  double confidence = 0.0;  // two-sided level of the intervals
  std::string method;                // formula and reference
  std::string edf_method;  // how the EDF was approximated
  double seconds = 0.0;              // wall time
  // Number of taus.
  std::size_t size() const { return tau_s.size(); }
};

// Deviation of `kind` of one rate series (deg/s) at fs_hz on the tau grid of `options` (grid,
// points_per_decade, confidence). kAdev returns ComputeAllan's curve in this form. Errors as
// ComputeAllan: fs_hz <= 0 or non-finite, fewer than 4 samples (3 for adev), non-finite values
// (kInvalidInput), invalid options or grid = all above kMaxSamplesForAllTaus (kInvalidArgument).
Result<DeviationCurve> ComputeDeviation(std::span<const double> rate_dps, double fs_hz,
                                        DeviationKind kind, const AllanOptions& options = {});

}  // namespace gyrocomp
