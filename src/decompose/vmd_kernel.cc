// The VMD inner kernel: see vmd_kernel.h. Compiled with -ffp-contract=off (CMakeLists.txt).
//
// Vectorisation: GCC vector extensions of kLanes doubles (the compiler lowers one to a 512-bit,
// two 256-bit or four 128-bit registers); the kernel is compiled three times (target
// attributes AVX-512F, AVX2 and the x86-64 baseline) and the best path the CPU supports is
// picked at the first call (no -march=native: the binary runs on any x86-64). Every lane does the same IEEE operations in the same order on
// every path (add, subtract, multiply, divide are correctly rounded; no reassociation, no FMA),
// so the paths give bit-identical results.
#include "vmd_kernel.h"

#include <cstring>

namespace gyrocomp::vmd_internal {
namespace {

typedef double Vec __attribute__((vector_size(kLanes * sizeof(double))));

inline __attribute__((always_inline)) Vec Load(const double* p) {
  Vec v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}
inline __attribute__((always_inline)) void Store(double* p, Vec v) { std::memcpy(p, &v, sizeof(v)); }

// One bin (scalar tail), lane l: the same operations as one lane of the vector body.
template <bool kLambda>
inline __attribute__((always_inline)) void UpdateBin(const ModeChunk& c, std::size_t i, std::size_t l,
                                                      double wk, double alpha, LaneSums& acc) {
  const double sr = (c.prev_re[i] + c.s_re[i]) - c.old_re[i];
  const double si = (c.prev_im[i] + c.s_im[i]) - c.old_im[i];
  c.s_re[i] = sr;
  c.s_im[i] = si;
  const double d = c.freq[i] - wk;
  const double rcp = 1.0 / (1.0 + alpha * (d * d));
  double nr = c.f_re[i] - sr, ni = c.f_im[i] - si;
  if constexpr (kLambda) {
    nr = nr - c.l_re[i] * 0.5;
    ni = ni - c.l_im[i] * 0.5;
  }
  const double ur = nr * rcp, ui = ni * rcp;
  c.u_re[i] = ur;
  c.u_im[i] = ui;
  const double pw = ur * ur + ui * ui;
  acc.freq_power[l] += c.freq[i] * pw;
  acc.power[l] += pw;
  const double dr = ur - c.old_re[i], di = ui - c.old_im[i];
  acc.diff[l] += dr * dr + di * di;
  acc.old_power[l] += c.old_re[i] * c.old_re[i] + c.old_im[i] * c.old_im[i];
}

template <bool kLambda>
inline __attribute__((always_inline)) void UpdateChunk(const ModeChunk& c, std::size_t n, double wk,
                                                        double alpha, LaneSums& acc) {
  Vec fp = Load(acc.freq_power), p = Load(acc.power), df = Load(acc.diff), op = Load(acc.old_power);
  std::size_t i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    const Vec o_re = Load(c.old_re + i), o_im = Load(c.old_im + i);
    const Vec sr = (Load(c.prev_re + i) + Load(c.s_re + i)) - o_re;
    const Vec si = (Load(c.prev_im + i) + Load(c.s_im + i)) - o_im;
    Store(c.s_re + i, sr);
    Store(c.s_im + i, si);
    const Vec freq = Load(c.freq + i);
    const Vec d = freq - wk;
    const Vec rcp = 1.0 / (1.0 + alpha * (d * d));  // Eq. (4) denominator, one division per bin
    Vec nr = Load(c.f_re + i) - sr, ni = Load(c.f_im + i) - si;
    if constexpr (kLambda) {
      nr = nr - Load(c.l_re + i) * 0.5;
      ni = ni - Load(c.l_im + i) * 0.5;
    }
    const Vec ur = nr * rcp, ui = ni * rcp;
    Store(c.u_re + i, ur);
    Store(c.u_im + i, ui);
    const Vec pw = ur * ur + ui * ui;
    fp += freq * pw;  // Eq. (5) numerator
    p += pw;          // Eq. (5) denominator
    const Vec dr = ur - o_re, di = ui - o_im;
    df += dr * dr + di * di;  // stopping rule
    op += o_re * o_re + o_im * o_im;
  }
  Store(acc.freq_power, fp);
  Store(acc.power, p);
  Store(acc.diff, df);
  Store(acc.old_power, op);
  for (std::size_t l = 0; i < n; ++i, ++l) UpdateBin<kLambda>(c, i, l, wk, alpha, acc);
}

}  // namespace

void LaneSums::Clear() {
  for (std::size_t l = 0; l < kLanes; ++l) freq_power[l] = power[l] = diff[l] = old_power[l] = 0.0;
}

double LaneTotal(const double (&v)[kLanes]) {
  static_assert(kLanes == 8, "LaneTotal's tree is written for 8 lanes");
  return ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]));
}

namespace {

// One function per instruction set: the same source (UpdateChunk is inlined into each and
// compiled for the function's target).
template <bool kLambda>
__attribute__((target("avx512f"))) void ChunkAvx512f(const ModeChunk& c, std::size_t n, double wk, double alpha,
                                                     LaneSums& acc) {
  UpdateChunk<kLambda>(c, n, wk, alpha, acc);
}
template <bool kLambda>
__attribute__((target("avx2"))) void ChunkAvx2(const ModeChunk& c, std::size_t n, double wk, double alpha,
                                               LaneSums& acc) {
  UpdateChunk<kLambda>(c, n, wk, alpha, acc);
}
template <bool kLambda>
void ChunkBaseline(const ModeChunk& c, std::size_t n, double wk, double alpha, LaneSums& acc) {
  UpdateChunk<kLambda>(c, n, wk, alpha, acc);
}

using ChunkFn = void (*)(const ModeChunk&, std::size_t, double, double, LaneSums&);

ChunkFn Select(KernelPath path, bool lambda) {
  switch (path) {
    case KernelPath::kAvx512f: return lambda ? ChunkAvx512f<true> : ChunkAvx512f<false>;
    case KernelPath::kAvx2: return lambda ? ChunkAvx2<true> : ChunkAvx2<false>;
    case KernelPath::kBaseline: break;
  }
  return lambda ? ChunkBaseline<true> : ChunkBaseline<false>;
}

KernelPath BestPath() {
  if (KernelPathSupported(KernelPath::kAvx512f)) return KernelPath::kAvx512f;
  if (KernelPathSupported(KernelPath::kAvx2)) return KernelPath::kAvx2;
  return KernelPath::kBaseline;
}

}  // namespace

bool KernelPathSupported(KernelPath path) {
  __builtin_cpu_init();
  switch (path) {
    case KernelPath::kAvx512f: return __builtin_cpu_supports("avx512f");
    case KernelPath::kAvx2: return __builtin_cpu_supports("avx2");
    case KernelPath::kBaseline: return true;
  }
  return false;
}

void UpdateModeChunkOn(KernelPath path, const ModeChunk& c, std::size_t n, double omega_k, double alpha,
                       LaneSums& sums) {
  Select(path, c.l_re != nullptr)(c, n, omega_k, alpha, sums);
}

void UpdateModeChunk(const ModeChunk& c, std::size_t n, double omega_k, double alpha, LaneSums& sums) {
  static const ChunkFn with_lambda = Select(BestPath(), true);
  static const ChunkFn without_lambda = Select(BestPath(), false);
  (c.l_re != nullptr ? with_lambda : without_lambda)(c, n, omega_k, alpha, sums);
}

const char* KernelIsa() {
  switch (BestPath()) {
    case KernelPath::kAvx512f: return "avx512f";
    case KernelPath::kAvx2: return "avx2";
    case KernelPath::kBaseline: break;
  }
  return "baseline";
}

}  // namespace gyrocomp::vmd_internal
