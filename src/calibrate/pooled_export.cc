// A pooled sensor's exported cubic for CalibrateOptions::optimise_for (calibrate_internal.h):
// the pooled curve with the thermal term the fit kept, projected at the condition as a single
// run's drift model is (ProjectOntoCubic).
#include <cmath>

#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "calibrate_internal.h"

namespace gyrocomp::calibrate_internal {
namespace {

// The pooled curve with the thermal term the fit kept, as a DriftModel (model unit) that
// ProjectOntoCubic projects at a CubicCondition, as the single run's model is projected:
//   a dT/dt term: y = f(T) + g s, s = dT/dt (kTempAndRate);
//   a lag:        y = f(T_lag) = f(T - s), s = T - T_lag (Eq. TS-2, kTempAndLag), with
//                 (T - ref - s)^k = sum_j C(k, j) (T - ref)^(k - j) (-s)^j.
// f is the steady cubic c (T_lag = T at steady state: the same curve).
DriftModel StateModelOf(const TemperatureCubic& c, double rate_gain, bool lagged) {
  DriftModel m;
  m.kind = DriftModelKind::kPolynomial;
  m.inputs = lagged ? DriftInputSet::kTempAndLag : DriftInputSet::kTempAndRate;
  PolynomialModel poly;
  poly.input_scaler.offset = {c.ref_temp_c, 0.0};
  poly.input_scaler.scale = {1.0, 1.0};
  for (int k = 0; k < 4; ++k) {
    const double ck = c.coeff[static_cast<std::size_t>(k)];
    double binomial = 1.0;  // C(k, j)
    for (int j = 0; j <= (lagged ? k : 0); ++j) {
      poly.terms.push_back({k - j, j, ck * binomial * (j % 2 ? -1.0 : 1.0)});
      binomial = binomial * (k - j) / (j + 1);
    }
  }
  if (!lagged) poly.terms.push_back({0, 1, rate_gain});
  m.structured = poly;
  m.summary.temp_min_c = c.temp_min_c, m.summary.temp_max_c = c.temp_max_c;
  return m;
}

}  // namespace

// The exported cubic of one axis (model unit) for CalibrateOptions::optimise_for: the steady
// cubic c itself, or the projection of the curve with its thermal term at the heating state
// (StateModelOf, ProjectOntoCubic: warm-up at the state, both the mean with steady); c where the
// axis has no term. `model` gets the curve with its term (ModelOf's cubic when none), for the
// condition errors.
TemperatureCubic ForCondition(const Sensor& s, const Args& a, const TemperatureCubic& c, double rate_gain, DriftModel* model) {
  const bool lagged = s.temp_lag_s > 0.0;
  const bool term = !s.heating_state.state.empty() && (lagged || rate_gain != 0.0);
  if (!term) return c;
  *model = StateModelOf(c, rate_gain, lagged);
  const CubicCondition condition = *ParseCubicCondition(a.optimise_for);
  if (condition == CubicCondition::kSteady) return c;
  CubicProjectionOptions po;
  po.condition = condition;
  po.warm_up = s.heating_state;
  po.temp_min_c = c.temp_min_c, po.temp_max_c = c.temp_max_c, po.ref_temp_c = c.ref_temp_c;
  // The range spans min_span_c or more and the coefficients are finite: the projection does not
  // fail; if it did, the steady cubic is the one that is known to be valid.
  Result<TemperatureCubic> projected = ProjectOntoCubic(*model, po);
  return projected.ok() ? *projected : c;
}

}  // namespace gyrocomp::calibrate_internal
