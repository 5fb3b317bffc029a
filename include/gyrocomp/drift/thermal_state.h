// Thermal states: the second input of a drift model besides the measured temperature T.
//
// The measured temperature is not the die's: the die lags it, and a MEMS structure remembers
// whether it was last heated or cooled. A drift model therefore takes, besides T, one state s:
//
//   rate    dT/dt. Batch (apply's default): the centred least-squares slope of
//           temperature_rate.h. Causal (Step, firmware, apply --causal): two cascaded first-order
//           lags of time constant tau_r = causal_rate_tau_s,
//             L1 += a (T - L1),  L2 += a (L1 - L2),  a = 1 - exp(-dt / tau_r),
//             s = (L1 - L2) / d,  d = dt / (exp(dt / tau_r) - 1)                  (Eq. TS-1)
//           d (= tau_r - dt/2 + O(dt^2)) is the exact delay of a ramp through one discrete lag, so
//           s equals dT/dt on a steady ramp; the temperature noise is low-passed twice. 2 states,
//           ~8 operations per sample (a, d are constants at a fixed rate; 2 exp when dt varies).
//   lag     first-order lag of the die behind the sensor, T_lag += a (T - T_lag),
//           a = 1 - exp(-dt / tau), s = T - T_lag (deg C; = tau dT/dt on a steady ramp). (Eq. TS-2)
//           tau is fitted (1-D search on the cross-validation score). 1 state, 3 operations.
//   memory  heating/cooling memory m in [-1, 1]: driven by the sign of the causal rate r of
//           Eq. TS-1 once |r| exceeds a deadband, at a speed set by a temperature width w:
//             m += min(1, |r| dt / w) (sign(r) - m)   when |r| > deadband, else m holds (Eq. TS-3)
//           so m tends to +1 after heating by a few w, to -1 after cooling, and keeps its value
//           during holds (a play operator on the filtered temperature). 3 states, ~12 operations.
//
// Two states: `temp,dtemp,memory` takes the rate of Eq. TS-1 AND the memory of
// Eq. TS-3 (computed from the same L1, L2): the drift cubic(T) + k_dot dT/dt + k_h (T - P_w(T))
// of a unit with a die gain and a hysteresis together (docs/explanation/simulator.md "Deterministic drift")
// needs both; with one state the gain absorbs the hysteresis (docs/explanation/drift-models.md). Its primary
// state s is the rate (batch: the centred slope; causal: Eq. TS-1), the memory m is a second,
// always causal, column.
//
// Every state has the causal one-sample-at-a-time update ThermalStateEvaluator::Step; the batch
// computation ComputeThermalState runs exactly that update for lag and memory (and for rate when
// causal is asked). Initial state: every lag equals the first temperature, m = 0.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/temperature_rate.h"

namespace gyrocomp {

// Model inputs: temperature only (the paper), temperature and one thermal state, or temperature,
// rate and memory (kTempRateAndMemory: state s = the rate, plus the memory m as a second state).
enum class DriftInputSet { kTemp, kTempAndRate, kTempAndLag, kTempAndMemory, kTempRateAndMemory };
// "temp" | "temp,dtemp" | "temp,lag" | "temp,memory" | "temp,dtemp,memory".
std::optional<DriftInputSet> ParseDriftInputSet(std::string_view name);
// The name ParseDriftInputSet reads.
const char* DriftInputSetName(DriftInputSet inputs);
// Name of the state column in model files and reports: "dtemp_c_per_s", "lag_excess_c",
// "memory"; "" for kTemp. kTempRateAndMemory: "dtemp_c_per_s" (its second state's column is
// kMemoryColumnName).
const char* ThermalStateColumnName(DriftInputSet inputs);
// Column of the second state (memory) of kTempRateAndMemory.
inline constexpr const char* kMemoryColumnName = "memory";
// Whether the inputs carry the memory of Eq. TS-3 as a second state (kTempRateAndMemory).
inline bool HasSecondMemoryState(DriftInputSet inputs) { return inputs == DriftInputSet::kTempRateAndMemory; }
// Whether the inputs' states need the causal rate of Eq. TS-1 (rate, memory, or both).
inline bool UsesCausalRate(DriftInputSet inputs) {
  return inputs == DriftInputSet::kTempAndRate || inputs == DriftInputSet::kTempAndMemory ||
         inputs == DriftInputSet::kTempRateAndMemory;
}

// Parameters of the thermal states (Eqs. TS-1..TS-3).
struct ThermalStateOptions {
  // rate: tau_r of the causal update (Eq. TS-1), s. Default 75 s = a quarter of the batch slope's
  // 300 s window: the two lags then delay the rate by 150 s, the centred window's half-length.
  double causal_rate_tau_s = 75.0;
  // lag: time constant tau of T_lag (Eq. TS-2), s. Fitted by `--model auto` / `--state-tau auto`.
  double lag_tau_s = 600.0;
  // memory: width w (deg C of filtered temperature change for m to move most of the way) and
  // deadband on |r| (deg C / s) below which m holds (Eq. TS-3). 4 C, 1e-3 C/s (0.06 C/min).
  double memory_width_c = 4.0;
  double memory_deadband_c_per_s = 1e-3;  // deg C / s
  // False with the reason in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// Causal evaluator of one thermal state, one sample at a time (what firmware runs).
class ThermalStateEvaluator {
 public:
  // Starts before the first sample; `options` is copied.
  ThermalStateEvaluator(DriftInputSet inputs, const ThermalStateOptions& options);
  // Advances by one sample (dt_s since the previous one; ignored for the first) and returns the
  // state s after it (0 for kTemp). Units: deg C / s (rate), deg C (lag), 1 (memory).
  double Step(double dt_s, double temp_c);
  // The memory m of Eq. TS-3 after the last Step (kTempAndMemory, kTempRateAndMemory; 0 else).
  double memory() const { return memory_; }
  // Back to before the first sample: the next Step starts every state afresh.
  void Reset() { started_ = false; }

 private:
  DriftInputSet inputs_;
  ThermalStateOptions options_;
  bool started_ = false;
  double l1_ = 0.0, l2_ = 0.0;  // Eq. TS-1 lags
  double lag_ = 0.0;            // Eq. TS-2
  double memory_ = 0.0;         // Eq. TS-3
};

// The state at every sample of a uniformly sampled record (kTempRateAndMemory: its primary
// state, the rate; its memory is ComputeThermalState(kTempAndMemory)). kTempAndRate with causal = false:
// the centred least-squares slope (TemperatureRate with `rate`); everything else: Step over the
// record. Errors: fewer than 2 samples or fs_hz <= 0 when a state is needed, non-finite values.
Result<std::vector<double>> ComputeThermalState(std::span<const double> temp_c, double fs_hz,
                                                DriftInputSet inputs, const TemperatureRateOptions& rate,
                                                const ThermalStateOptions& options, bool causal);

}  // namespace gyrocomp
