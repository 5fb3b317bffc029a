// gyrocomp simulate: the thermal-chamber experiment with ground truth (docs/explanation/simulator.md).
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "commands.h"
#include "gyrocomp/core/units.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/io/ulog.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kSimulateName = "simulate";

struct SimulateArgs {
  SimulatorOptions sim;  // library defaults
  std::string profile = "paper";
  std::string drift_poly;  // comma-separated, overrides the default polynomial when given
  std::string profile_csv;  // --profile-csv: the user's chamber schedule (profile user)
  std::optional<double> duration_s;
  std::string output;
  std::string json_path;
  int imus = 1;                       // .ulg / .bin: IMUs on the board
  std::optional<double> log_rate_hz;  // .ulg / .bin: rows per second (default: --fs)
  int ahrs_orientation = 0;           // .bin: board rotation logged (AHRS_ORIENTATION)
};

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// A whole board as a PX4 ULog (.ulg) or ArduPilot DataFlash (.bin) log: --imus IMUs, each gyro
// x, y, z and accel x, y, z (SimulateBoard: IMU 0's gyro x is the CSV run of the same options and
// seed, y and z seeds + 1 and + 2; accelerometers with gravity on z), and a barometer in the ULog;
// realistic PX4 device ids; no ground truth (write a CSV for that).
Status WriteBoardLog(const std::string& path, const SimulateArgs& a, bool ulog) {
  BoardSimOptions b;
  b.chamber = a.sim;
  b.num_imus = a.imus;
  auto board = SimulateBoard(b);
  if (!board.ok()) return board.error();
  Result<std::string> bytes = ulog ? EncodeBoardULog(*board, a.log_rate_hz.value_or(board->fs_hz))
                                   : EncodeBoardDataFlash(*board, a.log_rate_hz.value_or(board->fs_hz), a.ahrs_orientation);
  if (!bytes.ok()) return bytes.error();
  return WriteText(path, *bytes);
}

// --profile-csv FILE: a CSV with a header and the columns time_s and chamber_temp_c (or temp_c),
// one row per breakpoint of the chamber schedule. Errors name the file and the row.
Status ReadUserProfile(const std::string& path, ThermalProfileOptions* p) {
  Result<Table> t = ReadCsv(path);
  if (!t.ok()) return t.error();
  const int time = t->Find("time_s");
  int temp = t->Find("chamber_temp_c");
  if (temp < 0) temp = t->Find("temp_c");
  if (time < 0 || temp < 0)
    return InvalidInput(path + ":1: --profile-csv needs the columns time_s and chamber_temp_c (or temp_c)");
  const std::vector<double>& ts = t->columns[time];
  const std::vector<double>& cs = t->columns[temp];
  if (ts.size() < 2) return InvalidInput(path + ": --profile-csv needs at least 2 rows, got " + std::to_string(ts.size()));
  for (std::size_t i = 0; i < ts.size(); ++i) {
    if (ts[i] < 0.0 || (i > 0 && !(ts[i] > ts[i - 1])))
      return InvalidInput(path + ":" + std::to_string(i + 2) + ": time_s " + std::to_string(ts[i]) +
                          " must be >= 0 and greater than the previous row's");
    if (cs[i] < -273.15 || cs[i] > 1000.0)
      return InvalidInput(path + ":" + std::to_string(i + 2) + ": chamber temperature " + std::to_string(cs[i]) +
                          " C is outside [-273.15, 1000]");
  }
  p->user_time_s = ts;
  p->user_temp_c = cs;
  return Status::Ok();
}

int Run(SimulateArgs& a) {
  if (!a.profile_csv.empty()) {
    if (a.profile != "paper" && a.profile != "user")
      return ReportError(kSimulateName, InvalidArgument("--profile-csv: the profile is the file's (got --profile " + a.profile + ")"));
    a.profile = "user";
    if (Status s = ReadUserProfile(a.profile_csv, &a.sim.profile); !s.ok()) return ReportError(kSimulateName, s.error());
  } else if (a.profile == "user") {
    return ReportError(kSimulateName, InvalidArgument("--profile user: give the schedule with --profile-csv FILE"));
  }
  const auto kind = ParseThermalProfileKind(a.profile);
  if (!kind)
    return ReportError(kSimulateName, InvalidArgument("--profile " + a.profile + ": must be paper, soak, ramp, cycle, heat-cool, stairs, rate-cycles or user"));
  a.sim.profile.kind = *kind;
  a.sim.duration_s = a.duration_s;
  if (!a.drift_poly.empty()) {
    a.sim.bias.poly_dps.clear();
    for (const std::string& item : SplitList(a.drift_poly)) {
      char* end = nullptr;
      const double v = std::strtod(item.c_str(), &end);
      if (end == item.c_str() || *end != '\0') {
        return ReportError(kSimulateName, InvalidArgument("--drift-poly: '" + item + "' is not a number"));
      }
      a.sim.bias.poly_dps.push_back(v);
    }
  }
  Result<SimulatedRun> run = Simulate(a.sim);
  if (!run.ok()) return ReportError(kSimulateName, run.error());
  const SimulationSummary sum = run->summary;
  const double fs_hz = run->fs_hz;
  const bool ulog = EndsWith(a.output, ".ulg"), dataflash = EndsWith(a.output, ".bin");
  if (ulog || dataflash) {
    *run = SimulatedRun{};  // the board simulates its own axes
    if (Status s = WriteBoardLog(a.output, a, ulog); !s.ok()) return ReportError(kSimulateName, s.error());
  } else if (Status s = WriteCsv(a.output, std::move(*run).ToTable()); !s.ok()) {
    return ReportError(kSimulateName, s.error());
  }
  if (!a.json_path.empty()) {
    nlohmann::json j;
    j["output"] = a.output;
    j["output_format"] = ulog ? "ulog" : dataflash ? "dataflash" : "csv";
    if (ulog || dataflash) j["imus"] = a.imus;
    j["profile"] = ThermalProfileKindName(a.sim.profile.kind);
    j["fs_hz"] = fs_hz;
    j["seed"] = a.sim.seed;
    j["n_samples"] = sum.num_samples;
    j["duration_s"] = sum.duration_s;
    j["sensor_temp_range_c"] = {sum.min_temp_c, sum.max_temp_c};
    j["true_drift_range_dps"] = {sum.min_drift_dps, sum.max_drift_dps};
    j["arw_deg_per_sqrt_h"] = a.sim.noise.arw_deg_per_sqrt_h;
    j["bias_instability_deg_per_h"] = a.sim.noise.bias_instability_deg_per_h;
    j["rrw_deg_per_h_per_sqrt_h"] = a.sim.noise.rrw_deg_per_h_per_sqrt_h;
    j["flicker_processes"] = sum.num_flicker_processes;
    j["flicker_process_sigma_dps"] = sum.flicker_process_sigma_dps;
    j["seconds"] = sum.seconds;
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kSimulateName, s.error());
  }
  Note(kSimulateName, sum.BriefReport() + " -> " + a.output);
  return kExitOk;
}

Command MakeSimulate(CLI::App& app) {
  auto a = std::make_shared<SimulateArgs>();
  SimulatorOptions& o = a->sim;
  CLI::App* sub = app.add_subcommand(
      kSimulateName, "Simulate a MEMS gyro in a temperature chamber, with ground truth (default: the paper's run, "
             "Section 4.1)");
  sub->footer(
      "Output columns: time_s, rate_dps, temp_c, chamber_temp_c, sensor_temp_c, true_rate_dps,\n"
      "true_drift_dps, true_noise_dps (rate = true_rate + true_drift + true_noise).\n"
      "Profiles: paper = 1 h at room temperature, ramp to 60 C, 1 h, then 10 C steps down to -40 C,\n"
      "each held 1 h (14.25 h at 1 C/min); soak; ramp (room -> --ramp-end); cycle (room -> hot ->\n"
      "cold -> room, --cycles times: heating and cooling, for hysteresis); heat-cool (--room-hold at\n"
      "--cold, heat to --hot, --hold, cool to --cold, --hold: both directions over the whole range,\n"
      "6.3 h at 1 C/min); stairs (--room-hold at --cold, up in 2 x --step steps at --ramp-rate, down\n"
      "in steps between those at half the rate, every plateau held --hold / 2: 11.5 h); rate-cycles\n"
      "(--room-hold / 2 at --cold, 4 x (heat to --hot, --hold / 3, cool to --cold, --hold / 3), heating\n"
      "at 2, 1, 2, 1 x --ramp-rate and cooling at 1, 2, 1, 2 x: 13.2 h); user\n"
      "(--profile-csv FILE: columns time_s and chamber_temp_c or temp_c, one row per breakpoint,\n"
      "linear in between).\n"
      "Noise in datasheet units (IEEE 952); bias instability = flicker floor / 0.664, made of a sum of\n"
      "Gauss-Markov processes (docs/explanation/simulator.md). Same options and --seed: identical output.\n"
      "-o run.ulg writes a PX4 ULog instead: a board of --imus IMUs as sensor_gyro (rad/s) and sensor_accel\n"
      "(m/s^2, gravity on z) multi_id 0.., float32, realistic PX4 device ids, and sensor_baro (Pa);\n"
      "IMU 0's gyro x is the run, y and z --seed + 1 and + 2. -o run.bin writes an ArduPilot DataFlash\n"
      "log (IMU rows with I and T, rotated by --ahrs-orientation, PARM rows). No ground truth in either.\n"
      "Example: gyrocomp simulate --fs 100 --seed 7 -o run.csv.gz");
  AddOutputOption(sub, "-o,--output", &a->output, "Output CSV (.gz: gzip), PX4 ULog (.ulg) or ArduPilot DataFlash (.bin)")->required();
  sub->add_option("--imus", a->imus, ".ulg / .bin: IMUs on the simulated board (1..4; DataFlash 1..3)")
      ->check(CLI::Range(1, 4))->capture_default_str();
  sub->add_option("--log-rate", a->log_rate_hz, ".ulg / .bin: logged rows per second (default: --fs)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--ahrs-orientation", a->ahrs_orientation, ".bin: board rotation AHRS_ORIENTATION (0..43) applied to the logged IMU rows")
      ->check(CLI::Range(0, 43))->capture_default_str();
  AddOutputOption(sub, "--json", &a->json_path, "Write a summary of the run as JSON ('-' = stdout)");
  sub->add_option("--profile", a->profile, "paper | soak | ramp | cycle | heat-cool | stairs | rate-cycles | user")->capture_default_str();
  AddInputOption(sub, "--profile-csv", &a->profile_csv,
                 "Chamber schedule CSV (time_s, chamber_temp_c or temp_c): profile user");
  sub->add_option("--fs", o.fs_hz, "Sample rate, Hz")->check(CLI::PositiveNumber)->capture_default_str();
  sub->add_option("--seed", o.seed, "Random seed")->capture_default_str();
  sub->add_option("--duration", a->duration_s, "Record length, s (default: the profile's; longer holds the end)")
      ->check(CLI::PositiveNumber);
  // Thermal profile.
  ThermalProfileOptions& p = o.profile;
  sub->add_option("--room-temp", p.room_temp_c, "Room (start) temperature, deg C")->capture_default_str();
  sub->add_option("--room-hold", p.room_hold_s, "Hold at room temperature first, s")->capture_default_str();
  sub->add_option("--hot", p.hot_temp_c, "Hot extreme, deg C")->capture_default_str();
  sub->add_option("--cold", p.cold_temp_c, "Cold extreme, deg C")->capture_default_str();
  sub->add_option("--step", p.step_c, "Staircase step of the paper profile, deg C")->capture_default_str();
  sub->add_option("--hold", p.hold_s, "Hold at each plateau, s")->capture_default_str();
  sub->add_option("--ramp-rate", p.ramp_rate_c_per_min, "Chamber slew rate, deg C per minute")->capture_default_str();
  sub->add_option("--soak-temp", p.soak_temp_c, "soak: temperature, deg C")->capture_default_str();
  sub->add_option("--soak-duration", p.soak_duration_s, "soak: duration, s")->capture_default_str();
  sub->add_option("--ramp-end", p.ramp_end_c, "ramp: end temperature, deg C")->capture_default_str();
  sub->add_option("--cycles", p.num_cycles, "cycle: number of hot-cold-room cycles")
      ->check(IntegerRange(1, 1000, "ThermalProfileOptions::num_cycles"))->capture_default_str();
  sub->add_option("--thermal-lag", o.thermal_lag_s, "Sensor thermal time constant behind the chamber, s")
      ->capture_default_str();
  sub->add_option("--temp-noise", o.temp_noise_c, "Temperature reading noise (1 sigma), deg C")->capture_default_str();
  // Drift.
  sub->add_option("--drift-poly", a->drift_poly,
                  "bias(T) coefficients c0,c1,... in deg/s per C^k of (T - --drift-ref) (default 0.02,1.5e-3,1.2e-5,-2e-7)");
  sub->add_option("--drift-ref", o.bias.reference_temp_c, "Reference temperature of the polynomial, deg C")
      ->capture_default_str();
  sub->add_option("--dtemp-coeff", o.bias.dtemp_coeff_dps_per_c_per_s, "Drift per temperature rate, deg/s per (C/s)")
      ->capture_default_str();
  sub->add_option("--hysteresis-width", o.bias.hysteresis_width_c, "Hysteresis (play) width, deg C")
      ->capture_default_str();
  sub->add_option("--hysteresis-coeff", o.bias.hysteresis_coeff_dps_per_c, "Hysteresis gain, deg/s per deg C")
      ->capture_default_str();
  // Noise.
  NoiseOptions& n = o.noise;
  sub->add_option("--arw", n.arw_deg_per_sqrt_h, "Angle random walk, deg/sqrt(h)")->capture_default_str();
  sub->add_option("--bias-instability", n.bias_instability_deg_per_h, "Bias instability B, deg/h (floor 0.664 B)")
      ->capture_default_str();
  sub->add_option("--rrw", n.rrw_deg_per_h_per_sqrt_h, "Rate random walk, deg/h/sqrt(h)")->capture_default_str();
  sub->add_option("--quantization", n.quantization_deg, "Angle quantization Q, deg (0 = off)")->capture_default_str();
  sub->add_option("--resolution", n.resolution_dps, "Output LSB, deg/s (0 = off)")->capture_default_str();
  // True rate.
  TrueRateOptions& t = o.true_rate;
  sub->add_option("--true-rate", t.constant_dps, "Constant true rate, deg/s (e.g. Earth rate)")->capture_default_str();
  sub->add_option("--step-amplitude", t.step_amplitude_dps, "Rate steps 0,+A,0,-A,..., deg/s (0 = off)")
      ->capture_default_str();
  sub->add_option("--step-period", t.step_period_s, "Duration of each rate step, s")->capture_default_str();
  sub->add_option("--sine-amplitude", t.sine_amplitude_dps, "Sinusoidal rate amplitude, deg/s (0 = off)")
      ->capture_default_str();
  sub->add_option("--sine-frequency", t.sine_frequency_hz, "Sinusoidal rate frequency, Hz")->capture_default_str();
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kSimulateRegistrar(kSimulateName, 20, &MakeSimulate);

}  // namespace
}  // namespace gyrocomp::cli
