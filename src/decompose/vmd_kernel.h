// The VMD inner kernel (internal to src/decompose/): one fused pass of Eq. (4) over a chunk of
// bins of one mode, with the partial sums that Eq. (5) and the stopping rule need.
//
// Determinism: the sums are kept in kLanes fixed lanes (bin j of a block goes to lane
// j mod kLanes, added in increasing j) and combined in a fixed tree, so every code path (the
// run-time dispatched SIMD clones and the scalar tail) performs the same IEEE operations in the
// same order. vmd_kernel.cc is compiled with -ffp-contract=off: no path fuses a multiply-add.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "gyrocomp/decompose/vmd.h"

namespace gyrocomp::vmd_internal {

// The compiled paths, for tests that check they agree bit for bit.
enum class KernelPath { kBaseline, kAvx2, kAvx512f };

// Lanes of the partial sums (one 512-bit vector, two 256-bit or four 128-bit ones).
constexpr std::size_t kLanes = 8;

// Partial sums of one mode over the bins of one block, per lane.
struct LaneSums {
  alignas(64) double freq_power[kLanes];  // sum freq_j |u_kj|^2 (Eq. 5 numerator)
  alignas(64) double power[kLanes];       // sum |u_kj|^2         (Eq. 5 denominator)
  alignas(64) double diff[kLanes];        // sum |u_kj^new - u_kj^old|^2 (stopping rule)
  alignas(64) double old_power[kLanes];   // sum |u_kj^old|^2 (Eq. 7 relative rule)
  void Clear();
};

// Fixed-order total of the lanes: ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)).
double LaneTotal(const double (&lanes)[kLanes]);

// The arrays of one chunk of bins [0, n) of mode k (pointers already offset to the chunk start).
struct ModeChunk {
  const double* freq;     // bin frequency, cycles per sample
  const double* f_re;     // f_hat_plus
  const double* f_im;
  const double* l_re;     // lambda / 2 is subtracted; nullptr when tau = 0 (lambda stays 0)
  const double* l_im;
  const double* prev_re;  // mode k-1 of this update (mode K-1 of the previous one for k = 0)
  const double* prev_im;
  const double* old_re;   // mode k of the previous update
  const double* old_im;
  double* s_re;           // the accumulator sum_uk (updated in place)
  double* s_im;
  double* u_re;           // mode k of this update (written)
  double* u_im;
};

// Eq. (4) on n bins of one mode, Gauss-Seidel order of vmdpy:
//   sum_uk = (u_{k-1} + sum_uk) - u_k^{old}
//   u_k    = ((f - sum_uk) - lambda / 2) * rcp,  rcp = 1 / (1 + alpha (freq - omega_k)^2)
// (one reciprocal per bin shared by the real and imaginary parts), and adds the bins to `sums`:
// bin i of the chunk goes to lane i mod kLanes (chunks start at multiples of kLanes from the
// block start, so this is the block's lane). The SIMD width is chosen at run time (AVX-512F,
// AVX2 or the x86-64 baseline); all give the same bits.
void UpdateModeChunk(const ModeChunk& c, std::size_t n, double omega_k, double alpha, LaneSums& sums);

// ---- all modes of a bin at once (K <= kMaxModesAtOnce) -----------------------------------------
//
// The same Eq. (4) and sums as UpdateModeChunk, walked bin-major: for each vector of kLanes bins,
// every mode in Gauss-Seidel order, so that the accumulator, the spectrum, lambda and mode k-1
// stay in registers; per bin-update only the previous iterate of mode k is loaded and the new one
// stored. The K reciprocals of a bin come from one division (batch inversion, below). Per mode,
// bin i still goes to lane i mod kLanes in increasing i, so the sums are those of the mode-major
// walk of the same values.
constexpr int kMaxModesAtOnce = 8;

// The bins [0, n) of one chunk for all modes (pointers already offset to the chunk start; mode k
// at + k * stride). src and dst may be the same arrays (in-place update: every load of a bin
// precedes its store, and mode K-1's old value is read as mode 0's predecessor before it is
// overwritten).
struct BinChunk {
  const double* freq;
  const double* l_re;  // nullptr when tau = 0
  const double* l_im;
  double* r_re;        // residual f - sum_uk (updated in place; f_hat_plus before the first update)
  double* r_im;
  const double* src_re;  // previous iterate, mode 0
  const double* src_im;
  double* dst_re;        // new iterate, mode 0
  double* dst_im;
  std::size_t stride;    // distance between modes (>= H)
  // Reciprocals of a 256-bin sub-chunk first, then Eq. (4) (in cache: the passes overlap better),
  // or both per vector in one pass (iterates streaming from memory: no pass leaves the memory
  // idle). The same operations either way: the same bits. UseTwoPass says which.
  bool two_pass = true;
};

// Whether the iterate (K modes, `stride` bins each, re and im) is small enough for the two-pass
// kernel: measured on the 2-core Zen 4 (32 MiB L3): two-pass faster up to H = 100k (9.6 MB),
// slower from 200k (19 MB; 1.3 vs 0.95 ns per bin-update at 1M).
constexpr std::size_t kTwoPassMaxIterateBytes = std::size_t{12} << 20;
inline bool UseTwoPass(int num_modes, std::size_t stride) {
  return static_cast<std::size_t>(num_modes) * stride * 2 * sizeof(double) <= kTwoPassMaxIterateBytes;
}

// Reciprocals of the K denominators of Eq. (4), D_k = 1 + alpha (freq - omega_k)^2 (all >= 1), by
// batch inversion: prefix products P_k = D_0 ... D_k, one division 1 / P_{K-1}, then backwards
// rcp_k = inv P_{k-1}, inv <- inv D_k: 3 (K-1) multiplications and one division instead of K
// divisions; each rcp_k within ~3K roundings of 1 / D_k. When P could overflow (alpha so large
// that (1 + alpha / 4)^K > 2^1000), every reciprocal is a direct division instead.
bool BatchInversionSafe(int num_modes, double alpha);

// Which stopping-rule sums UpdateBinChunk adds (LaneSums::diff, and old_power for Eq. 7). kNone
// leaves both untouched: DecomposeVmd skips them on updates where the rule cannot be met yet
// (vmd.cc: StopSchedule); Eq. (4) and the Eq. (5) sums are the same bits either way.
enum class StopSums { kNone, kAbsolute, kRelative };

// Eq. (4) and the Eq. (5) / stopping-rule sums for all K (<= kMaxModesAtOnce) modes on n bins;
// sums[k] receives mode k. The running quantity is the residual r = f - sum_uk, updated per mode
// as r <- (r - u_{k-1}) + u_k^old (one subtraction fewer than keeping sum_uk). batch_inversion:
// pass BatchInversionSafe(num_modes, alpha). diff is summed unless stop = kNone, old_power (Eq. 7's
// denominator) only for kRelative.
// With BinChunk::two_pass, two passes per sub-chunk of kRecipBins bins: the K reciprocals of every
// bin into a buffer on the stack, then Eq. (4). The reciprocals depend only on the bin and the
// centre frequencies, so the passes give the same bits as one; separated, each pass's vectors are
// independent of each other and the out-of-order core overlaps them (0.67 vs 0.82 ns per
// bin-update at N = 20k; docs/explanation/performance.md). Without it, one pass (iterates in memory).
constexpr std::size_t kRecipBins = 256;
void UpdateBinChunk(const BinChunk& c, std::size_t n, int num_modes, const double* omega, double alpha,
                    bool batch_inversion, StopSums stop, LaneSums* sums);
void UpdateBinChunkOn(KernelPath path, const BinChunk& c, std::size_t n, int num_modes, const double* omega,
                      double alpha, bool batch_inversion, StopSums stop, LaneSums* sums);

// The path the dispatcher picks on this machine, and a path's name ("avx512f", "avx2",
// "baseline") for benchmark, test and log output; KernelIsa() = the picked path's name.
KernelPath BestKernelPath();
const char* KernelPathName(KernelPath path);
const char* KernelIsa();

bool KernelPathSupported(KernelPath path);
// UpdateModeChunk on the given path (which must be supported by this CPU).
void UpdateModeChunkOn(KernelPath path, const ModeChunk& c, std::size_t n, double omega_k, double alpha,
                       LaneSums& sums);

// ---- helpers of DecomposeVmd (vmd_options.cc) ----------------------------------------------------

// Initial centre frequencies (cycles per sample): uniform, random (vmdpy's init = 2), zero, or
// VmdOptions::initial_center_frequencies; n_even = the even working length.
std::vector<double> InitialCenterFrequencies(const VmdOptions& opt, std::size_t n_even);
// Refuses a K the record cannot hold (K > N / 2) or a working set above max_memory_bytes.
Status CheckProblemSize(const VmdOptions& opt, std::size_t n);

// DecomposeVmd's internal schedules (vmd.cc). None changes a bit of the result, only memory
// traffic, work and how often the iteration is run again.
struct VmdTuning {
  // KeepPrevious's horizon: keep update n when this many more falls of the stopping value like
  // the last would meet tol. 0 never predicts, so every converged run is run a second time.
  double lookahead_steps = 4;
  // StopSchedule: skip the stopping-rule sums on updates where the rule cannot be met yet,
  // predicted with a fall per update of min(stop_fall_cap, (measured fall)^stop_safety_exponent)
  // (pessimistic), computing at least every stop_max_gap updates. Exponent 0 with cap 1 predicts
  // no fall: the meeting update is then found late (unless it falls on a computed pair) and the
  // iteration run again.
  // Defaults: no rerun on the four golden inputs, the 20k / 40k soak and side-by-side records,
  // two MPU-6050 logs (K = 4, 6) and two pure tones, computing the sums on 16-52% of the updates
  // (docs/explanation/performance.md).
  bool stop_schedule = true;
  // The first updates always compute the sums: early on the value can rise and then collapse
  // by 1e9 within three updates (two pure tones), which no measured fall predicts.
  int stop_warmup_updates = 16;
  double stop_safety_exponent = 8;
  double stop_fall_cap = 0.5;  // the assumed fall per update is at least this steep (<= it)
  int stop_max_gap = 8;
};

// DecomposeVmd with its schedules exposed (DecomposeVmd uses VmdTuning{}): tests use them to
// check that reruns give the same bits. *reruns (if given) counts reruns.
Result<VmdResult> DecomposeVmdTuned(std::span<const double> signal, const VmdOptions& opt, const VmdTuning& tuning,
                                    int* reruns);

}  // namespace gyrocomp::vmd_internal
