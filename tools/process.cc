// gyrocomp process: the whole parallel model (VMD -> SE -> WFLP | drift model -> reconstruction)
// on a recorded log, with Allan analysis before and after, and optionally the HTML report.
#include <iostream>

#include "commands.h"
#include "console.h"
#include "gyrocomp/io/flight_log.h"
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
  bool verbose = false;
};

// Output column name for axis `axis` (one of `num_axes`): the contract's names for one axis.
std::string Column(const std::string& base, const std::string& axis, std::size_t num_axes) {
  return num_axes == 1 ? base + "_dps" : axis + "_" + base;
}

// --known-rate-col in deg/s; empty without the option.
Result<std::vector<double>> KnownRate(const ProcessCli& c, const Table& table, const std::string& source) {
  if (c.known_rate_col.empty()) return std::vector<double>{};
  const int j = table.Find(c.known_rate_col);
  if (j < 0) return InvalidInput(source + ": no column '" + c.known_rate_col + "' (--known-rate-col)");
  std::vector<double> known = table.columns[j];
  const double to_dps = units::ToDegPerSec(*ParseRateUnit(c.log.rate_unit));
  for (double& v : known) v *= to_dps;
  return known;
}

using NamedColumns = std::vector<std::pair<std::string, std::vector<double>>>;

// The output CSV's columns of one axis, moved out of the result (not copied: 6 x N doubles).
void TakeResultColumns(PipelineResult* r, const std::string& axis, std::size_t num_axes, NamedColumns* out) {
  out->emplace_back(Column("compensated", axis, num_axes), std::move(r->compensated_dps));
  out->emplace_back(Column("drift_feature", axis, num_axes), std::move(r->features.drift));
  out->emplace_back(Column("mixed_feature", axis, num_axes), std::move(r->features.mixed));
  out->emplace_back(Column("noise_feature", axis, num_axes), std::move(r->features.noise));
  out->emplace_back(Column("mixed_denoised", axis, num_axes), std::move(r->mixed_denoised));
  out->emplace_back(Column("predicted_drift", axis, num_axes), std::move(r->predicted_drift_dps));
}

// The JSON of one axis (cli.md, process).
nlohmann::json AxisJson(const PipelineResult& r, const std::optional<ComparisonResult>& comparison) {
  nlohmann::json j;
  j["before"] = AllanJson(r.allan_before);
  j["after"] = AllanJson(r.allan_after);
  MarkNotApplicable(r, &j);  // ARW / RRW the processing makes meaningless: null + reason (report_builder.h)
  j["modes"] = ModesJson(r.mode_reports);
  j["classification_rule"] = r.classification_rule;
  j["drift_mode_forced"] = r.drift_mode_forced;
  j["vmd"] = {{"iterations", r.vmd.iterations}, {"converged", r.vmd.converged},
              {"final_update", r.vmd.final_update}};
  j["drift_model"] = r.drift_model ? DriftSummaryJson(r.drift_model->summary) : nlohmann::json();
  j["bandwidth_hz"] = r.bandwidth ? Num(r.bandwidth->bandwidth_hz) : nlohmann::json();
  if (r.bandwidth) j["bandwidth"] = BandwidthJson(*r.bandwidth);
  j["timings_s"] = r.timings_s;
  if (comparison) {
    nlohmann::json rows = nlohmann::json::array();
    for (const MethodRow& m : comparison->rows) rows.push_back(MethodRowJson(m));
    j["comparison"] = rows;
  }
  j["warnings"] = r.warnings;
  j["notes"] = HonestyNotes(r);
  return j;
}

// The input table is needed only for the output CSV (its columns come first). A 5 M-sample
// record holds 330 MB of input columns; while the VMD runs (1.7 GB at 5 M) they are dropped and
// read again for the output when the input can be read again: a CSV file (not stdin), not
// resampled. The second read must give the same rate and temperature, else it is an error.
bool CanReadAgain(const LogOptions& options, const GyroLog& log) {
  return options.input != "-" && DetectLogFormat(options.input) == LogFormat::kCsv && !log.sampling.resampled;
}

Result<Table> ReadInputAgain(const std::string& cmd, const ProcessCli& c, const GyroLog& first) {
  PipelineCliOptions pipe = c.pipeline;
  Result<LoadedLog> again = LoadPipelineLog(cmd, c.log, &pipe);
  if (!again) return again.error();
  if (again->log.rate_dps != first.rate_dps || again->log.temp_c != first.temp_c) {
    return InvalidInput(first.source + ": the file changed while it was processed (read again for the output "
                        "CSV, its rate or temperature differ): no output written");
  }
  return std::move(again->table);
}

// The default summary: what was read, the modes, the drift model and the headline Allan figures
// before -> after beside the bandwidth they hold; --verbose prints every stage's BriefReport.
void PrintAxisSummary(const GyroLog& log, const std::string& axis, const PipelineResult& r, bool verbose) {
  if (verbose) {
    std::cerr << "gyrocomp process: " << axis << ": " << r.BriefReport() << "\n";
    return;
  }
  Headline("process", log.source + ", " + axis + ": " + std::to_string(r.num_samples) + " samples at " +
                          Figure(r.fs_hz) + " Hz (" + Figure(r.num_samples / r.fs_hz / 3600.0) + " h)");
  int counts[3] = {0, 0, 0};
  for (const ModeReport& m : r.mode_reports) ++counts[static_cast<int>(m.feature) % 3];
  std::ostringstream modes;
  modes << r.mode_reports.size() << " modes by VMD (" << (r.vmd.converged ? "converged" : "NOT converged")
        << " after " << r.vmd.iterations << " iterations):";
  for (FeatureClass f : {FeatureClass::kDrift, FeatureClass::kMixed, FeatureClass::kNoise}) {
    modes << " " << counts[static_cast<int>(f) % 3] << " " << FeatureClassName(f);
  }
  Line(modes.str());
  if (r.drift_model) {
    const DriftFitSummary& d = r.drift_model->summary;
    Line("drift model: " + std::string(DriftModelKindName(d.model)) + "(" + DriftInputSetName(d.inputs) +
         "), CV error " + RateDps(d.cv_rmse) + " against a drift span of " + RateDps(d.drift_span) + ", over " +
         Figure(d.temp_min_c) + " .. " + Figure(d.temp_max_c) + " C");
  } else {
    Line("drift model: none (no mode was classed as drift)");
  }
  std::string allan = "ARW " + BeforeAfter(r.allan_before.terms.arw_deg_per_sqrt_h.value_or(NAN),
                                           r.allan_after.terms.arw_deg_per_sqrt_h.value_or(NAN), "deg/sqrt(h)");
  if (r.bandwidth && r.bandwidth->bandwidth_hz) allan += " at a bandwidth of " + Figure(*r.bandwidth->bandwidth_hz) + " Hz";
  Line(allan);
  Line("ADEV min " + BeforeAfter(r.allan_before.terms.adev_min_deg_per_h, r.allan_after.terms.adev_min_deg_per_h, "deg/h"));
}

int Run(const ProcessCli& c) {
  const std::string cmd = "process";
  PipelineCliOptions pipe = c.pipeline;
  // The input's other columns are needed now only for an output CSV that cannot read them again.
  const bool whole = !c.output.empty() && !(c.log.input != "-" && DetectLogFormat(c.log.input) == LogFormat::kCsv &&
                                            !c.log.resample_hz);
  std::optional<std::vector<std::string>> keep;
  if (!whole) keep = std::vector<std::string>{c.known_rate_col};
  Result<LoadedLog> loaded = LoadPipelineLog(cmd, c.log, &pipe, keep);
  if (!loaded) return ReportError(cmd, loaded.error());
  const GyroLog& log = loaded->log;
  WarnIfTemperatureFlat(cmd, log);
  Result<std::vector<double>> known = KnownRate(c, loaded->table, log.source);
  if (!known) return ReportError(cmd, known.error());
  const bool read_again = !c.output.empty() && CanReadAgain(c.log, log);
  Table out;  // the output CSV: the input's columns, then time_s (if absent) and the results
  if (!c.output.empty() && !read_again) out = std::move(loaded->table);
  loaded->table = Table{};  // freed before the VMD
  NamedColumns result_columns;

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
    const PipelineInput input{log.rate_dps[a], log.temp_c, log.fs_hz, *known};
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

    axes[axis] = AxisJson(*r, comparison);
    if (!c.quiet) PrintAxisSummary(log, axis, *r, c.verbose);
    if (!c.report.empty() && a == 0) {
      PipelineReportContext ctx;
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
    if (!c.output.empty()) TakeResultColumns(&*r, axis, log.axis_names.size(), &result_columns);  // last use of r
  }
  if (log.axis_names.size() == 1) {
    for (auto& [key, value] : axes.begin().value().items()) json[key] = value;
  } else {
    json["axes"] = axes;
  }
  if (!c.output.empty()) {
    if (read_again) {
      Result<Table> table = ReadInputAgain(cmd, c, log);
      if (!table) return ReportError(cmd, table.error());
      out = std::move(*table);
    }
    if (out.Find("time_s") < 0) SetColumn(cmd, &out, "time_s", log.time_s);
    for (auto& [name, values] : result_columns) SetColumn(cmd, &out, name, std::move(values));
    result_columns.clear();
    if (Status s = WriteCsv(c.output, out); !s) return ReportError(cmd, s.error());
  }
  if (!c.json.empty()) {
    if (Status s = WriteJson(c.json, json); !s) return ReportError(cmd, s.error());
  }
  if (report) {
    if (Status s = WriteText(c.report, RenderReportHtml(*report)); !s) return ReportError(cmd, s.error());
  }
  if (!c.quiet) Wrote({c.output, c.json, c.report});
  return kExitOk;
}

Command MakeProcess(CLI::App& app) {
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
  sub->add_flag("-v,--verbose", c->verbose,
                "Every stage's detail on stderr (VMD, entropies, the drift model's candidates, timings)");
  sub->add_option("--threads", c->pipeline.options.num_threads,
                  "Threads of the VMD, sample entropy, cuckoo search and the two branches (default: each stage's "
                  "automatic choice, at most the cores); results do not depend on it")
      ->check(CLI::PositiveNumber);
  AddPipelineOptions(sub, &c->pipeline);
  return {sub, [c] { return Run(*c); }};
}

const CommandRegistrar kProcessRegistrar("process", 70, &MakeProcess);

}  // namespace
}  // namespace gyrocomp::cli
