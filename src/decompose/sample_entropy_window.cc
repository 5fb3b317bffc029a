// Sample entropy by a sorted window: see sample_entropy_window.h.
//
// Vectorisation: GCC vector extensions of 8 doubles, compiled for AVX-512F, AVX2 and the x86-64
// baseline (target attributes; no -march=native) and chosen at the first call. The counts are
// integers and every lane evaluates the brute-force predicate fl(|a - b|) < r (a subtraction, the
// sign bit cleared, a comparison: no rounding choice), so every path gives the same counts.
#include "sample_entropy_window.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cstring>
#include <limits>
#include <thread>
#include <utility>

// The 512-bit vector helpers are always inlined, never passed across an ABI boundary.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace gyrocomp::se_detail {
namespace {

constexpr std::size_t kLanes = 8;
typedef double V8 __attribute__((vector_size(kLanes * sizeof(double))));
typedef std::int64_t I8 __attribute__((vector_size(kLanes * sizeof(std::int64_t))));

// ---- radix sort ---------------------------------------------------------------------------------

constexpr int kRadixBits = 11;  // 2048-entry histograms stay in L1
constexpr std::size_t kRadixBuckets = std::size_t{1} << kRadixBits;
constexpr int kRadixPasses = (64 + kRadixBits - 1) / kRadixBits;

// Order-preserving map of a double's bits to an unsigned integer: negative values have every
// bit flipped, non-negative ones the sign bit set. (-0.0 sorts just before +0.0: equal values,
// so the order stays non-decreasing in value.)
std::uint64_t SortableBits(double v) {
  const std::uint64_t u = std::bit_cast<std::uint64_t>(v);
  return (u >> 63) ? ~u : (u | (std::uint64_t{1} << 63));
}

// Sorts `items` by `keys` (both permuted; LSD radix, stable). One read for all histograms; a
// pass whose digit is the same for every key is skipped.
void RadixSort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& items) {
  const std::size_t n = keys.size();
  if (n < 2) return;
  std::vector<std::uint64_t> keys_tmp(n);
  std::vector<std::uint32_t> items_tmp(n);
  std::vector<std::uint32_t> hist(kRadixPasses * kRadixBuckets, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (int p = 0; p < kRadixPasses; ++p) ++hist[p * kRadixBuckets + ((keys[i] >> (p * kRadixBits)) & (kRadixBuckets - 1))];
  }
  for (int p = 0; p < kRadixPasses; ++p) {
    std::uint32_t* h = hist.data() + p * kRadixBuckets;
    const int shift = p * kRadixBits;
    if (h[(keys[0] >> shift) & (kRadixBuckets - 1)] == n) continue;
    std::uint32_t sum = 0;
    for (std::size_t d = 0; d < kRadixBuckets; ++d) sum += std::exchange(h[d], sum);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t at = h[(keys[i] >> shift) & (kRadixBuckets - 1)]++;
      keys_tmp[at] = keys[i];
      items_tmp[at] = items[i];
    }
    keys.swap(keys_tmp);
    items.swap(items_tmp);
  }
}

// ---- the kernel ---------------------------------------------------------------------------------

inline __attribute__((always_inline)) V8 Load(const double* p) {
  V8 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

// fl(|a - b|) per lane, as the brute force computes it: clearing the sign bit is the exact |.|.
inline __attribute__((always_inline)) V8 AbsDiff(V8 a, V8 centre) {
  const I8 abs_mask = (I8){} + std::int64_t{0x7fffffffffffffff};
  return (V8)((I8)(a - centre) & abs_mask);
}

inline __attribute__((always_inline)) V8 Max(V8 a, V8 b) { return a > b ? a : b; }

// The pairs (k, j .. j + 7) match in coordinates 0..M-1 (B) exactly when the largest fl(|.|) of
// those coordinates is < r, and in 0..M (A) when the largest over 0..M is (the max is exact, no
// NaN here). Coordinates below kFrom are known to match (the run's construction). `pad` (tail
// blocks): 0 in the lanes to count, +inf in the lanes past the run. Counts accumulate as -1 per
// match.
template <int M, int kFrom, bool kTail>
inline __attribute__((always_inline)) void Block(const WindowPlan& w, std::size_t j, const V8* centre, V8 r, V8 pad,
                                                 I8& acc_a, I8& acc_b) {
  V8 d = pad;  // full blocks: no pad, d starts at the first coordinate checked
  for (int l = kFrom; l < M; ++l) {
    const V8 dl = AbsDiff(Load(w.Column(l) + j), centre[l]);
    d = (l == kFrom && !kTail) ? dl : Max(d, dl);
  }
  const V8 da = AbsDiff(Load(w.Column(M) + j), centre[M]);
  if constexpr (kFrom == M && !kTail) {  // B: nothing to check (m = 1 within the run)
    acc_b -= 1;
    acc_a = da < r ? acc_a - 1 : acc_a;
  } else {
    acc_b = d < r ? acc_b - 1 : acc_b;
    acc_a = Max(d, da) < r ? acc_a - 1 : acc_a;
  }
}

// kTailPad + 8 - n: 0 in lanes 0..n-1, +inf in lanes n..7 (n valid lanes of 8).
constexpr double kInf = std::numeric_limits<double>::infinity();
alignas(64) constexpr double kTailPad[2 * kLanes] = {0, 0, 0, 0, 0, 0, 0, 0, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf};

// Template k against the candidates [j, end).
template <int M, int kFrom>
inline __attribute__((always_inline)) void Run(const WindowPlan& w, std::size_t j, std::size_t end, const V8* centre,
                                               V8 r, I8& acc_a, I8& acc_b) {
  const V8 none = {};
  for (; j + kLanes <= end; j += kLanes) Block<M, kFrom, false>(w, j, centre, r, none, acc_a, acc_b);
  if (j < end) Block<M, kFrom, true>(w, j, centre, r, Load(kTailPad + kLanes - (end - j)), acc_a, acc_b);
}

template <int M>
inline __attribute__((always_inline)) WindowCounts SliceBody(const WindowPlan& w, std::size_t k0, std::size_t k1,
                                                             double r) {
  const V8 rv = (V8){} + r;
  I8 acc_a = {}, acc_b = {};
  V8 centre[M + 1];
  for (std::size_t k = k0; k < k1; ++k) {
    for (int l = 0; l <= M; ++l) centre[l] = (V8){} + w.Column(l)[k];
    const WindowPlan::Runs& runs = w.runs[k];
    Run<M, 1>(w, k + 1, runs.same_end, centre, rv, acc_a, acc_b);  // coordinate 0 within r
    Run<M, 0>(w, runs.next_begin, runs.next_end, centre, rv, acc_a, acc_b);
  }
  WindowCounts out;
  for (std::size_t l = 0; l < kLanes; ++l) {
    out.a -= static_cast<std::uint64_t>(acc_a[l]);
    out.b -= static_cast<std::uint64_t>(acc_b[l]);
  }
  return out;
}

using SliceFn = WindowCounts (*)(const WindowPlan&, std::size_t, std::size_t, double);

template <int M>
__attribute__((target("avx512f"))) WindowCounts SliceAvx512f(const WindowPlan& w, std::size_t k0, std::size_t k1,
                                                              double r) {
  return SliceBody<M>(w, k0, k1, r);
}
template <int M>
__attribute__((target("avx2"))) WindowCounts SliceAvx2(const WindowPlan& w, std::size_t k0, std::size_t k1,
                                                        double r) {
  return SliceBody<M>(w, k0, k1, r);
}
template <int M>
WindowCounts SliceBaseline(const WindowPlan& w, std::size_t k0, std::size_t k1, double r) {
  return SliceBody<M>(w, k0, k1, r);
}

template <int M>
SliceFn BestSlice() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return &SliceAvx512f<M>;
  if (__builtin_cpu_supports("avx2")) return &SliceAvx2<M>;
  return &SliceBaseline<M>;
}

SliceFn Slice(int m) {
  static_assert(kWindowMaxM == 4);
  static const std::array<SliceFn, kWindowMaxM> fns = {BestSlice<1>(), BestSlice<2>(), BestSlice<3>(),
                                                       BestSlice<4>()};
  return fns[static_cast<std::size_t>(m - 1)];
}

// Group of every value: the values in sorted order cut greedily into maximal runs whose first
// and last values are within r (sample_entropy.cc, Groups: two groups apart never match).
std::vector<std::uint32_t> ValueGroups(std::span<const double> x, std::span<const std::uint32_t> order, double r) {
  std::vector<std::uint32_t> group(x.size());
  std::uint32_t g = 0;
  double first = order.empty() ? 0.0 : x[order[0]];
  for (std::uint32_t i : order) {
    if (!(x[i] - first < r)) {
      ++g;
      first = x[i];
    }
    group[i] = g;
  }
  return group;
}

}  // namespace

std::vector<std::uint32_t> OrderByValue(std::span<const double> x) {
  std::vector<std::uint64_t> keys(x.size());
  std::vector<std::uint32_t> order(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    keys[i] = SortableBits(x[i]);
    order[i] = static_cast<std::uint32_t>(i);
  }
  RadixSort(keys, order);
  return order;
}

WindowPlan PlanWindow(std::span<const double> x, std::span<const std::uint32_t> order, std::size_t templates, int m,
                      double r) {
  assert(m >= 1 && m <= kWindowMaxM && templates + static_cast<std::size_t>(m) <= x.size());
  const std::size_t M = static_cast<std::size_t>(m);
  // Strip: templates by first value; run 1 = the later ones within r (two pointers), no run 2.
  std::vector<std::uint32_t> by_value;
  by_value.reserve(templates);
  for (std::uint32_t i : order) {
    if (i < templates) by_value.push_back(i);
  }
  std::vector<WindowPlan::Runs> strip(templates);
  std::uint64_t strip_pairs = 0;
  for (std::size_t k = 0, h = 0; k < templates; ++k) {
    if (h <= k) h = k + 1;
    while (h < templates && x[by_value[h]] - x[by_value[k]] < r) ++h;
    strip[k] = {static_cast<std::uint32_t>(h), static_cast<std::uint32_t>(h), static_cast<std::uint32_t>(h)};
    strip_pairs += h - k - 1;
  }
  // Cells: (group of x[i], group of x[i+1]) (m >= 2; for m = 1 the second is 0), sorted.
  const std::vector<std::uint32_t> group = ValueGroups(x, order, r);
  std::vector<std::uint64_t> cell(templates);
  std::vector<std::uint32_t> by_cell(templates);
  for (std::size_t i = 0; i < templates; ++i) {
    cell[i] = (std::uint64_t{group[i]} << 32) | (m >= 2 ? group[i + 1] : 0u);
    by_cell[i] = static_cast<std::uint32_t>(i);
  }
  RadixSort(cell, by_cell);
  // Run 1: cells (a, b), (a, b + 1) after k; run 2: (a + 1, b - 1) .. (a + 1, b + 1). Each bound
  // is non-decreasing in k (cells are sorted), so three pointers walk the cells once.
  constexpr std::uint64_t kRow = std::uint64_t{1} << 32;
  std::vector<WindowPlan::Runs> grid(templates);
  std::uint64_t grid_same = 0, grid_next = 0;
  for (std::size_t k = 0, same_end = 0, next_begin = 0, next_end = 0; k < templates; ++k) {
    const std::uint64_t c = cell[k];
    while (same_end < templates && cell[same_end] <= c + 1) ++same_end;
    while (next_begin < templates && cell[next_begin] < c + kRow - ((c & (kRow - 1)) > 0 ? 1 : 0)) ++next_begin;
    next_end = std::max(next_end, next_begin);
    while (next_end < templates && cell[next_end] <= c + kRow + 1) ++next_end;
    grid[k] = {static_cast<std::uint32_t>(same_end), static_cast<std::uint32_t>(next_begin),
               static_cast<std::uint32_t>(next_end)};
    grid_same += same_end - k - 1;
    grid_next += next_end - next_begin;
  }
  // The cheaper layout: run 1 checks coordinates 1..m, run 2 coordinates 0..m.
  WindowPlan w;
  w.m = m;
  const std::uint64_t strip_checks = strip_pairs * M;
  const std::uint64_t grid_checks = grid_same * M + grid_next * (M + 1);
  const bool use_grid = grid_checks < strip_checks;
  const std::vector<std::uint32_t>& sorted = use_grid ? by_cell : by_value;
  w.runs = use_grid ? std::move(grid) : std::move(strip);
  w.pairs = use_grid ? grid_same + grid_next : strip_pairs;
  w.coordinate_checks = std::min(grid_checks, strip_checks);
  w.stride = templates + kLanes;
  w.columns.assign((M + 1) * w.stride, 0.0);
  for (std::size_t l = 0; l <= M; ++l) {
    double* y = w.columns.data() + l * w.stride;
    for (std::size_t k = 0; k < templates; ++k) y[k] = x[sorted[k] + l];
  }
  return w;
}

WindowCounts CountWindowed(const WindowPlan& w, double r, int num_threads) {
  assert(num_threads >= 1);
  const std::size_t n = w.runs.size();
  const SliceFn slice = Slice(w.m);
  // Slices of about equal pair checks (a template's cost is its runs), one per thread.
  const std::size_t threads = std::max<std::size_t>(1, std::min<std::size_t>(num_threads, n / 1024 + 1));
  std::vector<std::size_t> bounds(threads + 1, n);
  bounds[0] = 0;
  std::uint64_t run = 0;
  for (std::size_t k = 0, t = 1; k < n && t < threads; ++k) {
    run += (w.runs[k].same_end - k - 1) + (w.runs[k].next_end - w.runs[k].next_begin);  // pairs
    if (run * threads >= w.pairs * t) bounds[t++] = k + 1;
  }
  std::vector<WindowCounts> part(threads);
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) {
    pool.emplace_back([&, t] { part[t] = slice(w, bounds[t], bounds[t + 1], r); });
  }
  part[0] = slice(w, bounds[0], bounds[1], r);
  for (auto& th : pool) th.join();
  WindowCounts out;
  for (const WindowCounts& p : part) {
    out.a += p.a;
    out.b += p.b;
  }
  return out;
}

}  // namespace gyrocomp::se_detail
