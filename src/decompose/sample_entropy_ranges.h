// Range counting, the second exact counter of sample entropy's matching template pairs
// (sample_entropy.cc takes it when the sorted window, sample_entropy_window.h, would cost more).
// Internal to src/decompose/.
//
// Range counting: fast exact counting of matching template pairs. A template is its start index
// i; its coordinates are x[i], x[i+1], ..., x[i+d-1] (d = m for B, m + 1 for A). Two templates match
// when fl(|x[i+l] - x[j+l]|) < r for every l, exactly the brute-force predicate. Because rounding
// is monotone, for a fixed value v the values w that match it form one contiguous run of the
// sorted order, so every "window" below is found with the same predicate as the brute force,
// never with v +- r (which would round differently and break ties on quantized data).
//
// Recursion on the coordinate c (templates sorted by coordinate c):
//   Self(S, c)    pairs within S that match in coordinates c..d-1;
//   Cross(L, R, c) pairs q in L, p in R (every L value <= every R value in coordinate c);
//   - if coordinate c spans less than r over S (resp. L u R), every pair matches in it: go to
//     coordinate c+1 (re-sorted) — for Cross, as a bipartite count (labels);
//   - two coordinates left: a sweep along c with a window, and a Fenwick tree over the ranks of
//     coordinate c+1 (per label for bipartite counts);
//   - one coordinate left: a sweep with a window;
//   - otherwise split S in halves: Self(left) + Self(right) + Cross(left, right), and Cross by
//     halving the larger side after trimming both to the values within r of the other.
// Bipartite counts (pairs with different labels) reuse Self with a label bit on each item.
//
// Cost: the values are ranked once per series (RankValues), so every re-sort of a
// subset by another coordinate is an integer sort of packed (rank, item) keys (a radix sort from
// kRadixMin items), and the top-level order is a filter of the ranked order. The window counts of
// the two-coordinate sweep use a bitset (popcounts over the run's words) up to kBitsetMax items,
// where most leaves are, and a Fenwick tree above. Tie order never matters: every count is
// symmetric in equal values.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "gyrocomp/core/cancel.h"
#include "gyrocomp/decompose/sample_entropy.h"

namespace gyrocomp::se_detail {

// Longest series range counting handles: a template's start index takes 31 bits (bit 31 labels
// the items of bipartite counts).
constexpr std::size_t kRangeMaxSamples = 0x7fffffffu;

// A and B (the matching pairs of length m + 1 and m among the `templates` = N - m templates of
// x) by range counting. `order`: the indices 0..N-1 of x by value (OrderByValue). `threads`
// workers share the work; `cancel` (nullptr: not polled) stops every worker early, leaving
// partial counts that the caller discards.
TemplateMatchCounts CountByRanges(std::span<const double> x, int m, double r, std::vector<std::uint32_t> order,
                                  std::size_t templates, int threads, const CancellationToken* cancel);

}  // namespace gyrocomp::se_detail
