// Window counters of the two-coordinate sweep of sample entropy (sample_entropy_ranges.cc): a set of
// positions 0..n-1 per label (0 or 1) with Insert / Remove and Count(label, lo, hi) = members in
// [lo, hi). Internal to src/decompose/.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gyrocomp::se_detail {

// Set bits of b in positions [lo, hi), lo < hi. Inlined into the two entry points below, so the
// popcounts compile to the popcnt instruction in the first and to the baseline's library call in
// the second (the x86-64 baseline has no popcnt; every x86-64 CPU since 2008 has it).
[[gnu::always_inline]] inline std::uint64_t RangeBits(const std::uint64_t* b, std::size_t lo, std::size_t hi) {
  const std::size_t wl = lo / 64, wh = (hi - 1) / 64;
  const std::uint64_t mlo = ~std::uint64_t{0} << (lo % 64);
  const std::uint64_t mhi = ~std::uint64_t{0} >> (63 - (hi - 1) % 64);
  if (wl == wh) return std::popcount(b[wl] & mlo & mhi);
  std::uint64_t count = std::popcount(b[wl] & mlo) + std::popcount(b[wh] & mhi);
  for (std::size_t i = wl + 1; i < wh; ++i) count += std::popcount(b[i]);
  return count;
}
using RangeBitsFn = std::uint64_t (*)(const std::uint64_t*, std::size_t, std::size_t);
inline std::uint64_t RangeBitsBaseline(const std::uint64_t* b, std::size_t lo, std::size_t hi) { return RangeBits(b, lo, hi); }
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("popcnt"))) inline std::uint64_t RangeBitsPopcnt(const std::uint64_t* b, std::size_t lo, std::size_t hi) {
  return RangeBits(b, lo, hi);
}
inline RangeBitsFn ChooseRangeBits() { return __builtin_cpu_supports("popcnt") ? &RangeBitsPopcnt : &RangeBitsBaseline; }
#else
inline RangeBitsFn ChooseRangeBits() { return &RangeBitsBaseline; }
#endif
inline const RangeBitsFn kRangeBits = ChooseRangeBits();  // the same count either way

// Set of positions 0..n-1 per label as bits: O(1) updates, (hi - lo) / 64 words per count.
struct BitsetCounter {
  BitsetCounter(std::size_t n, bool bi, std::vector<std::uint64_t>* store)
      : words((n + 63) / 64) {
    store->assign(bi ? 2 * words : words, 0);
    bits = store->data();
  }
  void Insert(int label, std::size_t pos) { bits[label * words + pos / 64] ^= std::uint64_t{1} << (pos % 64); }
  void Remove(int label, std::size_t pos) { Insert(label, pos); }
  std::uint64_t Count(int label, std::size_t lo, std::size_t hi) const {  // lo < hi
    return kRangeBits(bits + label * words, lo, hi);
  }
  std::size_t words;
  std::uint64_t* bits;
};

// Fenwick tree over positions 0..n-1 per label.
struct FenwickCounter {
  FenwickCounter(std::size_t n_in, bool bi, std::vector<std::uint32_t>* store) : n(n_in) {
    store->assign(bi ? 2 * (n + 1) : n + 1, 0);
    tree = store->data();
  }
  void Add(int label, std::size_t pos, std::uint32_t delta) {
    std::uint32_t* t = tree + label * (n + 1);
    for (std::size_t i = pos + 1; i <= n; i += i & (~i + 1)) t[i] += delta;
  }
  void Insert(int label, std::size_t pos) { Add(label, pos, 1u); }
  void Remove(int label, std::size_t pos) { Add(label, pos, ~0u); }  // -1
  std::uint32_t Prefix(int label, std::size_t pos) const {  // positions < pos
    const std::uint32_t* t = tree + label * (n + 1);
    std::uint32_t sum = 0;
    for (std::size_t i = pos; i > 0; i -= i & (~i + 1)) sum += t[i];
    return sum;
  }
  std::uint64_t Count(int label, std::size_t lo, std::size_t hi) const { return Prefix(label, hi) - Prefix(label, lo); }
  std::size_t n;
  std::uint32_t* tree;
};

}  // namespace gyrocomp::se_detail
