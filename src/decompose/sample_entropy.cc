// Sample entropy: see include/gyrocomp/sample_entropy.h. Two exact counters: the sorted window
// (sample_entropy_window.{h,cc}, pairs checked directly with SIMD; the cheaper one for the VMD
// modes of records up to ~10^5 samples) and range counting (sample_entropy_ranges.{h,cc});
// CountTemplateMatches picks.
#include "gyrocomp/decompose/sample_entropy.h"

#include "sample_entropy_ranges.h"
#include "sample_entropy_window.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

namespace gyrocomp {
namespace {

using Item = std::uint32_t;  // an index of x

// kFast takes the sorted window (sample_entropy_window.h) when it compares at most this many
// coordinates per template and at least half the values are distinct. Measured (one thread,
// sample_entropy_benchmark BM_SampleEntropyCounter and BM_SampleEntropyOfVmdModes;
// docs/explanation/performance.md, "Sample entropy and the decompose whole process"): the window
// costs ~0.03 ns per coordinate check with 16-bit ranks (<= 65,536 distinct values), ~0.05 ns
// with 32-bit ones; range counting 0.67-1.3 us per template on continuous values at
// N = 20k-200k (crossover ~18,000-22,000 checks per template), but only ~0.1-0.16 us with heavy
// ties (quantized data: its groups of equal values cost nothing per pair) while the window
// checks every tie.
constexpr std::uint64_t kWindowChecksPerTemplate = 16000;

// cancel: polled every 256 rows (templates^2 / 2 pair checks in all: the brute force is for
// small N; 256 rows of 10^5 templates are ~25 ms).
std::uint64_t CountBrute(std::span<const double> x, int d, double r, std::size_t templates,
                         const CancellationToken* cancel) {
  std::uint64_t count = 0;
  for (std::size_t i = 0; i < templates; ++i) {
    if (i % 256 == 0 && cancel != nullptr && cancel->cancelled()) return count;
    for (std::size_t j = i + 1; j < templates; ++j) {
      int l = 0;
      while (l < d && std::abs(x[i + l] - x[j + l]) < r) ++l;
      count += (l == d);
    }
  }
  return count;
}

double PairwiseSum(const double* x, std::size_t n) {
  if (n <= 128) {
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += x[i];
    return s;
  }
  const std::size_t h = n / 2;
  return PairwiseSum(x, h) + PairwiseSum(x + h, n - h);
}

// 0 for ordinary data; otherwise the exponent e with max |x| in [2^e, 2^(e+1)), when max |x| is
// outside [2^-256, 2^256] (there the squares of the SD or the differences may leave the range).
int NormalisingExponent(std::span<const double> x) {
  double max_abs = 0.0;
  for (double v : x) max_abs = std::max(max_abs, std::abs(v));
  if (max_abs == 0.0) return 0;
  const int e = std::ilogb(max_abs);
  return (e > 256 || e < -256) ? e : 0;
}

// Few ties: at least half the values distinct (kWindowChecksPerTemplate). `order`: x by value.
bool FewTies(std::span<const double> x, std::span<const Item> order) {
  std::size_t distinct = order.empty() ? 0 : 1;
  for (std::size_t k = 1; k < order.size(); ++k) distinct += x[order[k]] != x[order[k - 1]];
  return 2 * distinct >= order.size();
}

}  // namespace

bool SampleEntropyOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = "SampleEntropyOptions::" + what;
    return false;
  };
  auto str = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  if (m < 1 || m > 10) return fail("m = " + std::to_string(m) + ": must be in 1..10");
  if (!(r_factor > 0) || !std::isfinite(r_factor)) return fail("r_factor = " + str(r_factor) + ": must be > 0");
  if (reference_sd && (!(*reference_sd > 0) || !std::isfinite(*reference_sd))) {
    return fail("reference_sd = " + str(*reference_sd) + ": must be > 0 when set");
  }
  if (r_absolute && (!(*r_absolute > 0) || !std::isfinite(*r_absolute))) {
    return fail("r_absolute = " + str(*r_absolute) + ": must be > 0 when set");
  }
  if (num_threads && *num_threads < 1) return fail("num_threads = " + std::to_string(*num_threads) + ": must be >= 1 when set");
  return true;
}

std::string SampleEntropyResult::BriefReport() const {
  std::ostringstream os;
  os.precision(5);
  os << "SampEn(m=" << m << ", r=" << r << ") = " << sample_entropy << " (A=" << a_matches
     << ", B=" << b_matches << ", N=" << n << ") in " << elapsed_s << " s";
  if (!defined) os << " [undefined: no template match of length m]";
  return os.str();
}

double PopulationSd(std::span<const double> x) {
  if (x.empty()) return 0.0;
  const double mean = PairwiseSum(x.data(), x.size()) / x.size();
  std::vector<double> sq(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) sq[i] = (x[i] - mean) * (x[i] - mean);
  return std::sqrt(PairwiseSum(sq.data(), sq.size()) / x.size());
}

namespace {

TemplateMatchCounts CountTemplateMatchesPolling(std::span<const double> x, int m, double r,
                                                SampleEntropyAlgorithm algorithm, int num_threads,
                                                const CancellationToken* cancel) {
  TemplateMatchCounts out;
  if (m < 1 || x.size() < static_cast<std::size_t>(m) + 2) return out;
  const std::size_t templates = x.size() - m;  // the same N - m start points for m and m + 1
  if (algorithm == SampleEntropyAlgorithm::kBruteForce) {
    out.b = CountBrute(x, m, r, templates, cancel);
    out.a = CountBrute(x, m + 1, r, templates, cancel);
    return out;
  }
  const int threads = num_threads > 0 ? num_threads
                                      : std::max(1, std::min(2, static_cast<int>(std::thread::hardware_concurrency())));
  std::vector<Item> order = se_detail::OrderByValue(x);
  const bool window_allowed = algorithm != SampleEntropyAlgorithm::kRangeCount && m <= se_detail::kWindowMaxM &&
                              x.size() <= se_detail::kWindowMaxSamples;
  if (window_allowed && (algorithm == SampleEntropyAlgorithm::kSortedWindow || FewTies(x, order))) {
    const se_detail::WindowPlan plan = se_detail::PlanWindow(x, order, templates, m, r);
    if (algorithm == SampleEntropyAlgorithm::kSortedWindow ||
        plan.coordinate_checks <= kWindowChecksPerTemplate * templates) {
      const se_detail::WindowCounts w = se_detail::CountWindowed(plan, threads, std::nullopt, cancel);
      out.a = w.a;
      out.b = w.b;
      return out;
    }
  }
  return se_detail::CountByRanges(x, m, r, std::move(order), templates, threads, cancel);
}

}  // namespace

TemplateMatchCounts CountTemplateMatches(std::span<const double> x, int m, double r,
                                         SampleEntropyAlgorithm algorithm, int num_threads,
                                         const CancellationToken* cancel) {
  // Every counter stops early once `cancel` is set; the partial counts never leave: Cancelled is
  // thrown here, on the calling thread, after the counting threads joined.
  const TemplateMatchCounts out = CountTemplateMatchesPolling(x, m, r, algorithm, num_threads, cancel);
  if (cancel != nullptr && cancel->cancelled()) throw Cancelled();
  return out;
}

namespace {

// The series checks of SampleEntropy, in the order it reports them; nullopt when x can be counted.
std::optional<Error> SeriesError(std::span<const double> x, int m) {
  if (x.size() < static_cast<std::size_t>(m) + 2) {
    return InvalidInput("sample entropy needs at least m + 2 = " + std::to_string(m + 2) + " samples, got " +
                        std::to_string(x.size()));
  }
  if (x.size() > se_detail::kRangeMaxSamples) {
    return InvalidInput("sample entropy: series longer than 2^31 - 1 samples");
  }
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i])) return InvalidInput("sample entropy: value " + std::to_string(i) + " is not finite");
  }
  return std::nullopt;
}

// Extreme but finite values (|x| near 1e308: differences and squares overflow; near 1e-300:
// squares underflow and the SD reads 0) are counted as x / 2^e (e = NormalisingExponent(x)). A
// power of two commutes exactly with every difference and comparison |x_i - x_j| < r, so the
// counts are those of the definition. Returns x itself when e = 0, else x / 2^e in *scaled.
std::span<const double> Normalised(std::span<const double> x, int e, std::vector<double>* scaled) {
  if (e == 0) return x;
  scaled->resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) (*scaled)[i] = std::ldexp(x[i], -e);
  return *scaled;
}

// The tolerance r in the units of xs = x / 2^e: r_absolute, else r_factor x (reference_sd, or
// the population SD of xs).
double NormalisedTolerance(const SampleEntropyOptions& opt, std::span<const double> xs, int e) {
  if (opt.r_absolute) return std::ldexp(*opt.r_absolute, -e);
  return opt.r_factor * (opt.reference_sd ? std::ldexp(*opt.reference_sd, -e) : PopulationSd(xs));
}

// Eq. (13): SampEn = -ln(A / B); +infinity when A = 0 < B, NaN when B = 0 (undefined).
double SampEnOfCounts(const TemplateMatchCounts& counts) {
  if (counts.b == 0) return std::numeric_limits<double>::quiet_NaN();
  if (counts.a == 0) return std::numeric_limits<double>::infinity();
  return -std::log(static_cast<double>(counts.a) / static_cast<double>(counts.b));
}

}  // namespace

Result<SampleEntropyResult> SampleEntropy(std::span<const double> x, const SampleEntropyOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  std::string why;
  if (!opt.IsValid(&why)) return InvalidArgument(why);
  if (std::optional<Error> bad = SeriesError(x, opt.m)) return *bad;
  const int e = NormalisingExponent(x);
  std::vector<double> scaled;
  const std::span<const double> xs = Normalised(x, e, &scaled);
  const double r = NormalisedTolerance(opt, xs, e);  // in the units of xs
  if (!(r > 0)) {
    return InvalidInput("sample entropy: tolerance r = 0 (the series is constant), SampEn is undefined");
  }
  SampleEntropyResult res;
  res.m = opt.m;
  res.r = std::ldexp(r, e);
  if (!std::isfinite(res.r)) {
    return InvalidArgument("sample entropy: tolerance r = r_factor x SD exceeds the double range");
  }
  res.n = x.size();
  if (opt.cancel != nullptr && opt.cancel->cancelled()) throw Cancelled();
  const TemplateMatchCounts counts =
      CountTemplateMatches(xs, opt.m, r, opt.algorithm, opt.num_threads.value_or(0), opt.cancel);
  res.a_matches = counts.a;
  res.b_matches = counts.b;
  res.defined = counts.b > 0;
  res.sample_entropy = SampEnOfCounts(counts);
  res.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

}  // namespace gyrocomp
