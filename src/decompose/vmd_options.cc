// VmdOptions validation, VmdSummary::BriefReport and the option-derived helpers of DecomposeVmd
// (initial centre frequencies, the problem-size bound): see include/gyrocomp/decompose/vmd.h.
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "gyrocomp/decompose/vmd.h"
#include "vmd_kernel.h"

namespace gyrocomp {
namespace {

// numpy's legacy np.random.rand after np.random.seed(seed): 53-bit doubles from MT19937.
std::vector<double> NumpyRand(std::uint32_t seed, int count) {
  std::mt19937 mt(seed);
  std::vector<double> out(count);
  for (double& v : out) {
    const std::uint32_t a = mt() >> 5;
    const std::uint32_t b = mt() >> 6;
    v = (a * 67108864.0 + b) / 9007199254740992.0;
  }
  return out;
}

// Initial centre frequencies (cycles per sample): uniform, random (vmdpy's init = 2) or zero.
}  // namespace

std::vector<double> vmd_internal::InitialCenterFrequencies(const VmdOptions& opt, std::size_t n_even) {
  const int K = opt.num_modes;
  std::vector<double> omega(K, 0.0);
  if (opt.init == VmdInit::kUniform) {
    for (int k = 0; k < K; ++k) omega[k] = (0.5 / K) * k;
  } else if (opt.init == VmdInit::kRandom) {
    const double fs = 1.0 / static_cast<double>(n_even);
    const std::vector<double> u = NumpyRand(opt.seed, K);
    for (int k = 0; k < K; ++k) omega[k] = std::exp(std::log(fs) + (std::log(0.5) - std::log(fs)) * u[k]);
    std::sort(omega.begin(), omega.end());
  }
  if (opt.initial_center_frequencies) omega = *opt.initial_center_frequencies;
  if (opt.dc) omega[0] = 0.0;
  return omega;
}

bool VmdOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, const std::string& value, const char* what) {
    if (error) *error = "VmdOptions::" + field + " = " + value + ": " + what;
    return false;
  };
  auto str = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  if (num_modes < 1) return fail("num_modes", std::to_string(num_modes), "must be >= 1");
  if (!(alpha > 0) || !std::isfinite(alpha)) return fail("alpha", str(alpha), "must be > 0 and finite");
  // tau is the dual-ascent step of Eq. (6). An ADMM dual step converges only below a bound of the
  // order of the penalty (Glowinski: (1 + sqrt 5) / 2 times it); measured on simulated records,
  // tau = 2 stays bounded and tau = 5 diverges (1e173 after 500 updates), tau = 1e300 gives NaN
  // at once. Valid: [0, kMaxTau].
  if (!(tau >= 0 && tau <= kMaxTau)) return fail("tau", str(tau), "must be in [0, 2]");
  if (!(tol > 0) || !std::isfinite(tol)) return fail("tol", str(tol), "must be > 0 and finite");
  if (initial_center_frequencies) {
    if (initial_center_frequencies->size() != static_cast<std::size_t>(num_modes)) {
      return fail("initial_center_frequencies", std::to_string(initial_center_frequencies->size()) + " values",
                  "must hold num_modes values");
    }
    for (double w : *initial_center_frequencies) {
      if (!(w >= 0 && w <= 0.5)) return fail("initial_center_frequencies", str(w), "must be in [0, 0.5] cycles per sample");
    }
  }
  if (omega_extrapolation_period && *omega_extrapolation_period < 3) {
    return fail("omega_extrapolation_period", std::to_string(*omega_extrapolation_period), "must be >= 3 when set");
  }
  if (max_iterations < 2) return fail("max_iterations", std::to_string(max_iterations), "must be >= 2");
  if (!(fs_hz > 0) || !std::isfinite(fs_hz)) return fail("fs_hz", str(fs_hz), "must be > 0 and finite");
  if (num_threads && *num_threads < 1) {
    return fail("num_threads", std::to_string(*num_threads), "must be >= 1 when set");
  }
  return true;
}

std::string VmdSummary::BriefReport() const {
  std::ostringstream os;
  os.precision(4);
  os << "VMD K=" << num_modes << " N=" << num_samples << ": "
     << (converged ? "converged after " : "did not converge in ") << iterations
     << " iterations (update " << final_update << (converged ? " <= tol" : " > tol") << ") in "
     << elapsed_s << " s on " << threads_used << " thread(s); centre frequencies [Hz]:";
  for (double f : center_frequency_hz) os << " " << f;
  if (omega_extrapolation_period) os << "; centre frequencies extrapolated every " << *omega_extrapolation_period << " updates";
  return os.str();
}

// Bounds K by what the record can support, before anything is allocated: a mode needs frequency
// bins to live on (the one-sided spectrum holds about N of them, so K <= N / 2 leaves each mode
// two bins at least), and the working set (two complex iterates and the accumulator per mode and
// bin, plus the K x N modes returned: ~56 K N bytes) must fit `max_memory_bytes`.
Status vmd_internal::CheckProblemSize(const VmdOptions& opt, std::size_t n) {
  const auto K = static_cast<std::size_t>(opt.num_modes);
  if (K > n / 2)
    return InvalidArgument("VmdOptions::num_modes = " + std::to_string(K) + ": a record of " + std::to_string(n) +
                           " samples holds at most " + std::to_string(n / 2) + " modes (N / 2)");
  const double bytes = 56.0 * static_cast<double>(K) * static_cast<double>(n);
  if (bytes > static_cast<double>(opt.max_memory_bytes)) {
    std::ostringstream os;
    os.precision(3);
    os << "VMD of K = " << K << " modes on " << n << " samples needs " << bytes / (1u << 30) << " GB; at most "
       << static_cast<double>(opt.max_memory_bytes) / (1u << 30) << " allowed (VmdOptions::max_memory_bytes)";
    return InvalidArgument(os.str());
  }
  return {};
}

}  // namespace gyrocomp
