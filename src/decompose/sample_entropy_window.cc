// Sample entropy by a sorted window: see sample_entropy_window.h.
//
// Exact comparisons as integers: the distinct values ranked, the values that match value v
// (fl(|v - u|) < r, the brute-force predicate) form one run of ranks [lo, lo + len) (rounding is
// monotone), found once per distinct value with that same predicate. So x[j] matches x[i]
// exactly when rank(x[j]) - lo(x[i]) < len(x[i]) as unsigned integers (a rank below lo wraps
// to a large number). Ranks are 16-bit when the series has at most 65,536 distinct values
// (32 to a 512-bit vector), else 32-bit (16); the lanes' comparisons are ANDed over the
// coordinates (mask registers on AVX-512) and A and B counted in one pass.
//
// Vectorisation: GCC vector extensions, compiled for AVX-512BW, AVX2 and the x86-64 baseline
// (target attributes; no -march=native) and chosen at the first call. Integer arithmetic only:
// every path gives the same counts.
#include "sample_entropy_window.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstring>
#include <optional>
#include <thread>
#include <type_traits>
#include <utility>

// The 512-bit vector helpers are always inlined, never passed across an ABI boundary.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace gyrocomp::se_detail {
namespace {

constexpr std::size_t kVectorBytes = 64;
// Columns are padded by this many entries: the last vector of a run may read that far past it.
constexpr std::size_t kPad = kVectorBytes / sizeof(std::uint16_t);

// ---- radix sort ---------------------------------------------------------------------------------

constexpr int kRadixBits = 11;  // 2048-entry histograms stay in L1
constexpr std::size_t kRadixBuckets = std::size_t{1} << kRadixBits;

// Order-preserving map of a double's bits to an unsigned integer: negative values have every
// bit flipped, non-negative ones the sign bit set. (-0.0 sorts just before +0.0: equal values,
// so the order stays non-decreasing in value.)
std::uint64_t SortableBits(double v) {
  const std::uint64_t u = std::bit_cast<std::uint64_t>(v);
  return (u >> 63) ? ~u : (u | (std::uint64_t{1} << 63));
}

// Sorts `items` by `keys` < 2^key_bits (both permuted; LSD radix, stable). One read for all
// histograms; a pass whose digit is the same for every key is skipped.
void RadixSort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& items, int key_bits = 64) {
  const std::size_t n = keys.size();
  if (n < 2) return;
  const int passes = std::max(1, (key_bits + kRadixBits - 1) / kRadixBits);
  std::vector<std::uint64_t> keys_tmp(n);
  std::vector<std::uint32_t> items_tmp(n);
  std::vector<std::uint32_t> hist(static_cast<std::size_t>(passes) * kRadixBuckets, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (int p = 0; p < passes; ++p) ++hist[p * kRadixBuckets + ((keys[i] >> (p * kRadixBits)) & (kRadixBuckets - 1))];
  }
  for (int p = 0; p < passes; ++p) {
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

// ---- the kernel, once per instruction set --------------------------------------------------------

namespace avx512bw_path {
#pragma GCC push_options
#pragma GCC target("avx512bw")
#include "sample_entropy_window_kernel.inc"
#pragma GCC pop_options
}  // namespace avx512bw_path

namespace avx2_path {
#pragma GCC push_options
#pragma GCC target("avx2")
#include "sample_entropy_window_kernel.inc"
#pragma GCC pop_options
}  // namespace avx2_path

namespace baseline_path {
#include "sample_entropy_window_kernel.inc"
}  // namespace baseline_path

using SliceFn = WindowCounts (*)(const WindowPlan&, std::size_t, std::size_t);

template <int M>
SliceFn SliceOn(WindowPath path) {
  switch (path) {
    case WindowPath::kAvx512bw: return &avx512bw_path::SliceAny<M>;
    case WindowPath::kAvx2: return &avx2_path::SliceAny<M>;
    case WindowPath::kBaseline: break;
  }
  return &baseline_path::SliceAny<M>;
}

SliceFn Slice(int m, WindowPath path) {
  static_assert(kWindowMaxM == 4);
  switch (m) {
    case 1: return SliceOn<1>(path);
    case 2: return SliceOn<2>(path);
    case 3: return SliceOn<3>(path);
    default: return SliceOn<4>(path);
  }
}

WindowPath BestWindowPath() {
  if (WindowPathSupported(WindowPath::kAvx512bw)) return WindowPath::kAvx512bw;
  if (WindowPathSupported(WindowPath::kAvx2)) return WindowPath::kAvx2;
  return WindowPath::kBaseline;
}

// Dense ranks of the values (equal values, equal ranks); for every sample i, the run of ranks
// [lo, lo + len) that match x[i] (two pointers over the distinct values with the brute-force
// predicate: u_q - u_lo < r, u_hi - u_q >= r); and the group of every value: the distinct values
// cut greedily into maximal runs whose first and last values are within r (sample_entropy_ranges.cc,
// Groups: two groups apart never match). Returns the groups; sets w.rank, run_lo, run_len, narrow.
std::vector<std::uint32_t> RankRunsAndGroups(std::span<const double> x, std::span<const std::uint32_t> order,
                                             double r, WindowPlan& w) {
  std::vector<double> distinct;
  distinct.reserve(x.size());
  w.rank.resize(x.size());
  for (std::uint32_t i : order) {
    if (distinct.empty() || x[i] != distinct.back()) distinct.push_back(x[i]);
    w.rank[i] = static_cast<std::uint32_t>(distinct.size() - 1);
  }
  w.narrow = distinct.size() <= 65536;  // ranks and run lengths - 1 fit 16 bits
  std::vector<std::uint32_t> lo_of(distinct.size()), len_of(distinct.size()), group_of(distinct.size());
  std::uint32_t g = 0;
  for (std::size_t q = 0, lo = 0, hi = 0, first = 0; q < distinct.size(); ++q) {
    while (!(distinct[q] - distinct[lo] < r)) ++lo;
    if (hi <= q) hi = q + 1;
    while (hi < distinct.size() && distinct[hi] - distinct[q] < r) ++hi;
    lo_of[q] = static_cast<std::uint32_t>(lo);
    len_of[q] = static_cast<std::uint32_t>(hi - lo);
    if (!(distinct[q] - distinct[first] < r)) {
      ++g;
      first = q;
    }
    group_of[q] = g;
  }
  w.run_lo.resize(x.size());
  w.run_len.resize(x.size());
  std::vector<std::uint32_t> group(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const std::size_t q = w.rank[i];
    w.run_lo[i] = lo_of[q];
    w.run_len[i] = len_of[q];
    group[i] = group_of[q];
  }
  return group;
}

// Column l (0..m) at position k: the rank of x[start[k] + l] as R; the kPad entries after each
// column are 0 (read by a run's last vector, masked off).
template <typename R>
void FillColumns(const WindowPlan& w, std::vector<R>& columns) {
  const std::size_t templates = w.start.size();
  const std::size_t M = static_cast<std::size_t>(w.m);
  columns.assign((M + 1) * w.stride, R{0});
  for (std::size_t l = 0; l <= M; ++l) {
    R* y = columns.data() + l * w.stride;
    for (std::size_t k = 0; k < templates; ++k) y[k] = static_cast<R>(w.rank[w.start[k] + l]);
  }
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
  WindowPlan w;
  w.m = m;
  const std::vector<std::uint32_t> group = RankRunsAndGroups(x, order, r, w);
  // Strip: templates by first value; run 1 = the later ones within r (rank below the end of the
  // first one's run of ranks: two pointers), no run 2.
  std::vector<std::uint32_t> by_value;
  by_value.reserve(templates);
  for (std::uint32_t i : order) {
    if (i < templates) by_value.push_back(i);
  }
  std::vector<std::uint32_t> ranks(templates);
  for (std::size_t k = 0; k < templates; ++k) ranks[k] = w.rank[by_value[k]];
  std::vector<WindowPlan::Runs> strip(templates);
  std::uint64_t strip_pairs = 0;
  for (std::size_t k = 0, h = 0; k < templates; ++k) {
    const std::uint32_t hi = w.run_lo[by_value[k]] + w.run_len[by_value[k]];  // end of the run
    if (h <= k) h = k + 1;
    while (h < templates && ranks[h] < hi) ++h;
    strip[k] = {static_cast<std::uint32_t>(h), static_cast<std::uint32_t>(h), static_cast<std::uint32_t>(h)};
    strip_pairs += h - k - 1;
  }
  // Cells: (group of x[i], group of x[i+1]) (m >= 2; for m = 1 the second is 0), sorted.
  const std::uint32_t last_group = group.empty() ? 0u : *std::max_element(group.begin(), group.end());
  const int bits = static_cast<int>(std::bit_width(last_group)) + 1;  // one spare bit for b + 1
  std::vector<std::uint64_t> cell(templates);
  std::vector<std::uint32_t> by_cell(templates);
  for (std::size_t i = 0; i < templates; ++i) {
    cell[i] = (std::uint64_t{group[i]} << bits) | (m >= 2 ? group[i + 1] : 0u);
    by_cell[i] = static_cast<std::uint32_t>(i);
  }
  RadixSort(cell, by_cell, 2 * bits);
  // Run 1: cells (a, b), (a, b + 1) after k; run 2: (a + 1, b - 1) .. (a + 1, b + 1). Each bound
  // is non-decreasing in k (cells are sorted), so three pointers walk the cells once. (b + 1
  // stays below 2^bits: one spare bit.)
  const std::uint64_t row = std::uint64_t{1} << bits;
  std::vector<WindowPlan::Runs> grid(templates);
  std::uint64_t grid_same = 0, grid_next = 0;
  for (std::size_t k = 0, same_end = 0, next_begin = 0, next_end = 0; k < templates; ++k) {
    const std::uint64_t c = cell[k];
    while (same_end < templates && cell[same_end] <= c + 1) ++same_end;
    while (next_begin < templates && cell[next_begin] < c + row - ((c & (row - 1)) > 0 ? 1 : 0)) ++next_begin;
    next_end = std::max(next_end, next_begin);
    while (next_end < templates && cell[next_end] <= c + row + 1) ++next_end;
    grid[k] = {static_cast<std::uint32_t>(same_end), static_cast<std::uint32_t>(next_begin),
               static_cast<std::uint32_t>(next_end)};
    grid_same += same_end - k - 1;
    grid_next += next_end - next_begin;
  }
  // The cheaper layout: run 1 checks coordinates 1..m, run 2 coordinates 0..m.
  const std::uint64_t strip_checks = strip_pairs * M;
  const std::uint64_t grid_checks = grid_same * M + grid_next * (M + 1);
  const bool use_grid = grid_checks < strip_checks;
  w.runs = use_grid ? std::move(grid) : std::move(strip);
  w.pairs = use_grid ? grid_same + grid_next : strip_pairs;
  w.coordinate_checks = std::min(grid_checks, strip_checks);
  w.start = use_grid ? std::move(by_cell) : std::move(by_value);
  w.stride = templates + kPad;
  if (w.narrow) {
    FillColumns(w, w.columns16);
  } else {
    FillColumns(w, w.columns32);
  }
  return w;
}

bool WindowPathSupported(WindowPath path) {
  __builtin_cpu_init();
  switch (path) {
    case WindowPath::kAvx512bw: return __builtin_cpu_supports("avx512bw");
    case WindowPath::kAvx2: return __builtin_cpu_supports("avx2");
    case WindowPath::kBaseline: return true;
  }
  return false;
}

// The slice [k0, k1) in chunks of at most kCancelChunkPairs pairs / kCancelChunkTemplates
// templates, `cancel` polled between them (the counts are integer sums: chunking changes nothing).
static WindowCounts ChunkedSlice(SliceFn slice, const WindowPlan& w, std::size_t k0, std::size_t k1,
                          const CancellationToken* cancel) {
  if (cancel == nullptr) return slice(w, k0, k1);
  WindowCounts out;
  for (std::size_t k = k0; k < k1 && !cancel->cancelled();) {
    std::size_t end = k;
    std::uint64_t pairs = 0;
    while (end < k1 && end - k < kCancelChunkTemplates && pairs < kCancelChunkPairs) {
      pairs += (w.runs[end].same_end - end - 1) + (w.runs[end].next_end - w.runs[end].next_begin);
      ++end;
    }
    const WindowCounts part = slice(w, k, end);
    out.a += part.a;
    out.b += part.b;
    k = end;
  }
  return out;
}

WindowCounts CountWindowed(const WindowPlan& w, int num_threads, std::optional<WindowPath> path,
                           const CancellationToken* cancel) {
  assert(num_threads >= 1 && (!path || WindowPathSupported(*path)));
  static const WindowPath best = BestWindowPath();
  const std::size_t n = w.runs.size();
  const SliceFn slice = Slice(w.m, path.value_or(best));
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
    pool.emplace_back([&, t] { part[t] = ChunkedSlice(slice, w, bounds[t], bounds[t + 1], cancel); });
  }
  part[0] = ChunkedSlice(slice, w, bounds[0], bounds[1], cancel);
  for (auto& th : pool) th.join();
  WindowCounts out;
  for (const WindowCounts& p : part) {
    out.a += p.a;
    out.b += p.b;
  }
  return out;
}

}  // namespace gyrocomp::se_detail
