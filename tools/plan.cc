// gyrocomp plan: compare chamber profiles for a unit by the drift error they leave on the next
// run, per hour of chamber time (docs/explanation/calibration-design.md). The comparison is the
// library's (gyrocomp/plan/plan.h, PlanChamberRun); this file reads the options and the
// recordings, and prints.
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "console.h"
#include "gyrocomp/plan/plan.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kPlanName = "plan";

std::string CommaList(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

struct PlanArgs {
  PlanOptions options;  // the unit (noise, drift family, range), profiles, seeds, fs: the library's defaults
  std::string profiles = CommaList(PlanOptions{}.profiles);  // PlanOptions::profiles, comma-separated
  std::string drift_poly;
  std::string json_path;
  bool verbose = false;  // the full table (models, left-out terms, per-direction RMS, SE)
  // The unit from recordings (PlanUnitFromRecordings): a pilot chamber run (its drift family, and
  // the noise of its residual unless given otherwise) and an Allan run (a static recording).
  std::string pilot_path, pilot_col = "rate_dps", pilot_temp_col = "temp_c", pilot_time_col = "time_s";
  std::string noise_path, noise_col = "rate_dps", noise_time_col = "time_s";
  std::optional<double> pilot_fs_hz, noise_fs_hz;
};

std::string Join(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s.empty() ? "-" : s;
}

// "12%" (one seed: "-").
std::string SePercent(double rel) {
  if (!std::isfinite(rel)) return "-";
  std::ostringstream os;
  os << static_cast<int>(std::lround(100.0 * rel)) << "%";
  return os.str();
}

// The reader's advice names the -i commands' flags; plan's are `flag`-col, -temp-col, -time-col, -fs.
std::string PlanFlags(std::string message, const std::string& flag) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"--rate-col", flag + "-col"},
                                 {"--temp-col", flag + "-temp-col"}, {"--time-col", flag + "-time-col"},
                                 {"--fs ", flag + "-fs "}})
    for (std::size_t at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
      message.replace(at, from.size(), to);
  return message;
}

// A one-axis recording named by --pilot or --noise-from (read as `fit -i` / `allan -i`); `flag`:
// the option's prefix (--pilot, --noise) for the reader's advice.
Result<GyroLog> ReadRun(const std::string& flag, const std::string& path, const std::string& rate_col,
                        const std::string& temp_col, const std::string& time_col, std::optional<double> fs_hz,
                        bool temp_required) {
  LogOptions lo;
  lo.input = path;
  lo.time_col = time_col;
  lo.rate_col = rate_col;
  lo.temp_col = temp_col;
  lo.fs_hz = fs_hz;
  auto spec = ToLogSpec(lo);
  if (!spec.ok()) return spec.error();
  spec->min_samples = 3;
  spec->temp_required = temp_required;
  spec->keep_cols.emplace();
  auto loaded = LoadLog(kPlanName, lo, *spec);
  if (!loaded.ok()) return Error{loaded.error().kind, PlanFlags(loaded.error().message, flag)};
  if (loaded->log.rate_dps.size() != 1) return InvalidArgument(path + ": name one rate column with " + flag + "-col");
  return std::move(loaded->log);
}

PlanRecording Recording(const std::string& name, const GyroLog& log) {
  return {name, log.rate_dps.front(), log.temp_c, log.fs_hz};
}

nlohmann::json UnitJson(const PlanUnit& unit) {
  const SimulatorOptions& u = unit.sim;
  return {{"noise", {{"arw_deg_per_sqrt_h", u.noise.arw_deg_per_sqrt_h},
                     {"bias_instability_deg_per_h", u.noise.bias_instability_deg_per_h},
                     {"rrw_deg_per_h_per_sqrt_h", u.noise.rrw_deg_per_h_per_sqrt_h},
                     {"source", unit.noise_source}}},
          {"drift", {{"reference_temp_c", u.bias.reference_temp_c}, {"poly_dps", u.bias.poly_dps},
                     {"dtemp_coeff_dps_per_c_per_s", u.bias.dtemp_coeff_dps_per_c_per_s},
                     {"hysteresis_width_c", u.bias.hysteresis_width_c},
                     {"hysteresis_coeff_dps_per_c", u.bias.hysteresis_coeff_dps_per_c},
                     {"thermal_lag_s", u.thermal_lag_s}, {"source", unit.family_source}}},
          {"cold_c", u.profile.cold_temp_c}, {"hot_c", u.profile.hot_temp_c}, {"notes", unit.notes}};
}

int RunPlan(PlanArgs& a) {
  // The recordings are read here (the CLI's readers and their advice); the library reads the unit
  // from them (an Allan run first, then the pilot run).
  std::optional<GyroLog> noise_log, pilot_log;
  if (!a.noise_path.empty()) {
    auto log = ReadRun("--noise", a.noise_path, a.noise_col, "temp_c", a.noise_time_col, a.noise_fs_hz,
                       /*temp_required=*/false);
    if (!log.ok()) return ReportError(kPlanName, log.error());
    noise_log = std::move(*log);
  }
  if (!a.pilot_path.empty()) {
    auto log = ReadRun("--pilot", a.pilot_path, a.pilot_col, a.pilot_temp_col, a.pilot_time_col, a.pilot_fs_hz,
                       /*temp_required=*/true);
    if (!log.ok()) return ReportError(kPlanName, log.error());
    pilot_log = std::move(*log);
  }
  PlanOptions& options = a.options;
  if (!a.drift_poly.empty()) {
    options.unit.bias.poly_dps.clear();
    for (const std::string& item : SplitList(a.drift_poly)) {
      char* end = nullptr;
      const double v = std::strtod(item.c_str(), &end);
      if (end == item.c_str() || *end != '\0') return ReportError(kPlanName, InvalidArgument("--drift-poly: '" + item + "' is not a number"));
      options.unit.bias.poly_dps.push_back(v);
    }
  }
  options.profiles = SplitList(a.profiles);
  const std::optional<PlanRecording> pilot =
      pilot_log ? std::optional<PlanRecording>(Recording(a.pilot_path, *pilot_log)) : std::nullopt;
  const std::optional<PlanRecording> noise =
      noise_log ? std::optional<PlanRecording>(Recording(a.noise_path, *noise_log)) : std::nullopt;
  auto plan = PlanChamberRun(options, pilot ? &*pilot : nullptr, noise ? &*noise : nullptr);
  if (!plan.ok()) return ReportError(kPlanName, plan.error());
  const PlanUnit& unit = plan->unit;
  const PlanProfileOutcome* pick = &plan->Recommended();
  nlohmann::json j;
  j["unit"] = UnitJson(unit);
  j["profiles"] = nlohmann::json::array();
  const bool print = a.json_path != "-";
  if (print && a.verbose) {
    std::cout << unit.BriefReport() << "\n";
    std::cout << "| profile | hours | model(s) | left out | predicted RMS heat / cool (deg/s) | simulated RMS heat / cool "
                 "| predicted / simulated | simulated: 1 SE (seeds) | predicted x hours |\n|---|---|---|---|---|---|---|---|---|\n";
  } else if (print) {
    const SimulatorOptions& u = unit.sim;
    std::cout << "unit: ARW " << Figure(u.noise.arw_deg_per_sqrt_h) << " deg/sqrt(h), bias instability "
              << Figure(u.noise.bias_instability_deg_per_h) << " deg/h (" << unit.noise_source << "); drift family from "
              << unit.family_source << "; " << Figure(u.profile.cold_temp_c) << " .. " << Figure(u.profile.hot_temp_c)
              << " C\n";
    std::cout << "  profile        hours   expected next-run drift error, predicted / simulated (heating and cooling)\n";
  }
  for (const PlanProfileOutcome& o : plan->profiles) {
    if (print && a.verbose) {
      std::cout << "| " << o.profile << " | " << o.hours << " | " << Join(o.models) << " | " << Join(o.excluded) << " | "
                << o.predicted_heat_dps << " / " << o.predicted_cool_dps << " | " << o.simulated_heat_dps << " / "
                << o.simulated_cool_dps << " | " << o.predicted_dps() / o.simulated_dps() << " | "
                << SePercent(o.simulated_rel_se()) << " | " << o.predicted_dps() * o.hours << " |\n";
    } else if (print) {
      std::ostringstream row;
      row << "  " << std::left << std::setw(14) << o.profile << " " << std::setw(7) << Figure(o.hours) << " "
          << RateDps(o.predicted_dps()) << " / " << RateDps(o.simulated_dps()) << (&o == pick ? "   <- recommended" : "");
      std::cout << row.str() << "\n";
    }
    j["profiles"].push_back({{"profile", o.profile}, {"hours", o.hours}, {"models", o.models}, {"left_out", o.excluded},
                             {"predicted_rms_heating", o.predicted_heat_dps}, {"predicted_rms_cooling", o.predicted_cool_dps},
                             {"simulated_rms_heating", o.simulated_heat_dps}, {"simulated_rms_cooling", o.simulated_cool_dps},
                             {"predicted_rms", o.predicted_dps()}, {"simulated_rms", o.simulated_dps()},
                             {"simulated_rms_rel_se", std::isfinite(o.simulated_rel_se()) ? nlohmann::json(o.simulated_rel_se())
                                                                                          : nlohmann::json(nullptr)}});
  }
  j["recommended"] = pick->profile;
  j["seeds"] = plan->seeds;
  if (print && a.verbose) {
    std::cout << "recommended: " << pick->profile << " (" << pick->hours << " h): predicted next-run drift error RMS "
              << pick->predicted_dps() << " deg/s (simulated " << pick->simulated_dps()
              << "); the lowest of max(predicted, simulated), the shortest within 10% of it\n";
  } else if (print) {
    std::cout << "recommended: " << pick->profile << " (" << Figure(pick->hours) << " h), " << RateDps(pick->score_dps())
              << " expected on the next run (the lowest of max(predicted, simulated); the shortest within 10%)\n";
  }
  if (!a.json_path.empty())
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kPlanName, s.error());
  return kExitOk;
}

Command MakePlan(CLI::App& app) {
  auto a = std::make_shared<PlanArgs>();
  SimulatorOptions& o = a->options.unit;
  CLI::App* sub = app.add_subcommand(
      kPlanName, "Compare chamber profiles for a unit by the predicted drift error on the next run per chamber hour");
  sub->footer(
      "For each profile (and --seeds noise seeds): simulate the calibration run with the unit's noise and drift\n"
      "family, fit the default model, and on a heating ramp and the paper's cooling staircase (other seeds)\n"
      "compare the band's predicted RMS error with the simulated one against the true drift; the simulated\n"
      "figure's own standard error over the seeds is printed (one run's error is mostly the calibration\n"
      "run's slow noise on the drift's constant: up to a third for 3 seeds; 20-30 seeds for 10%).\n"
      "Recommends the lowest of max(predicted, simulated) (the shortest profile within 10% of it).\n"
      "JSON: profiles[] (profile, hours, models, left_out, predicted_rms_heating/_cooling, simulated_rms_...),\n"
      "  simulated_rms_rel_se (null with one seed), recommended, seeds.\n"
      "The unit: datasheet noise flags or --noise-from (an Allan run), the drift family's flags or --pilot (a\n"
      "chamber run, which also gives the noise and the range unless given otherwise). JSON unit{noise, drift}.\n"
      "Example: gyrocomp plan --arw 0.3 --bias-instability 10 --thermal-lag 900 --dtemp-coeff 2\n"
      "         gyrocomp plan --pilot pilot_run.csv --noise-from static_4h.csv");
  sub->add_option("--profiles", a->profiles, "Profiles to compare (paper, heat-cool, stairs, rate-cycles, cycle, ramp, soak)")->capture_default_str();
  sub->add_option("--seeds", a->options.seeds, "Noise seeds per profile")
      ->check(IntegerRange(1, 50, "plan: noise seeds per profile"))->capture_default_str();
  sub->add_option("--fs", a->options.fs_hz, "Sample rate of the simulated runs, Hz")->check(CLI::PositiveNumber)->capture_default_str();
  AddOutputOption(sub, "--json", &a->json_path, "Write the comparison as JSON ('-' = stdout)");
  sub->add_flag("-v,--verbose", a->verbose,
                "The full table: models fitted, terms left out, predicted and simulated RMS per direction, their SE");
  std::vector<CLI::Option*> unit;  // the unit's flags: each overrides --pilot / --noise-from
  unit.push_back(sub->add_option("--arw", o.noise.arw_deg_per_sqrt_h, "Angle random walk, deg/sqrt(h)")->capture_default_str());
  unit.push_back(sub->add_option("--bias-instability", o.noise.bias_instability_deg_per_h, "Bias instability, deg/h")->capture_default_str());
  unit.push_back(sub->add_option("--rrw", o.noise.rrw_deg_per_h_per_sqrt_h, "Rate random walk, deg/h/sqrt(h)")->capture_default_str());
  unit.push_back(sub->add_option("--drift-poly", a->drift_poly, "Drift family: bias(T) coefficients (as simulate)"));
  unit.push_back(sub->add_option("--dtemp-coeff", o.bias.dtemp_coeff_dps_per_c_per_s, "Drift per dT/dt, deg/s per (C/s)")->capture_default_str());
  unit.push_back(sub->add_option("--hysteresis-width", o.bias.hysteresis_width_c, "Hysteresis width, deg C")->capture_default_str());
  unit.push_back(sub->add_option("--hysteresis-coeff", o.bias.hysteresis_coeff_dps_per_c, "Hysteresis gain, deg/s per C")->capture_default_str());
  sub->add_option("--thermal-lag", o.thermal_lag_s, "Sensor thermal time constant, s")->capture_default_str();
  unit.push_back(sub->add_option("--hot", o.profile.hot_temp_c, "Hot extreme, deg C")->capture_default_str());
  unit.push_back(sub->add_option("--cold", o.profile.cold_temp_c, "Cold extreme, deg C")->capture_default_str());
  sub->add_option("--cycles", o.profile.num_cycles, "cycle: number of cycles")
      ->check(IntegerRange(1, 1000, "ThermalProfileOptions::num_cycles"))->capture_default_str();
  AddInputOption(sub, "--pilot", &a->pilot_path,
                 "A pilot chamber run (CSV, ULog, DataFlash, as fit -i): the drift family from the structured model "
                 "auto fits on it, the noise from its residual and the range from its temperatures, unless given "
                 "otherwise");
  sub->add_option("--pilot-col", a->pilot_col, "--pilot: its rate column")->capture_default_str();
  sub->add_option("--pilot-temp-col", a->pilot_temp_col, "--pilot: its temperature column")->capture_default_str();
  sub->add_option("--pilot-time-col", a->pilot_time_col, "--pilot: its time column, s ('none': i / --pilot-fs)")
      ->capture_default_str();
  sub->add_option("--pilot-fs", a->pilot_fs_hz, "--pilot: its sample rate, Hz, when it has no time column")
      ->check(CLI::PositiveNumber);
  AddInputOption(sub, "--noise-from", &a->noise_path,
                 "An Allan run (a static recording, as allan -i): ARW sigma(1 s), B = ADEV min / 0.664, RRW from "
                 "the +1/2 region");
  sub->add_option("--noise-col", a->noise_col, "--noise-from: its rate column")->capture_default_str();
  sub->add_option("--noise-time-col", a->noise_time_col, "--noise-from: its time column, s ('none': i / --noise-fs)")
      ->capture_default_str();
  sub->add_option("--noise-fs", a->noise_fs_hz, "--noise-from: its sample rate, Hz, when it has no time column")
      ->check(CLI::PositiveNumber);
  return {sub, [a, unit] {
            PlanStated& stated = a->options.stated;
            for (CLI::Option* x : unit) {
              if (x->count() == 0) continue;
              const std::string name = x->get_name();
              for (auto [flag, field] : {std::pair<const char*, bool*>{"--arw", &stated.arw},
                                         {"--bias-instability", &stated.bias_instability}, {"--rrw", &stated.rrw},
                                         {"--drift-poly", &stated.drift_poly}, {"--dtemp-coeff", &stated.dtemp_coeff},
                                         {"--hysteresis-width", &stated.hysteresis_width},
                                         {"--hysteresis-coeff", &stated.hysteresis_coeff}, {"--hot", &stated.hot},
                                         {"--cold", &stated.cold}})
                if (name == flag) *field = true;
            }
            return RunPlan(*a);
          }};
}

const CommandRegistrar kPlanRegistrar(kPlanName, 68, &MakePlan);

}  // namespace
}  // namespace gyrocomp::cli
