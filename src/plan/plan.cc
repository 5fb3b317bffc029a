// Planning a calibration run (gyrocomp/plan/plan.h): each profile simulated with the unit, fitted
// with the default model, and scored on a heating ramp and the paper's cooling staircase.
#include "gyrocomp/plan/plan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "gyrocomp/core/format.h"

namespace gyrocomp {
namespace {

// z(0.9): a 90% band's half-width over its standard deviation (DriftModel::PredictBand).
constexpr double kZ90 = 1.6448536269514722;

Result<SimulatedRun> Run(const SimulatorOptions& unit, ThermalProfileKind kind, std::uint64_t seed, bool heating_ramp) {
  SimulatorOptions o = unit;
  o.profile.kind = kind;
  o.seed = seed;
  if (heating_ramp) {
    o.profile.room_temp_c = o.profile.cold_temp_c;
    o.profile.ramp_end_c = o.profile.hot_temp_c;
  }
  return Simulate(o);
}

// Adds the predicted (band) and simulated (truth) mean square error of `m` on `run`.
Status Score(const DriftModel& m, const SimulatedRun& run, double* predicted, double* simulated) {
  auto b = m.PredictBand({run.temp_c, run.fs_hz});
  if (!b.ok()) return b.error();
  double p = 0.0, s = 0.0;
  for (std::size_t i = 0; i < b->center.size(); ++i) {
    p += std::pow(0.5 * (b->hi[i] - b->lo[i]) / kZ90, 2);
    s += std::pow(b->center[i] - run.true_drift_dps[i], 2);
  }
  const double n = static_cast<double>(std::max<std::size_t>(1, b->center.size()));
  *predicted += p / n;
  *simulated += s / n;
  return Status::Ok();
}

// Checks a profile name: a simulator profile other than the user's schedule.
Result<ThermalProfileKind> ProfileKind(const std::string& name) {
  const auto kind = ParseThermalProfileKind(name);
  if (!kind || *kind == ThermalProfileKind::kUser)
    return InvalidArgument("--profiles: '" + name +
                           "' must be paper, soak, ramp, cycle, heat-cool, stairs or rate-cycles");
  return *kind;
}

Result<PlanProfileOutcome> Evaluate(const SimulatorOptions& unit, int seeds, const std::string& name) {
  auto kind = ProfileKind(name);
  if (!kind.ok()) return kind.error();
  PlanProfileOutcome out;
  out.profile = name;
  for (int k = 0; k < seeds; ++k) {
    const auto seed = static_cast<std::uint64_t>(k + 1);
    auto cal = Run(unit, *kind, seed, *kind == ThermalProfileKind::kRamp);
    if (!cal.ok()) return cal.error();
    out.hours = cal->summary.duration_s / 3600.0;
    auto m = FitDriftModel({cal->temp_c, cal->fs_hz}, cal->rate_dps, DriftFitOptions{});
    if (!m.ok()) return m.error();
    const std::string model = std::string(DriftModelKindName(m->kind)) + "(" + DriftInputSetName(m->inputs) + ")";
    if (std::find(out.models.begin(), out.models.end(), model) == out.models.end()) out.models.push_back(model);
    for (const ExcludedTerm& e : m->summary.excluded_terms)
      if (std::find(out.excluded.begin(), out.excluded.end(), e.term) == out.excluded.end())
        out.excluded.push_back(e.term);
    auto heat = Run(unit, ThermalProfileKind::kRamp, seed + 100, true);
    auto cool = Run(unit, ThermalProfileKind::kPaper, seed + 200, false);
    if (!heat.ok()) return heat.error();
    if (!cool.ok()) return cool.error();
    const double before = out.simulated_heat_dps + out.simulated_cool_dps;
    if (Status s = Score(*m, *heat, &out.predicted_heat_dps, &out.simulated_heat_dps); !s.ok()) return s.error();
    if (Status s = Score(*m, *cool, &out.predicted_cool_dps, &out.simulated_cool_dps); !s.ok()) return s.error();
    out.simulated_ms_per_seed.push_back(0.5 * (out.simulated_heat_dps + out.simulated_cool_dps - before));
  }
  for (double* v : {&out.predicted_heat_dps, &out.predicted_cool_dps, &out.simulated_heat_dps, &out.simulated_cool_dps})
    *v = std::sqrt(*v / seeds);
  return out;
}

}  // namespace

bool PlanOptions::IsValid(std::string* error) const {
  auto fail = [&](std::string message) {
    if (error) *error = std::move(message);
    return false;
  };
  if (seeds < 1 || seeds > 50) return fail("--seeds must be in 1..50");
  if (profiles.empty()) return fail("--profiles: none given");
  for (const std::string& p : profiles)
    if (auto k = ProfileKind(p); !k.ok()) return fail(k.error().message);
  if (!std::isfinite(fs_hz) || fs_hz <= 0.0)
    return fail("PlanOptions::fs_hz = " + FormatNumber(fs_hz) + ": must be finite and > 0");
  if (!std::isfinite(min_pilot_span_c) || min_pilot_span_c <= 0.0)
    return fail("PlanOptions::min_pilot_span_c = " + FormatNumber(min_pilot_span_c) + ": must be finite and > 0");
  return true;
}

double PlanProfileOutcome::predicted_dps() const {
  return std::sqrt(0.5 * (predicted_heat_dps * predicted_heat_dps + predicted_cool_dps * predicted_cool_dps));
}

double PlanProfileOutcome::simulated_dps() const {
  return std::sqrt(0.5 * (simulated_heat_dps * simulated_heat_dps + simulated_cool_dps * simulated_cool_dps));
}

double PlanProfileOutcome::score_dps() const { return std::max(predicted_dps(), simulated_dps()); }

double PlanProfileOutcome::simulated_rel_se() const {
  const std::size_t k = simulated_ms_per_seed.size();
  if (k < 2) return std::nan("");
  double mean = 0.0, ss = 0.0;
  for (double v : simulated_ms_per_seed) mean += v / static_cast<double>(k);
  for (double v : simulated_ms_per_seed) ss += (v - mean) * (v - mean);
  const double se_mean = std::sqrt(ss / static_cast<double>(k - 1) / static_cast<double>(k));
  return mean > 0.0 ? 0.5 * se_mean / mean : std::nan("");
}

std::string PlanResult::BriefReport() const {
  if (profiles.empty()) return "no profiles compared";
  const PlanProfileOutcome& r = Recommended();
  return "recommended: " + r.profile + " (" + FormatNumber(r.hours, 3) + " h of " + std::to_string(profiles.size()) +
         " profile" + (profiles.size() == 1 ? "" : "s") + ", " + std::to_string(seeds) + " seed" +
         (seeds == 1 ? "" : "s") + "): next-run drift error predicted " + FormatNumber(r.predicted_dps(), 3) +
         " deg/s, simulated " + FormatNumber(r.simulated_dps(), 3) + " deg/s";
}

Result<PlanResult> PlanChamberRun(const PlanOptions& options, const PlanRecording* pilot,
                                  const PlanRecording* noise_run) {
  auto unit = PlanUnitFromRecordings(options, pilot, noise_run);
  if (!unit.ok()) return unit.error();
  if (std::string why; !options.IsValid(&why)) return InvalidArgument(why);
  PlanResult result;
  result.unit = std::move(*unit);
  result.seeds = options.seeds;
  for (const std::string& p : options.profiles) {
    auto o = Evaluate(result.unit.sim, options.seeds, p);
    if (!o.ok()) return o.error();
    result.profiles.push_back(std::move(*o));
  }
  // The lowest score; within 10% of it, the shortest profile (the first of equal length).
  double best = result.profiles[0].score_dps();
  for (const PlanProfileOutcome& o : result.profiles) best = std::min(best, o.score_dps());
  const PlanProfileOutcome* pick = nullptr;
  for (const PlanProfileOutcome& o : result.profiles)
    if (o.score_dps() <= 1.1 * best && (!pick || o.hours < pick->hours)) pick = &o;
  result.recommended = static_cast<std::size_t>(pick - result.profiles.data());
  return result;
}

}  // namespace gyrocomp
