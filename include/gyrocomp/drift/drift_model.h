// Temperature-drift model (paper Section 3.4, comparison in 4.3.3; method.md section 4): drift as
// a function of temperature and one thermal state (thermal_state.h), fitted on a calibration run,
// saved as JSON, applied to later records.
//
// Models:
//   poly      least squares (Eigen) in standardised temperature, degree 1..5, plus powers of the
//             state when the inputs include one: what calibration engineers use today;
//   svr       epsilon-SVR (svr.h) with the parameters given (LIBSVM defaults unless set);
//   grid-svr  SVR with C and sigma chosen by a log-spaced grid at the cuckoo search's budget;
//   cs-svr    SVR with C and sigma (optionally epsilon) chosen by cuckoo search (the paper);
//   hybrid    the polynomial (structured part) plus a cuckoo-searched SVR fitted to its residual.
//             The SVR's intercept is folded into the polynomial's constant, so far from the
//             training support (where an RBF kernel vanishes) the model is the polynomial alone:
//             extrapolation falls back to the physics, inside the support the kernel learns what
//             the polynomial cannot;
//   auto      (fit option only) fits the candidates above with each thermal state and keeps the one
//             with the lowest cross-validation score over left-out thermal segments.
// Parameter choice minimises a blocked cross-validation RMSE. kBlocks (poly/svr/grid-svr/cs-svr
// by default, the paper's pipeline): the (decimated) record is cut into `cv_folds` contiguous
// blocks, each predicted by a model fitted on the others. kThermalSegments (hybrid and auto): the
// temperature trace is cut into ramps and holds and each fold leaves out whole segments, so the
// score includes the extrapolation a new run demands. Random folds would leak: the drift is
// strongly autocorrelated.
//
// Decimation: the drift is slow (minutes to hours), so the SVR family is trained on block means
// over `train_period_s` (the block mean is the anti-alias filter) and predicts at the full rate.
// The polynomial is fitted on every sample (cheap), and scored with the same blocked CV.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "gyrocomp/drift/cuckoo_search.h"
#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/noise_model.h"
#include "gyrocomp/drift/svr.h"
#include "gyrocomp/drift/term_admission.h"
#include "gyrocomp/drift/temperature_rate.h"
#include "gyrocomp/drift/thermal_state.h"

namespace gyrocomp {

// kAuto is a fit option only: a fitted model has one of the other kinds.
enum class DriftModelKind { kPolynomial, kSvr, kGridSvr, kCsSvr, kHybrid, kAuto };
// "poly" | "svr" | "grid-svr" | "cs-svr" | "hybrid" | "auto".
std::optional<DriftModelKind> ParseDriftModelKind(std::string_view name);
// The name ParseDriftModelKind reads.
const char* DriftModelKindName(DriftModelKind kind);

// What a model does with a temperature outside the range it was fitted on. One policy for
// `apply`, the exporters (src/export/) and the generated C:
//   kExtrapolate  evaluate the model at the temperature as it is (the default, and what every
//                 version-1 model file did); `apply` warns with the amounts;
//   kClamp        clamp the temperature input to [temp_min_c, temp_max_c] of the fit before the
//                 model function; the thermal state is computed from the unclamped temperature
//                 and never clamped (its extrapolation is what the structured part is for).
enum class OutOfRangePolicy { kExtrapolate, kClamp };
// "extrapolate" | "clamp".
std::optional<OutOfRangePolicy> ParseOutOfRangePolicy(std::string_view name);
// The name ParseOutOfRangePolicy reads.
const char* OutOfRangePolicyName(OutOfRangePolicy policy);

// How the cross-validation folds are made (see the top of this file).
enum class DriftCvScheme { kBlocks, kThermalSegments };
// "blocks" | "segments".
std::optional<DriftCvScheme> ParseDriftCvScheme(std::string_view name);
// The name ParseDriftCvScheme reads.
const char* DriftCvSchemeName(DriftCvScheme scheme);

// What a model reads: a uniformly sampled temperature record. dT/dt, when the model uses it, is
// computed from it with the model's own TemperatureRateOptions.
struct DriftInputs {
  std::span<const double> temp_c;  // deg C
  double fs_hz = 0.0;              // sample rate of temp_c, Hz
};

// Degrees of the polynomial drift model (poly, and the structured part of hybrid).
struct PolynomialOptions {
  // Degree in temperature, 1..5.
  int degree = 3;
  // Degree in the thermal state (dT/dt, lag excess or memory; used only when the inputs include
  // one), 1..3.
  int dtemp_degree = 1;
  // Degree in temperature of the state's gain, 0..2: terms s t, .., s t^gain_temp_degree beside
  // s (t the standardised temperature). 0: a constant gain (no cross terms). 2 is the first-order
  // expansion of a cubic read at a lagged temperature, f(T - d) ~ f(T) - d f'(T), with d ~ tau
  // dT/dt. `--model auto` does not choose it (docs/explanation/accuracy.md, "A gain that varies
  // with temperature").
  int gain_temp_degree = 0;
  // False with the reason in `error` when a degree is out of range.
  bool IsValid(std::string* error) const;
};

// Cuckoo search settings for CS-SVR: Yang & Deb's pa, beta and step, with nests and generations
// cut to the budget that fits a 14 h, 5 Hz record within 60 s on 2 cores.
inline CuckooSearchOptions DefaultSvrCuckooOptions() {
  CuckooSearchOptions o;
  o.num_nests = 15;
  o.max_generations = 10;
  return o;
}

// Search space and budget for grid-svr and cs-svr. C and sigma are in the SVR's scaled units
// (SvrOptions::scaling; standardised by default: sigma in input SDs).
struct SvrSearchOptions {
  SearchDimension C{"C", 1e-2, 1e3, true};  // search range of C, log scale
  SearchDimension sigma{"sigma", 0.03, 10.0, true};  // search range of sigma, log scale
  // Also search epsilon (target SDs when scaled) within these bounds; otherwise SvrOptions::epsilon.
  std::optional<SearchDimension> epsilon;
  // Cuckoo search settings (nests, pa, beta, step, generations, seed, threads). The defaults
  // below fit a 14 h, 5 Hz record within 60 s on 2 cores (see docs/explanation/drift-models.md).
  CuckooSearchOptions cuckoo = DefaultSvrCuckooOptions();
  // Grid-search budget (evaluations); automatic = the cuckoo search's budget
  // num_nests * (1 + 2 * max_generations), split as a square grid over C x sigma.
  std::optional<long> grid_budget;
  // False with the reason in `error` when a bound or the budget is out of range.
  bool IsValid(std::string* error) const;
};

// --model auto: what it tries and the budget of each searched candidate.
struct DriftAutoOptions {
  // Cuckoo-search generations of the cs-svr and hybrid candidates (nests as in
  // SvrSearchOptions::cuckoo). 4: on the 14.25 h paper run the CV score is within 1% of 10
  // generations' (docs/explanation/drift-models.md), and auto stays within 60 s.
  int search_generations = 4;
  // Also try the cs-svr and hybrid candidates (the slow ones). Off: structured candidates only.
  bool try_svr = true;
  // 1-D search of the lag state's tau (golden section on log tau), s, and its evaluations.
  double lag_tau_min_s = 30.0;
  double lag_tau_max_s = 5400.0;  // upper end of the tau search, s
  int lag_tau_evaluations = 12;  // evaluations of the tau search
  // The lagged-curve candidate poly(T) + g(T) (T - T_lag) on runs that heat and cool (Eq. I-3): the
  // drift as a function of a temperature seen through a first-order lag (a structure behind the
  // die thermometer), f(T_lag) ~ f(T) - f'(T) (T - T_lag), so the lag state's gain is a polynomial
  // of this degree in T. 1..2; 0: not tried. Admitted only by Eq. A-4 (lagged_curve_pieces).
  // 0 by default: with 2, Eq. A-4 admitted it on none of 9 two-direction bench/sim2 runs, where,
  // forced, it was 0.65-0.94x poly(T, dT/dt)'s held-out error (docs/explanation/accuracy.md,
  // "A lagged curve").
  int lagged_curve_gain_degree = 0;
  // Eq. A-4's pairs for the lagged curve: every thermal segment cut into this many contiguous
  // pieces, one pair each, so that every piece is predicted with the other direction present at
  // its temperatures (leaving out a whole ramp confounds a gain in T with the curve). >= 1.
  int lagged_curve_pieces = 3;
  // False with the reason in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// Settings of FitDriftModel: the model, its inputs, the search and the cross-validation.
struct DriftFitOptions {
  // Model to fit; kAuto scores the candidates and keeps the best.
  DriftModelKind model = DriftModelKind::kAuto;
  // Temperature alone or with a thermal state (dT/dt, lag excess, memory).
  DriftInputSet inputs = DriftInputSet::kTemp;
  TemperatureRateOptions rate;  // how dT/dt is computed from temperature
  // Parameters of the lag / memory states and of the causal rate (thermal_state.h).
  ThermalStateOptions state;
  // kTempAndLag: fit lag_tau_s by the 1-D search of DriftAutoOptions instead of using state.lag_tau_s.
  bool fit_lag_tau = true;
  // What the model does with a temperature outside the fitted range.
  OutOfRangePolicy out_of_range = OutOfRangePolicy::kExtrapolate;
  // Cross-validation folds; automatic = kThermalSegments for hybrid and auto, kBlocks otherwise
  // (the paper's pipeline keeps its scoring).
  std::optional<DriftCvScheme> cv_scheme;
  DriftAutoOptions auto_select;  // what auto tries and its budgets
  // SVR family: block-mean period of the training copy, seconds (> 0; <= 1/fs means no
  // decimation). Automatic: no decimation when the record has at most max_train_samples samples,
  // otherwise the larger of 30 s and duration / max_train_samples: 85.5 s for the paper's 14.25 h
  // run. Why that is safe: a block mean of P seconds passes periods longer than
  // about 2P (-3 dB near 0.44/P Hz) and the drift follows the sensor temperature, which lags the
  // chamber by ~10 min and ramps over tens of minutes; why it is needed: LIBSVM's cost grows
  // roughly with the square of the samples (600 samples: ~20-40 ms per fit, 1500: ~100-200 ms,
  // measured in docs/explanation/drift-models.md), and CS-SVR makes cv_folds fits per parameter set.
  std::optional<double> train_period_s;
  std::size_t max_train_samples = 600;  // automatic train_period_s: no decimation up to this many samples
  // Contiguous blocks for the blocked cross-validation (>= 2).
  int cv_folds = 5;
  // kBlocks: score a held-out block only where its temperature lies inside the range of the
  // blocks it was predicted from (kThermalSegments scores every held-out sample). A calibration run sweeps each temperature only once or twice, so the
  // first and last blocks often lie outside the others' range: scoring them measures
  // extrapolation, and the search then prefers over-smoothed models (measured in
  // docs/explanation/drift-models.md). `apply` warns whenever a model is used outside its range.
  bool cv_in_range_only = true;
  PolynomialOptions polynomial;  // degrees of poly and of hybrid's structured part
  // SVR settings: the parameters for kSvr; scaling, tolerance (and epsilon unless searched) for
  // the searched models, whose C and gamma come from the search.
  SvrOptions svr;
  SvrSearchOptions search;  // search space and budget of grid-svr and cs-svr
  // Polled between the steps of a fit (each candidate of auto, each lag tau tried, the
  // feature building, each model's fit, the band); once cancelled, FitDriftModel throws
  // Cancelled. Also handed to search.cuckoo.cancel and svr.cancel where those are null (the SVR
  // fits stop inside LIBSVM). nullptr: not polled. Not owned.
  const CancellationToken* cancel = nullptr;
  // hybrid: keep the kernel only when it is supported (Eq. H-1 in drift_fit.cc): over cv_folds
  // contiguous blocks (in-range scoring), its per-block CV gain over the structured part alone must
  // exceed the block-to-block spread of that gain, mean(g) > SD(g). Otherwise the kernel learnt
  // the calibration run's flicker wander, not drift: it is dropped and the model is its
  // structured part (kind poly; DriftFitSummary::kernel_decision says so). false: always keep it.
  bool hybrid_kernel_test = true;
  // Noise model of the polynomial fit (model poly only; noise_model.h). kWhite (default):
  // ordinary least squares on every sample. kAllan: generalised least squares (Eq. G-3) on block
  // means of gls_block_s, with the white + flicker + random-walk model (Eq. G-0) fitted to the
  // Allan variance of the OLS residual (Eq. G-1) and its block-mean covariance (Eq. G-2); the
  // CV score is of the GLS fit. Measured (docs/explanation/drift-noise-model.md): it
  // lowers the held-out error in expectation only where the polynomial's form is right (the
  // best linear unbiased estimator: 0.90-0.93x heating RMS, simulated runs) and raises it where
  // the residual is misfit (hysteresis: 1.2x); no test on the calibration run alone told them
  // apart, so auto does not use it.
  DriftNoiseModel noise_model = DriftNoiseModel::kWhite;
  NoisePsdOptions noise_psd;  // kAllan: how the noise model is fitted to the OLS residual
  // kAllan: block-mean period of the GLS fit, s (> 0): 60 s. Longer when the record would give
  // more than max_gls_blocks blocks (dense n x n Cholesky, O(n^3)): 2000 blocks (14.25 h: 855).
  double gls_block_s = 60.0;
  std::size_t max_gls_blocks = 2000;  // kAllan: most GLS blocks; gls_block_s grows beyond it
  // Name of the target (for the model file and reports), e.g. "rate_dps" or "drift-mode".
  std::string target_name = "rate_dps";
  // Attach the prediction band (DriftModel::band, Eqs. B-1..B-3) to the fitted model.
  bool band = true;
  // False with the reason in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// One term of the polynomial: its powers and coefficient.
struct PolynomialTerm {
  int temp_power = 0;   // of the standardised temperature
  int dtemp_power = 0;  // of the standardised state (dT/dt, lag excess or memory)
  double coefficient = 0.0;  // target units
  // Of the standardised memory, the second state of temp,dtemp,memory (0 or 1). Last,
  // so {temp_power, dtemp_power, coefficient} initialisers keep their meaning.
  int memory_power = 0;
};

// The polynomial drift model (the structured part): a sum of terms in standardised inputs.
struct PolynomialModel {
  AffineScaler input_scaler;          // (temp_c[, state[, memory]]) -> standardised
  // sum of coefficient * t^temp_power * r^dtemp_power * m^memory_power
  std::vector<PolynomialTerm> terms;
  // inputs[j][i] raw (column 0 temperature, column 1 the state if used, column 2 the memory of
  // temp,dtemp,memory).
  std::vector<double> Predict(const std::vector<std::vector<double>>& inputs) const;
  // At one raw (temperature, state[, memory]); a state the model does not have is ignored.
  double PredictOne(double temp_c, double state, double memory = 0.0) const;
};

// One candidate that --model auto scored.
struct DriftCandidateScore {
  std::string name;        // e.g. "poly(temp,lag tau=812 s)"
  DriftModelKind kind = DriftModelKind::kPolynomial;  // model family
  DriftInputSet inputs = DriftInputSet::kTemp;  // inputs it reads
  double cv_rmse = 0.0;    // on the auto's CV scheme, target units; +inf when the fit failed
  std::string note;        // why it was skipped / failed, "" otherwise
};

// A calibration run's dT/dt as a polynomial in temperature: sum c_k ((T - offset_c) / scale_c)^k
// (Eq. I-1 (b), least squares on its block means), C/s.
struct RateCurve {
  double offset_c = 0.0;  // deg C, subtracted from T
  double scale_c = 1.0;  // deg C, divides T - offset_c
  std::vector<double> coefficients;  // c_k, C/s, k = 0..degree
  // dT/dt of the curve at temp_c, C/s.
  double At(double temp_c) const;
};

// A candidate term the calibration run does not identify, left out of the model (drift_identify.cc,
// docs/explanation/drift-models.md "What a run identifies"). Written into the model file's "training".
struct ExcludedTerm {
  std::string term;            // "dT/dt gain" | "lag tau" | "memory" | "kernel" | "degree"
  std::string reason;          // the test and the numbers it failed on
  std::string would_identify;  // what calibration run would identify it
};

// auto: one candidate term's admission test (term_admission.h, Eq. A-4): the paired
// leave-one-segment-out CV gain of the model with the term over the simpler model it extends.
struct TermAdmission {
  std::string term;       // "dT/dt", "memory", "lag"
  std::string candidate;  // the model with the term, e.g. "poly(temp,dtemp)"
  std::string simpler;    // the model it extends, e.g. "poly(temp)"
  TermGain gain;          // target units; pairs = 0 when not tested (see note)
  bool admitted = false;  // the test admitted the term
  std::string note;       // why it was not tested, "" otherwise
  // "+dT/dt (poly(temp,dtemp) over poly(temp)): gain 0.12 +- 0.05 mdps (7 segments), admitted";
  // gain and SE times `scale`, labelled `unit`.
  std::string BriefReport(double scale = 1.0, const std::string& unit = "") const;
};

// What the fit did: the numbers the CLI, the report and the model file show.
struct DriftFitSummary {
  DriftModelKind model = DriftModelKind::kPolynomial;  // kind fitted (never kAuto)
  DriftInputSet inputs = DriftInputSet::kTemp;  // inputs of the fitted model
  std::string target_name;  // DriftFitOptions::target_name
  std::size_t num_samples = 0;      // full-rate samples given
  double fs_hz = 0.0;  // sample rate, Hz
  double duration_s = 0.0;  // record length, s
  std::size_t num_train = 0;        // samples the model was fitted on (after decimation)
  double train_period_s = 0.0;      // 1/fs when not decimated
  double temp_min_c = 0.0;  // lowest temperature of the fitted range, deg C
  double temp_max_c = 0.0;  // highest temperature of the fitted range, deg C
  double dtemp_min_c_per_s = 0.0;  // lowest dT/dt in the fit, C/s
  double dtemp_max_c_per_s = 0.0;  // highest dT/dt in the fit, C/s
  // SVR family: the parameters chosen (C; gamma and sigma in the SVR's units; epsilon).
  std::optional<double> C;  // regularisation C
  std::optional<double> gamma;  // RBF gamma, SVR units
  std::optional<double> sigma;  // RBF width sigma, SVR units
  std::optional<double> epsilon;  // tube half-width epsilon
  std::size_t num_support = 0;  // support vectors of the kernel
  // Polynomial: degrees.
  int degree = 0;  // degree in temperature
  int dtemp_degree = 0;  // degree in the thermal state
  int gain_temp_degree = 0;  // degree in temperature of the state's gain (PolynomialOptions)
  int cv_folds = 0;  // CV folds used
  double cv_rmse = 0.0;             // blocked CV RMSE on the training copy, target units
  bool cv_in_range_only = true;     // see DriftFitOptions::cv_in_range_only
  double train_rmse = 0.0;          // in-sample RMSE at the full rate, target units
  long evaluations = 0;             // parameter sets tried (each = cv_folds + ... SVR fits)
  int generations = 0;              // cuckoo search
  std::vector<double> best_cv_history;  // cs-svr: best CV RMSE after each generation
  DriftCvScheme cv_scheme = DriftCvScheme::kBlocks;  // CV scheme used
  int cv_segments = 0;              // thermal segments found (kThermalSegments)
  // State range seen in the fit (lag: deg C, memory: 1); the dtemp_* fields for the rate.
  double state_min = 0.0;  // lowest state value
  double state_max = 0.0;  // highest state value
  std::optional<double> lag_tau_s;  // temp,lag: the tau used (fitted or given)
  // auto: every candidate scored, and why the chosen one won.
  std::vector<DriftCandidateScore> candidates;
  // auto: each structured term's admission test, in the nested order poly(T) -> +dT/dt ->
  // +memory / +lag (Eq. A-4). Not written to the model file (selection_reason carries the text).
  std::vector<TermAdmission> term_admissions;
  std::string selection_reason;  // auto: why the chosen candidate won
  // What this calibration run can identify (heating and cooling coverage), for the fit summary.
  std::string identifiability;
  // hybrid: whether its kernel was kept or dropped, with the per-block gains (Eq. H-1); "" else.
  std::string kernel_decision;
  // auto: terms left out because the run does not identify them (Eqs. I-0..I-3), with why.
  std::vector<ExcludedTerm> excluded_terms;
  // auto: the dT/dt gain Eq. I-1 fitted but did not accept, and its segment-jackknife SE
  // (deg/s per C/s for a rate); used by the band (Eq. B-4).
  std::optional<double> unidentified_rate_gain;  // the gain, deg/s per C/s for a rate
  std::optional<double> unidentified_rate_gain_se;  // its segment-jackknife SE, same unit
  RateCurve calibration_rate_vs_temp;  // with them: the run's dT/dt against T
  // auto: how many points the fit had and which candidates they support (Eq. I-0); "" else.
  std::string data_support;
  // Span (max - min) of the target's training copy, target units: the scale CV figures are read on.
  double drift_span = 0.0;
  // Polynomial: its noise model (DriftFitOptions::noise_model) and, kAllan, the Eq. G-0
  // coefficients fitted to the OLS residual.
  DriftNoiseModel noise_model = DriftNoiseModel::kWhite;
  std::optional<NoisePsd> noise_psd;  // kAllan: the Eq. G-0 coefficients
  // Wall time of the fit, s. Not written to the model file (two fits of the same data give
  // byte-identical files); reported in fit --json.
  double fit_time_s = 0.0;
  // One line for logs: kind, inputs, samples, training copy, temperature range, parameters, CV scores.
  std::string BriefReport() const;
};

// By how much a record leaves the temperature range a model was fitted on.
struct TemperatureExcursion {
  bool outside = false;  // the record leaves the fitted range
  double below_c = 0.0;            // fitted min - record min, when > 0
  double above_c = 0.0;            // record max - fitted max, when > 0
  double fraction_outside = 0.0;   // share of samples outside
  std::string Message() const;     // "" when inside
};

// A prediction with its band (DriftModel::PredictBand): per sample, the predicted drift and the
// interval that holds the true drift of another run with probability `level`
// (docs/explanation/prediction-bands.md).
struct DriftBand {
  std::vector<double> center;  // predicted drift per sample, target units
  std::vector<double> lo;  // lower edge of the band
  std::vector<double> hi;  // upper edge of the band
  double level = 0.9;  // probability that the band holds the true drift
};

// What the band is made of, stored per axis in the model file ("band"; docs/explanation/drift-models.md
// "Prediction bands"). Eq. B-1: var_i = a_i' C a_i + model_form_rms^2, half-width z(level)
// sqrt(var_i), a_i the structured part's terms at sample i (standardised inputs).
struct DriftBandModel {
  double level = 0.9;  // probability the band is built for (z(level) of Eq. B-1)
  // Covariance C of the structured coefficients (row-major, terms x terms; empty for a model
  // without a structured part), from the OLS fit under the run's measured noise (Eq. B-2).
  std::vector<double> parameter_cov;
  // The Eq. G-0 noise model fitted to the residual's Allan variance (h0, h_1, h_2).
  NoisePsd noise;
  // The model-form spread the thermal-segment CV shows, target units (Eq. B-3).
  double model_form_rms = 0.0;
  // Eq. B-4: |g| of a dT/dt gain the run did not identify (0: none; capped), target units
  // per C/s, and the calibration run's dT/dt against T (what the T polynomial absorbed of it).
  double unidentified_rate_gain_rms = 0.0;
  RateCurve calibration_rate_vs_temp;  // the calibration run's dT/dt against T (Eq. B-4)
  // Eq. B-5: the direction the calibration run did not cover over enough of its range (Eq. I-3),
  // +1 heating, -1 cooling, 0 none or no dT/dt term; on a sample moving that way the band adds
  // the model's own dT/dt contribution there in quadrature (the heating/cooling difference the
  // run cannot tell from a rate effect).
  int unseen_direction = 0;
  // Where the coverage was measured.
  std::string coverage_check;
  // RMS of the band's standard deviation over the calibration run: the expected RMS drift error
  // on a next run like it, target units.
  double expected_rms = 0.0;
};

// A fitted drift model of one rate column: inputs, parts, out-of-range policy, fit summary, band.
struct DriftModel {
  DriftModelKind kind = DriftModelKind::kPolynomial;  // never kAuto
  DriftInputSet inputs = DriftInputSet::kTemp;  // temperature alone or with a thermal state
  TemperatureRateOptions rate;        // batch dT/dt (kTempAndRate)
  ThermalStateOptions state;          // causal rate, lag and memory parameters
  // What the model does with a temperature outside the fitted range.
  OutOfRangePolicy out_of_range = OutOfRangePolicy::kExtrapolate;
  // The two parts; the prediction is their sum (each absent part contributes 0):
  //   poly: structured only; svr / grid-svr / cs-svr: kernel only; hybrid: both, with the
  //   kernel's intercept and target offset folded into the structured constant (both 0 here).
  std::optional<PolynomialModel> structured;
  std::optional<SvrModel> kernel;  // kernel part (SVR), or absent
  // Which rate column this model compensates and the unit of its output (model file v2).
  std::string rate_col = "rate_dps";
  std::string unit = "deg/s";  // unit of the output, e.g. "deg/s"
  DriftFitSummary summary;  // what the fit did
  // Prediction band (docs/explanation/prediction-bands.md); absent in older files: PredictBand then fails.
  std::optional<DriftBandModel> band;

  // ---- evaluator accessors (exporters, generated C) ----
  // The model function at one temperature and state value (after the out-of-range policy);
  // `memory`: the second state of temp,dtemp,memory (ignored by the other input sets).
  double PredictAt(double temp_c, double state, double memory = 0.0) const;
  // Temperature range of the fit and the input the model function sees under `out_of_range`.
  double temp_min_c() const { return summary.temp_min_c; }
  // Highest fitted temperature, deg C.
  double temp_max_c() const { return summary.temp_max_c; }
  // The temperature the model function sees: temp_c, clamped to the fitted range under kClamp.
  double EffectiveTemp(double temp_c) const;

  // Predicted drift (target units, deg/s for a rate) at every sample. causal = false: the rate
  // state is the centred slope (apply's default); causal = true: every state by its
  // one-sample update (DriftEvaluator, what firmware does). Lag and memory are causal either
  // way. Errors: empty record, or fs_hz <= 0 / fewer than 2 samples when a state is needed.
  Result<std::vector<double>> Predict(const DriftInputs& inputs, bool causal = false) const;
  // By how much `temp_c` leaves the fitted temperature range.
  TemperatureExcursion CheckTemperatureRange(std::span<const double> temp_c) const;
  // Predict with the band (Eq. B-1): center = Predict(inputs, causal), [lo, hi] the band at
  // band->level. Errors: those of Predict, or no band (an older model file).
  Result<DriftBand> PredictBand(const DriftInputs& inputs, bool causal = false) const;
};

// Causal evaluation, one sample at a time: the reference for firmware and generated C, and what
// DriftModel::Predict(..., causal = true) runs. Holds a reference to the model.
class DriftEvaluator {
 public:
  // Evaluates `model`, which must outlive the evaluator.
  explicit DriftEvaluator(const DriftModel& model)
      : model_(model), state_(model.inputs, model.state) {}
  // Predicted drift after a sample taken dt_s after the previous one (dt_s ignored for the first).
  double Step(double dt_s, double temp_c) {
    const double s = state_.Step(dt_s, temp_c);
    return model_.PredictAt(temp_c, s, state_.memory());
  }
  // Back to the first sample: the next Step starts the state afresh.
  void Reset() { state_.Reset(); }

 private:
  const DriftModel& model_;
  ThermalStateEvaluator state_;
};

// Fits a drift model of `target` (one value per sample of inputs.temp_c). Errors: length
// mismatch, too few samples (< 2 * cv_folds after decimation), non-finite values, invalid options.
Result<DriftModel> FitDriftModel(const DriftInputs& inputs, std::span<const double> target,
                                 const DriftFitOptions& options);

// ---- model file (JSON) ---------------------------------------------------------------------
// Version 2 (written): {"format": "gyrocomp-drift-model", "schema_version": 2,
//   "axes": [ one entry per compensated rate column:
//     {"rate_col", "unit", "target", "kind", "inputs": ["temp_c"(, state column)],
//      "thermal_state": {type and parameters, with the update equations},
//      "out_of_range": {"policy", "temp_min_c", "temp_max_c"},
//      "structured": null | {"input_offset", "input_scale", "terms": [...]},
//      "svr": null | {"input_offset", "input_scale", "target_offset", "target_scale", "gamma",
//                     "intercept", "coefficients", "support_vectors"},
//      "training": {parameters chosen, CV scores, candidates, ranges; no timings}} ]}
// Reproducible: the same inputs and options give byte-identical files (no timings, shortest
// round-trip doubles). Version 1 (older files: one model at the top level, "kind",
// "scaler", "model", "training") is still read, and predicts bit-identically.
inline constexpr int kDriftModelSchemaVersion = 2;

// Which sensor of a flight log the axes model (docs/reference/model-file.md): the optional
// top-level key "sensor": {"type": "gyro" | "accel" | "baro", "instance": ULog multi_id /
// DataFlash IMU I, "device_id": PX4 only, "frame": "sensor" (board rotation undone by the reader)}.
struct SensorIdentity {
  std::string type = "gyro";  // "gyro" | "accel" | "baro"
  int instance = 0;  // ULog multi_id or DataFlash IMU I
  std::optional<std::uint32_t> device_id;  // PX4 only
  std::string frame = "sensor";  // "sensor": board rotation undone by the reader
};

// Several axes in one file (fit --rate-col gx,gy,gz). Each axis names its rate column.
struct DriftModelSet {
  std::vector<DriftModel> axes;  // one per rate column
  // The gyro's device id when the calibration run was a PX4 ULog (sensor_gyro.device_id, what
  // PX4's TC_G{i}_ID must hold); written as the optional top-level key "device_id".
  std::optional<std::uint32_t> device_id;
  // Optional (older files have none); `device_id` above stays and is written too.
  std::optional<SensorIdentity> sensor;
  // The model for `rate_col`, or nullptr.
  const DriftModel* Find(std::string_view rate_col) const;
  // The model `apply` / `validate` use for a record's axis `rate_col`: the one fitted on that
  // column, else the file's only model (version-1 and single-axis files apply to every axis), else
  // nullptr.
  const DriftModel* ForAxis(std::string_view rate_col) const;
};

// The set as model-file JSON (version 2).
std::string DriftModelSetToJson(const DriftModelSet& models);
std::string DriftModelToJson(const DriftModel& model);  // a set of one axis
// `source` names the file in messages. Another format, an unknown schema version, or a missing /
// mistyped field -> error (kUnsupported for the version, kInvalidInput otherwise), never a
// misread model.
Result<DriftModelSet> DriftModelSetFromJson(std::string_view text, const std::string& source);
// One model: the file's only axis (an error naming the axes when it has several).
Result<DriftModel> DriftModelFromJson(std::string_view text, const std::string& source);
Status SaveDriftModelSet(const DriftModelSet& models, const std::string& path);  // atomic
Status SaveDriftModel(const DriftModel& model, const std::string& path);          // atomic
// Reads a model file: kIo when it cannot be read, else the errors of DriftModelSetFromJson.
Result<DriftModelSet> LoadDriftModelSet(const std::string& path);
// One model: the file's only axis (LoadDriftModelSet, then as DriftModelFromJson).
Result<DriftModel> LoadDriftModel(const std::string& path);

}  // namespace gyrocomp
