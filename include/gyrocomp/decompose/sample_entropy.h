// Sample entropy (paper Section 3.2, Eqs. 8-13): step 2 of the pipeline.
//
// Richman & Moorman (2000), as in antropy (tests/golden/sample_entropy/):
//   - templates of length m and m+1 start at the same N - m points i = 0 .. N-m-1;
//   - Chebyshev distance; a match when |x_{i+l} - x_{j+l}| < r for every l (strict: real gyro
//     data is quantized, so distances equal to r do occur and count as non-matches);
//   - no self-matches; B = matching pairs of length m, A = of length m+1;
//   - SampEn = -ln(A / B) (Eq. 13).
// Two fast exact counters, the same counts as the brute-force definition, ties included (every
// comparison is the same floating-point |a - b| < r):
//   - range counting: matching pairs counted without walking them (a sorted sweep for 1-D
//     templates, a sweep with a Fenwick tree or bitset for 2-D ones, divide and conquer over the
//     first coordinate above that), so smooth, narrow-band VMD modes, where nearly every pair
//     matches, cost O(N log^(m) N) rather than O(N^2);
//   - sorted window: templates sorted by their first value; the W pairs within r there are
//     checked directly, 8 at a time, A and B in one pass. Cheaper while W is a few thousand per
//     template (the noise-like VMD modes of records up to some 10^4-10^5 samples).
// kFast computes W (O(N) after the sort) and takes the window when W is below the range
// counting's measured cost (sample_entropy.cc, kWindowPairsPerTemplate). Both use a small pool
// of threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "gyrocomp/core/cancel.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp {

// How the matching pairs are counted; every algorithm gives the same counts.
enum class SampleEntropyAlgorithm {
  kFast,          // the cheaper of the two exact counters below for this series and r (default)
  kRangeCount,    // range counting, O(N log^m N) whatever r
  kSortedWindow,  // a sorted window checked pair by pair with SIMD: O(N log N + W), W = pairs
                  // within r in the first coordinate; m <= 4 (larger m: range counting)
  kBruteForce,    // the O(N^2) definition; for tests and tiny inputs
};

// Parameters of SampEn(m, r) and how it is computed.
struct SampleEntropyOptions {
  // Embedding dimension m (template length). 1 .. 10.
  int m = 2;
  // Tolerance r as a factor of a standard deviation: r = r_factor * SD, where SD is the
  // population SD (ddof = 0) of the series measured, or reference_sd when set. > 0.
  double r_factor = 0.2;
  // SD to scale r_factor with instead of the measured series' own SD, e.g. the SD of the
  // original signal when measuring its VMD modes (in the series' unit). > 0 when set.
  std::optional<double> reference_sd;
  // Absolute tolerance r in the series' unit; overrides r_factor and reference_sd. > 0.
  std::optional<double> r_absolute;
  // Pair counter; kFast (default) picks the cheaper exact one. The result does not depend on it.
  SampleEntropyAlgorithm algorithm = SampleEntropyAlgorithm::kFast;
  // Worker threads of the fast algorithm; nullopt = automatic (hardware concurrency, at most 2).
  // The counts do not depend on it. >= 1 when set.
  std::optional<int> num_threads;
  // Polled while the pairs are counted, by every counting thread, at most ~2^16
  // templates or ~2^22 candidate pairs apart (well under 0.1 s): once cancelled, the threads
  // stop, join, and SampleEntropy throws Cancelled on the calling thread. nullptr: not polled.
  // Not owned.
  const CancellationToken* cancel = nullptr;

  bool IsValid(std::string* error) const;  // "SampleEntropyOptions::m = 0: must be in 1..10"
};

// The sample entropy of one series and the counts it came from.
struct SampleEntropyResult {
  // -ln(A/B). +infinity when A = 0 < B (no match of length m+1); NaN when B = 0 (undefined:
  // no match of length m at all). `defined` is false only in the latter case.
  double sample_entropy = 0.0;
  bool defined = false;  // false when B = 0 (sample_entropy is NaN)
  int m = 0;             // embedding dimension used
  double r = 0.0;            // the absolute tolerance used (series unit)
  std::size_t n = 0;         // series length N
  std::uint64_t a_matches = 0;  // unordered matching pairs of length m+1
  std::uint64_t b_matches = 0;  // unordered matching pairs of length m
  double elapsed_s = 0.0;  // wall-clock time of SampleEntropy, s
  // "SampEn(m=2, r=0.2021) = 2.1863 (A=1234, B=10987, N=2000) in 0.001 s"
  std::string BriefReport() const;
};

// Population standard deviation (ddof = 0), two-pass.
double PopulationSd(std::span<const double> x);

// Matching-pair counts (A for length m+1, B for length m) for an absolute tolerance r > 0.
struct TemplateMatchCounts {
  std::uint64_t a = 0;  // unordered matching pairs of length m+1
  std::uint64_t b = 0;  // unordered matching pairs of length m
};
// num_threads: workers for the fast algorithm (0 = automatic: hardware concurrency, at most 2).
// cancel: polled as SampleEntropyOptions::cancel says; once it is set the counts are partial
// (meaningless) and CountTemplateMatches throws Cancelled on the calling thread.
TemplateMatchCounts CountTemplateMatches(std::span<const double> x, int m, double r,
                                         SampleEntropyAlgorithm algorithm, int num_threads = 0,
                                         const CancellationToken* cancel = nullptr);

// Errors (kInvalidArgument / kInvalidInput): invalid options; a series shorter than m + 2; a
// non-finite value; r = 0 (a constant series with a relative tolerance). Throws Cancelled when
// options.cancel is set before the counts are complete.
Result<SampleEntropyResult> SampleEntropy(std::span<const double> x,
                                          const SampleEntropyOptions& options = {});

}  // namespace gyrocomp
