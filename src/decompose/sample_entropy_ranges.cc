// Range counting of sample entropy's matching template pairs: see sample_entropy_ranges.h.
#include "sample_entropy_ranges.h"

#include "sample_entropy_counters.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <functional>
#include <thread>
#include <utility>
#include <vector>

namespace gyrocomp::se_detail {
namespace {

using Item = std::uint32_t;  // template start index, bit 31 = label
constexpr Item kLabel = 0x80000000u;
constexpr Item kIndex = static_cast<Item>(kRangeMaxSamples);
constexpr std::size_t kBruteSelf = 24;    // pairs checked directly below this many items
constexpr std::size_t kBruteCross = 512;  // |L| * |R| checked directly below this
constexpr std::size_t kRadixMin = 512;    // radix sort from this many keys, std::sort below
constexpr int kDigitBits = 11;            // radix digit from kWideDigitsMin keys, 8 bits below
constexpr std::size_t kWideDigitsMin = 8192;
constexpr std::size_t kDigits = std::size_t{1} << kDigitBits;
constexpr std::size_t kBitsetMax = 2048;  // window counts in a bitset up to this many items

// The series' values ranked once (equal values, equal ranks), so that every later sort of
// templates by a coordinate is an integer sort; `order` is the start indices 0..N-1 by value.
struct RankedSeries {
  std::vector<std::uint32_t> rank;
  std::vector<Item> order;
  int rank_bits = 0;
};

// Ranks from the values' order (se_detail::OrderByValue, a radix sort).
RankedSeries RankValues(std::span<const double> x, std::vector<Item> order) {
  RankedSeries out;
  out.rank.resize(x.size());
  std::uint32_t rank = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (k > 0 && x[order[k]] != x[order[k - 1]]) ++rank;
    out.rank[order[k]] = rank;
  }
  out.order = std::move(order);
  out.rank_bits = std::max(1, static_cast<int>(std::bit_width(rank)));
  return out;
}

class PairCounter {
 public:
  // cancel (nullptr: not polled): see Stop().
  PairCounter(const double* x, const RankedSeries& ranked, int d, double r, const CancellationToken* cancel = nullptr)
      : x_(x), rank_of_(ranked.rank.data()), rank_bits_(ranked.rank_bits), d_(d), r_(r), cancel_(cancel) {}

  // One share of a count, run by a worker on its own PairCounter (its scratch).
  using Task = std::function<std::uint64_t(PairCounter&)>;

  // All templates sorted by coordinate 0, as a list of independent counting tasks whose sum is
  // the pair count (the first level of Self, below, one task per group and per pair of adjacent
  // groups), so that several threads can share the work. Larger tasks first.
  std::vector<Task> Tasks(std::span<Item> sorted) const {
    std::vector<Task> tasks;
    if (d_ < 3 || sorted.size() < 4096 || Within(V(sorted.front(), 0), V(sorted.back(), 0))) {
      tasks.push_back([sorted](PairCounter& pc) { return pc.Self(sorted, 0, false); });
      return tasks;
    }
    std::vector<std::pair<std::size_t, Task>> sized;
    std::span<Item> previous;
    for (std::span<Item> group : Groups(sorted, 0)) {
      sized.push_back({group.size(), [group](PairCounter& pc) { return pc.WithinGroup(group, 0, false); }});
      if (!previous.empty()) {
        sized.push_back({(previous.size() + group.size()) / 2,
                         [previous, group](PairCounter& pc) { return pc.Cross(previous, group, 0, false); }});
      }
      previous = group;
    }
    std::stable_sort(sized.begin(), sized.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (auto& [size, task] : sized) tasks.push_back(std::move(task));
    return tasks;
  }

  std::uint64_t CountSorted(std::span<Item> sorted) { return Self(sorted, 0, false); }

 private:
  double V(Item it, int c) const { return x_[(it & kIndex) + c]; }
  // SampleEntropyOptions::cancel, polled where the recursion enters a subset of kCancelPollItems
  // items or more and every kCancelPollItems steps of the sweeps: between two polls at most
  // ~kCancelPollItems x (a few us) of work. Once set, every count returns early (partial counts:
  // the caller checks the token and throws Cancelled).
  bool Stop() const { return cancel_ != nullptr && cancel_->cancelled(); }
  static constexpr std::size_t kCancelPollItems = 1u << 14;
  bool Close(double a, double b) const { return std::abs(a - b) < r_; }  // the brute predicate
  // fl(hi - lo) < r for hi >= lo.
  bool Within(double lo, double hi) const { return hi - lo < r_; }
  static bool Label(Item it) { return (it & kLabel) != 0; }

  // Sorts items by coordinate c: by the precomputed rank of the value (equal values, equal
  // ranks), ties by item, so the order is the values' order and does not depend on the input
  // order. Keys packed as (rank << 32 | item): integer sorts, no indirection in the comparisons.
  void SortBy(std::vector<Item>& s, int c) {
    keys_.resize(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) keys_[i] = Key(rank_of_[(s[i] & kIndex) + c], s[i]);
    SortKeys(keys_);
    for (std::size_t i = 0; i < s.size(); ++i) s[i] = static_cast<Item>(keys_[i]);
  }

  static std::uint64_t Key(std::uint32_t rank, std::uint32_t low) {
    return (static_cast<std::uint64_t>(rank) << 32) | low;
  }

  // Sorts packed keys by their rank (the high word): std::sort for short lists, else a stable
  // LSD radix sort of the rank's bits only (ties may end in any order: the counts do not depend
  // on how equal values are ordered).
  void SortKeys(std::vector<std::uint64_t>& k) {
    if (k.size() < kRadixMin) {
      std::sort(k.begin(), k.end());
      return;
    }
    radix_tmp_.resize(k.size());
    std::uint64_t* from = k.data();
    std::uint64_t* to = radix_tmp_.data();
    // Short lists: 8-bit digits (the counts cost as much as the keys otherwise).
    const int digit_bits = k.size() < kWideDigitsMin ? 8 : kDigitBits;
    const std::size_t digits = std::size_t{1} << digit_bits;
    for (int shift = 32; shift < 32 + rank_bits_; shift += digit_bits) {
      // Cancelled: the keys are left part-sorted; every caller of a list this long polls the
      // token again before it uses the order (Self, Cross, Sweep2) and returns early.
      if (k.size() >= kCancelPollItems && Stop()) return;
      std::uint32_t counts[kDigits + 1];
      std::fill(counts, counts + digits + 1, 0u);
      for (std::size_t i = 0; i < k.size(); ++i) ++counts[((from[i] >> shift) & (digits - 1)) + 1];
      for (std::size_t d = 1; d <= digits; ++d) counts[d] += counts[d - 1];
      for (std::size_t i = 0; i < k.size(); ++i) to[counts[(from[i] >> shift) & (digits - 1)]++] = from[i];
      std::swap(from, to);
    }
    if (from != k.data()) std::copy(from, from + k.size(), k.data());
  }

  bool MatchFrom(Item a, Item b, int c) const {
    const double* xa = x_ + (a & kIndex);
    const double* xb = x_ + (b & kIndex);
    for (int l = c; l < d_; ++l) {
      if (!Close(xa[l], xb[l])) return false;
    }
    return true;
  }

  std::uint64_t AllPairs(std::span<const Item> s, bool bi) const {
    const std::uint64_t n = s.size();
    if (!bi) return n * (n - 1) / 2;
    std::uint64_t ones = 0;
    for (Item it : s) ones += Label(it);
    return ones * (n - ones);
  }

  std::uint64_t Self(std::span<Item> s, int c, bool bi) {
    const std::size_t n = s.size();
    if (n < 2 || (n >= kCancelPollItems && Stop())) return 0;
    if (c == d_) return AllPairs(s, bi);
    if (Within(V(s.front(), c), V(s.back(), c))) return WithinGroup(s, c, bi);
    if (n <= kBruteSelf) {
      std::uint64_t count = 0;
      for (std::size_t a = 0; a < n; ++a) {
        for (std::size_t b = a + 1; b < n; ++b) {
          if (bi && Label(s[a]) == Label(s[b])) continue;
          count += MatchFrom(s[a], s[b], c);
        }
      }
      return count;
    }
    if (d_ - c == 1) return Sweep1(s, c, bi);
    if (d_ - c == 2) return Sweep2(s, c, bi);
    // Three or more coordinates left: groups of span < r along c. Pairs within a group match in
    // c; pairs in adjacent groups may; pairs two or more groups apart cannot (see Groups). Each
    // item is in one group and two adjacent-group crosses (halving S instead puts it in a cross
    // at every level where the halves are closer than r: ~3x the work at N = 100k).
    std::uint64_t count = 0;
    std::span<Item> previous;
    for (std::span<Item> group : Groups(s, c)) {
      count += WithinGroup(group, c, bi) + Cross(previous, group, c, bi);
      previous = group;
    }
    return count;
  }

  // s (sorted by coordinate c) cut into maximal runs whose first and last values are within r.
  // Two groups a and a + 2 never match: every value v of group a + 2 has fl(v - f) >= r for the
  // first value f of group a + 1 (that is where group a + 1 ended), every value u of group a is
  // <= f, and fl(v - u) >= fl(v - f) because rounding is monotone.
  std::vector<std::span<Item>> Groups(std::span<Item> s, int c) const {
    std::vector<std::span<Item>> groups;
    for (std::size_t g0 = 0; g0 < s.size();) {
      const double first = V(s[g0], c);
      const auto end = std::partition_point(s.begin() + g0, s.end(), [&](Item it) { return Within(first, V(it, c)); });
      const std::size_t g1 = static_cast<std::size_t>(end - s.begin());
      groups.push_back(s.subspan(g0, g1 - g0));
      g0 = g1;
    }
    return groups;
  }

  // Pairs within a group (every pair matches in coordinate c): counted on coordinates c+1...
  std::uint64_t WithinGroup(std::span<const Item> group, int c, bool bi) {
    if (group.size() < 2) return 0;
    if (c + 1 == d_) return AllPairs(group, bi);
    std::vector<Item> t(group.begin(), group.end());
    SortBy(t, c + 1);
    return Self(t, c + 1, bi);
  }

  // One coordinate left: for each p, the earlier items within r form a window [lo, p).
  std::uint64_t Sweep1(std::span<const Item> s, int c, bool bi) const {
    std::uint64_t count = 0;
    std::size_t lo = 0;
    std::uint64_t ones = 0;  // label-1 items in the window
    for (std::size_t p = 0; p < s.size(); ++p) {
      if (p % kCancelPollItems == kCancelPollItems - 1 && Stop()) return count;
      const double vp = V(s[p], c);
      while (!Within(V(s[lo], c), vp)) ones -= Label(s[lo++]);
      const std::uint64_t w = p - lo;
      count += !bi ? w : (Label(s[p]) ? w - ones : ones);
      ones += Label(s[p]);
    }
    return count;
  }

  // Two coordinates left: a window along c; the items of the window are counted over their
  // positions in the order of coordinate c+1 (a bitset for short lists, a Fenwick tree above
  // kBitsetMax). Each item's matches in c+1 form the run [lo, hi) of positions, found by two
  // pointers with the brute-force predicate (monotone in the value).
  std::uint64_t Sweep2(std::span<const Item> s, int c, bool bi) {
    const std::size_t n = s.size();
    keys_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      keys_[i] = Key(rank_of_[(s[i] & kIndex) + c + 1], static_cast<std::uint32_t>(i));
    }
    SortKeys(keys_);
    if (n >= kCancelPollItems && Stop()) return 0;
    values_.resize(n);
    for (std::size_t k = 0; k < n; ++k) values_[k] = V(s[static_cast<std::uint32_t>(keys_[k])], c + 1);
    pos_.resize(n);
    lo_pos_.resize(n);
    hi_pos_.resize(n);
    std::size_t lo = 0, hi = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double y = values_[k];
      while (!Within(values_[lo], y)) ++lo;
      if (hi < k) hi = k;
      while (hi < n && Within(y, values_[hi])) ++hi;
      const std::uint32_t i = static_cast<std::uint32_t>(keys_[k]);
      pos_[i] = static_cast<std::uint32_t>(k);
      lo_pos_[i] = static_cast<std::uint32_t>(lo);
      hi_pos_[i] = static_cast<std::uint32_t>(hi);
    }
    return n <= kBitsetMax ? WindowCount(s, c, bi, se_detail::BitsetCounter(n, bi, &bits_))
                           : WindowCount(s, c, bi, se_detail::FenwickCounter(n, bi, &tree_));
  }

  // Sliding window along coordinate c over s; for each p, the earlier items of the window whose
  // position in the c+1 order is in [lo_pos_[p], hi_pos_[p]) (and of the other label when bi).
  template <typename Counter>
  std::uint64_t WindowCount(std::span<const Item> s, int c, bool bi, Counter counter) const {
    std::uint64_t count = 0;
    std::size_t w = 0;
    for (std::size_t p = 0; p < s.size(); ++p) {
      if (p % kCancelPollItems == kCancelPollItems - 1 && Stop()) return count;
      const double vp = V(s[p], c);
      while (!Within(V(s[w], c), vp)) {
        counter.Remove(bi ? Label(s[w]) : 0, pos_[w]);
        ++w;
      }
      count += counter.Count(bi ? !Label(s[p]) : 0, lo_pos_[p], hi_pos_[p]);
      counter.Insert(bi ? Label(s[p]) : 0, pos_[p]);
    }
    return count;
  }

  // Pairs (q in l, p in r) that match in coordinates c..d-1 (and differ in label when bi), no
  // order relation between l and r.
  std::uint64_t Bipartite(std::span<const Item> l, std::span<const Item> r, int c, bool bi) {
    if (l.empty() || r.empty()) return 0;
    if (!bi) {
      std::vector<Item> t;
      t.reserve(l.size() + r.size());
      for (Item it : l) t.push_back(it & kIndex);
      for (Item it : r) t.push_back((it & kIndex) | kLabel);
      if (c == d_) return AllPairs(t, true);
      SortBy(t, c);
      return Self(t, c, true);
    }
    // Labels must differ and sides must differ: (l0, r1) and (l1, r0), relabelled by side.
    std::uint64_t count = 0;
    for (int side_l_label = 0; side_l_label < 2; ++side_l_label) {
      std::vector<Item> t;
      for (Item it : l) {
        if (Label(it) == static_cast<bool>(side_l_label)) t.push_back(it & kIndex);
      }
      const std::size_t nl = t.size();
      for (Item it : r) {
        if (Label(it) != static_cast<bool>(side_l_label)) t.push_back((it & kIndex) | kLabel);
      }
      if (nl == 0 || nl == t.size()) continue;
      if (c == d_) {
        count += static_cast<std::uint64_t>(nl) * (t.size() - nl);
        continue;
      }
      SortBy(t, c);
      count += Self(t, c, true);
    }
    return count;
  }

  std::uint64_t Cross(std::span<Item> l, std::span<Item> r, int c, bool bi) {
    if (l.empty() || r.empty()) return 0;
    if (l.size() + r.size() >= kCancelPollItems && Stop()) return 0;
    // Trim: q in l can match only if it is within r of the smallest p; p only if within r of
    // the largest q.
    const double r0 = V(r.front(), c);
    const auto lcut = std::partition_point(l.begin(), l.end(), [&](Item q) { return !Within(V(q, c), r0); });
    l = l.subspan(lcut - l.begin());
    if (l.empty()) return 0;
    const double lmax = V(l.back(), c);
    const auto rcut = std::partition_point(r.begin(), r.end(), [&](Item p) { return Within(lmax, V(p, c)); });
    r = r.subspan(0, rcut - r.begin());
    if (r.empty()) return 0;
    if (Within(V(l.front(), c), V(r.back(), c))) return Bipartite(l, r, c + 1, bi);
    if (l.size() * r.size() <= kBruteCross) {
      std::uint64_t count = 0;
      for (Item q : l) {
        for (Item p : r) {
          if (bi && Label(q) == Label(p)) continue;
          count += MatchFrom(q, p, c);
        }
      }
      return count;
    }
    if (l.size() >= r.size()) {
      const std::size_t h = l.size() / 2;
      return Cross(l.subspan(0, h), r, c, bi) + Cross(l.subspan(h), r, c, bi);
    }
    const std::size_t h = r.size() / 2;
    return Cross(l, r.subspan(0, h), c, bi) + Cross(l, r.subspan(h), c, bi);
  }

  const double* x_;
  const std::uint32_t* rank_of_;  // rank_of_[i]: rank of x_[i] among the series' values
  int rank_bits_;                 // bits of the largest rank
  int d_;
  double r_;
  const CancellationToken* cancel_;
  // Scratch reused across calls (Sweep2 runs only at the leaves of the recursion).
  std::vector<std::uint64_t> keys_, radix_tmp_, bits_;
  std::vector<double> values_;
  std::vector<std::uint32_t> pos_, lo_pos_, hi_pos_, tree_;
};

}  // namespace

// A (m + 1 coordinates, the long count) split into tasks, B (m coordinates) one
// more task; `threads` workers take tasks in order (largest first), each with its own scratch.
TemplateMatchCounts CountByRanges(std::span<const double> x, int m, double r, std::vector<Item> order,
                                  std::size_t templates, int threads, const CancellationToken* cancel) {
  std::vector<Item> sorted;  // the templates by their first value
  sorted.reserve(templates);
  for (Item i : order) {
    if (i < templates) sorted.push_back(i);
  }
  const RankedSeries ranked = RankValues(x, std::move(order));
  TemplateMatchCounts out;
  auto tasks = PairCounter(x.data(), ranked, m + 1, r).Tasks(sorted);
  std::vector<int> is_b(tasks.size(), 0);
  tasks.push_back([&](PairCounter&) { return PairCounter(x.data(), ranked, m, r, cancel).CountSorted(sorted); });
  is_b.push_back(1);
  std::vector<std::uint64_t> results(tasks.size(), 0);
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    PairCounter pc(x.data(), ranked, m + 1, r, cancel);
    for (std::size_t t; (t = next.fetch_add(1)) < tasks.size() && !(cancel != nullptr && cancel->cancelled());) {
      results[t] = tasks[t](pc);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
  for (std::size_t t = 0; t < tasks.size(); ++t) (is_b[t] ? out.b : out.a) += results[t];
  return out;
}

}  // namespace gyrocomp::se_detail
