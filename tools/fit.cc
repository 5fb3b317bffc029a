// gyrocomp fit: fit a temperature-drift model (auto | poly | svr | grid-svr | cs-svr | hybrid) on a
// calibration run, one per rate column, and save them in one JSON model file for `gyrocomp apply`
// (method.md section 4; cli.md; docs/explanation/drift-models.md).
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "console.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/drift/drift_validate.h"
#include "gyrocomp/decompose/feature_classifier.h"
#include "gyrocomp/pipeline/pipeline.h"
#include "gyrocomp/decompose/vmd.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kFitName = "fit";

struct FitArgs {
  LogOptions log;
  DriftFitOptions fit;  // library defaults
  std::string model = "auto";
  std::string inputs = "temp";
  std::string target = "rate";
  std::string scale = "standard";
  std::optional<double> C, gamma, sigma;
  bool search_epsilon = false;
  bool cv_all = false;
  bool keep_kernel = false;
  bool verbose = false;  // the fit's full explanation (candidates, identifiability, data support, noise)
  std::optional<double> known_rate_dps;
  std::string known_rate_col;
  int modes = VmdOptions{}.num_modes;
  std::string out_of_range = "extrapolate";
  std::string cv_scheme;             // "" = automatic
  std::string noise_model = "white";
  std::optional<double> lag_tau_s;   // --lag-tau: fixed; absent: fitted
  std::string validate_path;
  std::string model_path;
  std::string json_path;
};

// The drift feature (sum of the modes classified drift) of `rate`, with the pipeline's defaults.
Result<std::vector<double>> DriftFeature(const std::vector<double>& rate, double fs_hz, int modes,
                                         std::string* report) {
  PipelineOptions p;
  p.vmd.num_modes = modes;
  p.vmd.fs_hz = fs_hz;
  Result<VmdResult> vmd = DecomposeVmd(rate, p.vmd);
  if (!vmd.ok()) return vmd.error();
  Result<ClassificationResult> classes =
      ClassifyVmdModes(*vmd, p.entropy, p.classifier, p.entropy_max_samples);
  if (!classes.ok()) return classes.error();
  *report = classes->BriefReport();
  bool any = false;
  for (const ModeClassification& m : classes->modes) any = any || m.feature == FeatureClass::kDrift;
  if (!any) return InvalidInput("--target drift-mode: no VMD mode was classified drift (" + *report + ")");
  return SumFeatures(*vmd, *classes).drift;
}

// Options from the arguments; an error names the offending flag.
Status ResolveOptions(FitArgs& a) {
  const auto kind = ParseDriftModelKind(a.model);
  const auto inputs = ParseDriftInputSet(a.inputs);
  const auto scale = ParseSvrScaling(a.scale);
  const auto policy = ParseOutOfRangePolicy(a.out_of_range);
  const auto noise = ParseDriftNoiseModel(a.noise_model);
  if (!kind || !inputs || !scale || !policy || !noise)
    return InvalidArgument("bad --model/--inputs/--scale/--out-of-range/--noise-model");
  if (*noise == DriftNoiseModel::kAllan && *kind != DriftModelKind::kPolynomial)
    return InvalidArgument("--noise-model allan: with --model poly only (got --model " + a.model + ")");
  DriftFitOptions& o = a.fit;
  o.model = *kind;
  o.inputs = *inputs;
  o.svr.scaling = *scale;
  o.out_of_range = *policy;
  o.noise_model = *noise;
  if ((a.C || a.gamma || a.sigma) && *kind != DriftModelKind::kSvr)
    return InvalidArgument("--C/--gamma/--sigma fix the SVR's parameters: use them with --model svr "
                           "(grid-svr, cs-svr, hybrid and auto search C and sigma)");
  if (a.C) o.svr.C = *a.C;
  o.svr.gamma = a.gamma;
  o.svr.sigma = a.sigma;
  if (a.cv_all) o.cv_in_range_only = false;
  if (a.keep_kernel) o.hybrid_kernel_test = false;
  if (a.search_epsilon) o.search.epsilon = SearchDimension{"epsilon", 1e-3, 0.5, true};
  if (!a.cv_scheme.empty()) {
    const auto scheme = ParseDriftCvScheme(a.cv_scheme);
    if (!scheme) return InvalidArgument("--cv-scheme must be blocks or segments");
    o.cv_scheme = *scheme;
  }
  if (a.lag_tau_s) {
    o.state.lag_tau_s = *a.lag_tau_s;
    o.fit_lag_tau = false;
  }
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  return Status::Ok();
}

// The target of one axis (rate column k, the drift mode of it, or another column), minus a known
// true rate (Earth rate, turntable) so the model learns the bias only.
Result<std::vector<double>> Target(const FitArgs& a, const LoadedLog& loaded, std::size_t k, std::string* name,
                                   std::string* feature_report) {
  const GyroLog& log = loaded.log;
  const Table& table = loaded.table;
  std::vector<double> target;
  if (a.target == "rate") {
    target = log.rate_dps[k];
    *name = log.axis_names[k];
  } else if (a.target == "drift-mode") {
    Result<std::vector<double>> drift = DriftFeature(log.rate_dps[k], log.fs_hz, a.modes, feature_report);
    if (!drift.ok()) return drift.error();
    target = std::move(*drift);
    *name = "drift-mode";
  } else {
    const int j = table.Find(a.target);
    if (j < 0) return InvalidInput(table.source + ":1: no column '" + a.target + "' for --target");
    target = table.columns[j];
    *name = a.target;
  }
  if (a.known_rate_dps)
    for (double& v : target) v -= *a.known_rate_dps;
  if (!a.known_rate_col.empty()) {
    const int j = table.Find(a.known_rate_col);
    if (j < 0) return InvalidInput(table.source + ":1: no column '" + a.known_rate_col + "' for --known-rate-col");
    for (std::size_t i = 0; i < target.size(); ++i) target[i] -= table.columns[j][i];
  }
  return target;
}

nlohmann::json AxisJson(const FitArgs& a, const DriftModel& m) {
  const DriftFitSummary& s = m.summary;
  nlohmann::json j = DriftSummaryJson(s);
  j["rate_col"] = m.rate_col;
  j["dtemp_range_c_per_s"] = {s.dtemp_min_c_per_s, s.dtemp_max_c_per_s};
  j["best_cv_history_dps"] = s.best_cv_history;
  j["dtemp_window_s"] = a.fit.rate.window_s;
  j["cv_in_range_only"] = s.cv_in_range_only;
  j["drift_span"] = s.drift_span;
  j["data_support"] = s.data_support;
  j["excluded_terms"] = nlohmann::json::array();
  for (const ExcludedTerm& e : s.excluded_terms)
    j["excluded_terms"].push_back({{"term", e.term}, {"reason", e.reason}, {"would_identify", e.would_identify}});
  // auto: each structured term's paired segment-CV gain +- SE over the simpler model (Eq. A-4).
  j["term_admissions"] = nlohmann::json::array();
  for (const TermAdmission& t : s.term_admissions) {
    auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
    j["term_admissions"].push_back({{"term", t.term}, {"candidate", t.candidate}, {"simpler", t.simpler},
                                    {"gain", t.gain.pairs ? finite(t.gain.gain) : nlohmann::json()},
                                    {"gain_se", t.gain.pairs ? finite(t.gain.se) : nlohmann::json()},
                                    {"segments", t.gain.pairs}, {"admitted", t.admitted}, {"note", t.note}});
  }
  if (const auto& b = m.band)
    j["band"] = {{"level", b->level}, {"expected_rms", b->expected_rms}, {"model_form_rms", b->model_form_rms},
                 {"noise", {{"white", b->noise.h0}, {"flicker", b->noise.h_1}, {"random_walk", b->noise.h_2}}}};
  if (s.model == DriftModelKind::kPolynomial) j["noise_model"] = DriftNoiseModelName(s.noise_model);
  if (s.noise_psd)
    j["noise_psd"] = {{"h0", s.noise_psd->h0}, {"h_1", s.noise_psd->h_1}, {"h_2", s.noise_psd->h_2},
                      {"arw_deg_per_sqrt_h", s.noise_psd->arw_deg_per_sqrt_h()},
                      {"bias_instability_deg_per_h", s.noise_psd->bias_instability_deg_per_h()},
                      {"rrw_deg_per_h_per_sqrt_h", s.noise_psd->rrw_deg_per_h_per_sqrt_h()}};
  return j;
}

// fit --validate: the fitted models on another run, per axis.
Result<nlohmann::json> ValidateOn(const FitArgs& a, const DriftModelSet& set) {
  LogOptions other = a.log;
  other.input = a.validate_path;
  Result<LogSpec> spec = ToLogSpec(other);
  if (!spec.ok()) return spec.error();
  spec->temp_required = true;
  spec->keep_cols = std::vector<std::string>{"true_drift_dps"};  // the log and the truth only (memory)
  Result<LoadedLog> loaded = LoadLog(kFitName, other, *spec);
  if (!loaded.ok()) return loaded.error();
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t k = 0; k < set.axes.size(); ++k) {
    const DriftModel& m = set.axes[k];
    const std::size_t axis = k < loaded->log.rate_dps.size() ? k : 0;
    const int truth = loaded->table.Find("true_drift_dps");
    std::vector<double> none;
    auto v = ValidateDriftModel(m, loaded->log.rate_dps[axis], loaded->log.temp_c, loaded->log.fs_hz,
                                truth >= 0 ? loaded->table.columns[truth] : none);
    if (!v.ok()) return v.error();
    if (a.json_path != "-") std::cout << m.rate_col << " on " << a.validate_path << ": " << v->BriefReport() << "\n";
    nlohmann::json j = DriftValidationJson(*v);
    j["rate_col"] = m.rate_col;
    out.push_back(j);
  }
  return out;
}

// One axis on stdout. Default: the model chosen, its fitted range and CV error beside the drift
// span, each candidate term's paired gain +- SE (admitted or rejected), the expected error on the
// next run and the terms left out; --verbose: the fit's full BriefReport and the band's noise.
void PrintAxis(const DriftModel& model, const std::string& feature_report, bool verbose) {
  const DriftFitSummary& s = model.summary;
  const bool dps = model.unit == "deg/s";
  auto figure = [&](double v) { return dps ? RateDps(v) : Figure(v) + " " + model.unit; };
  if (!feature_report.empty() && verbose) std::cout << "VMD modes: " << feature_report << "\n";
  if (verbose) {
    std::cout << model.rate_col << ": " << s.BriefReport() << "\n";
  } else {
    std::cout << model.rate_col << ": " << DriftModelKindName(s.model) << "(" << DriftInputSetName(s.inputs) << ") over "
              << Figure(s.temp_min_c) << " .. " << Figure(s.temp_max_c) << " C, " << s.num_samples << " samples; CV error "
              << figure(s.cv_rmse) << " against a drift span of " << figure(s.drift_span) << "\n";
  }
  // auto: each candidate term's paired gain +- SE over the simpler model, admitted or rejected.
  for (const TermAdmission& t : s.term_admissions)
    std::cout << "  term " << t.BriefReport(dps ? 1000.0 : 1.0, dps ? "mdps" : model.unit) << "\n";
  if (const auto& b = model.band) {
    std::cout << "  expected drift error on a next run like this one: " << figure(b->expected_rms) << " RMS (90% band)";
    if (verbose) std::cout << ", model-form part " << b->model_form_rms << "; noise " << b->noise.BriefReport();
    std::cout << "\n";
  }
  if (!verbose && !s.excluded_terms.empty()) {
    std::string left;
    for (const ExcludedTerm& e : s.excluded_terms) left += (left.empty() ? "" : ", ") + e.term;
    std::cout << "  left out (the run does not identify them; --verbose says why): " << left << "\n";
  }
}

int Run(FitArgs a) {
  if (Status st = ResolveOptions(a); !st.ok()) return ReportError(kFitName, st.error());
  DriftFitOptions& o = a.fit;
  // Which columns are needed: temperature always; the rate unless --target names another column.
  Result<LogSpec> spec = ToLogSpec(a.log);
  if (!spec.ok()) return ReportError(kFitName, spec.error());
  const bool target_is_column = a.target != "rate" && a.target != "drift-mode";
  spec->temp_required = true;
  spec->rates_required = !target_is_column;
  if (target_is_column && spec->rate_cols.size() != 1)
    return ReportError(kFitName, InvalidArgument("--rate-col: with --target COLUMN give one rate column"));
  spec->keep_cols.emplace();  // the log and what Target reads (memory)
  if (target_is_column) spec->keep_cols->push_back(a.target);
  if (!a.known_rate_col.empty()) spec->keep_cols->push_back(a.known_rate_col);
  Result<LoadedLog> loaded = LoadLog(kFitName, a.log, *spec);
  if (!loaded.ok()) return ReportError(kFitName, loaded.error());
  const GyroLog& log = loaded->log;
  WarnIfTemperatureFlat(kFitName, log);

  // One model per axis (--rate-col gx,gy,gz), all in one model file.
  DriftModelSet set;
  set.device_id = log.device_id;  // PX4 ULog: for export --format px4 (TC_G<i>_ID)
  // A flight log's gyro: the model file's "sensor" (docs/reference/model-file.md), which export
  // --index follows. Rate columns other than the gyro's (--target COLUMN) name no sensor.
  if (log.instance && !target_is_column) set.sensor = SensorIdentity{"gyro", *log.instance, log.device_id, "sensor"};
  std::string feature_report;
  const std::size_t axes = target_is_column ? 1 : log.rate_dps.size();
  for (std::size_t k = 0; k < axes; ++k) {
    Result<std::vector<double>> target = Target(a, *loaded, k, &o.target_name, &feature_report);
    if (!target.ok()) return ReportError(kFitName, target.error());
    Result<DriftModel> model = FitDriftModel({log.temp_c, log.fs_hz}, *target, o);
    if (!model.ok()) return ReportError(kFitName, model.error());
    model->rate_col = k < log.axis_names.size() ? log.axis_names[k] : o.target_name;
    if (a.json_path != "-") PrintAxis(*model, feature_report, a.verbose);
    set.axes.push_back(std::move(*model));
  }
  nlohmann::json validation;
  if (!a.validate_path.empty()) {
    auto v = ValidateOn(a, set);
    if (!v.ok()) return ReportError(kFitName, v.error());
    validation = std::move(*v);
  }
  // Through the run's output transaction the model set.
  if (Status s = WriteText(a.model_path, DriftModelSetToJson(set)); !s.ok()) return ReportError(kFitName, s.error());
  if (!a.json_path.empty()) {
    // One axis: its summary at the top level (as before); always: "axes" with one entry per axis.
    nlohmann::json j = AxisJson(a, set.axes[0]);
    j["axes"] = nlohmann::json::array();
    for (const DriftModel& m : set.axes) j["axes"].push_back(AxisJson(a, m));
    j["model_file"] = a.model_path;
    j["input"] = loaded->table.source;
    j["n_samples"] = log.num_samples();
    j["fs_hz"] = log.fs_hz;
    j["known_rate_dps"] = a.known_rate_dps ? nlohmann::json(*a.known_rate_dps) : nlohmann::json();
    j["known_rate_col"] = a.known_rate_col.empty() ? nlohmann::json() : nlohmann::json(a.known_rate_col);
    if (!feature_report.empty()) j["drift_feature"] = feature_report;
    if (!validation.is_null()) j["validation"] = validation;
    if (Status st = WriteJson(a.json_path, j); !st.ok()) return ReportError(kFitName, st.error());
  }
  if (a.json_path != "-") std::cout << "model written to " << a.model_path << "\n";
  return kExitOk;
}

// fit's "Search (grid-svr, cs-svr)" options: the cuckoo and grid searches, auto's budgets and CV.
void AddSearchOptions(CLI::App* sub, FitArgs* a) {
  const std::string s = "Search (grid-svr, cs-svr)";
  sub->add_option("--nests", a->fit.search.cuckoo.num_nests, "Cuckoo-search nests")->group(s)->capture_default_str();
  sub->add_option("--generations", a->fit.search.cuckoo.max_generations, "Cuckoo-search generations (2 x nests fits each)")
      ->group(s)->capture_default_str();
  sub->add_option("--pa", a->fit.search.cuckoo.discovery_probability, "Discovery probability pa")->group(s)->capture_default_str();
  sub->add_option("--seed", a->fit.search.cuckoo.seed, "Seed (the result depends on it only, not on threads)")
      ->group(s)->capture_default_str();
  sub->add_option("--threads", a->fit.search.cuckoo.num_threads, "Threads evaluating parameter sets (default: all cores)")
      ->check(IntegerRange(1, 4096, "CuckooSearchOptions::num_threads"))->group(s);
  sub->add_option("--C-min", a->fit.search.C.lower, "Lower bound of C")->group(s)->capture_default_str();
  sub->add_option("--C-max", a->fit.search.C.upper, "Upper bound of C")->group(s)->capture_default_str();
  sub->add_option("--sigma-min", a->fit.search.sigma.lower, "Lower bound of sigma")->group(s)->capture_default_str();
  sub->add_option("--sigma-max", a->fit.search.sigma.upper, "Upper bound of sigma")->group(s)->capture_default_str();
  sub->add_flag("--search-epsilon", a->search_epsilon, "cs-svr: also search epsilon in [0.001, 0.5]")->group(s);
  sub->add_option("--grid-budget", a->fit.search.grid_budget, "grid-svr: parameter sets (default: cs-svr's budget)")
      ->check(IntegerRange(4, 1'000'000'000, "SvrSearchOptions::grid_budget"))->group(s);
  sub->add_flag("--cv-all", a->cv_all,
                "Score every held-out sample in the blocked CV, also those outside the other blocks' temperature range "
                "(default: in-range only)")->group(s);
  sub->add_option("--cv-scheme", a->cv_scheme,
                  "Cross-validation folds: blocks | segments (default: segments for auto and hybrid, blocks otherwise)")
      ->check(CLI::IsMember({"blocks", "segments"}))->group(s);
  sub->add_option("--auto-generations", a->fit.auto_select.search_generations,
                  "auto: cuckoo-search generations of its cs-svr and hybrid candidates")
      ->check(IntegerRange(1, 1'000'000, "DriftAutoOptions::search_generations"))->group(s)->capture_default_str();
  sub->add_option("--auto-lagged-curve", a->fit.auto_select.lagged_curve_gain_degree,
                  "auto: also try poly(T) + g(T) (T - T_lag), the lag state with a gain of this degree in T (the "
                  "curve read at a lagged temperature), admitted only by its paired gain on segment pieces (Eq. A-4); "
                  "0: not tried")
      ->check(IntegerRange(0, 2, "DriftAutoOptions::lagged_curve_gain_degree"))->group(s)->capture_default_str();
  sub->add_option("--auto-lagged-curve-pieces", a->fit.auto_select.lagged_curve_pieces,
                  "auto: the lagged curve's paired test (Eq. A-4) cuts every thermal segment into this many contiguous "
                  "pieces, one pair each")
      ->check(IntegerRange(1, 1000, "DriftAutoOptions::lagged_curve_pieces"))->group(s)->capture_default_str();
  sub->add_flag("-v,--verbose", a->verbose,
                "The fit's full explanation: every candidate's score, what the run identifies, the data support, the band's noise");
  sub->add_flag("--keep-kernel", a->keep_kernel,
                "hybrid: keep the kernel even when it does not beat the structured part by more than the "
                "block-to-block spread of its CV gain (default: dropped then, and the model is its structured part)")
      ->group(s);
  sub->add_option("--cv-folds", a->fit.cv_folds, "Contiguous blocks of the blocked cross-validation")
      ->check(IntegerRange(2, 1'000'000, "DriftFitOptions::cv_folds"))->group(s)->capture_default_str();
}

Command MakeFit(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  CLI::App* sub = app.add_subcommand(
      kFitName, "Fit a temperature-drift model (auto, poly, SVR, grid/cuckoo-searched SVR, hybrid) per axis and save it");
  sub->footer(
      "The model maps temperature [and a thermal state: dT/dt, lag, memory] to drift. --model auto\n"
      "(default) fits poly with each state, svr, cs-svr and hybrid, scores them by cross-validation\n"
      "leaving out whole thermal segments, and keeps the best (it prints why). The SVR family trains\n"
      "on block means of --train-period seconds (automatic: none when the record has at most\n"
      "--max-train samples, else max(30 s, duration / --max-train)) and predicts at the full rate;\n"
      "grid-svr and cs-svr choose C and sigma by blocked cross-validation (--cv-folds contiguous\n"
      "blocks: random folds leak, the drift is autocorrelated); grid-svr uses the same number of\n"
      "parameter sets as cs-svr. The polynomial is fitted on every sample. With --scale standard\n"
      "(default) inputs and target are standardised: sigma in input SDs, epsilon in target SDs.\n"
      "dT/dt: least-squares slope over a centred --dtemp-window (robust to quantized temperature).\n"
      "JSON: model, inputs, target, C, gamma, sigma, epsilon, num_support, degree, cv_rmse_dps,\n"
      "  train_rmse_dps, num_train, train_period_s, temp_range_c, evaluations, fit_time_s, candidates,\n"
      "  selection_reason, identifiability, noise_model, noise_psd (--noise-model allan), axes (one entry\n"
      "  per rate column), validation, ...\n"
      "Examples:\n"
      "  gyrocomp fit -i chamber.csv --model cs-svr -o model.json --json fit.json\n"
      "  gyrocomp fit -i chamber.csv --model poly --degree 3 --inputs temp,dtemp -o poly.json\n"
      "  gyrocomp fit -i train.csv --target drift_dps --model svr --scale none --C 1 --gamma 0.001 \\\n"
      "      --epsilon 0.005 --svr-tol 1e-6 -o svr.json");
  AddLogOptions(sub, &a->log);
  sub->add_option("--model", a->model,
                  "Model: auto (compares the others on left-out thermal segments) | poly | svr | grid-svr | cs-svr "
                  "(the paper) | hybrid (poly + CS-SVR on its residual)")
      ->check(CLI::IsMember({"auto", "cs-svr", "svr", "grid-svr", "poly", "hybrid"}))->capture_default_str();
  sub->add_option("--inputs", a->inputs,
                  "Model inputs (not with auto): temp | temp,dtemp | temp,lag | temp,memory | temp,dtemp,memory")
      ->check(CLI::IsMember({"temp", "temp,dtemp", "temp,lag", "temp,memory", "temp,dtemp,memory"}))
      ->capture_default_str();
  sub->add_option("--lag-tau", a->lag_tau_s, "temp,lag: time constant of the lag state, s (default: fitted)");
  sub->add_option("--out-of-range", a->out_of_range,
                  "Temperature outside the fitted range: extrapolate | clamp (stored in the model file)")
      ->check(CLI::IsMember({"extrapolate", "clamp"}))->capture_default_str();
  AddInputOption(sub, "--validate", &a->validate_path,
                  "Also validate the fitted model on another run (as gyrocomp validate; its columns as -i)");
  sub->add_option("--target", a->target,
                  "What to model: rate (the rate column), drift-mode (sum of the VMD modes classified drift), or a column name")
      ->capture_default_str();
  sub->add_option("--modes", a->modes, "VMD modes K for --target drift-mode")->capture_default_str();
  sub->add_option("--known-rate", a->known_rate_dps, "Known true rate during calibration (deg/s), subtracted from the target");
  sub->add_option("--known-rate-col", a->known_rate_col, "Column of the known true rate (deg/s), subtracted from the target");
  const std::string g = "SVR";
  auto* c = sub->add_option("--C", a->C, "SVR regularisation C (--model svr; default 1)")->group(g);
  auto* gamma = sub->add_option("--gamma", a->gamma, "RBF gamma = 1/(2 sigma^2) (--model svr; default 1/inputs)")->group(g);
  auto* sigma = sub->add_option("--sigma", a->sigma, "RBF width sigma (--model svr)")->group(g);
  gamma->excludes(sigma);
  (void)c;
  sub->add_option("--epsilon", a->fit.svr.epsilon, "epsilon of the insensitive tube (target SDs when scaled, else deg/s)")
      ->group(g)->capture_default_str();
  sub->add_option("--svr-tol", a->fit.svr.tolerance, "LIBSVM stopping tolerance (its -e)")->group(g)->capture_default_str();
  sub->add_option("--scale", a->scale, "standard: standardise inputs and target; none: raw (gamma in 1/degC^2)")
      ->check(CLI::IsMember({"standard", "none"}))->group(g)->capture_default_str();
  AddSearchOptions(sub, a.get());
  const std::string d = "Data";
  sub->add_option("--train-period", a->fit.train_period_s, "Block-mean period of the SVR training copy, s (default automatic)")->group(d);
  sub->add_option("--max-train", a->fit.max_train_samples, "Automatic period: at most this many training samples")
      ->check(IntegerRange(10, 1'000'000'000'000, "DriftFitOptions::max_train_samples"))
      ->group(d)->capture_default_str();
  sub->add_option("--dtemp-window", a->fit.rate.window_s, "Window of the dT/dt slope, s")->group(d)->capture_default_str();
  sub->add_option("--degree", a->fit.polynomial.degree, "poly: degree in temperature (1..5)")
      ->check(IntegerRange(1, 5, "PolynomialOptions::degree"))->group(d)->capture_default_str();
  sub->add_option("--noise-model", a->noise_model,
                  "poly: white (ordinary least squares, default) | allan (generalised least squares with white + "
                  "flicker + random walk fitted to the Allan variance of the OLS residual; helps only where the "
                  "polynomial's form is right: docs/explanation/drift-models.md)")
      ->check(CLI::IsMember({"white", "allan"}))->group(d)->capture_default_str();
  sub->add_option("--gls-block", a->fit.gls_block_s, "--noise-model allan: block-mean period of the GLS fit, s")
      ->group(d)->capture_default_str();
  sub->add_option("--dtemp-degree", a->fit.polynomial.dtemp_degree, "poly: degree in dT/dt (1..3) with --inputs temp,dtemp")
      ->check(IntegerRange(1, 3, "PolynomialOptions::dtemp_degree"))
      ->group(d)->capture_default_str();
  sub->add_option("--gain-temp-degree", a->fit.polynomial.gain_temp_degree,
                  "poly with a state: degree in T of the state's gain (0: constant; 2: a cubic read at a lagged "
                  "temperature; not with auto)")
      ->check(IntegerRange(0, 2, "PolynomialOptions::gain_temp_degree"))
      ->group(d)->capture_default_str();
  AddOutputOption(sub, "-o,--output", &a->model_path, "Model file to write (JSON)")->required();
  AddOutputOption(sub, "--json", &a->json_path, "Write the fit summary as JSON to FILE ('-' = stdout)");
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kFitRegistrar(kFitName, 60, &MakeFit);

}  // namespace
}  // namespace gyrocomp::cli
