// Variable-step LMS forward linear predictor (paper Eqs. 14-16), normalised so it is scale-free.
#include "gyrocomp/denoise/flp.h"

#include "normalising_scale.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>

namespace gyrocomp {

std::optional<FlpInitialWeights> ParseFlpInitialWeights(std::string_view name) {
  if (name == "moving-average") return FlpInitialWeights::kMovingAverage;
  if (name == "zero") return FlpInitialWeights::kZero;
  if (name == "last-sample") return FlpInitialWeights::kLastSample;
  return std::nullopt;
}

const char* FlpInitialWeightsName(FlpInitialWeights w) {
  switch (w) {
    case FlpInitialWeights::kMovingAverage: return "moving-average";
    case FlpInitialWeights::kZero: return "zero";
    case FlpInitialWeights::kLastSample: return "last-sample";
  }
  return "?";
}

bool FlpOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = "FlpOptions::" + message;
    return false;
  };
  auto str = [](double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  if (order < 1 || order > 4096) return fail("order = " + std::to_string(order) + ": must be in [1, 4096]");
  if (!(beta > 0.0 && beta < 2.0)) return fail("beta = " + str(beta) + ": must be in (0, 2) (NLMS stability)");
  if (!(alpha > 0.0 && std::isfinite(alpha))) return fail("alpha = " + str(alpha) + ": must be > 0 and finite");
  if (!(power_forgetting >= 0.0 && power_forgetting < 1.0)) {
    return fail("power_forgetting = " + str(power_forgetting) + ": must be in [0, 1)");
  }
  if (!(regularization >= 0.0 && std::isfinite(regularization))) {
    return fail("regularization = " + str(regularization) + ": must be >= 0 and finite");
  }
  return true;
}

FlpFilter::FlpFilter(const FlpOptions& options)
    : options_(options),
      weights_(static_cast<std::size_t>(options.order)),
      history_(2 * static_cast<std::size_t>(options.order)) {
  Reset();
}

Result<FlpFilter> FlpFilter::Create(const FlpOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  return FlpFilter(options);
}

void FlpFilter::Reset() {
  const std::size_t n = weights_.size();
  std::fill(weights_.begin(), weights_.end(), 0.0);
  switch (options_.initial_weights) {
    case FlpInitialWeights::kMovingAverage:
      std::fill(weights_.begin(), weights_.end(), 1.0 / static_cast<double>(n));
      break;
    case FlpInitialWeights::kLastSample:
      weights_[0] = 1.0;
      break;
    case FlpInitialWeights::kZero:
      break;
  }
  std::fill(history_.begin(), history_.end(), 0.0);
  head_ = 0;
  n_ = 0;
  power_ = 0.0;
  last_error_ = 0.0;
  last_step_ = 0.0;
}

double FlpFilter::Process(double x) {
  const std::size_t n = weights_.size();
  if (n_ == 0) {
    // Start-up: the past is taken to equal the first sample, P(0) = x(0)^2.
    std::fill(history_.begin(), history_.end(), x);
    power_ = x * x;
  }
  // history_[head_ + p - 1] = x(n - p), p = 1..N (the ring is stored twice, so this is contiguous).
  const double* past = history_.data() + head_;
  double prediction = 0.0;  // Eq. (14): xhat(n) = C^T X(n-1)
  double energy = 0.0;      // |X(n-1)|^2
  for (std::size_t p = 0; p < n; ++p) {
    prediction += weights_[p] * past[p];
    energy += past[p] * past[p];
  }
  const double error = x - prediction;  // e(n) = x(n) - xhat(n)
  const double lambda = options_.power_forgetting;
  power_ = lambda * power_ + (1.0 - lambda) * x * x;  // P(n): scale of the signal
  double normalised_error2 = 0.0;
  if (power_ > 0.0) {
    normalised_error2 = error * error / power_;
  } else if (error != 0.0) {
    normalised_error2 = std::numeric_limits<double>::infinity();
  }
  // Eq. (16): eta(n) = beta (1 - exp(-alpha e(n)^2)), with e^2 measured in units of P(n).
  const double step = options_.beta * (1.0 - std::exp(-options_.alpha * normalised_error2));
  // Eq. (15), normalised by the regressor energy (NLMS): C += eta e X / (eps + |X|^2).
  const double denominator = options_.regularization * static_cast<double>(n) * power_ + energy;
  if (denominator > 0.0 && std::isfinite(denominator)) {
    const double gain = step * error / denominator;
    for (std::size_t p = 0; p < n; ++p) weights_[p] += gain * past[p];
  }
  // Shift x(n) into the history.
  head_ = (head_ == 0) ? n - 1 : head_ - 1;
  history_[head_] = x;
  history_[head_ + n] = x;
  ++n_;
  last_error_ = error;
  last_step_ = step;
  return prediction;
}

std::string FlpSummary::BriefReport() const {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "FLP order %d, beta %g, alpha %g: %zu samples, mean step %.3g (last %.3g), RMS prediction "
                "error %.4g (second half %.4g)",
                order, beta, alpha, num_samples, mean_step, final_step, rms_error, rms_error_second_half);
  std::ostringstream out;
  out << buf << ", weights [";
  for (std::size_t i = 0; i < final_weights.size(); ++i) out << (i ? " " : "") << final_weights[i];
  out << "]";
  return out.str();
}

Result<FlpResult> RunFlp(std::span<const double> x, const FlpOptions& options) {
  Result<FlpFilter> created = FlpFilter::Create(options);
  if (!created.ok()) return created.error();
  if (std::optional<Error> bad = denoise_internal::SignalError(x, "FLP")) return *bad;
  // Near the ends of the double range the prediction and its error overflow: filter a
  // power-of-two scaled copy (normalising_scale.h; ordinary records are not touched).
  if (const double scale = denoise_internal::NormalisingScale(x); scale != 1.0) {
    Result<FlpResult> r = RunFlp(denoise_internal::Scaled(x, scale), options);
    if (!r.ok()) return r.error();
    if (!denoise_internal::Unscale(&r->filtered, scale)) {
      return InvalidInput("FLP: the filtered signal exceeds the range of a double (the signal is within a factor 2 "
                          "of the largest double)");
    }
    r->summary.rms_error /= scale;
    r->summary.rms_error_second_half /= scale;
    return r;
  }
  FlpFilter& filter = *created;
  FlpResult result;
  result.filtered.resize(x.size());
  double step_sum = 0.0, e2 = 0.0, e2_late = 0.0;
  const std::size_t half = x.size() / 2;
  for (std::size_t i = 0; i < x.size(); ++i) {
    result.filtered[i] = filter.Process(x[i]);
    step_sum += filter.last_step();
    const double e = filter.last_error();
    e2 += e * e;
    if (i >= half) e2_late += e * e;
  }
  FlpSummary& s = result.summary;
  s.num_samples = x.size();
  s.order = options.order;
  s.beta = options.beta;
  s.alpha = options.alpha;
  s.final_weights = filter.weights();
  s.mean_step = step_sum / static_cast<double>(x.size());
  s.final_step = filter.last_step();
  s.rms_error = std::sqrt(e2 / static_cast<double>(x.size()));
  s.rms_error_second_half = std::sqrt(e2_late / static_cast<double>(x.size() - half));
  return result;
}

Result<std::vector<double>> FlpDenoise(std::span<const double> x, const FlpOptions& options) {
  Result<FlpResult> r = RunFlp(x, options);
  if (!r.ok()) return r.error();
  return std::move(r->filtered);
}

}  // namespace gyrocomp
