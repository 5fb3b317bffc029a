// gyrocomp demo: the main job on embedded defaults. Simulates the paper's chamber run (Section
// 4.1) and a held-out heating run, processes the first with the parallel model, runs the drift
// branch twice on the one VMD (the paper's CS-SVR and gyrocomp's default), prints the side-by-side
// table (raw / paper pipeline / default / paper's published figures, with the drift error against
// the truth on both runs) and writes the HTML report. Reduced search budgets unless --full-budget.
#include <chrono>
#include <cmath>
#include <ctime>
#include <map>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "console.h"
#include "demo_table.h"
#include "gyrocomp/drift/drift_validate.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/pipeline/compare.h"
#include "gyrocomp/sim/simulator.h"
#include "progress.h"
#include "report_builder.h"
#include "result_json.h"
#include "stage_options.h"
#include "validation_report.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kDemoName = "demo";

// The demo's reduced search budgets (docs/reference/cli-contract.md, demo): cuckoo-search nests of every searched
// model, generations of auto's searched candidates (hybrid, cs-svr) and of the paper's CS-SVR
// branch. --full-budget keeps `process`' defaults (15 nests; auto 4 generations; cs-svr 10).
constexpr int kDemoNests = 6;
constexpr int kDemoAutoGenerations = 1;
constexpr int kDemoCsSvrGenerations = 2;
// Sample entropy of each mode on its middle 100,000 samples (process: 200,000).
constexpr std::size_t kDemoEntropySamples = 100000;

struct DemoArgs {
  std::string out_dir = "demo-out";
  double fs_hz = 5.0;
  std::uint64_t seed = 1;
  std::optional<std::uint64_t> held_out_seed;  // default: seed + 1
  bool compare = true;
  bool quiet = false;
  bool full_budget = false;
  bool verbose = false;  // the drift models' whole explanations instead of one line each
  PipelineCliOptions pipeline;
  const CLI::App* app = nullptr;
};

// Process CPU time (all threads) and wall time of each demo phase, s: where the demo's time goes.
class PhaseClock {
 public:
  void Mark(const std::string& phase) {
    const double cpu = static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
    const auto wall = std::chrono::steady_clock::now();
    cpu_s_[phase] = cpu - cpu_;
    wall_s_[phase] = std::chrono::duration<double>(wall - wall_).count();
    cpu_ = cpu;
    wall_ = wall;
  }
  nlohmann::json Json() const { return {{"cpu_s", cpu_s_}, {"wall_s", wall_s_}}; }

 private:
  double cpu_ = static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
  std::chrono::steady_clock::time_point wall_ = std::chrono::steady_clock::now();
  std::map<std::string, double> cpu_s_, wall_s_;
};

// The budgets above, where the command line did not set them; returns what was applied, in words.
std::string ApplyDemoBudget(const DemoArgs& a, PipelineOptions* o, int* cs_svr_generations) {
  *cs_svr_generations = o->drift.search.cuckoo.max_generations;
  if (a.full_budget) return "full search budgets (as process)";
  if (a.app->count("--nests") == 0) o->drift.search.cuckoo.num_nests = kDemoNests;
  o->drift.auto_select.search_generations = kDemoAutoGenerations;
  if (a.app->count("--generations") == 0) *cs_svr_generations = kDemoCsSvrGenerations;
  if (a.app->count("--entropy-max-samples") == 0) o->entropy_max_samples = kDemoEntropySamples;
  return "reduced budgets for the demo: " + std::to_string(o->drift.search.cuckoo.num_nests) +
         " cuckoo nests; auto's searched candidates " + std::to_string(kDemoAutoGenerations) +
         " generation(s); the paper's CS-SVR " + std::to_string(*cs_svr_generations) +
         " generation(s); sample entropy on " +
         (o->entropy_max_samples ? std::to_string(*o->entropy_max_samples) : std::string("all")) +
         " samples per mode (--full-budget: process' defaults)";
}

// The held-out run: a heating ramp over the paper's range (the paper run mostly cools), other seed.
SimulatorOptions HeldOutOptions(const DemoArgs& a) {
  SimulatorOptions s;
  s.fs_hz = a.fs_hz;
  s.seed = a.held_out_seed ? *a.held_out_seed : a.seed + 1;
  s.profile.kind = ThermalProfileKind::kRamp;
  s.profile.room_temp_c = -40.0;
  s.profile.ramp_end_c = 60.0;
  s.profile.room_hold_s = 1800.0;
  s.profile.hold_s = 1800.0;
  return s;
}

std::string HeldOutLabel(const SimulatorOptions& s) {
  return "a held-out simulated heating ramp (-40 -> 60 C at 1 C/min, 30 min holds, seed " + std::to_string(s.seed) + ")";
}

// The paper's pipeline on the same VMD and WFLP: the drift feature C1 fitted by CS-SVR on T
// (the paper's drift branch), compensated = WFLP(C2) + (C1 - CS-SVR(T)).
Result<PipelineResult> PaperPipeline(const PipelineInput& input, const PipelineResult& ours,
                                     const PipelineOptions& options, int generations) {
  DriftFitOptions d = options.drift;
  d.model = DriftModelKind::kCsSvr;
  d.inputs = DriftInputSet::kTemp;
  d.cv_scheme.reset();
  d.search.cuckoo.max_generations = generations;
  d.target_name = "drift-mode";
  const auto t = std::chrono::steady_clock::now();
  const DriftInputs inputs{input.temp_c, input.fs_hz};
  Result<DriftModel> model = FitDriftModel(inputs, ours.features.drift, d);
  if (!model) return model.error();
  Result<std::vector<double>> predicted = model->Predict(inputs);
  if (!predicted) return predicted.error();
  PipelineResult p = ours;
  for (std::size_t i = 0; i < p.num_samples; ++i) {
    p.compensated_dps[i] = ours.compensated_dps[i] + ours.predicted_drift_dps[i] - (*predicted)[i];
  }
  p.predicted_drift_dps = std::move(*predicted);
  p.drift_model = std::move(*model);
  p.timings_s["drift_fit"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  p.timings_s["total"] += p.timings_s["drift_fit"] - ours.timings_s.at("drift_fit");
  Result<AllanResult> allan = ComputeAllan(p.compensated_dps, p.fs_hz, options.allan);
  if (!allan) return allan.error();
  p.allan_after = std::move(*allan);
  return p;
}

struct HeldOut {
  SimulatorOptions options;
  SimulatedRun run;
  DriftValidation paper, ours;
};

Result<HeldOut> ValidateOnHeldOut(const DemoArgs& a, const DriftModel& paper, const DriftModel& ours) {
  HeldOut h;
  h.options = HeldOutOptions(a);
  Result<SimulatedRun> run = Simulate(h.options);
  if (!run) return run.error();
  h.run = std::move(*run);
  for (auto [model, out] : {std::pair{&paper, &h.paper}, std::pair{&ours, &h.ours}}) {
    Result<DriftValidation> v = ValidateDriftModel(*model, h.run.rate_dps, h.run.temp_c, h.run.fs_hz, h.run.true_drift_dps);
    if (!v) return v.error();
    *out = std::move(*v);
  }
  return h;
}

// `requested`: the --model of the default branch (auto unless given).
SideBySideTable MakeDemoTable(const SimulatedRun& run, const PipelineResult& paper, const PipelineResult& ours,
                              const HeldOut& h, DriftModelKind requested) {
  const DemoVariant raw{"raw", "raw", &ours.allan_before, ours.fs_hz / 2.0, Rms(run.true_drift_dps, {}),
                        Rms(h.run.true_drift_dps, {}), Rms(run.rate_dps, run.true_rate_dps)};
  auto variant = [&](const std::string& key, const std::string& name, const PipelineResult& p, const DriftValidation& v) {
    return DemoVariant{key, name, &p.allan_after, ProcessedBandwidth(p), Rms(p.predicted_drift_dps, run.true_drift_dps),
                       v.rmse_vs_true_drift, Rms(p.compensated_dps, run.true_rate_dps)};
  };
  const std::string chosen = std::string(DriftModelKindName(ours.drift_model->kind)) + "(" +
                             DriftInputSetName(ours.drift_model->summary.inputs) + ")";
  const std::string ours_name = requested == DriftModelKind::kAuto
                                    ? "gyrocomp default (auto: " + chosen + ")"
                                    : "gyrocomp with --model " + std::string(DriftModelKindName(requested)) + " (" +
                                          chosen + ")";
  return DemoTable({raw, variant("paper_pipeline", "paper pipeline (cs-svr)", paper, h.paper),
                    variant("default", ours_name, ours, h.ours)},
                   HeldOutLabel(h.options));
}

// One line of a drift model for the console: what was chosen, its CV error beside the drift
// span, the terms auto tested (gain +- SE, Eq. A-4) and those the run does not identify.
std::string DriftModelLine(const DriftFitSummary& d) {
  std::string s = std::string(DriftModelKindName(d.model)) + "(" + DriftInputSetName(d.inputs) + "), CV error " +
                  RateDps(d.cv_rmse) + " against a drift span of " + RateDps(d.drift_span);
  if (d.C && d.sigma) s += ", C = " + Figure(*d.C) + ", sigma = " + Figure(*d.sigma);
  for (const TermAdmission& t : d.term_admissions) {
    if (!t.note.empty() || t.gain.pairs == 0) continue;
    // A kernel is held to its block SD (Eq. H-1), every other term to its SE (Eq. A-4).
    const bool kernel = t.term == "kernel";
    s += "; +" + t.term + " " + (t.admitted ? "admitted" : "rejected") + " (gain " + RateDps(t.gain.gain) +
         (kernel ? ", block SD " + RateDps(t.gain.Sd()) : " +- " + RateDps(t.gain.se)) + ")";
  }
  std::string left_out;
  for (const ExcludedTerm& e : d.excluded_terms) left_out += (left_out.empty() ? "" : ", ") + e.term;
  if (!left_out.empty()) s += "; not identified by this run: " + left_out;
  return s;
}

// The table, its notes, then the modes and one line per drift model (--verbose: their whole
// explanations, as `fit` prints them).
void PrintConsole(const PipelineResult& ours, const PipelineResult& paper, const SideBySideTable& table,
                  const std::string& budget, bool verbose) {
  std::printf("\n%s", FormatSideBySide(table).c_str());
  for (const std::string& note : HonestyNotes(ours)) std::printf("  note: %s\n", note.c_str());
  for (const std::string& w : ours.warnings) std::printf("  warning: %s\n", w.c_str());
  std::printf("\n  modes:");
  for (const ModeReport& m : ours.mode_reports) {
    std::printf(" %d:%s(SE %.3g, %.3g Hz)", m.index, FeatureClassName(m.feature), m.sample_entropy,
                m.center_frequency_hz);
  }
  const DriftFitSummary& mine = ours.drift_model->summary;
  const DriftFitSummary& theirs = paper.drift_model->summary;
  std::printf("\n  default drift model: %s", (verbose ? mine.BriefReport() : DriftModelLine(mine)).c_str());
  std::printf("\n  paper's drift model: %s\n", (verbose ? theirs.BriefReport() : DriftModelLine(theirs)).c_str());
  if (!verbose) std::printf("  (--verbose: why each term was admitted or left out)\n");
  std::printf("  %s\n", budget.c_str());
}

nlohmann::json SummaryJson(const DemoArgs& a, const PipelineResult& ours, const PipelineResult& paper,
                           const HeldOut& h, const SideBySideTable& table, const nlohmann::json& params) {
  const PaperFigures fig;
  nlohmann::json j;
  j["before"] = AllanTermsJson(ours.allan_before);
  j["after"] = AllanTermsJson(ours.allan_after);
  MarkNotApplicable(ours, &j);
  j["modes"] = ModesJson(ours.mode_reports);
  j["drift_model"] = DriftSummaryJson(ours.drift_model->summary);
  j["bandwidth_hz"] = ours.bandwidth ? Num(ours.bandwidth->bandwidth_hz) : nlohmann::json();
  j["timings_s"] = ours.timings_s;
  j["notes"] = HonestyNotes(ours);
  j["parameters"] = params;
  j["paper"] = {{"arw_before_deg_per_sqrt_h", fig.arw_raw}, {"arw_after_deg_per_sqrt_h", fig.arw_processed},
                {"bias_stability_before_deg_per_h", fig.bs_raw}, {"bias_stability_after_deg_per_h", fig.bs_processed},
                {"source", "Chang, Cao & Shen 2020, Section 4.3.1, Figure 13 and abstract"}};
  nlohmann::json after_paper = AllanTermsJson(paper.allan_after);
  MarkNotApplicable(paper.allan_after, ProcessedBandwidth(paper), &after_paper);
  j["paper_pipeline"] = {{"drift_model", DriftSummaryJson(paper.drift_model->summary)}, {"after", after_paper},
                         {"drift_fit_s", paper.timings_s.at("drift_fit")}};
  j["held_out"] = {{"simulator", {{"profile", "ramp"}, {"from_c", h.options.profile.room_temp_c},
                                  {"to_c", h.options.profile.ramp_end_c}, {"seed", h.options.seed},
                                  {"summary", h.run.summary.BriefReport()}}},
                   {"default", DriftValidationJson(h.ours)},
                   {"paper_pipeline", DriftValidationJson(h.paper)}};
  j["side_by_side"] = SideBySideJson(table);
  j["budget"] = {{"full", a.full_budget}, {"nests", params["drift_model"]["nests"]},
                 {"auto_generations", a.full_budget ? DriftAutoOptions{}.search_generations : kDemoAutoGenerations},
                 {"paper_cs_svr_generations", paper.drift_model->summary.generations}};
  return j;
}

// The report of the default pipeline, with the side-by-side and held-out tables first.
std::string ReportHtml(const DemoArgs& a, const SimulatedRun& run, const PipelineResult& ours,
                       const PipelineResult& paper, const HeldOut& h, const SideBySideTable& table,
                       const ComparisonResult* comparison, const nlohmann::json& params) {
  PipelineReportContext ctx;
  ctx.title = "gyrocomp demo: the paper's chamber run, simulated";
  ctx.source = "simulated paper profile (seed " + std::to_string(a.seed) + ")";
  ctx.axis = "rate_dps";
  ctx.time_s = run.time_s;
  ctx.rate_dps = run.rate_dps;
  ctx.temp_c = run.temp_c;
  ctx.parameters = params;
  ctx.comparison = comparison;
  ReportData data = BuildPipelineReport(ours, ctx);
  // The side-by-side table is the headline; the default's before/after table and the held-out
  // validation of both models come first among the tables.
  nlohmann::json& c = data.content;
  nlohmann::json before_after = c["summary"];
  before_after["title"] = "Before and after: gyrocomp default";
  const std::vector<ValidationSection> sections = {
      {"paper pipeline (cs-svr)", &h.paper, &paper.drift_model->summary},
      {"gyrocomp default", &h.ours, &ours.drift_model->summary}};
  c["tables"].insert(c["tables"].begin(), ValidationReportTable(sections, "Held-out run: " + HeldOutLabel(h.options)));
  c["tables"].insert(c["tables"].begin(), before_after);
  c["summary"] = SideBySideReportTable(table, "Side by side: raw, the paper's pipeline, gyrocomp's default and the "
                                              "paper's published figures");
  return RenderReportHtml(data);
}

Result<ComparisonResult> Compare(const SimulatedRun& run, const PipelineInput& input, const PipelineResult& paper,
                                 const PipelineOptions& options, int cs_svr_generations) {
  // The paper's comparisons (Section 4.3) around the paper's pipeline; the serial scheme reuses
  // the CS-SVR parameters (one fit, no second search) and the grid search is left to `compare`.
  ComparisonOptions co;
  co.pipeline = options;
  co.pipeline.drift.model = DriftModelKind::kCsSvr;
  co.pipeline.drift.inputs = DriftInputSet::kTemp;
  co.pipeline.drift.search.cuckoo.max_generations = cs_svr_generations;
  co.grid_search = false;
  co.serial_reuses_parallel_parameters = true;
  return CompareMethods(input, paper, {run.true_rate_dps, run.true_drift_dps}, co);
}

// processed.csv.gz, report.html and summary.json (staged; main() commits them together).
int WriteDemoFiles(const DemoArgs& a, const SimulatedRun& run, const PipelineResult& r, const PipelineResult& paper,
                   const HeldOut& held_out, const SideBySideTable& table, const ComparisonResult* comparison,
                   nlohmann::json params, const std::string& budget, PhaseClock* clock) {
  Table processed = run.ToTable();
  processed.Add("compensated_dps", r.compensated_dps);
  processed.Add("paper_compensated_dps", paper.compensated_dps);
  processed.Add("drift_feature_dps", r.features.drift);
  processed.Add("mixed_feature_dps", r.features.mixed);
  processed.Add("noise_feature_dps", r.features.noise);
  processed.Add("predicted_drift_dps", r.predicted_drift_dps);
  processed.Add("paper_predicted_drift_dps", paper.predicted_drift_dps);
  const std::filesystem::path dir(a.out_dir);
  const std::string csv = (dir / "processed.csv.gz").string();
  if (Status s = WriteCsv(csv, processed); !s) return ReportError(kDemoName, s.error());
  clock->Mark("csv");
  params["simulator"] = {{"profile", "paper"}, {"fs_hz", a.fs_hz}, {"seed", a.seed},
                         {"summary", run.summary.BriefReport()}};
  params["demo_budget"] = budget;
  const std::string report_path = (dir / "report.html").string();
  const std::string html = ReportHtml(a, run, r, paper, held_out, table, comparison, params);
  if (Status s = WriteText(report_path, html); !s) return ReportError(kDemoName, s.error());
  clock->Mark("report");
  nlohmann::json summary = SummaryJson(a, r, paper, held_out, table, params);
  summary["demo_phases"] = clock->Json();
  const std::string json_path = (dir / "summary.json").string();
  if (Status s = WriteJson(json_path, summary); !s) return ReportError(kDemoName, s.error());
  std::printf("\n  time by phase (CPU s, all threads / wall s):");
  for (const auto& [phase, cpu] : summary["demo_phases"]["cpu_s"].items()) {
    std::printf(" %s %.1f/%.1f;", phase.c_str(), cpu.get<double>(), summary["demo_phases"]["wall_s"][phase].get<double>());
  }
  std::printf("\n  wrote %s, %s, %s\n", report_path.c_str(), json_path.c_str(), csv.c_str());
  return kExitOk;
}

int Run(const DemoArgs& a) {
  PhaseClock clock;
  PipelineCliOptions pipe = a.pipeline;
  if (Status s = ResolvePipelineOptions(&pipe); !s) return ReportError(kDemoName, s.error());
  int cs_svr_generations = 0;
  const std::string budget = ApplyDemoBudget(a, &pipe.options, &cs_svr_generations);
  // Options first: a refused --fs must not leave an empty --out folder behind.
  SimulatorOptions sim;
  sim.fs_hz = a.fs_hz;
  sim.seed = a.seed;
  std::string why;
  if (!sim.IsValid(&why)) return ReportError(kDemoName, InvalidArgument(why));
  std::error_code ec;
  const bool existed = std::filesystem::exists(a.out_dir, ec);
  std::filesystem::create_directories(a.out_dir, ec);
  if (ec) return ReportError(kDemoName, IoError(a.out_dir + ": cannot create directory: " + ec.message()));
  // A failed run leaves no folder it created: its temporaries are discarded first.
  // Listed for the signal handler too (RemoveLiveTemporaryFiles: a Ctrl-C mid-run).
  struct RemoveCreatedFolder {
    std::string dir;
    bool armed;
    int listed = armed ? ListCreatedFolder(dir) : -1;
    ~RemoveCreatedFolder() {
      UnlistCreatedFolder(listed);
      if (!armed) return;
      Outputs().Discard();
      std::error_code ignored;
      std::filesystem::remove(dir, ignored);  // only when empty
    }
  } cleanup{a.out_dir, !existed};
  const std::filesystem::path dir(a.out_dir);
  // The three files, checked before the work (cli_common.h: written together at the end).
  for (const char* name : {"processed.csv.gz", "summary.json", "report.html"}) {
    if (Status s = Outputs().Declare((dir / name).string()); !s) return ReportError(kDemoName, s.error());
  }

  Result<SimulatedRun> run = Simulate(sim);
  if (!run) return ReportError(kDemoName, run.error());
  clock.Mark("simulate");
  std::printf("gyrocomp demo: the paper's chamber run (Section 4.1), simulated with ground truth\n  %s\n  %s\n",
              run->summary.BriefReport().c_str(), budget.c_str());

  const PipelineInput input{run->rate_dps, run->temp_c, run->fs_hz, {}};
  Result<PipelineResult> r = RunParallelModel(input, pipe.options, TerminalProgress(kDemoName, a.quiet));
  EndProgress();
  if (!r) return ReportError(kDemoName, r.error());
  if (!r->drift_model) return ReportError(kDemoName, InternalError("demo: the pipeline returned no drift model"));
  clock.Mark("pipeline (default)");
  Result<PipelineResult> paper = PaperPipeline(input, *r, pipe.options, cs_svr_generations);
  if (!paper) return ReportError(kDemoName, paper.error());
  clock.Mark("paper drift branch (cs-svr)");
  Result<HeldOut> held_out = ValidateOnHeldOut(a, *paper->drift_model, *r->drift_model);
  if (!held_out) return ReportError(kDemoName, held_out.error());
  clock.Mark("held-out run");
  std::optional<ComparisonResult> comparison;
  if (a.compare) {
    Result<ComparisonResult> c = Compare(*run, input, *paper, pipe.options, cs_svr_generations);
    if (!c) return ReportError(kDemoName, c.error());
    comparison = std::move(*c);
    clock.Mark("comparisons");
  }

  const SideBySideTable table = MakeDemoTable(*run, *paper, *r, *held_out, pipe.options.drift.model);
  PrintConsole(*r, *paper, table, budget, a.verbose);

  const int code = WriteDemoFiles(a, *run, *r, *paper, *held_out, table, comparison ? &*comparison : nullptr,
                                  PipelineOptionsJson(pipe.options), budget, &clock);
  if (code == kExitOk) cleanup.armed = false;
  return code;
}

Command MakeDemo(CLI::App& app) {
  auto a = std::make_shared<DemoArgs>();
  CLI::App* sub = app.add_subcommand(
      "demo", "Simulate the paper's chamber run and a held-out heating run, process the first with the paper's "
              "pipeline and gyrocomp's default, print the side-by-side table and write the HTML report (no input needed)");
  sub->add_option("--out", a->out_dir, "Output directory")->capture_default_str();
  sub->add_option("--fs", a->fs_hz, "Sample rate of the simulated runs, Hz")->check(CLI::PositiveNumber)->capture_default_str();
  sub->add_option("--sim-seed", a->seed, "Simulator seed")->capture_default_str();
  sub->add_option("--held-out-seed", a->held_out_seed, "Simulator seed of the held-out heating run (default: --sim-seed + 1)");
  sub->add_flag("!--no-compare", a->compare, "Skip the comparison tables");
  sub->add_flag("--full-budget", a->full_budget,
                "Budgets of process (default here: 6 nests, auto's searched candidates 1 generation, the paper's "
                "CS-SVR 2 generations, sample entropy on 100,000 samples per mode)");
  sub->add_flag("-q,--quiet", a->quiet, "No progress on stderr");
  sub->add_flag("-v,--verbose", a->verbose,
                "Each drift model's whole explanation (candidates, term tests, what the run identifies) "
                "instead of one line");
  AddPipelineOptions(sub, &a->pipeline);
  a->app = sub;
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kDemoRegistrar("demo", 10, &MakeDemo);

}  // namespace
}  // namespace gyrocomp::cli
