// Forward linear prediction (FLP) with a variable-step LMS (paper Section 3.3, Eqs. 14-16).
//
//   prediction   xhat(n) = C(n)^T X(n-1),  X(n-1) = [x(n-1) .. x(n-N)]^T          Eq. (14)
//   error        e(n) = x(n) - xhat(n)
//   update       C(n+1) = C(n) + eta(n) e(n) X(n-1) / (eps + |X(n-1)|^2)          Eq. (15)
//   step         eta(n) = beta (1 - exp(-alpha e(n)^2 / P(n)))                     Eq. (16)
// The filtered output is the prediction xhat(n) (method.md section 3): it uses only past samples,
// so the filter is causal and runs sample by sample (FlpFilter, for firmware).
//
// Scale-free by construction (LMS stability depends on input power): Eq. (15) is normalised by
// the regressor energy |X|^2 (NLMS; stable for 0 < eta < 2), and the error in Eq. (16) is measured
// against P(n), an exponentially weighted mean of x^2 (forgetting factor power_forgetting), so
// alpha and beta are dimensionless. eps = regularization * N * P(n) also scales with the input.
// Hence input * k gives output * k, to rounding (tested with k = 1e6).
//
// Start-up (not in the paper; chosen so the output does not start at 0): the history X is
// prefilled with the first sample, P(0) = x(0)^2, and C(0) = [1/N, ..., 1/N] (a moving average)
// unless told otherwise.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/status.h"

namespace gyrocomp {

// The weights C(0) the filter starts from.
enum class FlpInitialWeights {
  kMovingAverage,  // c_p = 1/N: the output starts as an N-tap mean of past samples
  kZero,           // c_p = 0: plain LMS start (the output starts at 0)
  kLastSample,     // c_1 = 1, others 0: the output starts as x(n-1)
};

// "moving-average" | "zero" | "last-sample".
std::optional<FlpInitialWeights> ParseFlpInitialWeights(std::string_view name);
// FlpInitialWeights -> "moving-average" | "zero" | "last-sample".
const char* FlpInitialWeightsName(FlpInitialWeights w);

// Parameters of the variable-step FLP (Eqs. 14-16).
struct FlpOptions {
  // Defaults of order, beta and alpha: chosen by a sweep on simulated records with known truth,
  // for WFLP (FLP on the level-4 approximation); docs/explanation/denoising.md has the sweep table. For FLP
  // alone on raw samples, order 16-32 with beta 0.003 did better on every record tried.
  // Prediction order N (number of taps, Eq. 14). Dimensionless, >= 1 (at most 4096). Larger N
  // averages more past samples (narrower bandwidth, longer lag).
  int order = 8;
  // Maximum step beta of Eq. (16) (normalised LMS step, dimensionless), 0 < beta < 2.
  double beta = 0.01;
  // alpha of Eq. (16): sensitivity of the step to the normalised squared error e^2 / P
  // (dimensionless), > 0. eta -> beta when e^2 >> P / alpha, -> 0 when the error is small.
  double alpha = 4.0;
  // Forgetting factor lambda of the power estimate P(n) = lambda P(n-1) + (1 - lambda) x(n)^2,
  // 0 <= lambda < 1 (0.999: a time constant of about 1000 samples).
  double power_forgetting = 0.999;
  // Relative regulariser of the NLMS denominator (eps = regularization * N * P), >= 0.
  double regularization = 1e-6;
  // C(0): an N-tap moving average by default (the output does not start at 0).
  FlpInitialWeights initial_weights = FlpInitialWeights::kMovingAverage;
  bool IsValid(std::string* error) const;  // "FlpOptions::beta = 3: must be in (0, 2)"
};

// Streaming FLP: one sample in, one filtered sample out. Copyable; no allocation after Create.
class FlpFilter {
 public:
  // A filter in its initial state. Errors: invalid options (kInvalidArgument).
  static Result<FlpFilter> Create(const FlpOptions& options);

  // Consumes x(n), returns xhat(n) (the prediction made from x(n-1)..x(n-N) before x(n) was
  // seen), then adapts the weights with e(n). Non-finite input is the caller's responsibility
  // (the batch functions check); it would poison the state.
  double Process(double x);

  // Back to the state before the first sample (weights re-initialised).
  void Reset();

  const FlpOptions& options() const { return options_; }  // as given to Create
  const std::vector<double>& weights() const { return weights_; }  // C(n): c_1 .. c_N
  std::size_t num_processed() const { return n_; }  // samples consumed since Create / Reset
  double last_error() const { return last_error_; }  // e(n) = x(n) - xhat(n) of the last sample
  double last_step() const { return last_step_; }   // eta(n) of Eq. (16)
  double power() const { return power_; }           // P(n)

 private:
  explicit FlpFilter(const FlpOptions& options);
  FlpOptions options_;
  std::vector<double> weights_;  // c_1 .. c_N
  std::vector<double> history_;  // ring buffer of the last N samples
  std::size_t head_ = 0;         // index of x(n-1) in history_
  std::size_t n_ = 0;
  double power_ = 0.0;
  double last_error_ = 0.0;
  double last_step_ = 0.0;
};

// What a batch FLP run did.
struct FlpSummary {
  std::size_t num_samples = 0;        // input length
  int order = 0;                      // N used
  double beta = 0.0;                  // beta used
  double alpha = 0.0;                 // alpha used
  std::vector<double> final_weights;  // C after the last sample
  double mean_step = 0.0;         // mean of eta(n)
  double final_step = 0.0;        // eta at the last sample
  double rms_error = 0.0;         // RMS prediction error e(n), signal units
  double rms_error_second_half = 0.0;  // the same over the second half (after the start-up)
  // "FLP order 8, beta 0.01, alpha 4: 1000 samples, mean step ..., weights [...]"
  std::string BriefReport() const;
};

// The filtered record and what happened.
struct FlpResult {
  std::vector<double> filtered;   // xhat(n), same length as the input
  FlpSummary summary;             // weights, steps and errors
};

// Batch FLP over a record. Errors: invalid options (kInvalidArgument), empty input or non-finite
// samples (kInvalidInput, naming the index).
Result<FlpResult> RunFlp(std::span<const double> x, const FlpOptions& options = {});
// Convenience: the filtered signal only.
Result<std::vector<double>> FlpDenoise(std::span<const double> x, const FlpOptions& options = {});

}  // namespace gyrocomp
