// Causal dT/dt (double first-order lag) and the causal drift prediction (see causal_drift.h).
#include "gyrocomp/export/causal_drift.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace gyrocomp {

bool CausalRateOptions::IsValid(std::string* error) const {
  if (tau_s && (!(*tau_s > 0.0) || !std::isfinite(*tau_s))) {
    if (error) {
      std::ostringstream s;
      s << "CausalRateOptions::tau_s = " << *tau_s << ": must be > 0";
      *error = s.str();
    }
    return false;
  }
  return true;
}

double ResolvedCausalTau(const CausalRateOptions& options, const TemperatureRateOptions& rate) {
  // Same white-noise variance as the centred window: tau = W / 48^(1/3) (causal_drift.h).
  return options.tau_s.value_or(rate.window_s / std::cbrt(48.0));
}

double CausalRateStep(CausalRateState* s, double dt_s, double temp_c, double tau_s) {
  if (!s->initialized) {
    s->initialized = true;
    s->prev_temp_c = temp_c;
    s->lag_error_c = 0.0;
    s->diff_c = 0.0;
    return 0.0;
  }
  if (!(dt_s > 0.0)) return s->diff_c / tau_s;     // no time elapsed: nothing new
  const double b = tau_s / (tau_s + dt_s);         // 1 - a, backward Euler
  const double a = 1.0 - b;                        // exact (b >= 1/2 when dt <= tau)
  // T_k - L_{k-1} = (T_k - T_{k-1}) + (T_{k-1} - L_{k-1}): only small numbers are carried.
  const double x = (temp_c - s->prev_temp_c) + s->lag_error_c;
  const double step = a * x;                       // L_k - L_{k-1}
  s->prev_temp_c = temp_c;
  s->lag_error_c = b * x;                          // T_k - L_k
  s->diff_c = b * (s->diff_c + step);              // D_k = (1 - a)(D_{k-1} + L_k - L_{k-1})
  // D / tau, written with the a and b the recursion used: on a ramp D = b s dt / a exactly in
  // the recursion's own arithmetic, so the rounding of a and b does not bias the estimate.
  return s->diff_c * a / (b * dt_s);
}

Result<std::vector<double>> CausalTemperatureRate(std::span<const double> temp_c, double fs_hz,
                                                  double tau_s) {
  if (temp_c.empty()) return InvalidInput("causal dT/dt: empty temperature record");
  if (!(fs_hz > 0.0) || !std::isfinite(fs_hz)) return InvalidArgument("causal dT/dt: fs_hz must be > 0");
  if (!(tau_s > 0.0) || !std::isfinite(tau_s)) return InvalidArgument("causal dT/dt: tau_s must be > 0");
  std::vector<double> rate(temp_c.size());
  CausalRateState state;
  const double dt = 1.0 / fs_hz;
  for (std::size_t i = 0; i < temp_c.size(); ++i) {
    if (!std::isfinite(temp_c[i]))
      return InvalidInput("causal dT/dt: non-finite temperature at sample " + std::to_string(i));
    rate[i] = CausalRateStep(&state, dt, temp_c[i], tau_s);
  }
  return rate;
}

std::string CausalPredictionSummary::BriefReport() const {
  std::ostringstream s;
  if (uses_rate)
    s << "causal dT/dt: double lag, tau = " << tau_s << " s, delay " << delay_s << " s";
  else
    s << "causal: the model reads temperature only (no delay)";
  s << "; " << num_clamped << " samples with inputs clamped to the fitted range";
  return s.str();
}

double EvaluateDriftModel(const DriftModel& model, double temp_c, double dtemp_c_per_s) {
  const bool rate = model.inputs == DriftInputSet::kTempAndRate;
  if (const PolynomialModel* poly = model.structured ? &*model.structured : nullptr) {
    std::vector<std::vector<double>> x = {{temp_c}};
    if (rate) x.push_back({dtemp_c_per_s});
    return poly->Predict(x)[0];
  }
  const double row[2] = {temp_c, dtemp_c_per_s};
  return model.kernel->PredictOne(std::span<const double>(row, rate ? 2 : 1));
}

Result<std::vector<double>> PredictDriftCausal(const DriftModel& model, const DriftInputs& in,
                                               const CausalRateOptions& options,
                                               CausalPredictionSummary* summary) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (in.temp_c.empty()) return InvalidInput("causal drift prediction: empty temperature record");
  const bool uses_rate = model.inputs == DriftInputSet::kTempAndRate;
  const double tau = ResolvedCausalTau(options, model.rate);
  std::vector<double> dtemp(in.temp_c.size(), 0.0);
  if (uses_rate) {
    auto r = CausalTemperatureRate(in.temp_c, in.fs_hz, tau);
    if (!r.ok()) return r.error();
    dtemp = std::move(*r);
  }
  const DriftFitSummary& f = model.summary;
  std::size_t clamped = 0;
  std::vector<double> out(in.temp_c.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!std::isfinite(in.temp_c[i]))
      return InvalidInput("causal drift prediction: non-finite temperature at sample " + std::to_string(i));
    const double t = std::clamp(in.temp_c[i], f.temp_min_c, f.temp_max_c);
    const double r = uses_rate ? std::clamp(dtemp[i], f.dtemp_min_c_per_s, f.dtemp_max_c_per_s) : 0.0;
    if (t != in.temp_c[i] || r != (uses_rate ? dtemp[i] : 0.0)) ++clamped;
    out[i] = EvaluateDriftModel(model, t, r);
  }
  if (summary) {
    summary->uses_rate = uses_rate;
    summary->tau_s = uses_rate ? tau : 0.0;
    summary->delay_s = uses_rate ? CausalRateDelay(tau) : 0.0;
    summary->num_clamped = clamped;
  }
  return out;
}

}  // namespace gyrocomp
