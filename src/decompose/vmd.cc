// Variational mode decomposition: see include/gyrocomp/vmd.h for the reference semantics.
//
// Layout: the one-sided spectrum has H = T/2 bins (0 .. T/2-1 of the extended signal; vmdpy's
// fftshifted indices T/2 .. T-1). Modes are stored mode-major with separate real and imaginary
// arrays (u_re[k * H + j]) so that the per-bin loops vectorise. Two iterates are kept (the
// previous one and the one being computed: ping-pong), because the reference returns the iterate
// before the last: memory is 4 K H doubles plus O(H) for the data, the accumulator, lambda and
// the frequency grid.
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

#include <fftw3.h>

#include <algorithm>
#include <atomic>
#include <barrier>
#include <functional>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>

namespace gyrocomp {
namespace {

// FFTW planning is not thread-safe; execution of an existing plan is.
std::mutex& FftwPlannerMutex() {
  static std::mutex mutex;
  return mutex;
}

template <class T>
struct FftwFree {
  void operator()(T* p) const { fftw_free(p); }
};
using RealBuffer = std::unique_ptr<double, FftwFree<double>>;
using ComplexBuffer = std::unique_ptr<fftw_complex, FftwFree<fftw_complex>>;

RealBuffer AllocReal(std::size_t n) { return RealBuffer(fftw_alloc_real(n)); }
ComplexBuffer AllocComplex(std::size_t n) { return ComplexBuffer(fftw_alloc_complex(n)); }

struct PlanDeleter {
  void operator()(fftw_plan_s* p) const {
    std::lock_guard<std::mutex> lock(FftwPlannerMutex());
    fftw_destroy_plan(p);
  }
};
using Plan = std::unique_ptr<fftw_plan_s, PlanDeleter>;

// Bins per reduction block: fixed, so that sums do not depend on the thread count.
constexpr std::size_t kBlockBins = 2048;
// Below this many bin-mode updates per iteration, one thread is faster.
constexpr std::size_t kMinWorkForThreads = 1u << 16;

// Partial sums of one block, per mode.
struct BlockSums {
  std::vector<double> freq_power;  // sum freq_j |u_kj|^2 (Eq. 5 numerator)
  std::vector<double> power;       // sum |u_kj|^2         (Eq. 5 denominator)
  std::vector<double> diff;        // sum |u_kj^new - u_kj^old|^2 (stopping rule)
  std::vector<double> old_power;   // sum |u_kj^old|^2 (Eq. 7 relative rule)
};

// Runs fn(t) for t = 0..threads-1, fn(0) on the calling thread.
template <class Fn>
void RunThreads(int threads, Fn&& fn) {
  if (threads <= 1) {
    fn(0);
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(threads - 1);
  for (int t = 1; t < threads; ++t) pool.emplace_back([&fn, t] { fn(t); });
  fn(0);
  for (auto& th : pool) th.join();
}

// Persistent workers for the iteration loop (hundreds of short rounds: starting threads each
// round would cost a noticeable part of a round at N ~ 10^4).
class WorkerPool {
 public:
  explicit WorkerPool(int threads) : threads_(threads), start_(threads), done_(threads) {
    for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { Loop(t); });
  }
  ~WorkerPool() {
    stop_ = true;
    if (threads_ > 1) start_.arrive_and_wait();
    for (auto& w : workers_) w.join();
  }
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  // fn(t) on every thread t, fn(0) on the caller; returns when all are done.
  void Run(const std::function<void(int)>& fn) {
    fn_ = &fn;
    if (threads_ > 1) start_.arrive_and_wait();
    fn(0);
    if (threads_ > 1) done_.arrive_and_wait();
  }

 private:
  void Loop(int t) {
    for (;;) {
      start_.arrive_and_wait();
      if (stop_) return;
      (*fn_)(t);
      done_.arrive_and_wait();
    }
  }
  int threads_;
  std::barrier<> start_, done_;
  std::atomic<bool> stop_{false};
  const std::function<void(int)>* fn_ = nullptr;
  std::vector<std::thread> workers_;
};

// numpy's legacy np.random.rand after np.random.seed(seed): 53-bit doubles from MT19937.
std::vector<double> NumpyRand(std::uint32_t seed, int count) {
  std::mt19937 mt(seed);
  std::vector<double> out(count);
  for (double& v : out) {
    const std::uint32_t a = mt() >> 5;
    const std::uint32_t b = mt() >> 6;
    v = (a * 67108864.0 + b) / 9007199254740992.0;
  }
  return out;
}

// Eq. (4) for one mode on bins [j0, j1): the accumulator update
//   sum_uk = u_{k-1} + sum_uk - u_k^{old}      (vmdpy's order of operations)
// and the Wiener filter of the residual around omega_k
//   u_k = (f - sum_uk - lambda/2) / (1 + alpha (freq - omega_k)^2).
// Separate restrict-qualified arrays so that the loop vectorises.
void UpdateMode(std::size_t j0, std::size_t j1, double wk, double alpha, const double* __restrict freq,
                const double* __restrict f_re, const double* __restrict f_im,
                const double* __restrict l_re, const double* __restrict l_im,
                const double* __restrict prev_re, const double* __restrict prev_im,
                const double* __restrict o_re, const double* __restrict o_im,
                double* __restrict s_re, double* __restrict s_im, double* __restrict u_re,
                double* __restrict u_im) {
  if (l_re == nullptr) {
    for (std::size_t j = j0; j < j1; ++j) {
      const double sr = (prev_re[j] + s_re[j]) - o_re[j];
      const double si = (prev_im[j] + s_im[j]) - o_im[j];
      s_re[j] = sr;
      s_im[j] = si;
      const double d = freq[j] - wk;
      const double den = 1.0 + alpha * (d * d);
      u_re[j] = (f_re[j] - sr) / den;
      u_im[j] = (f_im[j] - si) / den;
    }
  } else {
    for (std::size_t j = j0; j < j1; ++j) {
      const double sr = (prev_re[j] + s_re[j]) - o_re[j];
      const double si = (prev_im[j] + s_im[j]) - o_im[j];
      s_re[j] = sr;
      s_im[j] = si;
      const double d = freq[j] - wk;
      const double den = 1.0 + alpha * (d * d);
      u_re[j] = ((f_re[j] - sr) - l_re[j] / 2) / den;
      u_im[j] = ((f_im[j] - si) - l_im[j] / 2) / den;
    }
  }
}

// The mirror-extended, even-length signal's one-sided spectrum (f_hat_plus), its frequency grid
// and the FFT plans and buffers (reused for the inverse transforms).
struct VmdSpectrum {
  std::size_t n_even = 0;  // even working length (odd input: the last sample repeated)
  std::size_t offset = 0;  // mirrored samples before the signal (ltemp)
  std::size_t T = 0;       // extended length
  std::size_t H = 0;       // one-sided bins 0..H-1
  double inv_T = 0.0;
  RealBuffer time_buf;
  ComplexBuffer spec_buf;
  Plan forward, inverse;
  std::vector<double> f_re, f_im;  // f_hat_plus
  std::vector<double> freq;        // cycles per sample
};

// Even working length, mirror extension f[ltemp-1..0], f, f[N-1..N-ltemp], forward FFT, and the
// one-sided spectrum with vmdpy's frequency grid.
Result<VmdSpectrum> MirrorAndTransform(std::span<const double> signal, bool mirror_extension) {
  VmdSpectrum sp;
  // Even working length (odd input: repeat the last sample; the reference drops it).
  std::vector<double> f(signal.begin(), signal.end());
  if (f.size() % 2) f.push_back(f.back());
  sp.n_even = f.size();

  // Mirror extension: f[ltemp-1..0], f, f[N-1..N-ltemp].
  const std::size_t ltemp = mirror_extension ? sp.n_even / 2 : 0;
  sp.T = sp.n_even + 2 * ltemp;
  sp.H = sp.T / 2;  // one-sided bins 0..H-1
  sp.offset = ltemp;
  const std::size_t T = sp.T, H = sp.H, n_even = sp.n_even;

  sp.time_buf = AllocReal(T);
  sp.spec_buf = AllocComplex(H + 1);
  if (!sp.time_buf || !sp.spec_buf) return InternalError("VMD: out of memory for FFT buffers");
  double* tb = sp.time_buf.get();
  for (std::size_t i = 0; i < ltemp; ++i) tb[i] = f[ltemp - 1 - i];
  std::copy(f.begin(), f.end(), tb + ltemp);
  for (std::size_t i = 0; i < ltemp; ++i) tb[ltemp + n_even + i] = f[n_even - 1 - i];

  {
    std::lock_guard<std::mutex> lock(FftwPlannerMutex());
    // FFTW_ESTIMATE does not touch the arrays and is deterministic run to run.
    sp.forward.reset(fftw_plan_dft_r2c_1d(static_cast<int>(T), tb, sp.spec_buf.get(), FFTW_ESTIMATE));
    sp.inverse.reset(fftw_plan_dft_c2r_1d(static_cast<int>(T), sp.spec_buf.get(), tb, FFTW_ESTIMATE));
  }
  if (!sp.forward || !sp.inverse) return InternalError("VMD: FFTW planning failed");
  fftw_execute(sp.forward.get());
  f.clear();
  f.shrink_to_fit();  // the working copy is no longer needed (the spectrum is)

  // f_hat_plus on the one-sided grid; the frequency grid exactly as vmdpy computes it:
  // freqs = arange(1, T+1)/T - 0.5 - 1/T, positive half = indices T/2 .. T-1.
  sp.f_re.resize(H);
  sp.f_im.resize(H);
  sp.freq.resize(H);
  sp.inv_T = 1.0 / static_cast<double>(T);
  for (std::size_t j = 0; j < H; ++j) {
    sp.f_re[j] = sp.spec_buf.get()[j][0];
    sp.f_im[j] = sp.spec_buf.get()[j][1];
    const double t = static_cast<double>(H + j + 1) / static_cast<double>(T);
    sp.freq[j] = (t - 0.5) - sp.inv_T;
  }
  return sp;
}

// Initial centre frequencies (cycles per sample): uniform, random (vmdpy's init = 2) or zero.
std::vector<double> InitialCenterFrequencies(const VmdOptions& opt, std::size_t n_even) {
  const int K = opt.num_modes;
  std::vector<double> omega(K, 0.0);
  if (opt.init == VmdInit::kUniform) {
    for (int k = 0; k < K; ++k) omega[k] = (0.5 / K) * k;
  } else if (opt.init == VmdInit::kRandom) {
    const double fs = 1.0 / static_cast<double>(n_even);
    const std::vector<double> u = NumpyRand(opt.seed, K);
    for (int k = 0; k < K; ++k) omega[k] = std::exp(std::log(fs) + (std::log(0.5) - std::log(fs)) * u[k]);
    std::sort(omega.begin(), omega.end());
  }
  if (opt.dc) omega[0] = 0.0;
  return omega;
}

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
      : spectrum(sp), opt(options), K(options.num_modes), H(sp.H), use_lambda(options.tau != 0.0),
        relative(options.stopping_rule == VmdStoppingRule::kRelative) {
    const std::size_t KH = static_cast<std::size_t>(K) * H;
    ua_re.assign(KH, 0.0);
    ua_im.assign(KH, 0.0);
    ub_re.assign(KH, 0.0);
    ub_im.assign(KH, 0.0);
    s_re.assign(H, 0.0);
    s_im.assign(H, 0.0);
    l_re.assign(use_lambda ? H : 0, 0.0);
    l_im.assign(use_lambda ? H : 0, 0.0);
    num_blocks = (H + kBlockBins - 1) / kBlockBins;
    sums.resize(num_blocks);
    for (auto& b : sums) {
      b.freq_power.assign(K, 0.0);
      b.power.assign(K, 0.0);
      b.diff.assign(K, 0.0);
      b.old_power.assign(K, 0.0);
    }
    old_re = ua_re.data();
    old_im = ua_im.data();
    new_re = ub_re.data();
    new_im = ub_im.data();
  }
  AdmmState(const AdmmState&) = delete;  // old_* / new_* point into the vectors
  AdmmState& operator=(const AdmmState&) = delete;

  const VmdSpectrum& spectrum;
  const VmdOptions& opt;
  const int K;
  const std::size_t H;
  const bool use_lambda;
  const bool relative;
  std::vector<double> ua_re, ua_im, ub_re, ub_im;  // storage of the two iterates
  std::vector<double> s_re, s_im;                  // accumulator
  std::vector<double> l_re, l_im;                  // lambda (empty when tau = 0)
  std::size_t num_blocks = 0;
  std::vector<BlockSums> sums;
  double* old_re = nullptr;  // the previous iterate (update n-1 during update n)
  double* old_im = nullptr;
  double* new_re = nullptr;  // the iterate being computed
  double* new_im = nullptr;
  std::vector<double> omega;       // centre frequencies of the newest iterate
  std::vector<double> omega_prev;  // centre frequencies of the iterate before `omega`
  int n = 0;                       // updates run
  double u_diff = 0.0;             // the stopping rule's value after update n
};

// Partial sums of mode k over bins [j0, j1) for Eq. (5) and the stopping rule, in 4 interleaved
// lanes (fixed order: deterministic, and free of the loop-carried dependency of a single
// accumulator).
void AccumulateModeSums(std::size_t j0, std::size_t j1, int k, const double* freq, const double* u_re,
                        const double* u_im, const double* o_re, const double* o_im, bool relative,
                        BlockSums& bs) {
  double fp4[4] = {0, 0, 0, 0}, p4[4] = {0, 0, 0, 0}, df4[4] = {0, 0, 0, 0}, op4[4] = {0, 0, 0, 0};
  auto accumulate = [&](std::size_t q, std::size_t l) {
    const double pw = u_re[q] * u_re[q] + u_im[q] * u_im[q];
    fp4[l] += freq[q] * pw;
    p4[l] += pw;
    const double dr = u_re[q] - o_re[q];
    const double di = u_im[q] - o_im[q];
    df4[l] += dr * dr + di * di;
    if (relative) op4[l] += o_re[q] * o_re[q] + o_im[q] * o_im[q];
  };
  std::size_t j = j0;
  for (; j + 4 <= j1; j += 4) {
    for (std::size_t l = 0; l < 4; ++l) accumulate(j + l, l);
  }
  for (std::size_t l = 0; j < j1; ++j, ++l) accumulate(j, l);
  bs.freq_power[k] = (fp4[0] + fp4[1]) + (fp4[2] + fp4[3]);
  bs.power[k] = (p4[0] + p4[1]) + (p4[2] + p4[3]);
  bs.diff[k] = (df4[0] + df4[1]) + (df4[2] + df4[3]);
  bs.old_power[k] = (op4[0] + op4[1]) + (op4[2] + op4[3]);
}

// Eq. (6) on bins [j0, j1): lambda += tau (sum_k u_k - f).
void DualAscent(AdmmState& st, std::size_t j0, std::size_t j1) {
  const std::size_t H = st.H;
  const double tau = st.opt.tau;
  const VmdSpectrum& sp = st.spectrum;
  for (std::size_t j = j0; j < j1; ++j) {
    double ar = st.new_re[j], ai = st.new_im[j];
    for (int k = 1; k < st.K; ++k) {
      ar += st.new_re[static_cast<std::size_t>(k) * H + j];
      ai += st.new_im[static_cast<std::size_t>(k) * H + j];
    }
    st.l_re[j] = st.l_re[j] + tau * (ar - sp.f_re[j]);
    st.l_im[j] = st.l_im[j] + tau * (ai - sp.f_im[j]);
  }
}

// One update of every mode on the bins of `block`, Gauss-Seidel over k (Eq. 4), then Eq. (6).
void UpdateBlock(AdmmState& st, std::size_t block, const std::vector<double>& om) {
  const std::size_t H = st.H;
  const int K = st.K;
  const VmdSpectrum& sp = st.spectrum;
  const std::size_t j0 = block * kBlockBins;
  const std::size_t j1 = std::min(H, j0 + kBlockBins);
  BlockSums& bs = st.sums[block];
  for (int k = 0; k < K; ++k) {
    const double* prev_re = (k == 0) ? st.old_re + static_cast<std::size_t>(K - 1) * H
                                     : st.new_re + static_cast<std::size_t>(k - 1) * H;
    const double* prev_im = (k == 0) ? st.old_im + static_cast<std::size_t>(K - 1) * H
                                     : st.new_im + static_cast<std::size_t>(k - 1) * H;
    const double* o_re = st.old_re + static_cast<std::size_t>(k) * H;
    const double* o_im = st.old_im + static_cast<std::size_t>(k) * H;
    double* u_re = st.new_re + static_cast<std::size_t>(k) * H;
    double* u_im = st.new_im + static_cast<std::size_t>(k) * H;
    // Eq. (4)
    UpdateMode(j0, j1, om[k], st.opt.alpha, sp.freq.data(), sp.f_re.data(), sp.f_im.data(),
               st.use_lambda ? st.l_re.data() : nullptr, st.use_lambda ? st.l_im.data() : nullptr, prev_re,
               prev_im, o_re, o_im, st.s_re.data(), st.s_im.data(), u_re, u_im);
    AccumulateModeSums(j0, j1, k, sp.freq.data(), u_re, u_im, o_re, o_im, st.relative, bs);
  }
  if (st.use_lambda) DualAscent(st, j0, j1);
}

// Adds the block sums in block order: Eq. (5) centre frequencies (into st.omega) and the value
// of the stopping rule (reference absolute, or Eq. 7 relative).
double UpdateCenterFrequencies(AdmmState& st) {
  const VmdOptions& opt = st.opt;
  const double eps = std::numeric_limits<double>::epsilon();  // np.spacing(1)
  double total = 0.0;
  for (int k = 0; k < st.K; ++k) {
    double fp = 0, p = 0, df = 0, op = 0;
    for (const BlockSums& b : st.sums) {
      fp += b.freq_power[k];
      p += b.power[k];
      df += b.diff[k];
      op += b.old_power[k];
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
  return opt.stopping_rule == VmdStoppingRule::kAbsolute ? std::abs(eps + total) : total;
}

// The ADMM loop: updates until the stopping rule holds or max_iterations - 1 updates were run
// (vmdpy's Niter convention). Afterwards `old_*` hold update n and `new_*` update n-1.
void RunAdmm(AdmmState& st, int threads) {
  const VmdOptions& opt = st.opt;
  const double eps = std::numeric_limits<double>::epsilon();  // np.spacing(1)
  st.u_diff = opt.tol + eps;
  st.n = 0;
  st.omega_prev = st.omega;
  std::vector<double> om_snapshot;
  WorkerPool pool(threads);
  const std::size_t num_blocks = st.num_blocks;
  const std::function<void(int)> round = [&](int t) {
    const std::size_t b0 = num_blocks * t / threads;
    const std::size_t b1 = num_blocks * (t + 1) / threads;
    for (std::size_t b = b0; b < b1; ++b) UpdateBlock(st, b, om_snapshot);
  };
  while (st.u_diff > opt.tol && st.n < opt.max_iterations - 1) {
    om_snapshot = st.omega;
    pool.Run(round);
    st.omega_prev = st.omega;
    st.u_diff = UpdateCenterFrequencies(st);
    ++st.n;
    std::swap(st.old_re, st.new_re);
    std::swap(st.old_im, st.new_im);
    if (opt.on_iteration) opt.on_iteration(st.n, st.u_diff);
  }
}

// Reconstruction (vmdpy): Hermitian spectrum with X[0] = Re U_0, X[j] = U_j, and the Nyquist
// bin = Re U_{H-1} (the reference copies conj(U_{H-1}) there; real(ifft) keeps its real part);
// inverse FFT / T, keep the middle N samples (unmirror). Consumes the spectrum's buffers.
Result<std::vector<std::vector<double>>> ReconstructModes(VmdSpectrum& sp, const double* out_re,
                                                          const double* out_im, int K, std::size_t n_in,
                                                          int threads) {
  const std::size_t T = sp.T, H = sp.H;
  std::vector<std::vector<double>> modes(K, std::vector<double>(n_in));
  const int ifft_threads = std::min(threads, K);
  std::vector<RealBuffer> t_bufs;
  std::vector<ComplexBuffer> s_bufs;
  // Thread 0 reuses the forward transform's buffers (same size and alignment as the plan's).
  t_bufs.push_back(std::move(sp.time_buf));
  s_bufs.push_back(std::move(sp.spec_buf));
  for (int t = 1; t < ifft_threads; ++t) {
    t_bufs.push_back(AllocReal(T));
    s_bufs.push_back(AllocComplex(H + 1));
    if (!t_bufs.back() || !s_bufs.back()) return InternalError("VMD: out of memory for FFT buffers");
  }
  RunThreads(ifft_threads, [&](int t) {
    fftw_complex* X = s_bufs[t].get();
    double* y = t_bufs[t].get();
    for (int k = t; k < K; k += ifft_threads) {
      const double* ur = out_re + static_cast<std::size_t>(k) * H;
      const double* ui = out_im + static_cast<std::size_t>(k) * H;
      for (std::size_t j = 0; j < H; ++j) {
        X[j][0] = ur[j];
        X[j][1] = ui[j];
      }
      X[0][1] = 0.0;
      X[H][0] = ur[H - 1];
      X[H][1] = 0.0;
      fftw_execute_dft_c2r(sp.inverse.get(), X, y);
      std::vector<double>& mode = modes[k];
      for (std::size_t i = 0; i < n_in; ++i) mode[i] = y[sp.offset + i] * sp.inv_T;
    }
  });
  return modes;
}

}  // namespace

bool VmdOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, const std::string& value, const char* what) {
    if (error) *error = "VmdOptions::" + field + " = " + value + ": " + what;
    return false;
  };
  auto str = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  if (num_modes < 1) return fail("num_modes", std::to_string(num_modes), "must be >= 1");
  if (!(alpha > 0) || !std::isfinite(alpha)) return fail("alpha", str(alpha), "must be > 0 and finite");
  if (!(tau >= 0) || !std::isfinite(tau)) return fail("tau", str(tau), "must be >= 0 and finite");
  if (!(tol > 0) || !std::isfinite(tol)) return fail("tol", str(tol), "must be > 0 and finite");
  if (max_iterations < 2) return fail("max_iterations", std::to_string(max_iterations), "must be >= 2");
  if (!(fs_hz > 0) || !std::isfinite(fs_hz)) return fail("fs_hz", str(fs_hz), "must be > 0 and finite");
  if (num_threads && *num_threads < 1) {
    return fail("num_threads", std::to_string(*num_threads), "must be >= 1 when set");
  }
  return true;
}

std::string VmdSummary::BriefReport() const {
  std::ostringstream os;
  os.precision(4);
  os << "VMD K=" << num_modes << " N=" << num_samples << ": "
     << (converged ? "converged after " : "did not converge in ") << iterations
     << " iterations (update " << final_update << (converged ? " <= tol" : " > tol") << ") in "
     << elapsed_s << " s on " << threads_used << " thread(s); centre frequencies [Hz]:";
  for (double f : center_frequency_hz) os << " " << f;
  return os.str();
}

Result<VmdResult> DecomposeVmd(std::span<const double> signal, const VmdOptions& opt) {
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

  Result<VmdSpectrum> spectrum = MirrorAndTransform(signal, opt.mirror_extension);
  if (!spectrum.ok()) return spectrum.error();
  VmdSpectrum& sp = *spectrum;

  AdmmState st(sp, opt);
  st.omega = InitialCenterFrequencies(opt, sp.n_even);
  const int threads = ChooseThreads(opt, static_cast<std::size_t>(K) * sp.H, st.num_blocks);
  RunAdmm(st, threads);

  // `old_*` hold update n and `new_*` update n-1 (or zeros when n = 1... the reference then
  // returns its all-zero initial iterate too).
  const bool last = opt.return_last_iterate;
  const double* out_re = last ? st.old_re : st.new_re;
  const double* out_im = last ? st.old_im : st.new_im;
  const std::vector<double>& out_omega = last ? st.omega : st.omega_prev;

  VmdResult result;
  Result<std::vector<std::vector<double>>> modes = ReconstructModes(sp, out_re, out_im, K, n_in, threads);
  if (!modes.ok()) return modes.error();
  result.modes = std::move(*modes);

  VmdSummary& s = result.summary;
  s.num_modes = K;
  s.num_samples = n_in;
  s.extended_length = sp.T;
  s.iterations = st.n;
  s.converged = st.u_diff <= opt.tol;
  s.final_update = st.u_diff;
  s.center_frequency_cycles_per_sample = out_omega;
  s.fs_hz = opt.fs_hz;
  for (double w : out_omega) s.center_frequency_hz.push_back(w * opt.fs_hz);
  s.threads_used = threads;
  s.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace gyrocomp
