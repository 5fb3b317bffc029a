// Causal evaluation of a drift model: what firmware computes, one sample at a time, with only the
// past (docs/explanation/flight-controller-export.md).
//
// The thermal states and their causal updates are thermal_state.h's (gyrocomp/drift/thermal_state.h,
// Eqs. TS-1..TS-3; DriftModel::Predict(inputs, causal = true), DriftEvaluator). This header adds
// what the exporters need around them: a summary of the causal prediction (the delay it adds) and
// the model function at one input (the generated C and the cubic projection evaluate it).
//
// Clamping is the model's OutOfRangePolicy (drift_model.h), shared by `apply`, the exports and
// the generated C: kClamp clamps the temperature input to the fitted range, the state never;
// kExtrapolate evaluates as it is. The PX4 / ArduPilot files always clamp (their firmware does).
#pragma once

#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"

namespace gyrocomp {

// What a causal prediction did, for reports.
struct CausalPredictionSummary {
  DriftInputSet inputs = DriftInputSet::kTemp;  // the model's inputs (which thermal state)
  double rate_tau_s = 0.0;      // tau_r of Eq. TS-1 (rate and memory states)
  // Delay of the causal dT/dt at low frequency, s: two discrete lags, 2 d with
  // d = dt / (exp(dt / tau_r) - 1) = tau_r - dt/2 + O(dt^2). 0 without a rate.
  double delay_s = 0.0;
  std::size_t num_clamped = 0;  // samples whose temperature the policy clamped
  // One line for logs: the state, the rate's lag tau and delay, samples clamped.
  std::string BriefReport() const;
};

// DriftModel::Predict(inputs, causal = true), with its summary. Errors as Predict.
Result<std::vector<double>> PredictDriftCausal(const DriftModel& model, const DriftInputs& inputs,
                                               CausalPredictionSummary* summary = nullptr);

// The model function at one temperature and state value (DriftModel::PredictAt: the model's
// out-of-range policy applies to the temperature).
inline double EvaluateDriftModel(const DriftModel& model, double temp_c, double state) {
  return model.PredictAt(temp_c, state);
}

}  // namespace gyrocomp
