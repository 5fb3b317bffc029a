#include "stage_options.h"

#include "gyrocomp/denoise/wavelet.h"
#include "gyrocomp/denoise/wavelet_denoise.h"
#include "result_json.h"

namespace gyrocomp::cli {

// Integer counts are refused at parse time outside their range (IntegerRange); the
// ranges are the library's IsValid (named in each message).
void AddPipelineOptions(CLI::App* app, PipelineCliOptions* c) {
  PipelineOptions& o = c->options;
  const char* g = "VMD";
  app->add_option("--modes", o.vmd.num_modes, "Number of VMD modes K (paper: 6)")->group(g)->capture_default_str();
  app->add_option("--alpha", o.vmd.alpha, "VMD bandwidth penalty alpha (reference-code scale)")->group(g)->capture_default_str();
  app->add_option("--tau", o.vmd.tau, "VMD dual-ascent step (0 = noise-slack)")->group(g)->capture_default_str();
  app->add_option("--tol", o.vmd.tol, "VMD convergence tolerance")->group(g)->capture_default_str();
  app->add_option("--dc", o.vmd.dc, "Keep mode 1 at 0 Hz (0|1)")->group(g)->capture_default_str();
  app->add_option("--init", c->vmd_init, "Initial centre frequencies")->group(g)
      ->check(CLI::IsMember({"zero", "uniform", "random"}))->capture_default_str();
  app->add_option("--max-iter", o.vmd.max_iterations, "VMD maximum iterations")->group(g)->capture_default_str();
  app->add_option("--vmd-stop", c->vmd_stop, "Stopping rule: absolute (reference code) or relative (paper Eq. 7)")
      ->group(g)->check(CLI::IsMember({"absolute", "relative"}))->capture_default_str();
  app->add_option("--vmd-accel", c->vmd_accel,
                  "auto: extrapolate the VMD centre frequencies every 5 updates on records of >= 100000 samples; "
                  "off: the reference iteration at every length")
      ->group(g)->check(CLI::IsMember({"auto", "off"}))->capture_default_str();

  g = "Sample entropy";
  app->add_option("--m", o.entropy.m, "Embedding dimension m")->group(g)->capture_default_str();
  app->add_option("--r", o.entropy.r_factor, "Tolerance r as a factor of each mode's SD")->group(g)->capture_default_str();
  app->add_option("--entropy-max-samples", o.entropy_max_samples,
                  "Sample entropy on at most this many samples of each mode (middle window)")
      ->check(IntegerRange(100, 1'000'000'000'000, "PipelineOptions::entropy_max_samples"))->group(g);

  g = "Classification";
  app->add_option("--rule", c->rule, "drift/mixed/noise thresholds: standard (docs/explanation/classification.md) or paper (SE < 2 drift, > 4.2 noise)")
      ->group(g)->check(CLI::IsMember({"standard", "paper"}))->capture_default_str();
  app->add_option("--drift-max-se", c->drift_max_se, "Override: SE below this is drift")->group(g);
  app->add_option("--noise-min-se", c->noise_min_se, "Override: SE above this is noise-only")->group(g);

  g = "WFLP";
  app->add_option("--wavelet", o.wflp.wavelet, "Wavelet (haar, dbN, symN, coifN)")->group(g)->capture_default_str();
  app->add_option("--level", o.wflp.level, "Decomposition level")
      ->check(IntegerRange(0, 64, "WflpOptions::level"))->group(g);
  app->add_option("--extension", c->wavelet_extension, "Signal extension mode")->group(g)
      ->check(CLI::IsMember({"symmetric", "periodization", "periodic", "zero"}))->capture_default_str();
  app->add_option("--details", c->details, "Detail coefficients: threshold, keep or zero")->group(g)
      ->check(CLI::IsMember({"threshold", "keep", "zero"}))->capture_default_str();
  app->add_option("--threshold-mode", c->threshold_mode, "soft or hard")->group(g)
      ->check(CLI::IsMember({"soft", "hard"}))->capture_default_str();
  app->add_option("--flp-order", o.wflp.flp.order, "FLP order N (Eq. 14)")->group(g)->capture_default_str();
  app->add_option("--flp-beta", o.wflp.flp.beta, "FLP maximum step beta (Eq. 16)")->group(g)->capture_default_str();
  app->add_option("--flp-alpha", o.wflp.flp.alpha, "FLP step sensitivity alpha (Eq. 16)")->group(g)->capture_default_str();

  g = "Drift model";
  app->add_option("--model", c->model, "Drift model: auto | cs-svr (the paper) | svr | grid-svr | poly | hybrid")->group(g)
      ->check(CLI::IsMember({"auto", "cs-svr", "svr", "grid-svr", "poly", "hybrid"}))->capture_default_str();
  app->add_option("--inputs", c->inputs, "Model inputs: temp | temp,dtemp | temp,lag | temp,memory (not with auto)")->group(g)
      ->check(CLI::IsMember({"temp", "temp,dtemp", "temp,lag", "temp,memory"}))->capture_default_str();
  app->add_option("--degree", o.drift.polynomial.degree, "Polynomial degree in temperature (poly)")
      ->check(IntegerRange(1, 5, "PolynomialOptions::degree"))->group(g)->capture_default_str();
  app->add_option("--C", c->svr_C, "SVR C (svr)")->group(g);
  app->add_option("--gamma", c->svr_gamma, "SVR RBF gamma (svr)")->group(g);
  app->add_option("--sigma", c->svr_sigma, "SVR RBF sigma, gamma = 1/(2 sigma^2) (svr)")->group(g);
  app->add_option("--epsilon", o.drift.svr.epsilon, "SVR epsilon (target SDs when scaled)")->group(g)->capture_default_str();
  app->add_option("--svr-tol", o.drift.svr.tolerance, "LIBSVM stopping tolerance")->group(g)->capture_default_str();
  app->add_option("--scale", c->scale, "SVR input scaling")->group(g)
      ->check(CLI::IsMember({"standard", "none"}))->capture_default_str();
  app->add_option("--nests", o.drift.search.cuckoo.num_nests, "Cuckoo-search nests")->group(g)->capture_default_str();
  app->add_option("--generations", o.drift.search.cuckoo.max_generations, "Cuckoo-search generations")->group(g)->capture_default_str();
  app->add_option("--pa", o.drift.search.cuckoo.discovery_probability, "Cuckoo-search discovery probability")->group(g)->capture_default_str();
  app->add_option("--seed", o.drift.search.cuckoo.seed, "Cuckoo-search seed")->group(g)->capture_default_str();
  app->add_option("--cv-folds", o.drift.cv_folds, "Contiguous blocks of the blocked cross-validation")
      ->check(IntegerRange(2, 1'000'000, "DriftFitOptions::cv_folds"))->group(g)->capture_default_str();
  app->add_option("--train-period", o.drift.train_period_s, "Block-mean period of the SVR training copy, s")->group(g);

  g = "Allan";
  app->add_option("--taus", c->taus, "Tau grid: octave, decade, all or N per decade")->group(g)->capture_default_str();

  g = "Bandwidth";
  app->add_flag("--no-bandwidth", c->no_bandwidth, "Skip the effective-bandwidth measurement")->group(g);
  app->add_option("--bandwidth-segment", o.bandwidth_segment_samples, "Samples of the record used for it")
      ->check(IntegerRange(1024, 1'000'000'000, "PipelineOptions::bandwidth_segment_samples"))
      ->group(g)->capture_default_str();
}

Status ResolvePipelineOptions(PipelineCliOptions* c) {
  PipelineOptions& o = c->options;
  o.vmd.init = c->vmd_init == "zero" ? VmdInit::kZero : c->vmd_init == "random" ? VmdInit::kRandom : VmdInit::kUniform;
  o.vmd.stopping_rule = c->vmd_stop == "relative" ? VmdStoppingRule::kRelative : VmdStoppingRule::kAbsolute;
  if (c->vmd_accel == "off") o.vmd.omega_extrapolation_period.reset();
  o.classifier = c->rule == "paper" ? ClassifierOptions::Paper() : ClassifierOptions::Standard();
  if (c->drift_max_se) { o.classifier.drift_max_se = *c->drift_max_se; o.classifier.rule_name = "custom"; }
  if (c->noise_min_se) { o.classifier.noise_min_se = *c->noise_min_se; o.classifier.rule_name = "custom"; }
  o.wflp.extension = *ParseExtensionMode(c->wavelet_extension);
  o.wflp.details = *ParseDetailHandling(c->details);
  o.wflp.threshold_mode = *ParseThresholdMode(c->threshold_mode);
  o.drift.model = *ParseDriftModelKind(c->model);
  o.drift.inputs = *ParseDriftInputSet(c->inputs);
  o.drift.svr.scaling = *ParseSvrScaling(c->scale);
  if (c->svr_C) o.drift.svr.C = *c->svr_C;
  if (c->svr_gamma && c->svr_sigma) return InvalidArgument("--gamma and --sigma: give one of them");
  o.drift.svr.gamma = c->svr_gamma;
  o.drift.svr.sigma = c->svr_sigma;
  const auto grid = ParseTauGrid(c->taus, &o.allan.points_per_decade);
  if (!grid) return InvalidArgument("--taus " + c->taus + ": must be octave, decade, all or a positive integer");
  o.allan.grid = *grid;
  o.measure_bandwidth = !c->no_bandwidth;
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  return Status::Ok();
}

Result<LoadedLog> LoadPipelineLog(const std::string& command, const LogOptions& log, PipelineCliOptions* pipe,
                                  std::optional<std::vector<std::string>> keep_cols) {
  if (Status s = ResolvePipelineOptions(pipe); !s) return s.error();
  Result<LogSpec> spec = ToLogSpec(log);
  if (!spec) return spec.error();
  spec->temp_required = true;
  spec->min_samples = 256;  // the parallel model's floor (VMD + blocked CV)
  spec->keep_cols = std::move(keep_cols);
  return LoadLog(command, log, *spec);
}

}  // namespace gyrocomp::cli
