// Causal drift prediction summary (see causal_drift.h).
#include "gyrocomp/export/causal_drift.h"

#include <cmath>
#include <sstream>

namespace gyrocomp {

std::string CausalPredictionSummary::BriefReport() const {
  std::ostringstream s;
  s << "causal thermal state " << DriftInputSetName(inputs);
  if (delay_s > 0.0) s << ": dT/dt from two lags of tau " << rate_tau_s << " s, delay " << delay_s << " s";
  s << "; " << num_clamped << " samples with the temperature clamped to the fitted range";
  return s.str();
}

Result<std::vector<double>> PredictDriftCausal(const DriftModel& model, const DriftInputs& in,
                                               CausalPredictionSummary* summary) {
  auto out = model.Predict(in, /*causal=*/true);
  if (!out.ok()) return out.error();
  if (summary) {
    summary->inputs = model.inputs;
    const bool rate = UsesCausalRate(model.inputs);
    summary->rate_tau_s = rate ? model.state.causal_rate_tau_s : 0.0;
    if (rate && in.fs_hz > 0.0) {
      const double dt = 1.0 / in.fs_hz;
      summary->delay_s = 2.0 * dt / std::expm1(dt / model.state.causal_rate_tau_s);
    }
    summary->num_clamped = 0;
    if (model.out_of_range == OutOfRangePolicy::kClamp)
      for (double t : in.temp_c) summary->num_clamped += t != model.EffectiveTemp(t);
  }
  return out;
}

}  // namespace gyrocomp
