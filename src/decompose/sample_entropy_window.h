// Sample entropy by sorted windows (sample_entropy.cc picks it when it is cheaper than range
// counting). Internal to src/decompose/.
//
// Two layouts of the templates, the one with fewer coordinate checks kept (PlanWindow):
//   - strip: templates sorted by their first value x[i]; the later ones within r of template k
//     form one run [k + 1, hi_k) (rounding is monotone, so fl(y_j - y_k) < r holds on a prefix);
//   - cells: the values cut into groups along their sorted order (maximal runs of span < r: two
//     values two groups apart never match, sample_entropy_ranges.cc Groups) give template i the cell
//     (group of x[i], group of x[i+1]). A matching pair lies in the same or adjacent cells, so with
//     the templates sorted by cell, the candidates after template k form two runs: cells (a, b)
//     and (a, b + 1), then (a + 1, b - 1) .. (a + 1, b + 1). Best for noise-like series (~300
//     candidates per template for the noise-like VMD modes of a 20k-sample record against ~1,100
//     for the strip); the strip wins when x[i+1] follows x[i] closely.
// Every candidate is checked on every coordinate not known to match (coordinate 0 matches within
// a strip and within a group) with the brute-force predicate fl(|x_i+l - x_j+l|) < r, evaluated
// once per distinct value as a run of ranks and then compared as integers, 32 (16-bit ranks) or
// 16 pairs at a time (SIMD, the path chosen at run time); A and B come out of the same pass (B:
// coordinates 0..m-1 match; A: coordinate m too). Cost: proportional to the coordinate checks,
// whatever the match rate; quadratic when r spans most of the values, so the caller compares it
// with the range counting's cost first.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "gyrocomp/core/cancel.h"

namespace gyrocomp::se_detail {

// Largest m the window counter handles (one compiled variant per m).
constexpr int kWindowMaxM = 4;
// Longest series it handles (32-bit ranks and counts per lane).
constexpr std::size_t kWindowMaxSamples = std::size_t{1} << 29;
// Cancellation chunks of CountWindowed: ~2^22 pairs x (m + 1) checks at ~0.03-0.05 ns each
// (sample_entropy.cc kWindowChecksPerTemplate) is ~1 ms, far below the 0.1 s cancellation latency bound.
constexpr std::uint64_t kCancelChunkPairs = std::uint64_t{1} << 22;
constexpr std::size_t kCancelChunkTemplates = std::size_t{1} << 16;

// Start indices 0..x.size()-1 ordered by value (non-decreasing; equal values in any order).
// An LSD radix sort of the values' order-preserving bit patterns (no NaN in x).
std::vector<std::uint32_t> OrderByValue(std::span<const double> x);

struct WindowPlan {
  // Candidate partners of the template at sorted position k: [k + 1, same_end) and
  // [next_begin, next_end).
  struct Runs {
    std::uint32_t same_end, next_begin, next_end;
  };
  int m = 0;
  std::vector<std::uint32_t> start;  // start index of the template at sorted position k
  std::vector<Runs> runs;
  // Per sample i: dense rank of x[i] among the distinct values, and the run of ranks
  // [run_lo, run_lo + run_len) whose values match x[i].
  std::vector<std::uint32_t> rank, run_lo, run_len;
  bool narrow = false;                 // at most 65,536 distinct values: 16-bit columns
  std::size_t stride = 0;              // templates + 32 (a run's last vector may read 31 past it)
  // Column l (0..m), position k: rank[start[k] + l], 16-bit when narrow, else 32-bit.
  std::vector<std::uint16_t> columns16;
  std::vector<std::uint32_t> columns32;
  std::uint64_t pairs = 0;             // W: candidate pairs the count checks
  std::uint64_t coordinate_checks = 0; // sum over the candidates of the coordinates compared
};

// The layout and runs of templates 0..templates-1 (templates + m <= x.size()); `order`: every
// index of x ordered by value (OrderByValue). 1 <= m <= kWindowMaxM.
WindowPlan PlanWindow(std::span<const double> x, std::span<const std::uint32_t> order, std::size_t templates, int m,
                      double r);

struct WindowCounts {
  std::uint64_t a = 0;  // pairs matching in coordinates 0..m
  std::uint64_t b = 0;  // pairs matching in coordinates 0..m-1
};

// The compiled variants of the kernel (the same counts on every one).
enum class WindowPath { kAvx512bw, kAvx2, kBaseline };
bool WindowPathSupported(WindowPath path);

// A and B of sample entropy over `num_threads` >= 1 threads (the same counts for any number:
// integer sums over fixed slices of the templates), on `path` (nullopt: the best the CPU has).
// cancel (nullptr: not polled): each thread polls it between chunks of its slice (at most
// kCancelChunkPairs candidate pairs or kCancelChunkTemplates templates); once set, the threads
// stop early and the counts are partial: the caller checks the token after the call.
WindowCounts CountWindowed(const WindowPlan& plan, int num_threads, std::optional<WindowPath> path = std::nullopt,
                           const CancellationToken* cancel = nullptr);

}  // namespace gyrocomp::se_detail
