// epsilon-SVR with an RBF kernel (paper Section 3.4, Eqs. 17-23), solved by LIBSVM.
//
// LIBSVM is the reference solver (../golden/svr/ was made by it through scikit-learn). This header
// hides it completely: training copies the support vectors, their coefficients and the intercept
// out of LIBSVM's model, frees LIBSVM's memory, and the returned SvrModel is a plain value that
// predicts, saves and loads without LIBSVM.
//
// Kernel: K(x, x_i) = exp(-gamma |x - x_i|^2), gamma = 1 / (2 sigma^2)             (Eq. 20)
// Prediction: f(x) = sum_i (alpha_i - alpha_i^*) K(x, x_i) + b                       (Eq. 23)
//
// Scaling (SvrScaling::kStandard, the default): every input column AND the target are
// standardised (z-score with the population SD of the training data) before LIBSVM sees them, and
// predictions are mapped back to target units. Then C, epsilon and gamma are scale-free (epsilon
// in target SDs, gamma in 1/SD^2), so one set of search bounds fits any sensor. With kNone the raw
// numbers go to LIBSVM (gamma in 1/input-unit^2, epsilon in target units), as scikit-learn does.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/cancel.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp {

// Scaling of the SVR's inputs and target: kStandard to zero mean, unit SD (the default); kNone as given.
enum class SvrScaling { kStandard, kNone };

// "standard" | "none".
std::optional<SvrScaling> ParseSvrScaling(std::string_view name);
// "standard" | "none".
const char* SvrScalingName(SvrScaling scaling);

// Settings of one epsilon-SVR fit (LIBSVM, RBF kernel).
struct SvrOptions {
  // Regularisation C of Eq. (18) (dimensionless weight of the epsilon-insensitive loss). LIBSVM's
  // default 1.
  double C = 1.0;
  // RBF width. Give at most one of gamma (1/input-unit^2, or 1/SD^2 when scaled) and sigma
  // (input units or SDs), gamma = 1/(2 sigma^2). Neither: LIBSVM's default gamma = 1/num_inputs.
  std::optional<double> gamma;
  std::optional<double> sigma;  // RBF width, input units (SDs when scaled); see gamma
  // Half-width epsilon of the insensitive tube (Eq. 19): target SDs when scaling is kStandard,
  // target units (deg/s) when kNone. LIBSVM's default 0.1.
  double epsilon = 0.1;
  // LIBSVM's stopping tolerance on the KKT gap (its -e). LIBSVM's default 1e-3.
  double tolerance = 1e-3;
  SvrScaling scaling = SvrScaling::kStandard;  // how inputs and target are scaled before LIBSVM
  // LIBSVM kernel cache (MB) and shrinking heuristic (LIBSVM defaults 100 MB, on).
  double cache_mb = 100.0;
  bool shrinking = true;  // LIBSVM shrinking heuristic (its -h)
  // Polled inside LIBSVM's solver, every min(2 x samples, 1000) iterations (its
  // progress print): once cancelled, FitSvr throws Cancelled on the calling thread. The solver's
  // working arrays of that fit are not freed (LIBSVM has no way out but an exception: O(samples)
  // doubles, once per cancel; docs/explanation/performance.md). nullptr: not polled. Not owned.
  const CancellationToken* cancel = nullptr;

  // gamma actually used for `num_inputs` input columns (resolves sigma / the default).
  double ResolvedGamma(std::size_t num_inputs) const;
  // Valid ranges (IsValid): C in (0, kMaxC], gamma in (0, kMaxGamma], sigma in
  // [kMinSigma, kMaxSigma], epsilon in [0, kMaxEpsilon], tolerance in (0, 1]: a fit inside them
  // gives a model whose every number loads again (<= 1e100).
  static constexpr double kMaxC = 1e6;
  static constexpr double kMaxGamma = 1e6;  // upper bound of gamma
  static constexpr double kMinSigma = 1e-3;  // lower bound of sigma
  static constexpr double kMaxSigma = 1e3;  // upper bound of sigma
  static constexpr double kMaxEpsilon = 1e6;  // upper bound of epsilon
  // False with "SvrOptions::field = value: must be ..." in `error` when a value is out of its range.
  bool IsValid(std::string* error) const;
};

// Per-column affine map x -> (x - offset) / scale (identity: offset 0, scale 1).
struct AffineScaler {
  std::vector<double> offset;  // subtracted from each column
  std::vector<double> scale;  // each column divided by it after the offset
  // The identity for `n` columns.
  static AffineScaler Identity(std::size_t n);
  // Mean and population SD of each column (SD 0 -> scale 1, so a constant column stays finite).
  static AffineScaler Standardize(const std::vector<std::vector<double>>& columns);
};

// What one SVR fit did.
struct SvrSummary {
  std::size_t num_train = 0;  // training rows
  std::size_t num_support = 0;  // support vectors
  std::size_t num_bounded_support = 0;  // |alpha - alpha*| == C
  double C = 0.0;  // C used
  double gamma = 0.0;                   // in the units LIBSVM saw (see SvrScaling)
  double epsilon = 0.0;  // epsilon used (units LIBSVM saw)
  double tolerance = 0.0;  // stopping tolerance used
  double train_rmse = 0.0;              // target units
  double fit_time_s = 0.0;  // wall time of the fit, s
  // One line for logs: samples, support vectors, C, gamma, epsilon, RMSE, time.
  std::string BriefReport() const;
};

// A trained model: support vectors in scaled input space, coefficients alpha_i - alpha_i^*
// (scaled target units), intercept b, gamma, and the scalers. Cheap to copy.
struct SvrModel {
  std::size_t num_inputs = 0;  // input columns the model reads
  double gamma = 0.0;  // RBF gamma in the units LIBSVM saw (1/SD^2 when scaled)
  double intercept = 0.0;                      // b of Eq. (23) = -rho of LIBSVM
  std::vector<double> support_vectors;         // row-major, num_support x num_inputs (scaled)
  std::vector<double> coefficients;            // alpha_i - alpha_i^*, one per support vector
  AffineScaler input_scaler;                   // raw input -> LIBSVM input
  double target_offset = 0.0;                  // raw target = offset + scale * LIBSVM target
  double target_scale = 1.0;  // raw target = offset + scale * LIBSVM target
  SvrSummary summary;  // what the fit did

  // Number of support vectors.
  std::size_t num_support() const { return coefficients.size(); }
  // Eq. (23) at one raw input row (num_inputs values), in target units.
  double PredictOne(std::span<const double> x) const;
  // Eq. (23) at every row: inputs[j][i] = column j, row i (all columns the same length).
  std::vector<double> Predict(const std::vector<std::vector<double>>& inputs) const;
};

// Trains epsilon-SVR on inputs[j][i] (column j, row i) against target[i]. Errors: empty or ragged
// data, non-finite values, invalid options (kInvalidArgument / kInvalidInput), LIBSVM's
// svm_check_parameter refusal (kInvalidArgument), LIBSVM failure (kInternal). LIBSVM's console
// output is silenced. Thread-safe: several fits may run concurrently.
Result<SvrModel> FitSvr(const std::vector<std::vector<double>>& inputs,
                        std::span<const double> target, const SvrOptions& options);

}  // namespace gyrocomp
