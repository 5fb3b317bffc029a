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
#include <thread>
#include <utility>

// The 512-bit vector helpers are always inlined, never passed across an ABI boundary.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace gyrocomp::se_detail {
namespace {

constexpr std::size_t kLanes = 8;
typedef double V8 __attribute__((vector_size(kLanes * sizeof(double))));
typedef std::int64_t I8 __attribute__((vector_size(kLanes * sizeof(std::int64_t))));

// ---- radix sort of doubles --------------------------------------------------------------------

constexpr int kRadixBits = 11;  // 6 passes over 64 bits; 2048-entry histograms stay in L1
constexpr std::size_t kRadixBuckets = std::size_t{1} << kRadixBits;
constexpr int kRadixPasses = (64 + kRadixBits - 1) / kRadixBits;

// Order-preserving map of a double's bits to an unsigned integer: negative values have every
// bit flipped, non-negative ones the sign bit set. (-0.0 sorts just before +0.0: equal values,
// so the order stays non-decreasing in value.)
std::uint64_t SortableBits(double v) {
  const std::uint64_t u = std::bit_cast<std::uint64_t>(v);
  return (u >> 63) ? ~u : (u | (std::uint64_t{1} << 63));
}

// ---- the window kernel ------------------------------------------------------------------------

// Columns y[l][k] = x[sorted[k] + l], l = 0..m, each padded with kLanes zeros (read by the last
// vector of a window, masked off), and hi[k], the end of template k's window.
struct Columns {
  std::array<const double*, kWindowMaxM + 1> y{};
  const std::uint32_t* hi = nullptr;
};

inline __attribute__((always_inline)) V8 Load(const double* p) {
  V8 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

// fl(|a - b|) < r per lane, as the brute force: clearing the sign bit is the exact |.|.
inline __attribute__((always_inline)) I8 Close(V8 a, V8 centre, V8 r) {
  const I8 abs_mask = (I8){} + std::int64_t{0x7fffffffffffffff};
  const V8 d = (V8)((I8)(a - centre) & abs_mask);
  return d < r;
}

// Matches of the pairs (k, j), j in [j, j + 8), whose lanes are set in `valid`: B needs
// coordinates 1..M-1, A coordinate M too. Counts accumulate as -1 per set lane.
template <int M>
inline __attribute__((always_inline)) void Block(const Columns& c, std::size_t j, const V8* centre, V8 r, I8 valid,
                                                 I8& acc_a, I8& acc_b) {
  I8 mb = valid;
  for (int l = 1; l < M; ++l) mb &= Close(Load(c.y[l] + j), centre[l], r);
  acc_b += mb;
  acc_a += mb & Close(Load(c.y[M] + j), centre[M], r);
}

template <int M>
inline __attribute__((always_inline)) WindowCounts SliceBody(const Columns& c, std::size_t k0, std::size_t k1,
                                                             double r) {
  const V8 rv = (V8){} + r;
  const I8 lanes = {0, 1, 2, 3, 4, 5, 6, 7};
  const I8 all = (I8){} - 1;
  I8 acc_a = {}, acc_b = {};
  V8 centre[M + 1];
  for (std::size_t k = k0; k < k1; ++k) {
    for (int l = 1; l <= M; ++l) centre[l] = (V8){} + c.y[l][k];
    const std::size_t hi = c.hi[k];
    std::size_t j = k + 1;
    for (; j + kLanes <= hi; j += kLanes) Block<M>(c, j, centre, rv, all, acc_a, acc_b);
    if (j < hi) Block<M>(c, j, centre, rv, lanes < (I8){} + static_cast<std::int64_t>(hi - j), acc_a, acc_b);
  }
  WindowCounts out;
  for (std::size_t l = 0; l < kLanes; ++l) {
    out.a -= static_cast<std::uint64_t>(acc_a[l]);
    out.b -= static_cast<std::uint64_t>(acc_b[l]);
  }
  return out;
}

using SliceFn = WindowCounts (*)(const Columns&, std::size_t, std::size_t, double);

template <int M>
__attribute__((target("avx512f"))) WindowCounts SliceAvx512f(const Columns& c, std::size_t k0, std::size_t k1,
                                                              double r) {
  return SliceBody<M>(c, k0, k1, r);
}
template <int M>
__attribute__((target("avx2"))) WindowCounts SliceAvx2(const Columns& c, std::size_t k0, std::size_t k1, double r) {
  return SliceBody<M>(c, k0, k1, r);
}
template <int M>
WindowCounts SliceBaseline(const Columns& c, std::size_t k0, std::size_t k1, double r) {
  return SliceBody<M>(c, k0, k1, r);
}

template <int M>
SliceFn BestSlice() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return &SliceAvx512f<M>;
  if (__builtin_cpu_supports("avx2")) return &SliceAvx2<M>;
  return &SliceBaseline<M>;
}

SliceFn Slice(int m) {
  static const std::array<SliceFn, kWindowMaxM> fns = {BestSlice<1>(), BestSlice<2>(), BestSlice<3>(),
                                                       BestSlice<4>()};
  static_assert(kWindowMaxM == 4);
  return fns[static_cast<std::size_t>(m - 1)];
}

// hi[k] for every k (two pointers: hi is non-decreasing in k).
std::vector<std::uint32_t> WindowEnds(const double* y0, std::size_t n, double r) {
  std::vector<std::uint32_t> hi(n);
  std::size_t h = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (h <= k) h = k + 1;
    while (h < n && y0[h] - y0[k] < r) ++h;
    hi[k] = static_cast<std::uint32_t>(h);
  }
  return hi;
}

}  // namespace

std::vector<std::uint32_t> OrderByValue(std::span<const double> x) {
  const std::size_t n = x.size();
  std::vector<std::uint64_t> keys(n), keys_tmp(n);
  std::vector<std::uint32_t> order(n), order_tmp(n);
  // One read for all the histograms; a pass whose digit is the same for every key is skipped.
  std::vector<std::uint32_t> hist(kRadixPasses * kRadixBuckets, 0);
  for (std::size_t i = 0; i < n; ++i) {
    keys[i] = SortableBits(x[i]);
    order[i] = static_cast<std::uint32_t>(i);
    for (int p = 0; p < kRadixPasses; ++p) ++hist[p * kRadixBuckets + ((keys[i] >> (p * kRadixBits)) & (kRadixBuckets - 1))];
  }
  for (int p = 0; p < kRadixPasses; ++p) {
    std::uint32_t* h = hist.data() + p * kRadixBuckets;
    const int shift = p * kRadixBits;
    if (n == 0 || h[(keys[0] >> shift) & (kRadixBuckets - 1)] == n) continue;
    std::uint32_t sum = 0;
    for (std::size_t d = 0; d < kRadixBuckets; ++d) sum += std::exchange(h[d], sum);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t at = h[(keys[i] >> shift) & (kRadixBuckets - 1)]++;
      keys_tmp[at] = keys[i];
      order_tmp[at] = order[i];
    }
    keys.swap(keys_tmp);
    order.swap(order_tmp);
  }
  return order;
}

std::uint64_t WindowPairs(std::span<const double> x, std::span<const std::uint32_t> sorted, double r) {
  std::uint64_t pairs = 0;
  std::size_t h = 0;
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    if (h <= k) h = k + 1;
    while (h < sorted.size() && x[sorted[h]] - x[sorted[k]] < r) ++h;
    pairs += h - k - 1;
  }
  return pairs;
}

WindowCounts CountWindowed(std::span<const double> x, std::span<const std::uint32_t> sorted, int m, double r,
                           int num_threads) {
  assert(m >= 1 && m <= kWindowMaxM && num_threads >= 1);
  const std::size_t n = sorted.size();
  std::vector<double> store((static_cast<std::size_t>(m) + 1) * (n + kLanes), 0.0);
  Columns c;
  for (int l = 0; l <= m; ++l) {
    double* y = store.data() + static_cast<std::size_t>(l) * (n + kLanes);
    for (std::size_t k = 0; k < n; ++k) y[k] = x[sorted[k] + static_cast<std::size_t>(l)];
    c.y[static_cast<std::size_t>(l)] = y;
  }
  const std::vector<std::uint32_t> hi = WindowEnds(c.y[0], n, r);
  c.hi = hi.data();
  const SliceFn slice = Slice(m);
  // Slices of about equal pair checks (a template's cost is its window), one per thread.
  std::uint64_t total = 0;
  for (std::size_t k = 0; k < n; ++k) total += hi[k] - k - 1;
  const std::size_t threads = std::max<std::size_t>(1, std::min<std::size_t>(num_threads, n / 1024 + 1));
  std::vector<std::size_t> bounds(threads + 1, n);
  bounds[0] = 0;
  std::uint64_t run = 0;
  for (std::size_t k = 0, t = 1; k < n && t < threads; ++k) {
    run += hi[k] - k - 1;
    if (run * threads >= total * t) bounds[t++] = k + 1;
  }
  std::vector<WindowCounts> part(threads);
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) {
    pool.emplace_back([&, t] { part[t] = slice(c, bounds[t], bounds[t + 1], r); });
  }
  part[0] = slice(c, bounds[0], bounds[1], r);
  for (auto& th : pool) th.join();
  WindowCounts out;
  for (const WindowCounts& p : part) {
    out.a += p.a;
    out.b += p.b;
  }
  return out;
}

}  // namespace gyrocomp::se_detail
