// Internals shared by drift_model.cc, polynomial_model.cc, cs_svr.cc and drift_model_io.cc.
// Not installed; not part of the public API.
#pragma once

#include <cmath>
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/drift/term_admission.h"

namespace gyrocomp::drift_internal {

using Columns = std::vector<std::vector<double>>;  // columns[j][i]

// Model inputs at every sample: column 0 temperature (deg C), column 1 the thermal state when the
// input set includes one (thermal_state.h; the rate is the centred slope unless causal).
Result<Columns> BuildFeatures(const DriftInputs& inputs, DriftInputSet set, const TemperatureRateOptions& rate,
                              const ThermalStateOptions& state, bool causal);

// Means of consecutive blocks of `block` samples (the last block may be shorter).
std::vector<double> BlockMeans(std::span<const double> x, std::size_t block);

// A model fitted on training columns/target, returning predictions at other columns.
using FitPredict = std::function<Result<std::vector<double>>(
    const Columns& train_x, std::span<const double> train_y, const Columns& test_x)>;

// How the (decimated) training copy is split for cross-validation: the fold of every sample.
struct CvPlan {
  std::vector<int> fold_of;     // 0 .. folds - 1, one per training sample
  int folds = 0;
  bool in_range_only = false;   // score a held-out sample only inside the training folds' T range
  DriftCvScheme scheme = DriftCvScheme::kBlocks;
  int segments = 0;             // kThermalSegments: segments found
  // kThermalSegments: direction of each sample's segment (0 cooling, 1 holding, 2 heating). The
  // score is then balanced: sqrt of the mean over the directions present of their held-out MSE,
  // so the one heating leg of a cooling calibration weighs as much as all its cooling ramps (the
  // next run may go either way). Empty: pooled RMSE over every scored sample.
  std::vector<int> direction_of;
};
// `folds` contiguous blocks of (nearly) equal length: block k = [n k / folds, n (k+1) / folds).
CvPlan BlockPlan(std::size_t n, int folds, bool in_range_only);
// Ramps and holds from the (decimated) temperature rate: a sample is heating / cooling / holding
// by the sign of its rate beyond `threshold_c_per_s`; runs shorter than `min_run` samples join
// the previous one; segment j goes to fold j mod folds (fewer segments: one fold each). Falls
// back to BlockPlan (all samples scored) when fewer than 2 segments are found.
CvPlan SegmentPlan(std::span<const double> rate_c_per_s, int folds, double threshold_c_per_s);

// Cross-validation: each fold is predicted by a model fitted on the other folds (training and
// held-out rows keep their order). Returns the RMSE over the scored held-out predictions (an
// error if none is scored).
// fold_rmse (optional): the RMSE of each fold's scored held-out samples (pooled within the fold).
Result<double> CrossValidate(const Columns& x, std::span<const double> y, const CvPlan& plan,
                             const FitPredict& fit_predict, std::vector<double>* fold_rmse = nullptr);

// Eq. H-1, the kernel's test: the paired per-block gain of term_admission.h (Eqs. A-1..A-3) with
// the stricter threshold gain > Sd() (its gain exceeds its own block-to-block spread, t > sqrt(K)).
inline bool KernelWins(const TermGain& g) { return g.pairs >= 2 && g.gain > g.Sd(); }
// The contiguous-block plan Eq. H-1 is scored on: cv_folds blocks, in-range scoring.
CvPlan GainTestPlan(std::size_t n, const DriftFitOptions& o);

// Least squares polynomial (Eigen) on the standardised inputs.
Result<PolynomialModel> FitPolynomial(const Columns& x, std::span<const double> y,
                                      const PolynomialOptions& options);

// Generalised least squares (Eq. G-3 in polynomial_model.cc): the polynomial of FitPolynomial
// with residual covariance Sigma(i, j) = autocov[|index_i - index_j|] (noise_model.h, Eq. G-2;
// index = the sample's position in the evenly spaced series autocov describes).
Result<PolynomialModel> FitPolynomialGls(const Columns& x, std::span<const double> y,
                                         std::span<const double> autocov, std::span<const std::size_t> index,
                                         const PolynomialOptions& options);

// Outcome of a parameter search for the SVR family.
struct SvrChoice {
  SvrOptions options;      // with C, sigma (and epsilon) chosen
  double cv_rmse = 0.0;
  long evaluations = 0;
  int generations = 0;
  std::vector<double> history;
};

// The fit-and-predict one search point (SVR options with C, sigma[, epsilon] set) stands for:
// a plain SVR (cs-svr, grid-svr) or the hybrid's polynomial + SVR on its residual.
using MakeFitPredict = std::function<FitPredict(const SvrOptions&)>;
FitPredict SvrFitPredict(const SvrOptions& o);

// cs-svr: cuckoo search over (C, sigma[, epsilon]) minimising the CV RMSE.
Result<SvrChoice> SearchSvrCuckoo(const Columns& x, std::span<const double> y, const DriftFitOptions& options,
                                  const CvPlan& plan, const MakeFitPredict& make);
// grid-svr: log-spaced square grid over (C, sigma) at the same budget.
Result<SvrChoice> SearchSvrGrid(const Columns& x, std::span<const double> y, const DriftFitOptions& options,
                                const CvPlan& plan, const MakeFitPredict& make);

// Training data of one input set: full-rate features and target, their decimated copy, and the
// decimated centred dT/dt the segment plan reads.
struct FitData {
  Columns x;                  // full rate: temperature [, state]
  std::vector<double> y;
  Columns xd;                 // block means over train_period_s
  std::vector<double> yd;
  std::vector<double> rate_d; // block means of the centred dT/dt, deg C / s
  double dtemp_min_c_per_s = 0.0, dtemp_max_c_per_s = 0.0;  // its full-rate range
  std::size_t block = 1;
  double train_period_s = 0.0;
};

// |dT/dt| above which a sample is on a ramp (segment plan, identifiability), deg C / s: 0.06 C/min.
inline constexpr double kSegmentRateThreshold = 1e-3;

// What fit writes, apply must load (fuzz_numeric_drift: a +-1.8e308 target gave a
// training RMSE of inf, written as null and refused at load): the model through its JSON and
// back (drift_model_io.cc); kInvalidInput with the loader's reason otherwise.
Status CheckModelLoads(const DriftModel& model);
Status CheckFitArguments(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o);
Result<FitData> PrepareFitData(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o);
// The CV plan of o.cv_scheme (automatic: segments for hybrid and auto, blocks otherwise).
CvPlan MakeCvPlan(const FitData& d, const DriftFitOptions& o, DriftModelKind kind);
// The plan a fit with options `o` scores its candidates on: MakeCvPlan, and for auto made
// trainable for the largest candidate (EnsureTrainablePlan; *note says when it fell back).
CvPlan ModelCvPlan(const FitData& base, const DriftFitOptions& o, std::string* note);
// One model of `kind` (not kAuto) with o.inputs and o.state as given.
Result<DriftModel> FitPrepared(const FitData& d, const DriftInputs& inputs, DriftModelKind kind,
                               const DriftFitOptions& o, const CvPlan& plan);
// --model auto, and any model with the lag state whose tau is fitted (drift_auto.cc).
Result<DriftModel> FitSelected(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o);
// What the calibration run can identify: heating and cooling coverage (drift_auto.cc).
std::string DescribeIdentifiability(const DriftInputs& inputs, const DriftFitOptions& o);
// Whether both directions cover enough of the temperature range for the memory state.
bool MemoryIdentifiable(const DriftInputs& inputs, const DriftFitOptions& o);
// The direction the run does not cover over enough of its range (Eq. I-3): +1 heating, -1 cooling
// (the shorter one when both fall short), 0 when both cover >= 50% of it.
int UncoveredDirection(const DriftInputs& inputs, const DriftFitOptions& o);

// ---- what a run identifies (drift_identify.cc, Eqs. I-0..I-3) ----
// Eq. I-0: training points per coefficient a candidate needs, and the points a kernel needs.
inline constexpr std::size_t kPointsPerCoefficient = 6;
inline constexpr std::size_t kMinKernelPoints = 60;
// Coefficients `points` training points support (Eq. I-0).
std::size_t MaxCoefficients(std::size_t points);
// The outcome of one term's test: identified, or the ExcludedTerm to record.
struct TermTest {
  bool identified = false;
  ExcludedTerm why;
  std::string evidence;  // the numbers the test read
  // Eq. I-1 (d): the gain and its segment-jackknife SE (NaN when not fitted).
  double gain = std::nan(""), gain_se = std::nan("");
  // Eq. I-1 (b): the run's dT/dt as a polynomial in temperature (what poly(T) absorbs).
  RateCurve rate_vs_temp;
};
// Eq. I-1 on the decimated (T, dT/dt) training copy `d` (inputs kTempAndRate) and the CV plan.
TermTest TestRateGain(const FitData& d, const CvPlan& plan, const PolynomialOptions& p);
// Eq. I-2 from the lag search's segment-CV scores at tau, tau/3 and 3 tau.
TermTest TestLagTau(double tau_s, double score_at_tau, double score_below, double score_above, bool rate_identified,
                    bool both_directions);
// A CV plan every fold of which leaves at least 2 x `coefficients` training points at >=
// `coefficients` distinct temperatures; otherwise `folds` contiguous blocks (all samples scored),
// with *note saying why. `temp` is the training copy's temperature column.
CvPlan EnsureTrainablePlan(const CvPlan& plan, std::span<const double> temp, std::size_t coefficients, int folds,
                           std::string* note);

// The symmetric Toeplitz matrix of autocovariances r[0..n-1]: Sigma(i, j) = r[|i - j|].
Eigen::MatrixXd Toeplitz(const std::vector<double>& r);
// Eqs. B-2a, B-2b (drift_band.cc): the run's noise over its n block means: the floored Eq. G-2
// Toeplitz matrix `floored` plus the run's offset and linear trend, so that the record's mean and
// its two halves' difference carry the Allan variances of psd's white and flicker parts at T and
// T / 2 (IEEE 952) where the floored matrix holds less.
Eigen::MatrixXd RunCovariance(Eigen::MatrixXd floored, const NoisePsd& psd, double duration_s);

// Eq. B-3 (drift_band.cc): the thermal-segment CV of a model's structured form, refitted per
// fold by OLS (GLS for noise_model allan) on the plan the fit scored on (ModelCvPlan; contiguous
// blocks when its every fold is one whole segment, Eq. B-3s), pooled
// over the scored held-out points, and its expectation were the run exactly that form plus the
// noise `psd` (Eq. B-2's Sigma at the CV's block period cv_period_s).
struct FormCv {
  double mse = 0.0;        // realised mean square held-out error, target units^2
  double noise_mse = 0.0;  // its expectation under the noise alone
  std::size_t points = 0;  // held-out points scored
  DriftCvScheme scheme = DriftCvScheme::kBlocks;  // the plan scored (Eq. B-3s)
};
Result<FormCv> StructuredFormCv(const DriftModel& m, const DriftInputs& inputs, std::span<const double> target,
                                const DriftFitOptions& o, const NoisePsd& psd, double cv_period_s);

// Eqs. B-1..B-3 (drift_band.cc): the prediction band of a fitted model from its calibration run;
// cv_period_s = the block period of the training copy its CV score was computed on.
Status AttachBand(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o,
                  double cv_period_s, DriftModel* m);

// Evaluations the cuckoo search makes: num_nests * (1 + 2 * max_generations), capped.
long CuckooBudget(const CuckooSearchOptions& o);

inline double Rmse(std::span<const double> a, std::span<const double> b) {
  double ss = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) ss += (a[i] - b[i]) * (a[i] - b[i]);
  return a.empty() ? 0.0 : std::sqrt(ss / static_cast<double>(a.size()));
}

}  // namespace gyrocomp::drift_internal
