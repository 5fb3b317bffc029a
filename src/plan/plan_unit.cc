// The unit plan simulates (gyrocomp/plan/plan.h): the drift family of a pilot run's model
// (FamilyFromModel), and the noise, family and range read from an Allan run and a pilot run
// (PlanUnitFromRecordings).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "gyrocomp/allan/allan.h"
#include "gyrocomp/core/format.h"
#include "gyrocomp/plan/plan.h"

namespace gyrocomp {
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

namespace {

// The noise of `rate` as `allan` reads it (IEEE 952, the simulator's own definitions): ARW from
// sigma(1 s), B = ADEV minimum / 0.664, RRW from the +1/2 region (0 without one). Eq. G-0 fitted
// over tau <= record / 10 (FitNoisePsd, the band's noise model) read a simulated 44 deg/h unit
// as B 30-32 and RRW 140-240 (true 3) from 1-4 h soaks: its random walk stands in for the
// flicker's rise, and extrapolated over a 14 h profile it would make the unit far noisier.
Status NoiseFromAllan(std::span<const double> rate, double fs_hz, const std::string& what, const PlanStated& stated,
                      PlanUnit* unit) {
  auto allan = ComputeAllan(rate, fs_hz);
  if (!allan.ok()) return InvalidInput(what + ": " + allan.error().message);
  const AllanNoiseTerms& t = allan->terms;
  if (!t.arw_deg_per_sqrt_h) return InvalidInput(what + ": too short for sigma(1 s) (the ARW)");
  NoiseOptions& n = unit->sim.noise;
  if (!stated.arw) n.arw_deg_per_sqrt_h = *t.arw_deg_per_sqrt_h;
  if (!stated.bias_instability) n.bias_instability_deg_per_h = t.bias_instability_deg_per_h;
  if (!stated.rrw) n.rrw_deg_per_h_per_sqrt_h = t.rrw_deg_per_h_per_sqrt_h.value_or(0.0);
  unit->noise_source = what + " (" + FormatNumber(static_cast<double>(rate.size()) / fs_hz / 3600.0, 3) +
                       " h; B = ADEV min / 0.664" +
                       (t.min_at_longest_tau ? ", the minimum at the longest tau: an upper bound" : "") +
                       (t.rrw_deg_per_h_per_sqrt_h ? "" : "; no +1/2 region: RRW 0") + ")";
  return Status::Ok();
}

// The pilot's structured model as the drift family; a figure stated keeps its value.
Status ApplyPilotFamily(const DriftModel& m, const std::string& pilot_name, const PlanStated& stated, PlanUnit* unit) {
  BiasModelOptions family = unit->sim.bias;
  if (Status s = FamilyFromModel(m, &family, &unit->notes); !s.ok()) return s.error();
  BiasModelOptions& b = unit->sim.bias;
  if (!stated.drift_poly) b.poly_dps = family.poly_dps;
  if (!stated.dtemp_coeff) b.dtemp_coeff_dps_per_c_per_s = family.dtemp_coeff_dps_per_c_per_s;
  if (!stated.hysteresis_width) b.hysteresis_width_c = family.hysteresis_width_c;
  if (!stated.hysteresis_coeff) b.hysteresis_coeff_dps_per_c = family.hysteresis_coeff_dps_per_c;
  for (const ExcludedTerm& e : m.summary.excluded_terms) {
    const bool dtemp = e.term == "dT/dt gain", memory = e.term == "memory";
    const std::string flag = dtemp ? "--dtemp-coeff" : memory ? "--hysteresis-coeff" : "";
    const bool given = (dtemp && stated.dtemp_coeff) || (memory && stated.hysteresis_coeff);
    unit->notes.push_back("the pilot run does not identify the " + e.term +
                          (given ? " (simulated with " + flag + ")" : " (simulated without it)"));
  }
  unit->family_source =
      "pilot " + pilot_name + " (" + DriftModelKindName(m.kind) + "(" + DriftInputSetName(m.inputs) + "))";
  return Status::Ok();
}

// The noise of the pilot's residual, without the RRW: a chamber run's residual carries the drift
// the model does not follow, which rises with tau like a random walk (a simulated 3
// deg/h/sqrt(h) unit read 110 on a heat-cool pilot).
Status ApplyPilotNoise(const DriftModel& m, const PlanRecording& pilot, const PlanStated& stated, PlanUnit* unit) {
  auto pred = m.Predict({pilot.temp_c, pilot.fs_hz});
  if (!pred.ok()) return pred.error();
  std::vector<double> residual(pred->size());
  for (std::size_t i = 0; i < residual.size(); ++i) residual[i] = pilot.rate_dps[i] - (*pred)[i];
  if (Status s = NoiseFromAllan(residual, pilot.fs_hz, "the pilot run's residual", stated, unit); !s.ok())
    return s.error();
  if (!stated.rrw) {
    unit->sim.noise.rrw_deg_per_h_per_sqrt_h = 0.0;
    unit->noise_source += ", RRW not read from a chamber run (give --rrw or --noise-from a static run)";
  }
  return Status::Ok();
}

// The pilot run: the structured model auto chooses on it (no kernel: a family the simulator can
// run) as the drift family, the noise of its residual (unless an Allan run), its temperature
// range (unless cold / hot are stated).
Status ApplyPilot(const PlanRecording& pilot, bool have_noise_run, const PlanOptions& options, PlanUnit* unit) {
  if (pilot.temp_c.empty() || pilot.temp_c.size() != pilot.rate_dps.size())
    return InvalidInput(pilot.name + ": the pilot run needs a temperature per rate sample (" +
                        std::to_string(pilot.temp_c.size()) + " for " + std::to_string(pilot.rate_dps.size()) + ")");
  const auto [t_lo, t_hi] = std::minmax_element(pilot.temp_c.begin(), pilot.temp_c.end());
  if (*t_hi - *t_lo < options.min_pilot_span_c)
    return InvalidInput(pilot.name + ": the pilot run spans " + FormatNumber(*t_hi - *t_lo, 3) + " C (needs >= " +
                        FormatNumber(options.min_pilot_span_c, 3) +
                        " C of chamber temperature change for a drift family)");
  DriftFitOptions o;
  o.auto_select.try_svr = false;
  auto m = FitDriftModel({pilot.temp_c, pilot.fs_hz}, pilot.rate_dps, o);
  if (!m.ok()) return InvalidInput(pilot.name + ": " + m.error().message);
  if (Status s = ApplyPilotFamily(*m, pilot.name, options.stated, unit); !s.ok()) return s.error();
  if (!have_noise_run)
    if (Status s = ApplyPilotNoise(*m, pilot, options.stated, unit); !s.ok()) return s.error();
  ThermalProfileOptions& p = unit->sim.profile;
  if (!options.stated.cold) p.cold_temp_c = *t_lo;
  if (!options.stated.hot) p.hot_temp_c = *t_hi;
  if (p.cold_temp_c < *t_lo || p.hot_temp_c > *t_hi)
    unit->notes.push_back("the family is extrapolated beyond the pilot run's " + FormatNumber(*t_lo, 4) + ".." +
                          FormatNumber(*t_hi, 4) + " C");
  return Status::Ok();
}

}  // namespace

Result<PlanUnit> PlanUnitFromRecordings(const PlanOptions& options, const PlanRecording* pilot,
                                        const PlanRecording* noise_run) {
  PlanUnit unit;
  unit.sim = options.unit;
  unit.sim.fs_hz = options.fs_hz;
  if (noise_run) {
    if (Status s = NoiseFromAllan(noise_run->rate_dps, noise_run->fs_hz, "Allan run " + noise_run->name,
                                  options.stated, &unit);
        !s.ok())
      return s.error();
  }
  if (pilot)
    if (Status s = ApplyPilot(*pilot, noise_run != nullptr, options, &unit); !s.ok()) return s.error();
  return unit;
}

std::string PlanUnit::BriefReport() const {
  const SimulatorOptions& u = sim;
  std::string s = "unit: noise ARW " + FormatNumber(u.noise.arw_deg_per_sqrt_h, 4) + " deg/sqrt(h), bias instability " +
                  FormatNumber(u.noise.bias_instability_deg_per_h, 4) + " deg/h, RRW " +
                  FormatNumber(u.noise.rrw_deg_per_h_per_sqrt_h, 4) + " deg/h/sqrt(h) from " + noise_source +
                  "; drift: bias(T) about " + FormatNumber(u.bias.reference_temp_c, 4) + " C [";
  for (std::size_t k = 0; k < u.bias.poly_dps.size(); ++k) s += (k ? ", " : "") + FormatNumber(u.bias.poly_dps[k], 4);
  s += "] deg/s per C^k, dT/dt gain " + FormatNumber(u.bias.dtemp_coeff_dps_per_c_per_s, 4) +
       " deg/s per C/s, hysteresis " + FormatNumber(u.bias.hysteresis_width_c, 4) + " C x " +
       FormatNumber(u.bias.hysteresis_coeff_dps_per_c, 4) + " deg/s per C, sensor lag " +
       FormatNumber(u.thermal_lag_s, 4) + " s, from " + family_source + "; range " +
       FormatNumber(u.profile.cold_temp_c, 4) + ".." + FormatNumber(u.profile.hot_temp_c, 4) + " C";
  for (const std::string& n : notes) s += "; " + n;
  return s;
}

}  // namespace gyrocomp
