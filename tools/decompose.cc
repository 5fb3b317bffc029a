// gyrocomp decompose: VMD of the rate column(s), then sample entropy and the drift / mixed /
// noise class of every mode (steps 1-2 of the pipeline; method.md sections 1-2).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "entropy_memory.h"
#include "gyrocomp/decompose/feature_classifier.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/pipeline/pipeline.h"
#include "gyrocomp/decompose/sample_entropy.h"
#include "gyrocomp/decompose/vmd.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kDecomposeName = "decompose";

struct DecomposeArgs {
  LogOptions log;
  VmdOptions vmd;  // library defaults
  std::string init = "uniform";
  std::string stop = "absolute";
  std::string accel = "auto";
  int dc = 0;
  SampleEntropyOptions entropy;
  // Same default as `process` (PipelineOptions), so both classify the same way.
  std::optional<std::size_t> entropy_max_samples = kDefaultEntropyMaxSamples;
  bool entropy_all = false;
  std::string rule = "standard";
  std::optional<double> drift_max_se, noise_min_se, drift_max_frequency_hz;
  std::string json_path;
  std::string csv_path;
};

nlohmann::json Finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

struct AxisResult {
  std::string axis;
  VmdResult vmd;
  ClassificationResult classes;
};

nlohmann::json AxisJson(const AxisResult& r, const GyroLog& log, const SampleEntropyOptions& se,
                        std::optional<std::size_t> max_samples) {
  nlohmann::json j;
  const VmdSummary& s = r.vmd.summary;
  j["fs_hz"] = log.fs_hz;
  j["n_samples"] = log.num_samples();
  j["iterations"] = s.iterations;
  j["converged"] = s.converged;
  j["omega_extrapolation_period"] =
      s.omega_extrapolation_period ? nlohmann::json(*s.omega_extrapolation_period) : nlohmann::json();
  j["final_update"] = s.final_update;
  j["vmd_seconds"] = s.elapsed_s;
  j["modes"] = nlohmann::json::array();
  for (const ModeClassification& m : r.classes.modes) {
    const std::vector<double>& u = r.vmd.modes[m.index - 1];
    // RMS scaled by the largest |value| (no overflow of the squares for values near 1e308).
    double peak = 0, ss = 0;
    for (double v : u) peak = std::max(peak, std::abs(v));
    for (double v : u) ss += peak > 0 ? (v / peak) * (v / peak) : 0.0;
    j["modes"].push_back({{"index", m.index},
                          {"center_frequency_hz", m.center_frequency_hz},
                          {"center_frequency_cycles_per_sample", m.center_frequency_cycles_per_sample},
                          {"sample_entropy", Finite(m.sample_entropy)},
                          {"class", FeatureClassName(m.feature)},
                          {"rms_dps", u.empty() ? 0.0 : peak * std::sqrt(ss / u.size())}});
  }
  j["classification"] = {{"rule", r.classes.rule.rule_name},
                         {"description", r.classes.rule_text},
                         {"drift_max_se", r.classes.rule.drift_max_se},
                         {"noise_min_se", r.classes.rule.noise_min_se},
                         {"drift_max_frequency_hz", r.classes.rule.drift_max_frequency_hz
                                                        ? nlohmann::json(*r.classes.rule.drift_max_frequency_hz)
                                                        : nlohmann::json()},
                         {"keep_lowest_mode", r.classes.rule.keep_lowest_mode}};
  j["sample_entropy"] = {{"m", se.m},
                         {"r_factor", se.r_factor},
                         {"r_of", "each mode's own SD (population)"},
                         {"max_samples", max_samples ? nlohmann::json(*max_samples) : nlohmann::json()}};
  return j;
}

void PrintTable(const AxisResult& r) {
  std::cout << r.vmd.summary.BriefReport() << "\n";
  std::cout << "  mode  centre_Hz      cycles/sample  SampEn    class\n";
  for (const ModeClassification& m : r.classes.modes) {
    std::cout << "  " << std::setw(4) << m.index << "  " << std::setw(13) << std::setprecision(6)
              << m.center_frequency_hz << "  " << std::setw(13) << m.center_frequency_cycles_per_sample << "  "
              << std::setw(8) << std::setprecision(4) << m.sample_entropy << "  " << FeatureClassName(m.feature)
              << "\n";
  }
  std::cout << "  rule: " << r.classes.rule_text << "\n";
}

int Run(DecomposeArgs a) {
  ReuseFreedMemory();
  a.vmd.init = a.init == "zero" ? VmdInit::kZero : a.init == "random" ? VmdInit::kRandom : VmdInit::kUniform;
  a.vmd.stopping_rule = a.stop == "relative" ? VmdStoppingRule::kRelative : VmdStoppingRule::kAbsolute;
  if (a.accel == "off") a.vmd.omega_extrapolation_period.reset();
  a.vmd.dc = a.dc != 0;
  ClassifierOptions rule = a.rule == "paper" ? ClassifierOptions::Paper() : ClassifierOptions::Standard();
  if (a.drift_max_se) rule.drift_max_se = *a.drift_max_se;
  if (a.noise_min_se) rule.noise_min_se = *a.noise_min_se;
  if (a.drift_max_frequency_hz) rule.drift_max_frequency_hz = *a.drift_max_frequency_hz;
  if (a.drift_max_se || a.noise_min_se || a.drift_max_frequency_hz) rule.rule_name = "custom";
  if (a.entropy_all) a.entropy_max_samples.reset();
  std::string why;
  if (!a.vmd.IsValid(&why) || !a.entropy.IsValid(&why) || !rule.IsValid(&why)) {
    return ReportError(kDecomposeName, InvalidArgument(why));
  }

  Result<LogSpec> spec = ToLogSpec(a.log);
  if (!spec.ok()) return ReportError(kDecomposeName, spec.error());
  spec->min_samples = 4;
  Result<GyroLog> log = ReadGyroLog(a.log.input, *spec);
  if (!log.ok()) return ReportError(kDecomposeName, log.error());
  if (log->sampling.resampled) Note(kDecomposeName, log->sampling.BriefReport());

  std::vector<AxisResult> results;
  for (std::size_t axis = 0; axis < log->rate_dps.size(); ++axis) {
    VmdOptions vmd = a.vmd;
    vmd.fs_hz = log->fs_hz;
    Result<VmdResult> v = DecomposeVmd(log->rate_dps[axis], vmd);
    if (!v.ok()) return ReportError(kDecomposeName, Error{v.error().kind, log->source + ": " + log->axis_names[axis] + ": " + v.error().message});
    Result<ClassificationResult> c = ClassifyVmdModes(*v, a.entropy, rule, a.entropy_max_samples);
    if (!c.ok()) return ReportError(kDecomposeName, Error{c.error().kind, log->source + ": " + log->axis_names[axis] + ": " + c.error().message});
    if (!v->summary.converged) {
      Note(kDecomposeName, log->axis_names[axis] + ": VMD stopped at --max-iter without meeting --tol (" + v->summary.BriefReport() + ")");
    }
    results.push_back({log->axis_names[axis], std::move(*v), std::move(*c)});
  }

  if (!a.csv_path.empty()) {
    Table t;
    for (const AxisResult& r : results) {
      const std::string prefix = results.size() == 1 ? "" : r.axis + "_";
      for (std::size_t k = 0; k < r.vmd.modes.size(); ++k) t.Add(prefix + "mode_" + std::to_string(k + 1), r.vmd.modes[k]);
    }
    if (Status s = WriteCsv(a.csv_path, t); !s.ok()) return ReportError(kDecomposeName, s.error());
  }
  if (!a.json_path.empty()) {
    nlohmann::json j;
    if (results.size() == 1) {
      j = AxisJson(results.front(), *log, a.entropy, a.entropy_max_samples);
    } else {
      j["fs_hz"] = log->fs_hz;
      j["n_samples"] = log->num_samples();
      j["axes"] = nlohmann::json::object();
      for (const AxisResult& r : results) j["axes"][r.axis] = AxisJson(r, *log, a.entropy, a.entropy_max_samples);
    }
    j["input"] = log->source;
    j["vmd_options"] = {{"K", a.vmd.num_modes}, {"alpha", a.vmd.alpha}, {"tau", a.vmd.tau}, {"tol", a.vmd.tol},
                        {"dc", a.vmd.dc}, {"init", a.init}, {"seed", a.vmd.seed},
                        {"max_iterations", a.vmd.max_iterations}, {"stopping_rule", a.stop},
                        {"accel", a.accel}};
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kDecomposeName, s.error());
  }
  if (a.json_path != "-") {
    for (const AxisResult& r : results) {
      if (results.size() > 1) std::cout << r.axis << ":\n";
      PrintTable(r);
    }
  }
  return kExitOk;
}

Command MakeDecompose(CLI::App& app) {
  auto args = std::make_shared<DecomposeArgs>();
  CLI::App* sub = app.add_subcommand(
      kDecomposeName,
      "Variational mode decomposition of the rate, then the sample entropy and the drift / mixed / "
      "noise class of every mode (paper Sections 3.1, 3.2, 3.5; method.md sections 1-2)");
  sub->footer(
      "VMD is the reference algorithm (Dragomiretskiy & Zosso; vmdpy): mirror extension, one-sided\n"
      "spectrum, Gauss-Seidel mode updates, stop when sum ||du||^2 / T <= --tol or after --max-iter - 1\n"
      "updates. Modes are in the algorithm's order (mode k started from init centre frequency k).\n"
      "Sample entropy: Richman-Moorman, m = --m, r = --r x each mode's SD, strict '<', computed on the\n"
      "middle --entropy-max-samples samples of each mode (as `process`), exact fast counting.\n"
      "Classes (--rule standard, docs/explanation/classification.md): SE < 0.3 drift, 0.3..0.5 mixed, > 0.5 noise,\n"
      "  and the lowest-frequency mode (mean, bias, slowest drift) is never noise.\n"
      "  --rule paper: SE < 2 drift, 2..4.2 mixed, > 4.2 noise (the paper's scale; on the standard\n"
      "  scale white noise is ~2.18 and its VMD modes ~0.6, so 'noise' never fires).\n"
      "Outputs: -o CSV with columns mode_1..mode_K (<axis>_mode_k for several axes);\n"
      "  --json: iterations, converged, modes[] {index, center_frequency_hz,\n"
      "  center_frequency_cycles_per_sample, sample_entropy, class, rms_dps}, the rule and options.\n"
      "With --fs 1 and no time column, center_frequency_hz equals cycles per sample.\n"
      "Example: gyrocomp decompose -i log.csv --modes 6 -o modes.csv --json modes.json");
  AddLogOptions(sub, &args->log);
  const char* g = "VMD";
  sub->add_option("--modes", args->vmd.num_modes, "Number of modes K (paper: 6)")->group(g)->capture_default_str();
  sub->add_option("--alpha", args->vmd.alpha, "Bandwidth penalty alpha (reference-code scale)")->group(g)->capture_default_str();
  sub->add_option("--tau", args->vmd.tau, "Dual-ascent step tau (0 = noise-slack)")->group(g)->capture_default_str();
  sub->add_option("--tol", args->vmd.tol, "Convergence tolerance")->group(g)->capture_default_str();
  sub->add_option("--dc", args->dc, "Keep mode 1 at 0 Hz (0|1)")->group(g)->check(CLI::IsMember({0, 1}))->capture_default_str();
  sub->add_option("--init", args->init, "Initial centre frequencies: zero, uniform (k 0.5/K) or random (--seed)")
      ->group(g)->check(CLI::IsMember({"zero", "uniform", "random"}))->capture_default_str();
  sub->add_option("--seed", args->vmd.seed, "Seed of --init random (numpy np.random.seed semantics)")->group(g)->capture_default_str();
  sub->add_option("--max-iter", args->vmd.max_iterations, "Maximum iterations (reference Niter: at most N-1 updates)")
      ->group(g)->capture_default_str();
  sub->add_option("--vmd-stop", args->stop, "Stopping rule: absolute (reference code) or relative (paper Eq. 7)")
      ->group(g)->check(CLI::IsMember({"absolute", "relative"}))->capture_default_str();
  sub->add_option("--vmd-accel", args->accel,
                  "auto: extrapolate the centre frequencies every 5 updates on records of >= 100000 samples "
                  "(converges in ~4.5x fewer updates); off: the reference iteration at every length")
      ->group(g)->check(CLI::IsMember({"auto", "off"}))->capture_default_str();
  g = "Sample entropy";
  sub->add_option("--m", args->entropy.m, "Embedding dimension m")->group(g)->capture_default_str();
  sub->add_option("--r", args->entropy.r_factor, "Tolerance r as a factor of each mode's SD")->group(g)->capture_default_str();
  sub->add_option("--entropy-max-samples", args->entropy_max_samples,
                  "Sample entropy on at most this many samples of each mode (middle window; default " +
                      (args->entropy_max_samples ? std::to_string(*args->entropy_max_samples) : std::string("all")) +
                      ", as process)")
      ->check(IntegerRange(16, 1'000'000'000'000, "ClassifyVmdModes: entropy_max_samples"))
      ->group(g);
  sub->add_flag("--entropy-all", args->entropy_all, "Sample entropy on every sample of each mode")->group(g);
  g = "Classification";
  sub->add_option("--rule", args->rule, "Thresholds: standard (docs/explanation/classification.md) or paper (2 / 4.2)")
      ->group(g)->check(CLI::IsMember({"standard", "paper"}))->capture_default_str();
  sub->add_option("--drift-max-se", args->drift_max_se, "Override: SE below this is drift")->group(g);
  sub->add_option("--noise-min-se", args->noise_min_se, "Override: SE above this is noise-only")->group(g);
  sub->add_option("--drift-max-freq", args->drift_max_frequency_hz,
                  "Optional guard: a drift-by-SE mode at or above this centre frequency (Hz) is mixed")->group(g);
  g = "Output";
  AddOutputOption(sub, "-o,--output", &args->csv_path, "Write the modes as CSV to FILE")->group(g);
  AddOutputOption(sub, "--json", &args->json_path, "Write the results as JSON to FILE ('-' = stdout)")->group(g);
  return {sub, [args] { return Run(*args); }};
}

const CommandRegistrar kDecomposeRegistrar(kDecomposeName, 40, &MakeDecompose);

}  // namespace
}  // namespace gyrocomp::cli
