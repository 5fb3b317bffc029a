// Causal evaluation of a drift model: what firmware can compute, one sample at a time, with only
// the past (issue 12 part 2; docs/export.md).
//
// The fit computes dT/dt with a centred least-squares window (temperature_rate.h): it looks
// window_s / 2 into the future. Firmware cannot. Here dT/dt comes from two first-order lags in
// series, each discretised by backward Euler with a = dt / (tau + dt):
//     L_k = L_{k-1} + a (T_k - L_{k-1})                 (first lag)
//     D_k = (1 - a) (D_{k-1} + (L_k - L_{k-1}))         (D = L - M, M the second lag of L)
//     dT/dt estimate = D_k / tau
// On a steady ramp of slope s, T - L = s tau and L - M = s tau exactly (any dt), so the estimate
// equals s once the start-up transient (a few tau) has passed. Transfer function s / (1 + s tau)^2:
// a differentiator behind a double low-pass, delay 2 tau at low frequency. D is updated from the
// increments of L, never as a difference of two large temperatures, so a float build keeps its
// precision (T ~ 50 C would cost 4e-6 C per step in float as L - M). The estimate is returned as
// D a / (b dt) (b = 1 - a), equal to D / tau but unbiased by the rounding of a and b.
//
// Default tau: the centred window's noise matched. For white noise on T of two-sided density N0,
// the centred least-squares slope over W seconds has variance 12 N0 / W^3, the double lag
// N0 / (4 tau^3); equal when tau = W / 48^(1/3) = 0.275 W (82.5 s, delay 165 s for W = 300 s).
//
// Clamping (shared with the generated C and the parameter exports): the model's inputs are
// clamped to the range it was fitted on (temperature to [temp_min_c, temp_max_c], dT/dt to
// [dtemp_min_c_per_s, dtemp_max_c_per_s]); the estimator itself sees the raw temperature.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"

namespace gyrocomp {

struct CausalRateOptions {
  // Time constant of each of the two lags, seconds (> 0). Automatic: the model's centred window
  // divided by 48^(1/3) (same white-noise variance; see above).
  std::optional<double> tau_s;
  bool IsValid(std::string* error) const;
};

// tau actually used for a model whose centred window is `rate.window_s`.
double ResolvedCausalTau(const CausalRateOptions& options, const TemperatureRateOptions& rate);

// Delay of the causal dT/dt estimate at low frequency, seconds: 2 tau.
inline double CausalRateDelay(double tau_s) { return 2.0 * tau_s; }

// The estimator's state (plain data: the generated C holds the same numbers).
// Carried as small numbers (T_{k-1}, T - L, L - M), never as the lags themselves: in float a lag
// near 50 C would round its own increments (ulp 4e-6 C against increments of 1e-4 C on a plateau)
// and bias the estimate by up to 2.5e-4 relative (measured); this form keeps ~1e-6.
struct CausalRateState {
  bool initialized = false;
  double prev_temp_c = 0.0;  // T_{k-1}, deg C
  double lag_error_c = 0.0;  // T - L, deg C
  double diff_c = 0.0;       // D = L - M, deg C
};

// One step: the state after temperature `temp_c` arrived `dt_s` seconds after the previous one;
// returns the dT/dt estimate, deg C / s. The first call initialises L = T, D = 0 (estimate 0).
double CausalRateStep(CausalRateState* state, double dt_s, double temp_c, double tau_s);

// The estimate at every sample of a uniformly sampled record (dt = 1 / fs_hz). Errors: empty
// record, fs_hz <= 0, non-finite temperature, invalid options.
Result<std::vector<double>> CausalTemperatureRate(std::span<const double> temp_c, double fs_hz,
                                                  double tau_s);

// What a causal prediction did, for reports and the `apply --causal` JSON.
struct CausalPredictionSummary {
  bool uses_rate = false;       // the model reads dT/dt
  double tau_s = 0.0;           // lag time constant (when uses_rate)
  double delay_s = 0.0;         // 2 tau (when uses_rate), 0 otherwise
  std::size_t num_clamped = 0;  // samples whose temperature or dT/dt input was clamped
  std::string BriefReport() const;
};

// The drift predicted causally at every sample: dT/dt from the double lag, inputs clamped to the
// fitted range, then the model's own formula. Equal to what the generated C (c_export.h) computes
// for the same samples. Errors as CausalTemperatureRate.
Result<std::vector<double>> PredictDriftCausal(const DriftModel& model, const DriftInputs& inputs,
                                               const CausalRateOptions& options = {},
                                               CausalPredictionSummary* summary = nullptr);

// The model's formula at one (already clamped) input row: temperature [, dT/dt].
double EvaluateDriftModel(const DriftModel& model, double temp_c, double dtemp_c_per_s);

}  // namespace gyrocomp
