// gyrocomp allan: overlapping Allan deviation and noise terms of one or more rate columns.
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "gyrocomp/allan/allan.h"
#include "gyrocomp/allan/deviations.h"
#include "gyrocomp/allan/kalibr.h"
#include "gyrocomp/allan/vio_noise.h"
#include "gyrocomp/core/format.h"
#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/io/log_damage.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kAllanName = "allan";

struct AllanArgs {
  LogOptions log;
  std::string taus = "octave";
  std::string json_path;
  std::string csv_path;
  std::string deviation = "adev";
  std::string kalibr_yaml_path;
  std::string openvins_yaml_path;  // OpenVINS kalibr_imu_chain.yaml
  std::string vins_yaml_path;      // VINS-Fusion acc_n / gyr_n / acc_w / gyr_w
  std::string rostopic = KalibrYamlOptions{}.rostopic;
  bool rostopic_given = false;
  std::string accel_cols;  // comma-separated, m/s^2 (only for --kalibr-yaml)
  AllanOptions allan;  // library defaults
};

// Everything `allan` computed, per axis.
struct AllanOutputs {
  std::vector<AllanResult> results;
  std::vector<DeviationCurve> deviations;  // one per axis when --deviation is not adev
  std::vector<AllanResult> accel;          // --accel-col axes (a ROS bag: x_m_s2, y_m_s2, z_m_s2)
};

// The accelerometer columns: --accel-col, or a ROS bag's linear_acceleration columns (all six
// axes of a bag are analysed at once).
std::string AccelColumns(const AllanArgs& a, const LoadedLog& loaded) {
  if (!a.accel_cols.empty()) return a.accel_cols;
  if (DetectLogFormat(a.log.input) != LogFormat::kRosBag || loaded.table.Find(kBagAccelCols[0]) < 0) return "";
  return std::string(kBagAccelCols[0]) + "," + kBagAccelCols[1] + "," + kBagAccelCols[2];
}

// The curve as CSV: tau_s, m, then per axis adev, error, interval, EDF, n (column names carry the
// axis when there are several).
Table CurveTable(const std::vector<AllanResult>& results) {
  Table t;
  const AllanCurve& first = results.front().curve;
  t.names = {"tau_s", "m"};
  t.columns.push_back(first.tau_s);
  t.columns.emplace_back(first.m.begin(), first.m.end());
  for (const AllanResult& r : results) {
    const std::string p = results.size() == 1 ? "" : r.axis + "_";
    const AllanCurve& c = r.curve;
    t.names.push_back(p + "adev_dps");
    t.columns.push_back(c.adev_dps);
    t.names.push_back(p + "adev_error_dps");
    t.columns.push_back(c.adev_error_dps);
    t.names.push_back(p + "adev_lo_dps");
    t.columns.push_back(c.adev_lo_dps);
    t.names.push_back(p + "adev_hi_dps");
    t.columns.push_back(c.adev_hi_dps);
    t.names.push_back(p + "edf");
    t.columns.push_back(c.edf);
    t.names.push_back(p + "n_clusters");
    t.columns.emplace_back(c.n_clusters.begin(), c.n_clusters.end());
  }
  return t;
}

// The chosen deviation's curve as CSV: tau_s, m, then per axis <kind>_dps, error, interval, EDF, n.
Table DeviationTable(const std::vector<AllanResult>& results, const std::vector<DeviationCurve>& devs) {
  Table t;
  const DeviationCurve& first = devs.front();
  const std::string kind = DeviationKindName(first.kind);
  t.names = {"tau_s", "m"};
  t.columns.push_back(first.tau_s);
  t.columns.emplace_back(first.m.begin(), first.m.end());
  for (std::size_t a = 0; a < devs.size(); ++a) {
    const std::string p = (devs.size() == 1 ? "" : results[a].axis + "_") + kind;
    const DeviationCurve& d = devs[a];
    for (auto [suffix, column] : {std::pair{"_dps", &d.dev_dps}, std::pair{"_error_dps", &d.error_dps},
                                  std::pair{"_lo_dps", &d.lo_dps}, std::pair{"_hi_dps", &d.hi_dps},
                                  std::pair{"_edf", &d.edf}}) {
      t.names.push_back(p + suffix);
      t.columns.push_back(*column);
    }
    t.names.push_back(p + "_n");
    t.columns.emplace_back(d.n.begin(), d.n.end());
  }
  return t;
}

// The chosen deviation in an axis's JSON: <kind>_tau_s, <kind>_dps, its error and interval arrays.
void AddDeviationJson(const DeviationCurve& d, nlohmann::json* j) {
  const std::string k = DeviationKindName(d.kind);
  (*j)["deviation"] = k;
  (*j)[k + "_tau_s"] = d.tau_s;
  (*j)[k + "_dps"] = d.dev_dps;
  (*j)[k + "_error_dps"] = d.error_dps;
  (*j)[k + "_lo_dps"] = d.lo_dps;
  (*j)[k + "_hi_dps"] = d.hi_dps;
  (*j)[k + "_edf"] = d.edf;
  (*j)[k + "_n"] = d.n;
  (*j)[k + "_method"] = d.method;
  (*j)[k + "_edf_method"] = d.edf_method;
  (*j)[k + "_seconds"] = d.seconds;
}

// Allan analyses of the rate columns, the chosen deviation and the accelerometer columns.
Result<AllanOutputs> Analyse(const AllanArgs& a, const AllanOptions& options, DeviationKind kind,
                             const LoadedLog& loaded) {
  AllanOutputs out;
  const GyroLog& log = loaded.log;
  if (log.rate_dps.empty()) return InvalidInput(log.source + ": no rate column to analyse");
  std::optional<GyroLog> accel_log;
  const std::string accel_cols = AccelColumns(a, loaded);
  if (!accel_cols.empty()) {
    // Accelerometer columns (m/s^2), read as they are: the Allan arithmetic does not depend on the unit.
    Result<LogSpec> spec = ToLogSpec(a.log);
    if (!spec.ok()) return spec.error();
    spec->rate_cols = SplitList(accel_cols);
    spec->rate_unit = RateUnit::kDegPerSec;
    spec->resample_hz.reset();
    spec->min_samples = 3;
    Result<GyroLog> loaded_accel = LoadGyroLog(loaded.table, *spec);
    if (!loaded_accel.ok()) return loaded_accel.error();
    accel_log = std::move(*loaded_accel);
  }
  // Gyro and accelerometer axes in one parallel batch (an IMU's six axes on both cores).
  std::vector<AllanAxisInput> axes;
  const GyroLog* accel = accel_log ? &*accel_log : nullptr;
  for (const GyroLog* l : {&log, accel}) {
    for (std::size_t i = 0; l != nullptr && i < l->rate_dps.size(); ++i) {
      axes.push_back({i < l->axis_names.size() ? l->axis_names[i] : std::to_string(i), l->rate_dps[i], l->fs_hz});
    }
  }
  Result<std::vector<AllanResult>> results = ComputeAllan(axes, log.source, options);
  if (!results.ok()) return results.error();
  out.results.assign(std::make_move_iterator(results->begin()),
                     std::make_move_iterator(results->begin() + static_cast<std::ptrdiff_t>(log.rate_dps.size())));
  out.accel.assign(std::make_move_iterator(results->begin() + static_cast<std::ptrdiff_t>(log.rate_dps.size())),
                   std::make_move_iterator(results->end()));
  if (kind != DeviationKind::kAdev) {
    for (std::size_t i = 0; i < log.rate_dps.size(); ++i) {
      Result<DeviationCurve> d = ComputeDeviation(log.rate_dps[i], log.fs_hz, kind, options);
      if (!d.ok()) {
        Error e = d.error();
        e.message = log.source + ": column '" + out.results[i].axis + "': " + e.message;
        return e;
      }
      out.deviations.push_back(std::move(*d));
    }
  }
  return out;
}

struct SensorNoise {
  std::vector<KalibrAxisNoise> gyro, accel;
};

// Kalibr's continuous-time figures of every axis (docs/guides/imu-noise.md).
Result<SensorNoise> NoiseFigures(const AllanArgs& a, const AllanOutputs& out, const GyroLog& log) {
  SensorNoise n;
  std::vector<KalibrAxisNoise>& gyro = n.gyro;
  std::vector<KalibrAxisNoise>& accel = n.accel;
  for (const AllanResult& r : out.results) {
    Result<KalibrAxisNoise> k = KalibrNoiseFromAllan(r, KalibrSensor::kGyroscope, a.allan.min_edf_for_terms);
    if (!k.ok()) return Error{k.error().kind, log.source + ": " + k.error().message};
    gyro.push_back(*k);
  }
  for (const AllanResult& r : out.accel) {
    Result<KalibrAxisNoise> k = KalibrNoiseFromAllan(r, KalibrSensor::kAccelerometer, a.allan.min_edf_for_terms);
    if (!k.ok()) return Error{k.error().kind, log.source + ": " + k.error().message};
    accel.push_back(*k);
  }
  return n;
}

// The accelerometer axes in the JSON, in their own unit (the AllanResult fields say dps because
// the arithmetic is shared; here they are named for what they hold).
nlohmann::json AccelJson(const AllanResult& r, const KalibrAxisNoise* k) {
  nlohmann::json j;
  j["tau_s"] = r.curve.tau_s;
  j["adev_m_s2"] = r.curve.adev_dps;
  j["adev_lo_m_s2"] = r.curve.adev_lo_dps;
  j["adev_hi_m_s2"] = r.curve.adev_hi_dps;
  j["n_samples"] = r.n_samples;
  if (k) {
    j["noise_density_m_s2_per_sqrt_hz"] = k->noise_density;
    j["random_walk_m_s3_per_sqrt_hz"] = k->random_walk;
    j["random_walk_is_upper_bound"] = k->random_walk_is_upper_bound;
  }
  return j;
}

// The robotics noise files asked for: Kalibr imu.yaml, OpenVINS kalibr_imu_chain.yaml,
// VINS-Fusion's four keys, as (path, text).
Result<std::vector<std::pair<std::string, std::string>>> NoiseFiles(const AllanArgs& a, const SensorNoise& n,
                                                                    const GyroLog& log) {
  std::vector<std::pair<std::string, std::string>> files;
  std::string topic = a.rostopic;
  if (!a.rostopic_given && a.log.topic) topic = *a.log.topic;
  if (!a.kalibr_yaml_path.empty()) {
    KalibrYamlOptions yo;
    yo.rostopic = topic;
    yo.source = log.source;
    files.emplace_back(a.kalibr_yaml_path, KalibrImuYaml(n.gyro, n.accel, log.fs_hz, yo));
  }
  VioNoiseFileOptions vo;
  vo.rostopic = topic;
  vo.source = log.source;
  for (const auto& [path, name] : {std::pair{&a.openvins_yaml_path, "--openvins-yaml"}, std::pair{&a.vins_yaml_path, "--vins-yaml"}}) {
    if (path->empty()) continue;
    if (n.accel.empty()) {
      return InvalidArgument(std::string(name) + ": needs accelerometer axes (a ROS bag's, or --accel-col)");
    }
    files.emplace_back(*path, path == &a.openvins_yaml_path ? OpenVinsImuChainYaml(n.gyro, n.accel, log.fs_hz, vo)
                                                           : VinsFusionImuYaml(n.gyro, n.accel, log.fs_hz, vo));
  }
  return files;
}

// AllanNoiseTerms::unsupported on a result's JSON: each figure the curve cannot carry (and the tau
// that goes with it) becomes null, with "<key>_reason" (the reason key), "<key>_why" (what is
// missing) and, when a longer record would carry it, "<key>_needs_record_s".
void ApplySupport(const AllanResult& r, nlohmann::json* j) {
  static const std::map<std::string, std::vector<std::string>> companions = {
      {"adev_min_deg_per_h", {"tau_at_min_s"}},
      {"adev_min_usable_deg_per_h", {"tau_at_min_usable_s"}},
      {"rrw_deg_per_h_per_sqrt_h", {}}};
  for (const auto& [key, u] : r.terms.unsupported) {
    (*j)[key] = nullptr;
    (*j)[key + "_reason"] = u.reason;
    (*j)[key + "_why"] = u.text;
    if (u.needs_record_s) (*j)[key + "_needs_record_s"] = *u.needs_record_s;
    if (const auto it = companions.find(key); it != companions.end()) {
      for (const std::string& c : it->second) (*j)[c] = nullptr;
    }
  }
}

int Run(const AllanArgs& a) {
  int ppd = a.allan.points_per_decade;
  const std::optional<TauGrid> grid = ParseTauGrid(a.taus, &ppd);
  if (!grid) {
    return ReportError(kAllanName, InvalidArgument("--taus " + a.taus +
                                              ": must be octave, decade, all or a number of taus per decade (1-1000)"));
  }
  AllanOptions options = a.allan;
  options.grid = *grid;
  options.points_per_decade = ppd;
  std::string why;
  if (!options.IsValid(&why)) return ReportError(kAllanName, InvalidArgument(why));

  const std::optional<DeviationKind> kind = ParseDeviationKind(a.deviation);
  if (!kind) {
    return ReportError(kAllanName, InvalidArgument("--deviation " + a.deviation + ": must be adev, mdev, hdev, ohdev or totdev"));
  }
  const bool noise_file = !a.kalibr_yaml_path.empty() || !a.openvins_yaml_path.empty() || !a.vins_yaml_path.empty();
  if (!a.accel_cols.empty() && !noise_file) {
    return ReportError(kAllanName, InvalidArgument("--accel-col: only used with --kalibr-yaml, --openvins-yaml or --vins-yaml"));
  }

  Result<LogSpec> spec = ToLogSpec(a.log);
  if (!spec.ok()) return ReportError(kAllanName, spec.error());
  spec->min_samples = 3;  // one tau needs 3 samples
  // Without --accel-col a CSV's other columns are not used (memory); with it, the
  // accelerometer log is loaded from the whole table.
  if (a.accel_cols.empty()) spec->keep_cols.emplace();
  Result<LoadedLog> loaded = LoadLog(kAllanName, a.log, *spec);
  if (!loaded.ok()) return ReportError(kAllanName, loaded.error());
  const GyroLog& log = loaded->log;
  Result<AllanOutputs> out = Analyse(a, options, *kind, *loaded);
  if (!out.ok()) return ReportError(kAllanName, out.error());
  const std::vector<AllanResult>& results = out->results;

  nlohmann::json j;
  if (results.size() == 1) {
    j = AllanJson(results.front());
    ApplySupport(results.front(), &j);
    if (!out->deviations.empty()) AddDeviationJson(out->deviations.front(), &j);
  } else {
    j["fs_hz"] = log.fs_hz;
    j["n_samples"] = log.num_samples();
    j["axes"] = nlohmann::json::object();
    for (std::size_t i = 0; i < results.size(); ++i) {
      j["axes"][results[i].axis] = AllanJson(results[i]);
      ApplySupport(results[i], &j["axes"][results[i].axis]);
      if (!out->deviations.empty()) AddDeviationJson(out->deviations[i], &j["axes"][results[i].axis]);
    }
  }
  j["input"] = log.source;
  // The ARW's bandwidth bound (every axis shares the log's rate; Analyse gives at least one).
  j["bandwidth_max_hz"] = results.front().BandwidthMaxHz();
  j["sampling"] = log.sampling.BriefReport();
  j["damage"] = DamageJson(loaded->damage);
  std::vector<std::pair<std::string, std::string>> files;
  if (noise_file || !out->accel.empty()) {
    Result<SensorNoise> noise = NoiseFigures(a, *out, log);
    // Without a noise file to write, a record too short for tau = 1 s still gets its curves.
    if (!noise.ok() && noise_file) return ReportError(kAllanName, noise.error());
    if (!out->accel.empty()) {
      j["accel_axes"] = nlohmann::json::object();
      for (std::size_t i = 0; i < out->accel.size(); ++i) {
        j["accel_axes"][out->accel[i].axis] = AccelJson(out->accel[i], noise.ok() ? &noise->accel[i] : nullptr);
      }
    }
    if (noise.ok() && !out->accel.empty()) {
      nlohmann::json gyro = nlohmann::json::object();
      for (const KalibrAxisNoise& k : noise->gyro) {
        gyro[k.axis] = {{"noise_density_rad_s_per_sqrt_hz", k.noise_density},
                        {"random_walk_rad_s2_per_sqrt_hz", k.random_walk},
                        {"random_walk_is_upper_bound", k.random_walk_is_upper_bound}};
      }
      j["gyro_noise"] = gyro;
    }
    if (!noise_file) noise = SensorNoise{};
    Result<std::vector<std::pair<std::string, std::string>>> f = NoiseFiles(a, *noise, log);
    if (!f.ok()) return ReportError(kAllanName, f.error());
    files = std::move(*f);
  }

  if (!a.csv_path.empty()) {
    const Table table = out->deviations.empty() ? CurveTable(results) : DeviationTable(results, out->deviations);
    if (Status s = WriteCsv(a.csv_path, table); !s.ok()) return ReportError(kAllanName, s.error());
  }
  for (const auto& [path, text] : files) {
    if (Status s = WriteText(path, text); !s.ok()) return ReportError(kAllanName, s.error());
  }
  if (!a.json_path.empty()) {
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kAllanName, s.error());
  }
  const bool stdout_taken = a.json_path == "-" || a.kalibr_yaml_path == "-" || a.openvins_yaml_path == "-" || a.vins_yaml_path == "-";
  if (!stdout_taken) {
    for (std::size_t i = 0; i < results.size(); ++i) {
      std::cout << results[i].BriefReport() << "\n";
      if (!out->deviations.empty()) {
        const DeviationCurve& d = out->deviations[i];
        std::cout << "  " << DeviationKindName(d.kind) << ": " << d.size() << " taus\n";
      }
    }
    // A named copy: items() of the temporary j.value() returns would outlive it (ASan:
    // stack-use-after-scope).
    const nlohmann::json accel_axes = j.value("accel_axes", nlohmann::json::object());
    for (const auto& [name, axis] : accel_axes.items()) {
      if (!axis.contains("noise_density_m_s2_per_sqrt_hz")) continue;
      std::cout << name << ": accelerometer noise density " << FormatNumber(axis["noise_density_m_s2_per_sqrt_hz"].get<double>())
                << " m/s^2/sqrt(Hz), random walk " << FormatNumber(axis["random_walk_m_s3_per_sqrt_hz"].get<double>())
                << " m/s^3/sqrt(Hz)" << (axis["random_walk_is_upper_bound"].get<bool>() ? " (upper bound)" : "") << "\n";
    }
  }
  return kExitOk;
}

Command MakeAllan(CLI::App& app) {
  auto args = std::make_shared<AllanArgs>();
  CLI::App* sub = app.add_subcommand(
      kAllanName,
      "Overlapping Allan deviation of the rate column(s), with chi-square confidence intervals and the "
      "noise terms of IEEE 952 (method.md section 6)");
  sub->footer(
      "Conventions:\n"
      "  ADEV: overlapping, phase from the mean-removed rate (as allantools oadev, data_type='freq').\n"
      "  --taus octave: m = 1, 2, 4, ... (allantools 'octave'); decade: 1, 2, 4, 10, 20, 40, ...;\n"
      "    all: every m (O(N^2), at most 100000 samples); N: N log-spaced taus per decade.\n"
      "    Taus with fewer than 2 terms are dropped.\n"
      "  arw_deg_per_sqrt_h: sigma(1 s) (log-log interpolated between grid points) x 60.\n"
      "    bandwidth_max_hz = fs/2: the most bandwidth the record carries (a low-pass upstream of\n"
      "    the file leaves less); compare an ARW only with one of the same bandwidth.\n"
      "  adev_min_deg_per_h: minimum of the whole curve (as allantools users and the paper read it);\n"
      "    bias instability = min / 0.664; adev_min_at_longest_tau: the minimum is the last tau (floor\n"
      "    not reached). adev_min_usable_deg_per_h: minimum over the taus with EDF >= --min-edf.\n"
      "  --deviation mdev|hdev|ohdev|totdev: also that curve, exactly as allantools computes it\n"
      "    (JSON <kind>_tau_s, <kind>_dps, <kind>_lo_dps, ...; -o writes that curve). Hadamard\n"
      "    (hdev, ohdev) is blind to a linear rate drift (a temperature ramp).\n"
      "  --kalibr-yaml imu.yaml: Kalibr's noise densities (rad/s/sqrt(Hz), rad/s^2/sqrt(Hz); docs/guides/imu-noise.md).\n"
      "  --openvins-yaml / --vins-yaml: the same figures for OpenVINS (continuous) and VINS-Fusion\n"
      "    (discrete per-sample, x sqrt(fs)); docs/guides/imu-noise.md cites each convention.\n"
      "  ROS bag input (-i imu.bag / .mcap / .db3 / folder, --topic /imu0): the gyro axes x_rad_s,\n"
      "    y_rad_s, z_rad_s and the accelerometer axes x_m_s2, y_m_s2, z_m_s2 at once (JSON accel_axes,\n"
      "    gyro_noise).\n"
      "  rrw_deg_per_h_per_sqrt_h: sigma(3 s) on the +1/2 line fitted after the minimum (null if none).\n"
      "  Error bars: adev/sqrt(n) (allantools) and a chi-square interval from the EDF of\n"
      "    NIST SP 1065 Table 5 (Howe, Allan & Barnes), noise type per tau by lag-1\n"
      "    autocorrelation (Riley & Greenhall 2004).\n"
      "Several axes: --rate-col gx_dps,gy_dps,gz_dps gives JSON {axes: {name: {...}}}.\n"
      "Example: gyrocomp allan -i log.csv.gz --rate-col gx_dps --time-col t_s --json - -o adev.csv\n"
      "         gyrocomp allan -i imu.bag --topic /imu0 --kalibr-yaml imu.yaml --json adev.json");
  AddLogOptions(sub, &args->log);
  sub->add_option("--taus", args->taus, "Tau grid: octave | decade | all | N (taus per decade)")->capture_default_str();
  AddOutputOption(sub, "--json", &args->json_path, "Write the results as JSON to FILE ('-' = stdout)");
  AddOutputOption(sub, "-o,--output", &args->csv_path,
                  "Write the ADEV curve (or the --deviation curve) as CSV to FILE");
  sub->add_option("--confidence", args->allan.confidence, "Two-sided confidence level of the chi-square interval")
      ->check(CLI::Range(1e-6, 1.0 - 1e-6))
      ->capture_default_str();
  sub->add_option("--deviation", args->deviation, "Also compute: adev | mdev | hdev | ohdev | totdev")
      ->capture_default_str();
  AddOutputOption(sub, "--kalibr-yaml", &args->kalibr_yaml_path, "Write Kalibr's IMU noise file (imu.yaml) to FILE");
  AddOutputOption(sub, "--openvins-yaml", &args->openvins_yaml_path,
                  "Write an OpenVINS kalibr_imu_chain.yaml (continuous-time densities) to FILE");
  AddOutputOption(sub, "--vins-yaml", &args->vins_yaml_path,
                  "Write VINS-Fusion's acc_n / gyr_n / acc_w / gyr_w (discrete: x sqrt(fs); docs/guides/imu-noise.md) to FILE");
  sub->add_option("--rostopic", args->rostopic, "rostopic written in the noise files (default: --topic, else /imu0)")
      ->each([args](const std::string&) { args->rostopic_given = true; })
      ->capture_default_str();
  sub->add_option("--accel-col", args->accel_cols,
                  "Accelerometer column(s), m/s^2, for the Kalibr file's accelerometer keys (comma-separated)");
  sub->add_option("--min-edf", args->allan.min_edf_for_terms,
                  "The usable minimum and the ARW/RRW fits use only taus with at least this many "
                  "equivalent degrees of freedom")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  return {sub, [args] { return Run(*args); }};
}

const CommandRegistrar kAllanRegistrar(kAllanName, 30, &MakeAllan);

}  // namespace
}  // namespace gyrocomp::cli
