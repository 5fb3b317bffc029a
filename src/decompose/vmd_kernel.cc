// The VMD inner kernel: see vmd_kernel.h. Compiled with -ffp-contract=off (CMakeLists.txt).
//
// Vectorisation: GCC vector extensions: kLanes doubles (one 512-bit register) on the AVX-512 path,
// a native 256-bit / 128-bit vector on the AVX2 / baseline paths (a 64-byte vector there compiles
// to stack traffic); the kernels are compiled three times (target attributes AVX-512F, AVX2 and
// the x86-64 baseline) and the best path the CPU supports is picked at the first call (no
// -march=native: the binary runs on any x86-64). Every lane does the same IEEE operations in the
// same order on every path (add, subtract, multiply, divide are correctly rounded; no reassociation, no FMA),
// so the paths give bit-identical results.
#include "vmd_kernel.h"

#include <cmath>
#include <cstring>
#include <algorithm>

namespace gyrocomp::vmd_internal {
namespace {

#define GYROCOMP_INLINE inline __attribute__((always_inline))
#define GYROCOMP_INLINE_LAMBDA __attribute__((always_inline))

// The kernels' vector: kLanes doubles (one zmm register) on the AVX-512 path; on the AVX2 and
// baseline paths a native ymm / xmm vector, the kernels walking each block of kLanes bins in
// kLanes / width passes, lanes [h, h + width) at a time (UpdateChunk, BinSubChunk). GCC compiles
// the 64-byte vector on a 256-bit target through the stack (3.0 ns per bin-update with AVX2,
// 3.5 with SSE2, against 0.6 with AVX-512; docs/explanation/performance.md).
typedef double Vec __attribute__((vector_size(kLanes * sizeof(double))));
typedef double Vec4 __attribute__((vector_size(4 * sizeof(double))));
typedef double Vec2 __attribute__((vector_size(2 * sizeof(double))));
template <class V>
constexpr std::size_t kWidth = sizeof(V) / sizeof(double);

// Unaligned load / store of any of the vector types (Vec, Vec4, Vec2), or of one double (tails).
template <class V>
GYROCOMP_INLINE void Ld(V& v, const double* p) { std::memcpy(&v, p, sizeof(v)); }
template <class V>
GYROCOMP_INLINE void St(double* p, const V& v) { std::memcpy(p, &v, sizeof(v)); }
GYROCOMP_INLINE void Ld(double& v, const double* p) { v = *p; }
GYROCOMP_INLINE void St(double* p, double v) { *p = v; }

// Accumulators of one mode (width(V) lanes, or one lane as a double in the tail).
template <class V>
struct ModeAcc {
  V fp, p, df, op;
};

// The lanes [h, h + width(V)) of a LaneSums, to and from registers.
template <class V>
GYROCOMP_INLINE void LoadLanes(const LaneSums& s, std::size_t h, ModeAcc<V>& a) {
  Ld(a.fp, s.freq_power + h);
  Ld(a.p, s.power + h);
  Ld(a.df, s.diff + h);
  Ld(a.op, s.old_power + h);
}
template <class V>
GYROCOMP_INLINE void StoreLanes(const ModeAcc<V>& a, std::size_t h, LaneSums& s) {
  St(s.freq_power + h, a.fp);
  St(s.power + h, a.p);
  St(s.diff + h, a.df);
  St(s.old_power + h, a.op);
}

// ---- mode-major kernel: one mode over a chunk of bins (K > kMaxModesAtOnce) ---------------------

// Bins [i, i + width(V)) of one mode (V = double: one bin, the tail).
template <class V, bool kLambda>
GYROCOMP_INLINE void ModeStep(const ModeChunk& c, std::size_t i, double wk, double alpha, ModeAcc<V>& a) {
  V o_re, o_im, prev, s, f, freq;
  Ld(o_re, c.old_re + i);
  Ld(o_im, c.old_im + i);
  Ld(prev, c.prev_re + i);
  Ld(s, c.s_re + i);
  const V sr = (prev + s) - o_re;  // sum_uk = (u_{k-1} + sum_uk) - u_k^old
  Ld(prev, c.prev_im + i);
  Ld(s, c.s_im + i);
  const V si = (prev + s) - o_im;
  St(c.s_re + i, sr);
  St(c.s_im + i, si);
  Ld(freq, c.freq + i);
  const V d = freq - wk;
  const V rcp = 1.0 / (1.0 + alpha * (d * d));  // Eq. (4) denominator, one division per bin
  Ld(f, c.f_re + i);
  V nr = f - sr;
  Ld(f, c.f_im + i);
  V ni = f - si;
  if constexpr (kLambda) {
    V l;
    Ld(l, c.l_re + i);
    nr = nr - l * 0.5;
    Ld(l, c.l_im + i);
    ni = ni - l * 0.5;
  }
  const V ur = nr * rcp, ui = ni * rcp;
  St(c.u_re + i, ur);
  St(c.u_im + i, ui);
  const V pw = ur * ur + ui * ui;
  a.fp += freq * pw;  // Eq. (5) numerator
  a.p += pw;          // Eq. (5) denominator
  const V dr = ur - o_re, di = ui - o_im;
  a.df += dr * dr + di * di;  // stopping rule
  a.op += o_re * o_re + o_im * o_im;
}

// Bins [0, n) of one mode: lanes [h, h + width(V)) of every block of kLanes bins for each h in
// turn (every lane its bins in increasing order, for any width), then the tail bin by bin.
template <class V, bool kLambda>
GYROCOMP_INLINE void UpdateChunk(const ModeChunk& c, std::size_t n, double wk, double alpha, LaneSums& sums) {
  const std::size_t n_body = n - n % kLanes;
  for (std::size_t h = 0; h < kLanes; h += kWidth<V>) {
    ModeAcc<V> a;
    LoadLanes(sums, h, a);
    for (std::size_t i = h; i < n_body; i += kLanes) ModeStep<V, kLambda>(c, i, wk, alpha, a);
    StoreLanes(a, h, sums);
  }
  for (std::size_t i = n_body, l = 0; i < n; ++i, ++l) {
    ModeAcc<double> a;
    LoadLanes(sums, l, a);
    ModeStep<double, kLambda>(c, i, wk, alpha, a);
    StoreLanes(a, l, sums);
  }
}

// ---- bin-major kernel: all modes of a vector of bins --------------------------------------------

// Eq. (4) denominators D_k = 1 + alpha (freq - omega_k)^2 and their reciprocals: batch inversion
// (vmd_kernel.h) or, when it could overflow, one division each.
template <class V, int K>
GYROCOMP_INLINE void Reciprocals(V freq, const double (&omega)[K], double alpha, bool batch, V (&rcp)[K]) {
  V D[K];
  for (int k = 0; k < K; ++k) {
    const V d = freq - omega[k];
    D[k] = 1.0 + alpha * (d * d);
  }
  if (!batch) {
    for (int k = 0; k < K; ++k) rcp[k] = 1.0 / D[k];
    return;
  }
  V P[K];  // prefix products
  P[0] = D[0];
  for (int k = 1; k < K; ++k) P[k] = P[k - 1] * D[k];
  V inv = 1.0 / P[K - 1];  // the one division
  for (int k = K - 1; k > 0; --k) {
    rcp[k] = inv * P[k - 1];
    inv = inv * D[k];
  }
  rcp[0] = inv;
}

// The K reciprocals of bins i .. i + width(V) - 1 into rcp[k * kRecipBins + i] (pass 1).
template <class V, int K>
GYROCOMP_INLINE void RecipStep(const double* freq_in, std::size_t i, const double (&omega)[K], double alpha,
                               bool batch, double* rcp_out) {
  V freq, rcp[K];
  Ld(freq, freq_in + i);
  Reciprocals<V, K>(freq, omega, alpha, batch, rcp);
  for (int k = 0; k < K; ++k) St(rcp_out + k * kRecipBins + i, rcp[k]);
}

// Bins i .. i + width(V) - 1, every mode in Gauss-Seidel order (pass 2). Eq. (4) as UpdateBin,
// except that the running quantity is the residual r = f - sum_uk (updated as
// r <- (r - u_{k-1}) + u_k^old), which saves the subtraction f - sum_uk: two fewer additions per
// bin-update. rcp_at(k): the reciprocal of mode k for these bins (pass 1's buffer, or registers).
template <class V, int K, bool kLambda, StopSums kStop, class RcpAt>
GYROCOMP_INLINE void BinStep(const BinChunk& c, std::size_t i, const RcpAt& rcp_at, ModeAcc<V> (&acc)[K]) {
  V freq, r_re, r_im, pr, pi;
  Ld(freq, c.freq + i);
  Ld(r_re, c.r_re + i);
  Ld(r_im, c.r_im + i);
  Ld(pr, c.src_re + (K - 1) * c.stride + i);  // mode 0's predecessor: mode K-1 of the last update
  Ld(pi, c.src_im + (K - 1) * c.stride + i);
  for (int k = 0; k < K; ++k) {
    const std::size_t at = k * c.stride + i;
    V o_re, o_im;
    Ld(o_re, c.src_re + at);
    Ld(o_im, c.src_im + at);
    const V rk = rcp_at(k);
    r_re = (r_re - pr) + o_re;  // f - sum_uk
    r_im = (r_im - pi) + o_im;
    V nr = r_re, ni = r_im;
    if constexpr (kLambda) {
      V l_re, l_im;
      Ld(l_re, c.l_re + i);
      Ld(l_im, c.l_im + i);
      nr = nr - l_re * 0.5;
      ni = ni - l_im * 0.5;
    }
    const V ur = nr * rk, ui = ni * rk;  // Eq. (4)
    St(c.dst_re + at, ur);
    St(c.dst_im + at, ui);
    const V pw = ur * ur + ui * ui;
    acc[k].fp += freq * pw;  // Eq. (5) numerator
    acc[k].p += pw;          // Eq. (5) denominator
    if constexpr (kStop != StopSums::kNone) {
      const V dr = ur - o_re, di = ui - o_im;
      acc[k].df += dr * dr + di * di;  // stopping rule
    }
    if constexpr (kStop == StopSums::kRelative) acc[k].op += o_re * o_re + o_im * o_im;
    pr = ur;
    pi = ui;
  }
  St(c.r_re + i, r_re);
  St(c.r_im + i, r_im);
}

// The same bins and operations in one pass (the reciprocals of the vector computed in registers
// just before its modes): for iterates that stream from memory, where a separate reciprocal pass
// would leave the memory idle (BinChunk::two_pass).
template <class V, int K, bool kLambda, StopSums kStop>
GYROCOMP_INLINE void FusedStep(const BinChunk& c, std::size_t i, const double (&omega)[K], double alpha, bool batch,
                               ModeAcc<V> (&acc)[K]) {
  V freq, rcp[K];
  Ld(freq, c.freq + i);
  Reciprocals<V, K>(freq, omega, alpha, batch, rcp);
  BinStep<V, K, kLambda, kStop>(c, i, [&rcp](int k) GYROCOMP_INLINE_LAMBDA { return rcp[k]; }, acc);
}

// The sums of this variant, lanes [h, h + width(V)), between LaneSums and registers (only those
// it adds: an unused accumulator carried through the loop would cost a spill).
template <class V, int K, StopSums kStop>
GYROCOMP_INLINE void LoadSums(const LaneSums* sums, std::size_t h, ModeAcc<V> (&acc)[K]) {
  for (int k = 0; k < K; ++k) {
    Ld(acc[k].fp, sums[k].freq_power + h);
    Ld(acc[k].p, sums[k].power + h);
    if constexpr (kStop != StopSums::kNone) Ld(acc[k].df, sums[k].diff + h);
    if constexpr (kStop == StopSums::kRelative) Ld(acc[k].op, sums[k].old_power + h);
  }
}
template <class V, int K, StopSums kStop>
GYROCOMP_INLINE void StoreSums(const ModeAcc<V> (&acc)[K], std::size_t h, LaneSums* sums) {
  for (int k = 0; k < K; ++k) {
    St(sums[k].freq_power + h, acc[k].fp);
    St(sums[k].power + h, acc[k].p);
    if constexpr (kStop != StopSums::kNone) St(sums[k].diff + h, acc[k].df);
    if constexpr (kStop == StopSums::kRelative) St(sums[k].old_power + h, acc[k].op);
  }
}

// The tail bins [i, n) one at a time, bin i in lane l = i - (first tail bin): step(i, a) runs
// one bin on the scalar accumulators a.
template <int K, class Step>
GYROCOMP_INLINE void Tail(std::size_t i, std::size_t n, LaneSums* sums, const Step& step) {
  for (std::size_t l = 0; i < n; ++i, ++l) {
    ModeAcc<double> a[K];
    for (int k = 0; k < K; ++k) LoadLanes(sums[k], l, a[k]);
    step(i, a);
    for (int k = 0; k < K; ++k) StoreLanes(a[k], l, sums[k]);
  }
}

// Bins [0, n), n <= kRecipBins: pass 1 (reciprocals) then pass 2 (Eq. 4 and the sums). Pass 2
// walks the lanes [h, h + width(V)) of every block of kLanes bins, for each h in turn: every
// bin gets the same operations and every lane its bins in increasing order, for any width.
template <class V, int K, bool kLambda, StopSums kStop>
GYROCOMP_INLINE void BinSubChunk(const BinChunk& c, std::size_t n, const double (&omega)[K], double alpha, bool batch,
                                 LaneSums* sums) {
  constexpr std::size_t kW = kWidth<V>;
  alignas(64) double rcp[K * kRecipBins];
  const std::size_t n_body = n - n % kLanes;
  std::size_t i = 0;
  for (; i < n_body; i += kW) RecipStep<V, K>(c.freq, i, omega, alpha, batch, rcp);
  for (; i < n; ++i) RecipStep<double, K>(c.freq, i, omega, alpha, batch, rcp);
  for (std::size_t h = 0; h < kLanes; h += kW) {
    ModeAcc<V> acc[K];
    LoadSums<V, K, kStop>(sums, h, acc);
    for (i = h; i < n_body; i += kLanes) {
      BinStep<V, K, kLambda, kStop>(c, i, [&rcp, i](int k) GYROCOMP_INLINE_LAMBDA {
        V r;
        Ld(r, rcp + k * kRecipBins + i);
        return r;
      }, acc);
    }
    StoreSums<V, K, kStop>(acc, h, sums);
  }
  Tail<K>(n_body, n, sums, [&](std::size_t j, ModeAcc<double> (&a)[K]) GYROCOMP_INLINE_LAMBDA {
    BinStep<double, K, kLambda, kStop>(c, j, [&rcp, j](int k) GYROCOMP_INLINE_LAMBDA { return rcp[k * kRecipBins + j]; }, a);
  });
}

// Bins [0, n) in one pass (FusedStep), lanes [h, h + width(V)) of every block for each h in turn.
template <class V, int K, bool kLambda, StopSums kStop>
GYROCOMP_INLINE void BinChunkFused(const BinChunk& c, std::size_t n, const double (&omega)[K], double alpha, bool batch,
                                   LaneSums* sums) {
  const std::size_t n_body = n - n % kLanes;
  for (std::size_t h = 0; h < kLanes; h += kWidth<V>) {
    ModeAcc<V> acc[K];
    LoadSums<V, K, kStop>(sums, h, acc);
    for (std::size_t i = h; i < n_body; i += kLanes) FusedStep<V, K, kLambda, kStop>(c, i, omega, alpha, batch, acc);
    StoreSums<V, K, kStop>(acc, h, sums);
  }
  Tail<K>(n_body, n, sums, [&](std::size_t j, ModeAcc<double> (&a)[K]) GYROCOMP_INLINE_LAMBDA {
    FusedStep<double, K, kLambda, kStop>(c, j, omega, alpha, batch, a);
  });
}

template <class V, int K, bool kLambda, StopSums kStop>
GYROCOMP_INLINE void BinChunkBody(const BinChunk& chunk, std::size_t n, const double* omega_in, double alpha,
                                  bool batch, LaneSums* sums) {
  double omega[K];
  for (int k = 0; k < K; ++k) omega[k] = omega_in[k];
  if (!chunk.two_pass) {
    const BinChunk c = chunk;  // a local copy: the compiler need not reload the pointers after stores
    BinChunkFused<V, K, kLambda, kStop>(c, n, omega, alpha, batch, sums);
    return;
  }
  // Sub-chunks start at multiples of kRecipBins (a multiple of kLanes): a bin keeps its lane.
  for (std::size_t s0 = 0; s0 < n; s0 += kRecipBins) {
    BinChunk c = chunk;  // a local copy: the compiler need not reload the pointers after stores
    c.freq += s0, c.r_re += s0, c.r_im += s0, c.src_re += s0, c.src_im += s0, c.dst_re += s0, c.dst_im += s0;
    if (c.l_re) c.l_re += s0, c.l_im += s0;
    BinSubChunk<V, K, kLambda, kStop>(c, std::min(kRecipBins, n - s0), omega, alpha, batch, sums);
  }
}

using BinFn = void (*)(const BinChunk&, std::size_t, const double*, double, bool, LaneSums*);

template <int K, bool kLambda, StopSums kStop>
__attribute__((target("avx512f"))) void BinAvx512f(const BinChunk& c, std::size_t n, const double* omega, double alpha,
                                                   bool batch, LaneSums* sums) {
  BinChunkBody<Vec, K, kLambda, kStop>(c, n, omega, alpha, batch, sums);
}
template <int K, bool kLambda, StopSums kStop>
__attribute__((target("avx2"))) void BinAvx2(const BinChunk& c, std::size_t n, const double* omega, double alpha,
                                             bool batch, LaneSums* sums) {
  BinChunkBody<Vec4, K, kLambda, kStop>(c, n, omega, alpha, batch, sums);
}
template <int K, bool kLambda, StopSums kStop>
void BinBaseline(const BinChunk& c, std::size_t n, const double* omega, double alpha, bool batch, LaneSums* sums) {
  BinChunkBody<Vec2, K, kLambda, kStop>(c, n, omega, alpha, batch, sums);
}

template <int K, bool kLambda, StopSums kStop>
BinFn SelectBinPath(KernelPath path) {
  switch (path) {
    case KernelPath::kAvx512f: return BinAvx512f<K, kLambda, kStop>;
    case KernelPath::kAvx2: return BinAvx2<K, kLambda, kStop>;
    case KernelPath::kBaseline: break;
  }
  return BinBaseline<K, kLambda, kStop>;
}

template <int K, bool kLambda>
BinFn SelectBinStop(KernelPath path, StopSums stop) {
  switch (stop) {
    case StopSums::kNone: return SelectBinPath<K, kLambda, StopSums::kNone>(path);
    case StopSums::kAbsolute: return SelectBinPath<K, kLambda, StopSums::kAbsolute>(path);
    case StopSums::kRelative: break;
  }
  return SelectBinPath<K, kLambda, StopSums::kRelative>(path);
}

template <int K>
BinFn SelectBinK(KernelPath path, bool lambda, StopSums stop) {
  return lambda ? SelectBinStop<K, true>(path, stop) : SelectBinStop<K, false>(path, stop);
}

BinFn SelectBin(KernelPath path, int K, bool lambda, StopSums stop) {
  static_assert(kMaxModesAtOnce == 8, "SelectBin lists K = 1 .. 8");
  switch (K) {
    case 1: return SelectBinK<1>(path, lambda, stop);
    case 2: return SelectBinK<2>(path, lambda, stop);
    case 3: return SelectBinK<3>(path, lambda, stop);
    case 4: return SelectBinK<4>(path, lambda, stop);
    case 5: return SelectBinK<5>(path, lambda, stop);
    case 6: return SelectBinK<6>(path, lambda, stop);
    case 7: return SelectBinK<7>(path, lambda, stop);
    case 8: return SelectBinK<8>(path, lambda, stop);
    default: return nullptr;
  }
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
  UpdateChunk<Vec, kLambda>(c, n, wk, alpha, acc);
}
template <bool kLambda>
__attribute__((target("avx2"))) void ChunkAvx2(const ModeChunk& c, std::size_t n, double wk, double alpha,
                                               LaneSums& acc) {
  UpdateChunk<Vec4, kLambda>(c, n, wk, alpha, acc);
}
template <bool kLambda>
void ChunkBaseline(const ModeChunk& c, std::size_t n, double wk, double alpha, LaneSums& acc) {
  UpdateChunk<Vec2, kLambda>(c, n, wk, alpha, acc);
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

bool BatchInversionSafe(int num_modes, double alpha) {
  // |freq - omega| <= 0.5 cycles per sample, so D_k <= 1 + alpha / 4 and P <= (1 + alpha / 4)^K.
  return num_modes * std::log2(1.0 + alpha * 0.25) < 1000.0;
}

void UpdateBinChunkOn(KernelPath path, const BinChunk& c, std::size_t n, int num_modes, const double* omega,
                      double alpha, bool batch_inversion, StopSums stop, LaneSums* sums) {
  SelectBin(path, num_modes, c.l_re != nullptr, stop)(c, n, omega, alpha, batch_inversion, sums);
}

void UpdateBinChunk(const BinChunk& c, std::size_t n, int num_modes, const double* omega, double alpha,
                    bool batch_inversion, StopSums stop, LaneSums* sums) {
  static const KernelPath best = BestPath();
  UpdateBinChunkOn(best, c, n, num_modes, omega, alpha, batch_inversion, stop, sums);
}

KernelPath BestKernelPath() { return BestPath(); }

const char* KernelPathName(KernelPath path) {
  switch (path) {
    case KernelPath::kAvx512f: return "avx512f";
    case KernelPath::kAvx2: return "avx2";
    case KernelPath::kBaseline: break;
  }
  return "baseline";
}

const char* KernelIsa() { return KernelPathName(BestPath()); }

}  // namespace gyrocomp::vmd_internal
