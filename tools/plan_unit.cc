// gyrocomp plan: the drift family of a pilot run's model (plan_unit.h).
#include "plan_unit.h"

#include <cmath>
#include <numbers>

#include "gyrocomp/core/format.h"

namespace gyrocomp::cli {
namespace {

// Binomial coefficient C(n, k) for the small powers of a drift polynomial.
double Choose(int n, int k) {
  double c = 1.0;
  for (int i = 1; i <= k; ++i) c = c * (n - k + i) / i;
  return c;
}

// Adds c ((T - offset) / scale)^p to poly, a polynomial in d = T - reference:
// ((d + delta) / scale)^p = sum_k C(p, k) d^k delta^(p - k) / scale^p, delta = reference - offset.
void AddTemperatureTerm(double c, int p, double offset, double scale, double reference, std::vector<double>* poly) {
  if (poly->size() < static_cast<std::size_t>(p + 1)) poly->resize(static_cast<std::size_t>(p + 1), 0.0);
  const double delta = reference - offset;
  for (int k = 0; k <= p; ++k)
    (*poly)[static_cast<std::size_t>(k)] += c * Choose(p, k) * std::pow(delta, p - k) / std::pow(scale, p);
}

}  // namespace

Status FamilyFromModel(const DriftModel& m, BiasModelOptions* bias, std::vector<std::string>* notes) {
  if (!m.structured)
    return InvalidInput("--pilot: the model (" + std::string(DriftModelKindName(m.kind)) +
                        ") has no structured polynomial to simulate; give the drift family with --drift-poly, "
                        "--dtemp-coeff, --hysteresis-width / --hysteresis-coeff");
  double to_dps = 1.0;
  if (m.unit == "rad/s") to_dps = 180.0 / std::numbers::pi;
  else if (m.unit != "deg/s")
    return InvalidInput("--pilot: the model's unit is " + m.unit + "; plan simulates a gyro (deg/s or rad/s)");
  const PolynomialModel& p = *m.structured;
  const std::vector<double>& off = p.input_scaler.offset;
  const std::vector<double>& sc = p.input_scaler.scale;
  std::vector<double> poly;
  double gain = 0.0, memory = 0.0;
  for (const PolynomialTerm& t : p.terms) {
    const double c = t.coefficient * to_dps;
    if (t.dtemp_power == 0 && t.memory_power == 0) {
      AddTemperatureTerm(c, t.temp_power, off[0], sc[0], bias->reference_temp_c, &poly);
      continue;
    }
    if (t.temp_power != 0 || t.dtemp_power > 1 || t.memory_power > 1) {
      notes->push_back("a term of power " + std::to_string(t.dtemp_power) + " in the state is not simulated");
      continue;
    }
    const std::size_t col = t.memory_power == 1 ? 2 : 1;
    const double per_unit = c / sc[col];         // deg/s per unit of the state
    AddTemperatureTerm(-per_unit * off[col], 0, 0.0, 1.0, 0.0, &poly);  // its standardising offset
    const bool is_memory = col == 2 || m.inputs == DriftInputSet::kTempAndMemory;
    if (is_memory) memory += per_unit;
    else if (m.inputs == DriftInputSet::kTempAndLag) gain += per_unit * m.state.lag_tau_s;  // T - T_lag ~ tau dT/dt
    else gain += per_unit;
  }
  if (m.inputs == DriftInputSet::kTempAndLag)
    notes->push_back("the lag state (tau " + FormatNumber(m.state.lag_tau_s, 4) +
                     " s) simulated as its ramp equivalent, a dT/dt gain of " + FormatNumber(gain, 4) +
                     " deg/s per C/s");
  if (m.kernel) notes->push_back("the model's kernel residual is not simulated (its structured part is)");
  bias->poly_dps = poly;
  bias->dtemp_coeff_dps_per_c_per_s = gain;
  bias->hysteresis_width_c = m.state.memory_width_c;
  bias->hysteresis_coeff_dps_per_c = 2.0 * memory / m.state.memory_width_c;
  std::string why;
  if (!bias->IsValid(&why)) return InvalidInput("--pilot: " + why);
  return Status::Ok();
}

}  // namespace gyrocomp::cli
