// gyrocomp demo: the main job on embedded defaults. Simulates the paper's chamber run (Section
// 4.1), processes it with the parallel model, prints a before/after table like the paper's
// abstract (with the bandwidth beside the ARW) and writes the HTML report.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "gyrocomp/pipeline/compare.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/sim/simulator.h"
#include "progress.h"
#include "report_builder.h"
#include "result_json.h"
#include "stage_options.h"
#include "table_printer.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kName = "demo";

// The paper's published figures (Section 4.3.1 and the abstract).
constexpr double kPaperArwBefore = 1.667, kPaperArwAfter = 0.0667;
constexpr double kPaperBsBefore = 30.0, kPaperBsAfter = 4.0;

struct DemoArgs {
  std::string out_dir = "demo-out";
  double fs_hz = 5.0;
  std::uint64_t seed = 1;
  bool compare = true;
  bool quiet = false;
  PipelineCliOptions pipeline;
};

std::string Reduction(std::optional<double> before, std::optional<double> after) {
  if (!before || !after || *before == 0.0) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f%%", 100.0 * (*before - *after) / *before);
  return buf;
}

int Run(const DemoArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  PipelineCliOptions pipe = a.pipeline;
  if (Status s = ResolvePipelineOptions(&pipe); !s) return ReportError(kName, s.error());
  std::error_code ec;
  std::filesystem::create_directories(a.out_dir, ec);
  if (ec) return ReportError(kName, IoError(a.out_dir + ": cannot create directory: " + ec.message()));
  const std::filesystem::path dir(a.out_dir);
  // The three files, checked before the work (cli_common.h: written together at the end).
  for (const char* name : {"processed.csv.gz", "summary.json", "report.html"}) {
    if (Status s = Outputs().Declare((dir / name).string()); !s) return ReportError(kName, s.error());
  }

  SimulatorOptions sim;
  sim.fs_hz = a.fs_hz;
  sim.seed = a.seed;
  std::string why;
  if (!sim.IsValid(&why)) return ReportError(kName, InvalidArgument(why));
  Result<SimulatedRun> run = Simulate(sim);
  if (!run) return ReportError(kName, run.error());
  std::printf("gyrocomp demo: the paper's chamber run (Section 4.1), simulated with ground truth\n  %s\n",
              run->summary.BriefReport().c_str());

  const PipelineInput input{run->rate_dps, run->temp_c, run->fs_hz, {}};
  Result<PipelineResult> r = RunParallelModel(input, pipe.options, TerminalProgress(kName, a.quiet));
  EndProgress();
  if (!r) return ReportError(kName, r.error());
  std::optional<ComparisonResult> comparison;
  if (a.compare) {
    ComparisonOptions co;
    co.pipeline = pipe.options;
    // The grid and a second search cost as much as CS-SVR each; `gyrocomp compare` runs them.
    co.grid_search = false;
    co.serial_reuses_parallel_parameters = true;
    Result<ComparisonResult> c = CompareMethods(input, *r, {run->true_rate_dps, run->true_drift_dps}, co);
    if (!c) return ReportError(kName, c.error());
    comparison = std::move(*c);
  }

  // The table of the paper's abstract, ours beside it.
  const std::vector<SummaryRow> rows = BeforeAfterRows(*r);
  std::vector<std::vector<std::string>> table;
  for (const SummaryRow& row : rows) {
    std::string paper_before = "-", paper_after = "-", paper_red = "-";
    if (row.metric == "ARW") {
      paper_before = FormatNumber(kPaperArwBefore); paper_after = FormatNumber(kPaperArwAfter);
      paper_red = Reduction(kPaperArwBefore, kPaperArwAfter);
    } else if (row.metric.rfind("ADEV minimum (bias stability)", 0) == 0) {
      paper_before = FormatNumber(kPaperBsBefore); paper_after = FormatNumber(kPaperBsAfter);
      paper_red = Reduction(kPaperBsBefore, kPaperBsAfter);
    } else if (row.metric.rfind("bandwidth", 0) == 0) {
      paper_after = "not reported";
    }
    table.push_back({row.metric + " (" + row.unit + ")", FormatNumber(row.before), FormatNumber(row.after),
                     Reduction(row.before, row.after), paper_before, paper_after, paper_red});
  }
  std::printf("\n%s", FormatTable({"", "before", "after", "reduction", "paper before", "paper after", "paper reduction"},
                                   table).c_str());
  for (const std::string& note : HonestyNotes(*r)) std::printf("  note: %s\n", note.c_str());
  for (const std::string& w : r->warnings) std::printf("  warning: %s\n", w.c_str());
  std::printf("\n  modes:");
  for (const ModeReport& m : r->mode_reports) {
    std::printf(" %d:%s(SE %.3g, %.3g Hz)", m.index, FeatureClassName(m.feature), m.sample_entropy,
                m.center_frequency_hz);
  }
  if (r->drift_model) std::printf("\n  drift model: %s", r->drift_model->summary.BriefReport().c_str());
  double rms_raw = 0, rms_out = 0;
  for (std::size_t i = 0; i < run->num_samples(); ++i) {
    rms_raw += std::pow(run->rate_dps[i] - run->true_rate_dps[i], 2);
    rms_out += std::pow(r->compensated_dps[i] - run->true_rate_dps[i], 2);
  }
  std::printf("\n  error against the true rate (RMS): raw %.4g deg/s, compensated %.4g deg/s\n",
              std::sqrt(rms_raw / run->num_samples()), std::sqrt(rms_out / run->num_samples()));

  // Files: the simulated record, the processed record, the JSON summary and the report.
  Table processed = run->ToTable();
  processed.Add("compensated_dps", r->compensated_dps);
  processed.Add("drift_feature_dps", r->features.drift);
  processed.Add("mixed_feature_dps", r->features.mixed);
  processed.Add("noise_feature_dps", r->features.noise);
  processed.Add("predicted_drift_dps", r->predicted_drift_dps);
  const std::string csv = (dir / "processed.csv.gz").string();
  if (Status s = WriteCsv(csv, processed); !s) return ReportError(kName, s.error());

  nlohmann::json params = PipelineOptionsJson(pipe.options);
  params["simulator"] = {{"profile", "paper"}, {"fs_hz", a.fs_hz}, {"seed", a.seed},
                         {"summary", run->summary.BriefReport()}};
  nlohmann::json j;
  j["before"] = AllanTermsJson(r->allan_before);
  j["after"] = AllanTermsJson(r->allan_after);
  j["modes"] = ModesJson(r->mode_reports);
  j["drift_model"] = r->drift_model ? DriftSummaryJson(r->drift_model->summary) : nlohmann::json();
  j["bandwidth_hz"] = r->bandwidth ? Num(r->bandwidth->bandwidth_hz) : nlohmann::json();
  j["timings_s"] = r->timings_s;
  j["notes"] = HonestyNotes(*r);
  j["parameters"] = params;
  j["paper"] = {{"arw_before_deg_per_sqrt_h", kPaperArwBefore}, {"arw_after_deg_per_sqrt_h", kPaperArwAfter},
                {"bias_stability_before_deg_per_h", kPaperBsBefore}, {"bias_stability_after_deg_per_h", kPaperBsAfter}};
  const std::string json_path = (dir / "summary.json").string();
  if (Status s = WriteJson(json_path, j); !s) return ReportError(kName, s.error());

  ReportContext ctx;
  ctx.title = "gyrocomp demo: the paper's chamber run, simulated";
  ctx.source = "simulated paper profile (seed " + std::to_string(a.seed) + ")";
  ctx.axis = "rate_dps";
  ctx.time_s = run->time_s;
  ctx.rate_dps = run->rate_dps;
  ctx.temp_c = run->temp_c;
  ctx.parameters = params;
  ctx.comparison = comparison ? &*comparison : nullptr;
  const std::string report_path = (dir / "report.html").string();
  if (Status s = WriteText(report_path, RenderReportHtml(BuildPipelineReport(*r, ctx))); !s) {
    return ReportError(kName, s.error());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("\n  wrote %s, %s, %s (%.1f s)\n", report_path.c_str(), json_path.c_str(), csv.c_str(), seconds);
  return kExitOk;
}

Command Make(CLI::App& app) {
  auto a = std::make_shared<DemoArgs>();
  CLI::App* sub = app.add_subcommand(
      "demo", "Simulate the paper's chamber run, process it with the parallel model, print the before/after "
              "table and write the HTML report (no input needed)");
  sub->add_option("--out", a->out_dir, "Output directory")->capture_default_str();
  sub->add_option("--fs", a->fs_hz, "Sample rate of the simulated run, Hz")->check(CLI::PositiveNumber)->capture_default_str();
  sub->add_option("--sim-seed", a->seed, "Simulator seed")->capture_default_str();
  sub->add_flag("!--no-compare", a->compare, "Skip the comparison tables");
  sub->add_flag("-q,--quiet", a->quiet, "No progress on stderr");
  AddPipelineOptions(sub, &a->pipeline);
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kRegistrar("demo", 10, &Make);

}  // namespace
}  // namespace gyrocomp::cli
