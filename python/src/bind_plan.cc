// gyrocomp.plan: PlanChamberRun (gyrocomp/plan/plan.h), the work of `gyrocomp plan`. The unit as
// simulate's nested keywords (noise=, bias=, profile=, thermal_lag_s); a figure passed in them is
// stated (PlanStated: it keeps its value over what a pilot or an Allan run gives). The recordings
// are files read as `gyrocomp plan --pilot / --noise-from` reads them.
#include <cmath>
#include <optional>

#include "bindings.h"

#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/plan/plan.h"

namespace gyrocomp::python {
namespace {

// A one-axis recording read as `gyrocomp plan` reads --pilot / --noise-from (min 3 samples).
GyroLog ReadRecording(const std::string& path, Kwargs& kw, const std::string& prefix, bool temp_required) {
  LogSpec spec;
  std::string rate_col = "rate_dps";
  kw.Get((prefix + "_rate_col").c_str(), &rate_col);
  spec.rate_cols = {rate_col};
  kw.Get((prefix + "_time_col").c_str(), &spec.time_col);
  if (temp_required) kw.Get((prefix + "_temp_col").c_str(), &spec.temp_col);
  kw.Get((prefix + "_fs_hz").c_str(), &spec.fs_hz);
  spec.min_samples = 3;
  spec.temp_required = temp_required;
  return Unwrap(WithoutGil([&] { return ReadGyroLog(path, spec); }));
}

bool Has(const py::dict& d, const char* key) { return d.contains(key); }

py::dict UnitDict(const PlanUnit& u) {
  const SimulatorOptions& s = u.sim;
  py::dict d;
  d["noise"] = py::dict(py::arg("arw_deg_per_sqrt_h") = s.noise.arw_deg_per_sqrt_h,
                        py::arg("bias_instability_deg_per_h") = s.noise.bias_instability_deg_per_h,
                        py::arg("rrw_deg_per_h_per_sqrt_h") = s.noise.rrw_deg_per_h_per_sqrt_h);
  d["bias"] = py::dict(py::arg("reference_temp_c") = s.bias.reference_temp_c, py::arg("poly_dps") = s.bias.poly_dps,
                       py::arg("dtemp_coeff_dps_per_c_per_s") = s.bias.dtemp_coeff_dps_per_c_per_s,
                       py::arg("hysteresis_width_c") = s.bias.hysteresis_width_c,
                       py::arg("hysteresis_coeff_dps_per_c") = s.bias.hysteresis_coeff_dps_per_c);
  d["thermal_lag_s"] = s.thermal_lag_s;
  d["cold_temp_c"] = s.profile.cold_temp_c;
  d["hot_temp_c"] = s.profile.hot_temp_c;
  d["num_cycles"] = s.profile.num_cycles;
  d["fs_hz"] = s.fs_hz;
  d["noise_source"] = u.noise_source;
  d["family_source"] = u.family_source;
  d["notes"] = u.notes;
  d["brief_report"] = u.BriefReport();
  return d;
}

py::dict OutcomeDict(const PlanProfileOutcome& o) {
  py::dict d;
  d["profile"] = o.profile;
  d["hours"] = o.hours;
  d["models"] = o.models;
  d["excluded"] = o.excluded;
  d["predicted_heat_dps"] = o.predicted_heat_dps;
  d["predicted_cool_dps"] = o.predicted_cool_dps;
  d["simulated_heat_dps"] = o.simulated_heat_dps;
  d["simulated_cool_dps"] = o.simulated_cool_dps;
  d["predicted_dps"] = o.predicted_dps();
  d["simulated_dps"] = o.simulated_dps();
  d["score_dps"] = o.score_dps();
  const double se = o.simulated_rel_se();
  d["simulated_rel_se"] = std::isfinite(se) ? py::object(py::float_(se)) : py::object(py::none());  // one seed: None
  d["simulated_ms_per_seed"] = ToNumpy(std::vector<double>(o.simulated_ms_per_seed));
  return d;
}

}  // namespace

void BindPlan(py::module_& m) {
  m.def(
      "plan",
      [](std::optional<std::string> pilot_path, std::optional<std::string> noise_path, const py::kwargs& kwargs) {
        Kwargs kw(kwargs, "plan");
        PlanOptions o;
        py::object profiles = kw.Take("profiles");
        if (!profiles.is_none()) {
          if (py::isinstance<py::str>(profiles)) {  // "paper,ramp" as on the command line
            o.profiles.clear();
            std::string text = profiles.cast<std::string>(), item;
            for (char c : text + ",") {
              if (c != ',') { if (c != ' ') item += c; continue; }
              if (!item.empty()) o.profiles.push_back(item);
              item.clear();
            }
          } else {
            o.profiles = profiles.cast<std::vector<std::string>>();
          }
        }
        kw.Get("seeds", &o.seeds);
        kw.Get("fs_hz", &o.fs_hz);
        kw.Get("min_pilot_span_c", &o.min_pilot_span_c);
        kw.Get("thermal_lag_s", &o.unit.thermal_lag_s);
        // The unit's figures passed here are stated (PlanStated).
        const py::dict noise = kw.Nested("noise"), bias = kw.Nested("bias"), profile = kw.Nested("profile");
        PlanStated& st = o.stated;
        st.arw = Has(noise, "arw_deg_per_sqrt_h");
        st.bias_instability = Has(noise, "bias_instability_deg_per_h");
        st.rrw = Has(noise, "rrw_deg_per_h_per_sqrt_h");
        st.drift_poly = Has(bias, "poly_dps");
        st.dtemp_coeff = Has(bias, "dtemp_coeff_dps_per_c_per_s");
        st.hysteresis_width = Has(bias, "hysteresis_width_c");
        st.hysteresis_coeff = Has(bias, "hysteresis_coeff_dps_per_c");
        st.cold = Has(profile, "cold_temp_c");
        st.hot = Has(profile, "hot_temp_c");
        ReadNoise(noise, &o.unit.noise, "plan");
        ReadBias(bias, &o.unit.bias, "plan");
        ReadProfile(profile, &o.unit.profile, "plan");
        std::optional<GyroLog> pilot_log, noise_log;
        if (noise_path) noise_log = ReadRecording(*noise_path, kw, "noise", /*temp_required=*/false);
        if (pilot_path) pilot_log = ReadRecording(*pilot_path, kw, "pilot", /*temp_required=*/true);
        kw.Done();
        std::optional<PlanRecording> pilot, noise_run;
        if (pilot_log) pilot = PlanRecording{*pilot_path, pilot_log->rate_dps.front(), pilot_log->temp_c, pilot_log->fs_hz};
        if (noise_log) noise_run = PlanRecording{*noise_path, noise_log->rate_dps.front(), {}, noise_log->fs_hz};
        PlanResult r = Unwrap(WithoutGil(
            [&] { return PlanChamberRun(o, pilot ? &*pilot : nullptr, noise_run ? &*noise_run : nullptr); }));
        py::dict d;
        d["unit"] = UnitDict(r.unit);
        py::list outcomes;
        for (const PlanProfileOutcome& x : r.profiles) outcomes.append(OutcomeDict(x));
        d["profiles"] = outcomes;
        d["recommended"] = r.recommended;
        d["recommended_profile"] = r.Recommended().profile;
        d["seeds"] = r.seeds;
        d["brief_report"] = r.BriefReport();
        return d;
      },
      py::arg("pilot") = py::none(), py::arg("noise_from") = py::none(),
      "Compare chamber profiles for a unit by the drift error they leave on the next run (gyrocomp plan). "
      "pilot: a pilot chamber run (CSV / ULog / DataFlash: drift family, residual noise, range); noise_from: "
      "an Allan run (noise). Keywords: profiles (list or 'a,b'), seeds, fs_hz, min_pilot_span_c, thermal_lag_s, "
      "noise={...}, bias={...}, profile={cold_temp_c, hot_temp_c, num_cycles} (a figure given is kept over the "
      "recordings'), pilot_rate_col, pilot_temp_col, pilot_time_col, pilot_fs_hz, noise_rate_col, "
      "noise_time_col, noise_fs_hz.");
}

}  // namespace gyrocomp::python
