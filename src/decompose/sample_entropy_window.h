// Sample entropy by a sorted window (sample_entropy.cc picks it when it is cheaper than range
// counting). Internal to src/decompose/.
//
// The templates sorted by their first coordinate x[i]: for template k of that order, the later
// templates whose first coordinate is within r form one run [k + 1, hi_k) (rounding is
// monotone, so fl(y_j - y_k) < r holds on a prefix of the later ones; the same predicate as the
// brute force). Every pair of the run is checked directly on the other coordinates, eight pairs
// at a time (SIMD, the path chosen at run time), and A and B come out of the same pass: a pair
// counts in B when coordinates 1..m-1 match and in A when coordinate m matches too. Cost:
// W = sum_k (hi_k - k - 1) pair checks (WindowPairs), whatever the match rate. Narrow for the
// noise-like VMD modes of a 20k-sample record (W ~ 1,100 N); quadratic when r spans most of the
// values, so the caller compares W with the range counting's cost first.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace gyrocomp::se_detail {

// Largest m the window counter handles (one compiled variant per m).
constexpr int kWindowMaxM = 4;

// Start indices 0..x.size()-1 ordered by value (non-decreasing; equal values in any order).
// An LSD radix sort of the values' order-preserving bit patterns (no NaN in x).
std::vector<std::uint32_t> OrderByValue(std::span<const double> x);

// W = sum_k (hi_k - k - 1): the number of pairs the window counter checks. `sorted`: template
// start indices ordered by x[i].
std::uint64_t WindowPairs(std::span<const double> x, std::span<const std::uint32_t> sorted, double r);

struct WindowCounts {
  std::uint64_t a = 0;  // pairs matching in coordinates 0..m
  std::uint64_t b = 0;  // pairs matching in coordinates 0..m-1
};

// A and B of sample entropy for templates `sorted` (start indices ordered by x[i], each with
// i + m < x.size()), 1 <= m <= kWindowMaxM, over `num_threads` >= 1 threads (the same counts
// for any number: integer sums over fixed slices).
WindowCounts CountWindowed(std::span<const double> x, std::span<const std::uint32_t> sorted, int m, double r,
                           int num_threads);

}  // namespace gyrocomp::se_detail
