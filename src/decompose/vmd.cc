// Variational mode decomposition: see include/gyrocomp/vmd.h for the reference semantics.
//
// Layout: the one-sided spectrum has H = T/2 bins (0 .. T/2-1 of the extended signal; vmdpy's
// fftshifted indices T/2 .. T-1). Modes are stored mode-major with separate real and imaginary
// arrays (u_re[k * stride + j], stride >= H: ModeStride) so that the per-bin loops vectorise.
// Updates overwrite the iterate in place, except the last ones (the reference returns the
// iterate before the last: KeepPrevious), which write a second iterate: memory is 2 K H doubles
// while in place, 4 K H at the end, plus O(H) for the data, the residual / accumulator, lambda
// and the frequency grid. The stopping-rule sums are skipped where the rule cannot be met yet
// (StopSchedule). Options, validation and the initial centre frequencies: vmd_options.cc;
// threads: vmd_threads.h; the transforms: vmd_spectrum.cc.
//
// Parallelism: within one update every bin is independent (mode k's Wiener filter at bin j reads
// only bin j of f, lambda, the accumulator and the other modes, and the centre frequencies of the
// previous update), so the bins are cut into fixed blocks shared among threads; each block
// returns partial sums (for Eq. 5 and the stopping rule) that are added in block order, so the
// result does not depend on the number of threads.
//
// Steps of DecomposeVmd: MirrorAndTransform (even length, mirror extension, FFT, one-sided
// spectrum) -> InitialCenterFrequencies -> RunAdmm (per block UpdateBlock: Eq. 4 mode updates
// and Eq. 6 dual ascent; then UpdateCenterFrequencies: Eq. 5 and the stopping rule, Eq. 7) ->
// ReconstructModes (inverse FFT, unmirror) -> the summary.
#include "gyrocomp/decompose/vmd.h"
#include "gyrocomp/core/format.h"

#include "vmd_kernel.h"
#include "vmd_spectrum.h"
#include "vmd_threads.h"

#include <algorithm>
#include <functional>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <thread>

namespace gyrocomp {
namespace {

using vmd_internal::CheckProblemSize;
using vmd_internal::InitialCenterFrequencies;
using vmd_internal::MirrorAndTransform;
using vmd_internal::ReconstructModes;
using vmd_internal::AlignedVector;
using vmd_internal::VmdSpectrum;
using vmd_internal::RunThreads;
using vmd_internal::WorkerPool;

// Bins per reduction block: fixed, so that sums do not depend on the thread count.
constexpr std::size_t kBlockBins = 2048;
// Bins per chunk within a block (all modes of a chunk before the next; a multiple of
// vmd_internal::kLanes so that a bin's lane does not depend on the chunking).
constexpr std::size_t kChunkBins = 256;
static_assert(kBlockBins % kChunkBins == 0 && kChunkBins % vmd_internal::kLanes == 0);
// The iterate's distance between modes (doubles), >= H: a multiple of 4096 bytes (H a multiple of
// 512, e.g. N = 16384 or 65536) makes mode k+1's loads 4K-alias mode k's stores of the same bin,
// which on Zen 4 made the kernel 3x slower (1.66 vs 0.54 ns per bin-update at H = 16384). Padded
// to a multiple of 8 (every mode starts on a cache line) that is 32..56 doubles past a multiple of
// 512 (256..448 bytes past 4 KiB: even 7 strides stay clear of the next multiple), as H = 20,000
// (256 bytes) is. Layout only: the arithmetic, and so the results, are the same.
std::size_t ModeStride(std::size_t H) {
  std::size_t s = (H + 7) / 8 * 8;
  const std::size_t r = s % 512;
  if (r < 32) s += 32 - r;
  if (r > 56) s += 512 - r + 32;
  return s;
}
// Below this many bin-mode updates per iteration (K x H), one thread is faster (threads cost
// ~10 us per update to coordinate; WorkerPool runs rounds alone when two are slower anyway).
constexpr std::size_t kMinWorkForThreads = std::size_t{1} << 16;

// Threads for the iteration: as asked, else up to 2 when the work is large enough; never more
// than there are blocks.
int ChooseThreads(const VmdOptions& opt, std::size_t work, std::size_t num_blocks) {
  int threads = opt.num_threads.value_or(
      std::max(1, std::min(2, static_cast<int>(std::thread::hardware_concurrency()))));
  if (!opt.num_threads && work < kMinWorkForThreads) threads = 1;
  return std::max(1, std::min<int>(threads, static_cast<int>(num_blocks)));
}

// Working state of the ADMM iteration: two iterates of the K modes (ping-pong), the accumulator
// sum_uk, lambda, the per-block partial sums and the centre frequencies.
struct AdmmState {
  AdmmState(const VmdSpectrum& sp, const VmdOptions& options)
      : spectrum(sp), opt(options), K(options.num_modes), H(sp.H), stride(ModeStride(sp.H)),
        use_lambda(options.tau != 0.0),
        relative(options.stopping_rule == VmdStoppingRule::kRelative),
        bin_major(options.num_modes <= vmd_internal::kMaxModesAtOnce),
        batch_inversion(vmd_internal::BatchInversionSafe(options.num_modes, options.alpha)) {
    const std::size_t KH = static_cast<std::size_t>(K) * stride;
    ua_re.assign(KH, 0.0);
    ua_im.assign(KH, 0.0);
    if (bin_major) {  // the residual f - sum_uk, all modes zero
      s_re = sp.f_re;
      s_im = sp.f_im;
    } else {  // sum_uk
      s_re.assign(H, 0.0);
      s_im.assign(H, 0.0);
    }
    l_re.assign(use_lambda ? H : 0, 0.0);
    l_im.assign(use_lambda ? H : 0, 0.0);
    num_blocks = (H + kBlockBins - 1) / kBlockBins;
    sums.resize(num_blocks * static_cast<std::size_t>(K));
    cur_re = ua_re.data();
    cur_im = ua_im.data();
  }
  // The second iterate's storage, allocated at the first update that keeps its predecessor.
  void AllocateSecondIterate() {
    if (!ub_re.empty()) return;
    const std::size_t KH = static_cast<std::size_t>(K) * stride;
    ub_re.assign(KH, 0.0);
    ub_im.assign(KH, 0.0);
  }
  AdmmState(const AdmmState&) = delete;  // old_* / new_* point into the vectors
  AdmmState& operator=(const AdmmState&) = delete;

  const VmdSpectrum& spectrum;
  const VmdOptions& opt;
  const int K;
  const std::size_t H;
  const std::size_t stride;  // mode k of an iterate at [k * stride, k * stride + H) (ModeStride)
  const bool use_lambda;
  const bool relative;
  const bool bin_major;        // K <= kMaxModesAtOnce: UpdateBinChunk, s_* hold f - sum_uk
  const bool batch_inversion;  // UpdateBinChunk's reciprocals from one division per bin
  // 64-byte aligned (vmd_spectrum.h: AlignedVector); mode k at k * stride, stride a multiple of 8.
  AlignedVector ua_re, ua_im, ub_re, ub_im;  // storage of the iterates (ub_*: only when kept)
  AlignedVector s_re, s_im;                  // sum_uk, or f - sum_uk when bin_major
  AlignedVector l_re, l_im;                  // lambda (empty when tau = 0)
  std::size_t num_blocks = 0;
  std::vector<vmd_internal::LaneSums> sums;  // sums[block * K + k]: mode k over the block's bins
  // The stopping rule in the normalised units of the working signal (signal / 2^scale_exp):
  // tol of the absolute rule is in squared signal units, so it scales by 2^(-2 scale_exp)
  // (exactly: a power of two), which keeps every comparison, and so the iteration count, exact
  // for a scaled copy of a signal.
  int scale_exp = 0;
  double tol_norm = 0.0;
  double eps_norm = 0.0;
  double* cur_re = nullptr;   // the newest iterate (update n)
  double* cur_im = nullptr;
  double* prev_re = nullptr;  // update n-1 when the last update kept it (has_previous), else stale
  double* prev_im = nullptr;
  bool has_previous = false;
  vmd_internal::VmdTuning tuning;  // KeepPrevious's horizon and StopSchedule's parameters
  bool stop_schedule = false;      // StopSchedule may skip the stopping-rule sums (bin_major only)
  bool stop_sums_now = true;       // this update computes the stopping-rule sums
  // The last two updates whose stopping-rule value was computed (0: none) and their values.
  int stop_last_n = 0, stop_prev_n = 0;
  double stop_last = 0.0, stop_prev = 0.0;
  bool stop_missed = false;  // the rule was met after skipped sums: run again computing every update
  std::optional<int> extrapolation_period;  // VmdOptions' period when the record is long enough
  int report_after = 0;        // on_iteration only for updates after this one
  // Frees the working arrays except the iterate starting at keep_re / keep_im (before the modes
  // are reconstructed: the peak memory is then one iterate plus the modes).
  void ReleaseAllBut(const double* keep_re) {
    auto release = [](AlignedVector& v) { AlignedVector().swap(v); };
    if (keep_re != ua_re.data()) release(ua_re), release(ua_im);
    if (keep_re != ub_re.data()) release(ub_re), release(ub_im);
    release(s_re), release(s_im), release(l_re), release(l_im);
  }
  // The reference's output (update n-1) was overwritten by an in-place update n.
  bool NeedsRerun() const { return !opt.return_last_iterate && !has_previous; }
  std::vector<double> omega;       // centre frequencies for the next update (Eq. 5, or extrapolated)
  std::vector<double> omega_prev;  // centre frequencies the newest update used
  // Eq. (5) of the newest iterate and of the one before, never extrapolated: the returned ones.
  std::vector<double> eq5_omega, eq5_omega_prev;
  int n = 0;                       // updates run
  double u_diff = 0.0;             // the stopping rule's value after update n
};

// Where one update reads the previous iterate and writes the new one. In place (dst == src) the
// kernel reads bin j of mode k before it writes it, and mode K-1's previous value (the `prev` of
// mode 0) before mode K-1 is updated in the chunk: the arithmetic is the same as with two arrays.
struct IterateBuffers {
  const double* src_re;
  const double* src_im;
  double* dst_re;
  double* dst_im;
};

// Eq. (6) on bins [j0, j1): lambda += tau (sum_k u_k - f).
void DualAscent(AdmmState& st, const double* u_re, const double* u_im, std::size_t j0, std::size_t j1) {
  const double tau = st.opt.tau;
  const VmdSpectrum& sp = st.spectrum;
  for (std::size_t j = j0; j < j1; ++j) {
    double ar = u_re[j], ai = u_im[j];
    for (int k = 1; k < st.K; ++k) {
      ar += u_re[static_cast<std::size_t>(k) * st.stride + j];
      ai += u_im[static_cast<std::size_t>(k) * st.stride + j];
    }
    st.l_re[j] = st.l_re[j] + tau * (ar - sp.f_re[j]);
    st.l_im[j] = st.l_im[j] + tau * (ai - sp.f_im[j]);
  }
}

// One update of every mode on the bins of `block`, Gauss-Seidel over k (Eq. 4), then Eq. (6).
// The block is walked in chunks of kChunkBins bins, all K modes per chunk, so that the
// accumulator, the spectrum, lambda and mode k-1 stay in the L1 cache: per bin-update only the
// previous iterate of mode k is read from memory and the new one written (in place: to the same
// cache line).
void UpdateBlock(AdmmState& st, const IterateBuffers& io, std::size_t block, const std::vector<double>& om) {
  const std::size_t H = st.H;
  const int K = st.K;
  const VmdSpectrum& sp = st.spectrum;
  const std::size_t j0 = block * kBlockBins;
  const std::size_t j1 = std::min(H, j0 + kBlockBins);
  vmd_internal::LaneSums* bs = &st.sums[block * static_cast<std::size_t>(K)];
  for (int k = 0; k < K; ++k) bs[k].Clear();
  for (std::size_t c0 = j0; c0 < j1; c0 += kChunkBins) {
    const std::size_t c1 = std::min(j1, c0 + kChunkBins);
    if (st.bin_major) {  // all modes per vector of bins: Eq. (4)
      vmd_internal::BinChunk c;
      c.freq = sp.freq.data() + c0;
      c.l_re = st.use_lambda ? st.l_re.data() + c0 : nullptr;
      c.l_im = st.use_lambda ? st.l_im.data() + c0 : nullptr;
      c.r_re = st.s_re.data() + c0;  // the residual f - sum_uk on this path
      c.r_im = st.s_im.data() + c0;
      c.src_re = io.src_re + c0;
      c.src_im = io.src_im + c0;
      c.dst_re = io.dst_re + c0;
      c.dst_im = io.dst_im + c0;
      c.stride = st.stride;
      c.two_pass = vmd_internal::UseTwoPass(K, st.stride);
      using vmd_internal::StopSums;
      const StopSums stop = !st.stop_sums_now ? StopSums::kNone : st.relative ? StopSums::kRelative : StopSums::kAbsolute;
      vmd_internal::UpdateBinChunk(c, c1 - c0, K, om.data(), st.opt.alpha, st.batch_inversion, stop, bs);
      if (st.use_lambda) DualAscent(st, io.dst_re, io.dst_im, c0, c1);  // Eq. (6)
      continue;
    }
    for (int k = 0; k < K; ++k) {  // many modes: one mode at a time per chunk
      const std::size_t kk = static_cast<std::size_t>(k) * st.stride + c0;
      const std::size_t prev = (k == 0) ? static_cast<std::size_t>(K - 1) * st.stride + c0 : kk - st.stride;
      vmd_internal::ModeChunk c;
      c.freq = sp.freq.data() + c0;
      c.f_re = sp.f_re.data() + c0;
      c.f_im = sp.f_im.data() + c0;
      c.l_re = st.use_lambda ? st.l_re.data() + c0 : nullptr;
      c.l_im = st.use_lambda ? st.l_im.data() + c0 : nullptr;
      c.prev_re = (k == 0 ? io.src_re : io.dst_re) + prev;
      c.prev_im = (k == 0 ? io.src_im : io.dst_im) + prev;
      c.old_re = io.src_re + kk;
      c.old_im = io.src_im + kk;
      c.s_re = st.s_re.data() + c0;
      c.s_im = st.s_im.data() + c0;
      c.u_re = io.dst_re + kk;
      c.u_im = io.dst_im + kk;
      vmd_internal::UpdateModeChunk(c, c1 - c0, om[k], st.opt.alpha, bs[k]);  // Eq. (4)
    }
    if (st.use_lambda) DualAscent(st, io.dst_re, io.dst_im, c0, c1);  // Eq. (6)
  }
}

// Adds the block sums in block order: Eq. (5) centre frequencies (into st.omega) and the value
// of the stopping rule (reference absolute, or Eq. 7 relative), in normalised units.
double UpdateCenterFrequencies(AdmmState& st) {
  using vmd_internal::LaneTotal;
  const VmdOptions& opt = st.opt;
  const std::size_t K = static_cast<std::size_t>(st.K);
  double total = 0.0;
  for (std::size_t k = 0; k < K; ++k) {
    double fp = 0, p = 0, df = 0, op = 0;
    for (std::size_t b = 0; b < st.num_blocks; ++b) {
      const vmd_internal::LaneSums& ls = st.sums[b * K + k];
      fp += LaneTotal(ls.freq_power);
      p += LaneTotal(ls.power);
      df += LaneTotal(ls.diff);
      op += LaneTotal(ls.old_power);
    }
    // Eq. (5)
    if (!(opt.dc && k == 0) && p > 0) st.omega[k] = fp / p;
    if (opt.stopping_rule == VmdStoppingRule::kAbsolute) {
      total += st.spectrum.inv_T * df;
    } else if (op > 0) {
      total += df / op;  // Eq. (7)
    } else if (df > 0) {
      total = std::numeric_limits<double>::infinity();  // from zero: not converged
    }
  }
  if (!st.stop_sums_now) return std::numeric_limits<double>::quiet_NaN();  // diff not summed
  // The reference adds np.spacing(1) (squared signal units) to the absolute rule.
  return opt.stopping_rule == VmdStoppingRule::kAbsolute ? std::abs(st.eps_norm + total) : total;
}

// A value of the stopping rule back in its own units: squared signal units for the absolute
// rule (saturating at the largest double when the signal's square is not representable, |x| >
// ~1e154), dimensionless for the relative one.
double SignalUnits(const AdmmState& st, double u) {
  if (st.opt.stopping_rule != VmdStoppingRule::kAbsolute) return u;
  return std::min(std::ldexp(u, 2 * st.scale_exp), std::numeric_limits<double>::max());
}

// The stopping rule's fall per update, from its last two computed values (<= 1; 1 when fewer than
// two were computed or the value rose). Consecutive values: their plain ratio.
double StopFallPerUpdate(const AdmmState& st) {
  if (st.stop_prev_n == 0 || !(st.stop_prev > 0) || !std::isfinite(st.stop_prev)) return 1.0;
  const double ratio = st.stop_last / st.stop_prev;
  const int gap = st.stop_last_n - st.stop_prev_n;
  return std::min(1.0, gap == 1 ? ratio : std::pow(ratio, 1.0 / gap));
}

// The stopping rule's value predicted `steps` updates after the last computed one, falling by
// `fall` per update.
double PredictedStopValue(const AdmmState& st, double fall, double steps) {
  return steps == 0 ? st.stop_last : st.stop_last * std::pow(fall, steps);
}

// Whether update `next` (about to run) sums the stopping rule (~4 of the kernel's 13 additions
// and 2 of its 12 multiplications per bin-update). The rule can only be seen met on a computed
// update whose predecessor was computed too (else a skipped update may have met it first), so
// `next` is computed when `next` or `next + 1` could meet tol, predicted from the last computed
// value with a pessimistic fall per update, q = (measured fall)^stop_safety_exponent; also the
// first stop_warmup_updates, the last one the cap allows (its value is reported) and at least
// every stop_max_gap updates (a fresh fall). A faster fall than predicted is caught (stop_missed) and
// the whole iteration run again computing every update: the same bits (DecomposeVmdTuned).
bool StopSchedule(const AdmmState& st, int next) {
  if (!st.stop_schedule || st.stop_prev_n == 0 || next <= st.tuning.stop_warmup_updates) return true;
  if (next >= st.opt.max_iterations - 1 || next - st.stop_last_n >= st.tuning.stop_max_gap) return true;
  const double q = std::min(st.tuning.stop_fall_cap, std::pow(StopFallPerUpdate(st), st.tuning.stop_safety_exponent));
  return PredictedStopValue(st, q, next + 1 - st.stop_last_n) <= st.tol_norm;
}

// Whether update n+1 (about to run) must keep update n, i.e. run into the second array instead of
// in place: the reference returns the iterate before the one that meets the rule. Certain for the
// last update the cap allows and from `keep_from` on; otherwise predicted: the rule's value
// (computed after update n, or predicted from the last computed one) keeps falling as it did
// between the last two computed updates; keep when lookahead_steps more such falls would meet
// tol. Never for an update that skips the stopping sums (it cannot be seen meeting the rule). A
// wrong prediction (the rule met by an in-place update) is caught by DecomposeVmdTuned, which
// runs the iteration again with keep_from set (same bits: the run is deterministic).
bool KeepPrevious(const AdmmState& st, int keep_from) {
  if (st.opt.return_last_iterate) return false;
  const int next = st.n + 1;
  if (next >= st.opt.max_iterations - 1 || next >= keep_from) return true;
  if (!st.stop_sums_now || st.stop_prev_n == 0) return false;  // skipped, or no fall measured yet
  const double fall = StopFallPerUpdate(st);
  const double now = PredictedStopValue(st, fall, st.n - st.stop_last_n);
  return now * std::pow(fall, st.tuning.lookahead_steps) <= st.tol_norm;
}

// VmdOptions::omega_extrapolation_period: the Aitken limit of each w_k's last three values
// (w0 = older, w1 = w_prev, w2 = st.omega), applied in place to st.omega when the sequence
// contracts geometrically.
constexpr double kMaxExtrapolationRatio = 0.995;
void ExtrapolateCenterFrequencies(AdmmState& st, const std::vector<double>& older) {
  for (int k = 0; k < st.K; ++k) {
    if (st.opt.dc && k == 0) continue;
    const double d1 = st.omega_prev[k] - older[k], d2 = st.omega[k] - st.omega_prev[k];
    if (d1 == 0) continue;
    const double r = d2 / d1;
    if (!(r > 0 && r < kMaxExtrapolationRatio)) continue;
    st.omega[k] = std::clamp(st.omega[k] + d2 * (r / (1 - r)), 0.0, 0.5);
  }
}

// The ADMM loop: updates until the stopping rule holds or max_iterations - 1 updates were run
// (vmdpy's Niter convention). Afterwards `cur_*` hold update n and, when has_previous, `prev_*`
// update n-1. Updates run in place (one iterate: a third less memory traffic) except those that
// KeepPrevious says must keep their predecessor.
void RunAdmm(AdmmState& st, int threads, int keep_from) {
  const VmdOptions& opt = st.opt;
  // vmdpy starts from uDiff = tol + eps to enter the loop; with tol >= 1 squared signal units eps
  // is absorbed and it returns its all-zero initial modes. Here the first update always runs:
  // `n == 0` enters the loop even when tol_norm is +inf (an absolute tol on a signal near 1e-300
  // overflows when normalised; `inf > inf` would run no update and leave no iterate to return).
  st.u_diff = std::numeric_limits<double>::infinity();
  st.n = 0;
  st.has_previous = false;
  st.omega_prev = st.omega;
  st.eq5_omega = st.eq5_omega_prev = st.omega;
  std::vector<double> om_snapshot, omega_older = st.omega;
  WorkerPool pool(threads);
  const std::size_t num_blocks = st.num_blocks;
  IterateBuffers io{};
  const std::function<void(int, int)> round = [&](int t, int of) {
    const std::size_t b0 = num_blocks * t / of;
    const std::size_t b1 = num_blocks * (t + 1) / of;
    for (std::size_t b = b0; b < b1; ++b) UpdateBlock(st, io, b, om_snapshot);
  };
  while ((st.n == 0 || st.u_diff > st.tol_norm) && st.n < opt.max_iterations - 1) {
    if (opt.cancel != nullptr && opt.cancel->cancelled()) throw Cancelled();  // VmdOptions::cancel
    st.stop_sums_now = StopSchedule(st, st.n + 1);
    const bool keep = KeepPrevious(st, keep_from);
    io = {st.cur_re, st.cur_im, st.cur_re, st.cur_im};
    if (keep) {
      st.AllocateSecondIterate();
      double* other_re = st.cur_re == st.ua_re.data() ? st.ub_re.data() : st.ua_re.data();
      double* other_im = st.cur_im == st.ua_im.data() ? st.ub_im.data() : st.ua_im.data();
      io.dst_re = other_re;
      io.dst_im = other_im;
    }
    om_snapshot = st.omega;
    pool.Run(round);
    omega_older.swap(st.omega_prev);
    st.omega_prev = st.omega;
    const double value = UpdateCenterFrequencies(st);  // NaN when the sums were skipped
    st.eq5_omega_prev.swap(st.eq5_omega);
    st.eq5_omega = st.omega;
    ++st.n;
    if (st.stop_sums_now) {
      if (value <= st.tol_norm && st.stop_last_n != st.n - 1) st.stop_missed = true;  // see StopSchedule
      st.stop_prev_n = st.stop_last_n, st.stop_prev = st.stop_last;
      st.stop_last_n = st.n, st.stop_last = value;
      st.u_diff = value;
    }
    // Eq. (5)'s values are returned (eq5_omega); the last update needs no extrapolation.
    const bool last = st.u_diff <= st.tol_norm || st.n >= opt.max_iterations - 1;
    if (st.extrapolation_period && st.n >= 3 && st.n % *st.extrapolation_period == 0 && !last) {
      ExtrapolateCenterFrequencies(st, omega_older);
    }
    st.has_previous = keep;
    if (keep) {
      st.prev_re = st.cur_re;
      st.prev_im = st.cur_im;
      st.cur_re = io.dst_re;
      st.cur_im = io.dst_im;
    }
    if (opt.on_iteration && st.n > st.report_after) opt.on_iteration(st.n, SignalUnits(st, value));
  }
}

// A fresh ADMM state on the spectrum, iterated (RunAdmm with the given keep_from; on_iteration
// only for updates after report_after).
std::unique_ptr<AdmmState> IterateAdmm(const VmdSpectrum& sp, const VmdOptions& opt, int threads,
                                       const vmd_internal::VmdTuning& tuning, int keep_from, int report_after) {
  auto st = std::make_unique<AdmmState>(sp, opt);
  st->scale_exp = sp.scale_exp;
  const bool absolute = opt.stopping_rule == VmdStoppingRule::kAbsolute;
  st->tol_norm = absolute ? std::ldexp(opt.tol, -2 * sp.scale_exp) : opt.tol;
  // vmdpy's np.spacing(1) guard of the absolute rule, taken in the normalised units (i.e. relative
  // to the signal's scale) so that the rule is scale-free: for a signal with max |x| in [1, 2) it
  // is vmdpy's; otherwise it differs from vmdpy's by less than eps * max|x|^2 squared units.
  st->eps_norm = std::numeric_limits<double>::epsilon();
  st->omega = InitialCenterFrequencies(opt, sp.n_even);
  st->tuning = tuning;
  if (opt.omega_extrapolation_period && sp.n_in >= opt.omega_extrapolation_min_samples) {
    st->extrapolation_period = opt.omega_extrapolation_period;
  }
  // Not with the extrapolation: its jumps make the stopping value spike and then fall by 100x
  // within a few updates, which no fall measured between computed updates predicts (and those
  // long records are memory-bound, where the skipped arithmetic saves little).
  st->stop_schedule = tuning.stop_schedule && st->bin_major && !st->extrapolation_period;
  st->report_after = report_after;
  RunAdmm(*st, threads, keep_from);
  return st;
}

}  // namespace

Result<VmdResult> DecomposeVmd(std::span<const double> signal, const VmdOptions& opt) {
  return vmd_internal::DecomposeVmdTuned(signal, opt, vmd_internal::VmdTuning{}, nullptr);
}

Result<VmdResult> vmd_internal::DecomposeVmdTuned(std::span<const double> signal, const VmdOptions& opt,
                                                  const VmdTuning& tuning, int* reruns) {
  const auto start = std::chrono::steady_clock::now();
  std::string why;
  if (!opt.IsValid(&why)) return InvalidArgument(why);
  const std::size_t n_in = signal.size();
  if (n_in < 4) {
    return InvalidInput("VMD needs at least 4 samples, got " + std::to_string(n_in));
  }
  for (std::size_t i = 0; i < n_in; ++i) {
    if (!std::isfinite(signal[i])) {
      return InvalidInput("VMD input sample " + std::to_string(i) + " is not finite");
    }
  }
  const int K = opt.num_modes;
  if (Status s = CheckProblemSize(opt, n_in); !s.ok()) return s.error();

  Result<VmdSpectrum> spectrum = MirrorAndTransform(signal, opt.mirror_extension);
  if (!spectrum.ok()) return spectrum.error();
  VmdSpectrum& sp = *spectrum;

  const int threads = ChooseThreads(opt, static_cast<std::size_t>(K) * sp.H, (sp.H + kBlockBins - 1) / kBlockBins);
  std::unique_ptr<AdmmState> run = IterateAdmm(sp, opt, threads, tuning, std::numeric_limits<int>::max(), 0);
  if (run->stop_missed) {
    // The rule was seen met after skipped sums (StopSchedule): a skipped update after the last
    // computed one (stop_prev_n, not met) may have met it first. Run again (deterministic: the
    // same bits) computing every update and keeping each predecessor from there on.
    // on_iteration is not called again for the updates already reported.
    const int keep_from = run->stop_prev_n + 1, reported = run->n;
    if (reruns) ++*reruns;
    run.reset();
    VmdTuning every_update = tuning;
    every_update.stop_schedule = false;
    run = IterateAdmm(sp, opt, threads, every_update, keep_from, reported);
  } else if (run->NeedsRerun()) {
    // The rule was met by an in-place update: run again (deterministic: the same bits), keeping
    // from that update on. on_iteration is not called again for the updates already reported.
    const int keep_from = run->n;
    if (reruns) ++*reruns;
    run.reset();
    run = IterateAdmm(sp, opt, threads, tuning, keep_from, keep_from);
  }
  AdmmState& st = *run;

  // `cur_*` hold update n and `prev_*` update n-1 (zeros when n = 1: the reference then returns
  // its all-zero initial iterate too).
  const bool last = opt.return_last_iterate;
  const double* out_re = last ? st.cur_re : st.prev_re;
  const double* out_im = last ? st.cur_im : st.prev_im;
  const std::vector<double>& out_omega = last ? st.eq5_omega : st.eq5_omega_prev;
  if (st.n < 1 || out_re == nullptr || out_im == nullptr) {
    return InternalError("VMD: no update was run (n = " + std::to_string(st.n) + ")");
  }
  st.ReleaseAllBut(out_re);

  VmdResult result;
  Result<std::vector<std::vector<double>>> modes = ReconstructModes(sp, out_re, out_im, st.stride, K, n_in, threads);
  if (!modes.ok()) return modes.error();
  result.modes = std::move(*modes);
  for (int k = 0; k < K; ++k) {
    for (double v : result.modes[k]) {
      if (!std::isfinite(v)) {
        return InvalidInput("VMD: mode " + std::to_string(k + 1) +
                            " exceeds the double range (the input is within a factor 2 of the largest double)");
      }
    }
  }

  // The absolute rule with a tolerance above the signal's power stops after the first update and
  // returns the all-zero initial iterate (as vmdpy does): no decomposition at all. Say so rather
  // than hand the later stages K zero modes (e.g. a record scaled to ~1e-302).
  if (st.n == 1 && opt.max_iterations > 2 && st.u_diff <= st.tol_norm && !last &&
      opt.stopping_rule == VmdStoppingRule::kAbsolute) {
    double power = 0.0;  // mean square in normalised units (max |x| in [1, 2)), then signal units
    for (std::size_t i = 0; i < n_in; ++i) {
      const double v = std::ldexp(signal[i], -sp.scale_exp);
      power += v * v / static_cast<double>(n_in);
    }
    if (power > 0) {
      return InvalidInput("VMD: the absolute stopping tolerance " + FormatNumber(opt.tol) +
                          " (squared signal units) is not small against the signal's mean square (" +
                          "about 1e" + std::to_string(static_cast<long>(std::floor(
                                           std::log10(power) + 2.0 * sp.scale_exp * std::log10(2.0)))) +
                          "): the rule stops after one update with all-zero modes; use the relative "
                          "rule (--vmd-stop relative) or a smaller --tol");
    }
  }
  VmdSummary& s = result.summary;
  s.num_modes = K;
  s.num_samples = n_in;
  s.extended_length = sp.T;
  s.iterations = st.n;
  s.converged = st.u_diff <= st.tol_norm;
  s.final_update = SignalUnits(st, st.u_diff);
  s.center_frequency_cycles_per_sample = out_omega;
  s.fs_hz = opt.fs_hz;
  for (double w : out_omega) s.center_frequency_hz.push_back(w * opt.fs_hz);
  s.threads_used = threads;
  s.omega_extrapolation_period = st.extrapolation_period;
  s.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace gyrocomp
