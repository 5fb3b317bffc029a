// gyrocomp process: the whole parallel model (VMD -> SE -> WFLP | drift model -> reconstruction)
// on a recorded log, with Allan analysis before and after, and optionally the HTML report.
#include <iostream>

#include "commands.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/report/report.h"
#include "progress.h"
#include "report_builder.h"
#include "result_json.h"
#include "stage_options.h"

namespace gyrocomp::cli {
namespace {

struct ProcessCli {
  LogOptions log;
  PipelineCliOptions pipeline;
  std::string output;
  std::string json;
  std::string report;
  std::string known_rate_col;
  bool compare = false;
  bool quiet = false;
};

// Output column name for axis `axis` (one of `num_axes`): the contract's names for one axis.
std::string Column(const std::string& base, const std::string& axis, std::size_t num_axes) {
  return num_axes == 1 ? base + "_dps" : axis + "_" + base;
}

int Run(const ProcessCli& c) {
  const std::string cmd = "process";
  PipelineCliOptions pipe = c.pipeline;
  Result<LoadedLog> loaded = LoadPipelineLog(cmd, c.log, &pipe);
  if (!loaded) return ReportError(cmd, loaded.error());
  const GyroLog& log = loaded->log;
  WarnIfTemperatureFlat(cmd, log);
  Table out = loaded->table;
  if (out.Find("time_s") < 0) SetColumn(cmd, &out, "time_s", log.time_s);
  std::vector<double> known;
  if (!c.known_rate_col.empty()) {
    const int j = out.Find(c.known_rate_col);
    if (j < 0) {
      return ReportError(cmd, InvalidInput(log.source + ": no column '" + c.known_rate_col +
                                           "' (--known-rate-col)"));
    }
    known = out.columns[j];
    const double to_dps = units::ToDegPerSec(*ParseRateUnit(c.log.rate_unit));
    for (double& v : known) v *= to_dps;
  }

  nlohmann::json json;
  json["input"] = log.source;
  json["fs_hz"] = log.fs_hz;
  json["n_samples"] = log.num_samples();
  json["sampling"] = log.sampling.BriefReport();
  json["parameters"] = PipelineOptionsJson(pipe.options);
  nlohmann::json axes = nlohmann::json::object();
  std::optional<ReportData> report;
  const ProgressCallback progress = TerminalProgress(cmd, c.quiet);
  for (std::size_t a = 0; a < log.axis_names.size(); ++a) {
    const std::string& axis = log.axis_names[a];
    const PipelineInput input{log.rate_dps[a], log.temp_c, log.fs_hz, known};
    Result<PipelineResult> r = RunParallelModel(input, pipe.options, progress);
    EndProgress();
    if (!r) return ReportError(cmd, r.error());
    for (const std::string& w : r->warnings) Note(cmd, axis + ": warning: " + w);
    std::optional<ComparisonResult> comparison;
    if (c.compare) {
      ComparisonOptions co;
      co.pipeline = pipe.options;
      Result<ComparisonResult> cr = CompareMethods(input, *r, {}, co);
      if (!cr) return ReportError(cmd, cr.error());
      comparison = std::move(*cr);
    }
    const std::size_t na = log.axis_names.size();
    SetColumn(cmd, &out, Column("compensated", axis, na), r->compensated_dps);
    SetColumn(cmd, &out, Column("drift_feature", axis, na), r->features.drift);
    SetColumn(cmd, &out, Column("mixed_feature", axis, na), r->features.mixed);
    SetColumn(cmd, &out, Column("noise_feature", axis, na), r->features.noise);
    SetColumn(cmd, &out, Column("mixed_denoised", axis, na), r->mixed_denoised);
    SetColumn(cmd, &out, Column("predicted_drift", axis, na), r->predicted_drift_dps);

    nlohmann::json j;
    j["before"] = AllanJson(r->allan_before);
    j["after"] = AllanJson(r->allan_after);
    MarkNotApplicable(*r, &j);  // ARW / RRW the processing makes meaningless: null + reason (report_builder.h)
    j["modes"] = ModesJson(r->mode_reports);
    j["classification_rule"] = r->classification_rule;
    j["drift_mode_forced"] = r->drift_mode_forced;
    j["vmd"] = {{"iterations", r->vmd.iterations}, {"converged", r->vmd.converged},
                {"final_update", r->vmd.final_update}};
    j["drift_model"] = r->drift_model ? DriftSummaryJson(r->drift_model->summary) : nlohmann::json();
    j["bandwidth_hz"] = r->bandwidth ? Num(r->bandwidth->bandwidth_hz) : nlohmann::json();
    if (r->bandwidth) j["bandwidth"] = BandwidthJson(*r->bandwidth);
    j["timings_s"] = r->timings_s;
    if (comparison) {
      nlohmann::json rows = nlohmann::json::array();
      for (const MethodRow& m : comparison->rows) rows.push_back(MethodRowJson(m));
      j["comparison"] = rows;
    }
    j["warnings"] = r->warnings;
    j["notes"] = HonestyNotes(*r);
    axes[axis] = j;
    if (!c.quiet) std::cerr << "gyrocomp process: " << axis << ": " << r->BriefReport() << "\n";
    if (!c.report.empty() && a == 0) {
      ReportContext ctx;
      ctx.title = "gyrocomp: " + log.source;
      ctx.source = log.source;
      ctx.axis = axis;
      ctx.time_s = log.time_s;
      ctx.rate_dps = log.rate_dps[a];
      ctx.temp_c = log.temp_c;
      ctx.parameters = json["parameters"];
      ctx.comparison = comparison ? &*comparison : nullptr;
      report = BuildPipelineReport(*r, ctx);
    }
  }
  if (log.axis_names.size() == 1) {
    for (auto& [key, value] : axes.begin().value().items()) json[key] = value;
  } else {
    json["axes"] = axes;
  }
  if (!c.output.empty()) {
    if (Status s = WriteCsv(c.output, out); !s) return ReportError(cmd, s.error());
  }
  if (!c.json.empty()) {
    if (Status s = WriteJson(c.json, json); !s) return ReportError(cmd, s.error());
  }
  if (report) {
    if (Status s = WriteText(c.report, RenderReportHtml(*report)); !s) return ReportError(cmd, s.error());
  }
  return kExitOk;
}

Command Make(CLI::App& app) {
  auto c = std::make_shared<ProcessCli>();
  CLI::App* sub = app.add_subcommand(
      "process", "The parallel VMD-SE-WFLP-CS-SVR model on a log: denoise, compensate temperature drift, "
                 "Allan analysis before/after (needs rate and temperature)");
  AddLogOptions(sub, &c->log);
  AddOutputOption(sub, "-o,--output", &c->output,
                  "Output CSV: input columns plus compensated_dps and the feature columns");
  AddOutputOption(sub, "--json", &c->json, "JSON summary ('-' = stdout)");
  AddOutputOption(sub, "--report", &c->report, "Self-contained HTML report");
  sub->add_option("--known-rate-col", c->known_rate_col,
                  "Column of a rate known to be applied (Earth rate, turntable): the drift model learns bias only");
  sub->add_flag("--compare", c->compare, "Also run the baseline comparisons (in the JSON per axis, and tables in the report)");
  sub->add_flag("-q,--quiet", c->quiet, "No progress or summary on stderr");
  AddPipelineOptions(sub, &c->pipeline);
  return {sub, [c] { return Run(*c); }};
}

const CommandRegistrar kRegistrar("process", 70, &Make);

}  // namespace
}  // namespace gyrocomp::cli
