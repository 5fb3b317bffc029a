// gyrocomp allan: overlapping Allan deviation and noise terms of one or more rate columns.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "gyrocomp/allan/allan.h"
#include "gyrocomp/io/io.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kName = "allan";

struct AllanArgs {
  LogOptions log;
  std::string taus = "octave";
  std::string json_path;
  std::string csv_path;
  AllanOptions allan;  // library defaults
};

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

int Run(const AllanArgs& a) {
  int ppd = a.allan.points_per_decade;
  const std::optional<TauGrid> grid = ParseTauGrid(a.taus, &ppd);
  if (!grid) {
    return ReportError(kName, InvalidArgument("--taus " + a.taus +
                                              ": must be octave, decade, all or a number of taus per decade (1-1000)"));
  }
  AllanOptions options = a.allan;
  options.grid = *grid;
  options.points_per_decade = ppd;
  std::string why;
  if (!options.IsValid(&why)) return ReportError(kName, InvalidArgument(why));

  Result<LogSpec> spec = ToLogSpec(a.log);
  if (!spec.ok()) return ReportError(kName, spec.error());
  spec->min_samples = 3;  // one tau needs 3 samples
  Result<GyroLog> log = ReadGyroLog(a.log.input, *spec);
  if (!log.ok()) return ReportError(kName, log.error());
  if (log->sampling.resampled) Note(kName, log->sampling.BriefReport());

  Result<std::vector<AllanResult>> results = ComputeAllan(*log, options);
  if (!results.ok()) return ReportError(kName, results.error());
  if (results->empty()) return ReportError(kName, InvalidInput(log->source + ": no rate column to analyse"));

  nlohmann::json j;
  if (results->size() == 1) {
    j = AllanJson(results->front());
  } else {
    j["fs_hz"] = log->fs_hz;
    j["n_samples"] = log->num_samples();
    j["axes"] = nlohmann::json::object();
    for (const AllanResult& r : *results) j["axes"][r.axis] = AllanJson(r);
  }
  j["input"] = log->source;
  j["sampling"] = log->sampling.BriefReport();

  if (!a.csv_path.empty()) {
    if (Status s = WriteCsv(a.csv_path, CurveTable(*results)); !s.ok()) return ReportError(kName, s.error());
  }
  if (!a.json_path.empty()) {
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kName, s.error());
  }
  if (a.json_path != "-") {
    for (const AllanResult& r : *results) std::cout << r.BriefReport() << "\n";
  }
  return kExitOk;
}

Command Make(CLI::App& app) {
  auto args = std::make_shared<AllanArgs>();
  CLI::App* sub = app.add_subcommand(
      kName,
      "Overlapping Allan deviation of the rate column(s), with chi-square confidence intervals and the "
      "noise terms of IEEE 952 (method.md section 6)");
  sub->footer(
      "Conventions:\n"
      "  ADEV: overlapping, phase from the mean-removed rate (as allantools oadev, data_type='freq').\n"
      "  --taus octave: m = 1, 2, 4, ... (allantools 'octave'); decade: 1, 2, 4, 10, 20, 40, ...;\n"
      "    all: every m (O(N^2), at most 100000 samples); N: N log-spaced taus per decade.\n"
      "    Taus with fewer than 2 terms are dropped.\n"
      "  arw_deg_per_sqrt_h: sigma(1 s) (log-log interpolated between grid points) x 60.\n"
      "  adev_min_deg_per_h: minimum over the taus with EDF >= --min-edf; bias instability = min / 0.664.\n"
      "  rrw_deg_per_h_per_sqrt_h: sigma(3 s) on the +1/2 line fitted after the minimum (null if none).\n"
      "  Error bars: adev/sqrt(n) (allantools) and a chi-square interval from the EDF of\n"
      "    NIST SP 1065 Table 5 (Howe, Allan & Barnes), noise type per tau by lag-1\n"
      "    autocorrelation (Riley & Greenhall 2004).\n"
      "Several axes: --rate-col gx_dps,gy_dps,gz_dps gives JSON {axes: {name: {...}}}.\n"
      "Example: gyrocomp allan -i log.csv.gz --rate-col gx_dps --time-col t_s --json - -o adev.csv");
  AddLogOptions(sub, &args->log);
  sub->add_option("--taus", args->taus, "Tau grid: octave | decade | all | N (taus per decade)")->capture_default_str();
  AddOutputOption(sub, "--json", &args->json_path, "Write the results as JSON to FILE ('-' = stdout)");
  AddOutputOption(sub, "-o,--output", &args->csv_path, "Write the ADEV curve as CSV to FILE");
  sub->add_option("--confidence", args->allan.confidence, "Two-sided confidence level of the chi-square interval")
      ->check(CLI::Range(1e-6, 1.0 - 1e-6))
      ->capture_default_str();
  sub->add_option("--min-edf", args->allan.min_edf_for_terms,
                  "Noise terms use only taus with at least this many equivalent degrees of freedom")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  return {sub, [args] { return Run(*args); }};
}

const CommandRegistrar kReg(kName, 30, &Make);

}  // namespace
}  // namespace gyrocomp::cli
