// gyrocomp compare: the paper's comparisons (Section 4.3) on any record, with the polynomial
// baseline and serial vs parallel; errors against the truth when the record carries it.
#include <iostream>

#include "commands.h"
#include "gyrocomp/pipeline/compare.h"
#include "progress.h"
#include "result_json.h"
#include "stage_options.h"
#include "table_printer.h"

namespace gyrocomp::cli {
namespace {

struct CompareCli {
  LogOptions log;
  PipelineCliOptions pipeline;
  std::string json;
  std::string true_rate_col = "true_rate_dps";
  std::string true_drift_col = "true_drift_dps";
  bool no_grid = false;
  bool quiet = false;
};

std::string RowsTable(const ComparisonResult& r, bool with_truth) {
  std::vector<std::string> header = {"group", "method", "ARW deg/rt(h)", "ADEV min deg/h", "BW Hz"};
  if (with_truth) {
    header.push_back("RMSE vs true rate");
    header.push_back("drift RMSE vs truth");
  }
  header.push_back("drift CV RMSE");
  header.push_back("time s");
  std::vector<std::vector<std::string>> rows;
  for (const MethodRow& m : r.rows) {
    std::vector<std::string> row = {m.group, m.method, FormatNumber(m.arw_deg_per_sqrt_h),
                                    FormatNumber(m.adev_min_deg_per_h), FormatNumber(m.bandwidth_hz)};
    if (with_truth) {
      row.push_back(FormatNumber(m.rmse_vs_true_rate_dps));
      row.push_back(FormatNumber(m.drift_rmse_vs_truth_dps));
    }
    row.push_back(FormatNumber(m.drift_cv_rmse_dps));
    row.push_back(FormatNumber(m.seconds, 3));
    rows.push_back(row);
  }
  return FormatTable(header, rows);
}

int Run(const CompareCli& c) {
  const std::string cmd = "compare";
  PipelineCliOptions pipe = c.pipeline;
  Result<LoadedLog> loaded = LoadPipelineLog(cmd, c.log, &pipe, std::vector<std::string>{c.true_rate_col, c.true_drift_col});
  if (!loaded) return ReportError(cmd, loaded.error());
  const GyroLog& log = loaded->log;
  ComparisonTruth truth;
  const int jr = loaded->table.Find(c.true_rate_col);
  const int jd = loaded->table.Find(c.true_drift_col);
  if (jr >= 0) truth.true_rate_dps = loaded->table.columns[jr];
  if (jd >= 0) truth.true_drift_dps = loaded->table.columns[jd];
  const bool with_truth = jr >= 0 || jd >= 0;

  ComparisonOptions co;
  co.pipeline = pipe.options;
  co.grid_search = !c.no_grid;
  nlohmann::json json;
  json["input"] = log.source;
  json["parameters"] = PipelineOptionsJson(pipe.options);
  json["ground_truth"] = {{"true_rate", jr >= 0 ? c.true_rate_col : ""}, {"true_drift", jd >= 0 ? c.true_drift_col : ""}};
  nlohmann::json axes = nlohmann::json::object();
  const ProgressCallback progress = TerminalProgress(cmd, c.quiet);
  for (std::size_t a = 0; a < log.axis_names.size(); ++a) {
    const PipelineInput input{log.rate_dps[a], log.temp_c, log.fs_hz, {}};
    Result<PipelineResult> parallel = RunParallelModel(input, pipe.options, progress);
    EndProgress();
    if (!parallel) return ReportError(cmd, parallel.error());
    Result<ComparisonResult> r = CompareMethods(input, *parallel, truth, co);
    if (!r) return ReportError(cmd, r.error());
    std::cout << "== " << log.source << ", " << log.axis_names[a] << " (" << log.num_samples() << " samples at "
              << log.fs_hz << " Hz)" << (with_truth ? ", errors against the ground-truth columns" : "") << "\n"
              << RowsTable(*r, with_truth)
              << "Drift rows are in-sample (fitted and scored on this record). ARW and ADEV min are read "
                 "off each full output; compare them with the bandwidth beside them.\n\n";
    nlohmann::json rows = nlohmann::json::array();
    for (const MethodRow& m : r->rows) rows.push_back(MethodRowJson(m));
    axes[log.axis_names[a]] = {{"rows", rows}};
  }
  if (log.axis_names.size() == 1) {
    json["rows"] = axes.begin().value()["rows"];
  } else {
    json["axes"] = axes;
  }
  if (!c.json.empty()) {
    if (Status s = WriteJson(c.json, json); !s) return ReportError(cmd, s.error());
  }
  return kExitOk;
}

Command MakeCompare(CLI::App& app) {
  auto c = std::make_shared<CompareCli>();
  CLI::App* sub = app.add_subcommand(
      "compare", "The paper's comparisons on a log: wavelet threshold vs FLP vs WFLP; SVR vs grid vs CS-SVR; "
                 "polynomial baselines; serial vs parallel (errors against the truth on simulated records)");
  AddLogOptions(sub, &c->log);
  AddOutputOption(sub, "--json", &c->json, "JSON with every row ('-' = stdout)");
  sub->add_option("--true-rate-col", c->true_rate_col, "Ground-truth rate column, used when present")->capture_default_str();
  sub->add_option("--true-drift-col", c->true_drift_col, "Ground-truth drift column, used when present")->capture_default_str();
  sub->add_flag("--no-grid", c->no_grid, "Skip the grid-search SVR baseline");
  sub->add_flag("-q,--quiet", c->quiet, "No progress on stderr");
  AddPipelineOptions(sub, &c->pipeline);
  return {sub, [c] { return Run(*c); }};
}

const CommandRegistrar kCompareRegistrar("compare", 80, &MakeCompare);

}  // namespace
}  // namespace gyrocomp::cli
