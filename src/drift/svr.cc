// epsilon-SVR through LIBSVM, with LIBSVM's memory owned safely and copied out (see svr.h).
#include "gyrocomp/drift/svr.h"

#include <libsvm/svm.h>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

#include "gyrocomp/core/format.h"

// AddressSanitizer: GCC defines __SANITIZE_ADDRESS__, clang answers __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define GYROCOMP_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GYROCOMP_ASAN 1
#endif
#endif
#ifdef GYROCOMP_ASAN
#include <sanitizer/lsan_interface.h>
#endif

namespace gyrocomp {
namespace {

// SvrOptions::cancel. LIBSVM has no callback and no way to stop a fit, but its solver
// calls the print function every min(l, 1000) iterations (info(".")); that function pointer is
// process-wide, so it is set once (below) and reads the token of the fit running on its own
// thread (thread_local: the cuckoo search fits on several threads at once). Once the token is
// set it throws SolverStopped through LIBSVM's frames (Debian's libsvm3 is C++ built with
// exceptions: .eh_frame and __gxx_personality_v0; its SVR_Q and Cache are destroyed on the way
// out), caught at the svm_train call below. What LIBSVM allocated with new[] / malloc and frees
// only at the end of svm_train (the Solver's and solve_epsilon_svr's O(l) arrays, the model
// struct) is lost: a bounded leak, O(samples) doubles once per cancel. The alternatives were
// worse: a fit on a detached thread keeps the CPU busy and outlives the caller's buffers, and a
// smaller training set changes the models. Measured (docs/explanation/performance.md): the longest single
// svm_train of `fit --model cs-svr` on the 5 M-sample paper run takes up to 0.65 s.
struct SolverStopped {};
thread_local const CancellationToken* t_fit_cancel = nullptr;

void PrintOrStop(const char*) {  // LIBSVM's progress text is dropped
  if (t_fit_cancel != nullptr && t_fit_cancel->cancelled()) throw SolverStopped{};
}

// LIBSVM prints progress to stdout through a process-wide function pointer: set it once.
void SilenceLibsvm() {
  static std::once_flag once;
  std::call_once(once, [] { svm_set_print_string_function(&PrintOrStop); });
}

// svm_train with `cancel` polled as above; nullptr and *stopped when it was stopped. While a
// token is attached, LeakSanitizer ignores this thread's allocations (they are LIBSVM's, and a
// stopped fit leaks them by design), so the sanitizer suite can run the cancel tests.
svm_model* TrainOrStop(const svm_problem& problem, const svm_parameter& param, const CancellationToken* cancel,
                       bool* stopped) {
  struct Attach {
    explicit Attach(const CancellationToken* token) : token_(token) {
      t_fit_cancel = token;
#ifdef GYROCOMP_ASAN
      if (token_ != nullptr) __lsan_disable();
#endif
    }
    ~Attach() {
#ifdef GYROCOMP_ASAN
      if (token_ != nullptr) __lsan_enable();
#endif
      t_fit_cancel = nullptr;
    }
    const CancellationToken* token_;
  } attach(cancel);
  try {
    return svm_train(&problem, &param);
  } catch (const SolverStopped&) {
    *stopped = true;
    return nullptr;
  }
}

struct ModelDeleter {
  void operator()(svm_model* m) const { svm_free_and_destroy_model(&m); }
};
using ModelPtr = std::unique_ptr<svm_model, ModelDeleter>;

}  // namespace

std::optional<SvrScaling> ParseSvrScaling(std::string_view name) {
  if (name == "standard") return SvrScaling::kStandard;
  if (name == "none") return SvrScaling::kNone;
  return std::nullopt;
}

const char* SvrScalingName(SvrScaling scaling) {
  return scaling == SvrScaling::kStandard ? "standard" : "none";
}

double SvrOptions::ResolvedGamma(std::size_t num_inputs) const {
  if (gamma) return *gamma;
  if (sigma) return 1.0 / (2.0 * *sigma * *sigma);  // Eq. (20): gamma = 1 / (2 sigma^2)
  return 1.0 / static_cast<double>(num_inputs == 0 ? 1 : num_inputs);  // LIBSVM's default
}

bool SvrOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = "SvrOptions::" + what;
    return false;
  };
  // Bounds: every number of a fitted model must load again (model files refuse any
  // magnitude above 1e100, model_file_reader.h). C bounds the dual coefficients and with them the
  // intercept (C = 1e300 gave an intercept of 1.4e159); gamma = 1/(2 sigma^2) above 1e6 or sigma
  // outside [1e-3, 1e3] (in input SDs when scaled) makes the kernel a delta or a constant; an
  // epsilon above 1e6 target SDs is a tube nothing leaves.
  if (!(C > 0.0 && C <= kMaxC)) return fail("C = " + FormatNumber(C) + ": must be in (0, 1e6]");
  if (gamma && sigma) return fail("gamma and sigma both given: give one (gamma = 1/(2 sigma^2))");
  if (gamma && !(*gamma > 0.0 && *gamma <= kMaxGamma))
    return fail("gamma = " + FormatNumber(*gamma) + ": must be in (0, 1e6]");
  if (sigma && !(*sigma >= kMinSigma && *sigma <= kMaxSigma))
    return fail("sigma = " + FormatNumber(*sigma) + ": must be in [0.001, 1000]");
  if (!(epsilon >= 0.0 && epsilon <= kMaxEpsilon))
    return fail("epsilon = " + FormatNumber(epsilon) + ": must be in [0, 1e6]");
  if (!(tolerance > 0.0 && tolerance <= 1.0))
    return fail("tolerance = " + FormatNumber(tolerance) + ": must be in (0, 1]");
  if (!(cache_mb > 0.0)) return fail("cache_mb = " + FormatNumber(cache_mb) + ": must be > 0");
  return true;
}

AffineScaler AffineScaler::Identity(std::size_t n) {
  return AffineScaler{std::vector<double>(n, 0.0), std::vector<double>(n, 1.0)};
}

AffineScaler AffineScaler::Standardize(const std::vector<std::vector<double>>& columns) {
  AffineScaler s;
  for (const auto& c : columns) {
    double mean = 0.0;
    for (double v : c) mean += v;
    mean /= c.empty() ? 1.0 : static_cast<double>(c.size());
    double ss = 0.0;
    for (double v : c) ss += (v - mean) * (v - mean);
    const double sd = c.empty() ? 0.0 : std::sqrt(ss / static_cast<double>(c.size()));
    s.offset.push_back(mean);
    s.scale.push_back(sd > 0.0 && std::isfinite(sd) ? sd : 1.0);
  }
  return s;
}

std::string SvrSummary::BriefReport() const {
  std::ostringstream s;
  s << "epsilon-SVR (LIBSVM, RBF): " << num_train << " samples, " << num_support
    << " support vectors (" << num_bounded_support << " at C), C = " << C << ", gamma = " << gamma
    << ", epsilon = " << epsilon << ", tol = " << tolerance << ", train RMSE = " << train_rmse
    << ", " << fit_time_s << " s";
  return s.str();
}

double SvrModel::PredictOne(std::span<const double> x) const {
  assert(x.size() == num_inputs);
  double z[8];
  std::vector<double> zbig;
  double* zp = z;
  if (num_inputs > 8) {
    zbig.resize(num_inputs);
    zp = zbig.data();
  }
  for (std::size_t j = 0; j < num_inputs; ++j)
    zp[j] = (x[j] - input_scaler.offset[j]) / input_scaler.scale[j];
  // Eq. (23): f(x) = sum_i (alpha_i - alpha_i^*) exp(-gamma |x - x_i|^2) + b.
  double f = intercept;
  const std::size_t n = coefficients.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double* sv = &support_vectors[i * num_inputs];
    double d2 = 0.0;
    for (std::size_t j = 0; j < num_inputs; ++j) {
      const double d = zp[j] - sv[j];
      d2 += d * d;
    }
    f += coefficients[i] * std::exp(-gamma * d2);
  }
  return target_offset + target_scale * f;
}

std::vector<double> SvrModel::Predict(const std::vector<std::vector<double>>& inputs) const {
  assert(inputs.size() == num_inputs);
  const std::size_t n = inputs.empty() ? 0 : inputs[0].size();
  std::vector<double> out(n);
  auto range = [&](std::size_t a, std::size_t b) {
    std::vector<double> row(num_inputs);
    for (std::size_t i = a; i < b; ++i) {
      for (std::size_t j = 0; j < num_inputs; ++j) row[j] = inputs[j][i];
      out[i] = PredictOne(row);
    }
  };
  // Long records (full-rate prediction) are split over the cores; each sample is computed the
  // same way whatever the split, so the result does not depend on the thread count.
  const std::size_t work = n * (coefficients.size() + 1);
  const std::size_t threads =
      work < (1u << 22) ? 1 : std::max<std::size_t>(1, std::thread::hardware_concurrency());
  if (threads == 1) {
    range(0, n);
    return out;
  }
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(range, n * t / threads, n * (t + 1) / threads);
  range(0, n / threads);
  for (auto& th : pool) th.join();
  return out;
}

Result<SvrModel> FitSvr(const std::vector<std::vector<double>>& inputs,
                        std::span<const double> target, const SvrOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  const std::size_t d = inputs.size();
  const std::size_t n = target.size();
  if (d == 0) return InvalidArgument("FitSvr: no input columns");
  if (n < 2) return InvalidInput("FitSvr: need at least 2 training samples, got " + std::to_string(n));
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    return InvalidInput("FitSvr: too many training samples for LIBSVM");
  for (std::size_t j = 0; j < d; ++j) {
    if (inputs[j].size() != n)
      return InvalidInput("FitSvr: input column " + std::to_string(j) + " has " +
                          std::to_string(inputs[j].size()) + " rows, target has " + std::to_string(n));
    for (std::size_t i = 0; i < n; ++i)
      if (!std::isfinite(inputs[j][i]))
        return InvalidInput("FitSvr: non-finite input at column " + std::to_string(j) + ", row " +
                            std::to_string(i));
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(target[i]))
      return InvalidInput("FitSvr: non-finite target at row " + std::to_string(i));

  SvrModel model;
  model.num_inputs = d;
  if (options.scaling == SvrScaling::kStandard) {
    model.input_scaler = AffineScaler::Standardize(inputs);
    const AffineScaler ts =
        AffineScaler::Standardize({std::vector<double>(target.begin(), target.end())});
    model.target_offset = ts.offset[0];
    model.target_scale = ts.scale[0];
  } else {
    model.input_scaler = AffineScaler::Identity(d);
  }
  model.gamma = options.ResolvedGamma(d);

  // LIBSVM's problem: dense nodes (index 1..d, then the -1 terminator) in one buffer that stays
  // alive until the model's support vectors have been copied out below.
  std::vector<svm_node> nodes(n * (d + 1));
  std::vector<svm_node*> rows(n);
  std::vector<double> y(n);
  for (std::size_t i = 0; i < n; ++i) {
    svm_node* r = &nodes[i * (d + 1)];
    for (std::size_t j = 0; j < d; ++j) {
      r[j].index = static_cast<int>(j + 1);
      r[j].value = (inputs[j][i] - model.input_scaler.offset[j]) / model.input_scaler.scale[j];
    }
    r[d].index = -1;
    r[d].value = 0.0;
    rows[i] = r;
    y[i] = (target[i] - model.target_offset) / model.target_scale;
  }
  svm_problem problem;
  problem.l = static_cast<int>(n);
  problem.y = y.data();
  problem.x = rows.data();

  svm_parameter param{};
  param.svm_type = EPSILON_SVR;
  param.kernel_type = RBF;
  param.degree = 3;
  param.gamma = model.gamma;
  param.coef0 = 0.0;
  param.cache_size = options.cache_mb;
  param.eps = options.tolerance;
  param.C = options.C;
  param.nr_weight = 0;
  param.weight_label = nullptr;
  param.weight = nullptr;
  param.nu = 0.5;
  param.p = options.epsilon;
  param.shrinking = options.shrinking ? 1 : 0;
  param.probability = 0;
  if (const char* msg = svm_check_parameter(&problem, &param))
    return InvalidArgument(std::string("LIBSVM refused the parameters: ") + msg);

  SilenceLibsvm();
  if (options.cancel != nullptr && options.cancel->cancelled()) throw Cancelled();
  bool stopped = false;
  ModelPtr trained(TrainOrStop(problem, param, options.cancel, &stopped));
  if (stopped) throw Cancelled();  // SvrOptions::cancel (a fit that ended is kept: the caller polls)
  if (!trained) return InternalError("LIBSVM svm_train returned no model");

  // Copy the support vectors out (trained->SV points into `nodes`).
  const int nsv = trained->l;
  model.intercept = -trained->rho[0];
  model.coefficients.assign(trained->sv_coef[0], trained->sv_coef[0] + nsv);
  model.support_vectors.assign(static_cast<std::size_t>(nsv) * d, 0.0);
  for (int i = 0; i < nsv; ++i) {
    for (const svm_node* p = trained->SV[i]; p->index != -1; ++p) {
      if (p->index >= 1 && static_cast<std::size_t>(p->index) <= d)
        model.support_vectors[static_cast<std::size_t>(i) * d + (p->index - 1)] = p->value;
    }
  }
  trained.reset();

  SvrSummary& s = model.summary;
  s.num_train = n;
  s.num_support = model.coefficients.size();
  const double bound = options.C * (1.0 - 1e-12);
  for (double c : model.coefficients)
    if (std::abs(c) >= bound) ++s.num_bounded_support;
  s.C = options.C;
  s.gamma = model.gamma;
  s.epsilon = options.epsilon;
  s.tolerance = options.tolerance;
  const std::vector<double> fitted = model.Predict(inputs);
  double ss = 0.0;
  for (std::size_t i = 0; i < n; ++i) ss += (fitted[i] - target[i]) * (fitted[i] - target[i]);
  s.train_rmse = std::sqrt(ss / static_cast<double>(n));
  s.fit_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return model;
}

}  // namespace gyrocomp
