// The VMD's transforms: see vmd_spectrum.h.
#include "vmd_spectrum.h"

#include <algorithm>
#include <cmath>
#include <system_error>

#include "vmd_threads.h"

namespace gyrocomp::vmd_internal {

std::mutex& FftwPlannerMutex() {
  static std::mutex mutex;
  return mutex;
}

namespace {

Plan PlanInverse(std::size_t T, fftw_complex* spec, double* time) {
  std::lock_guard<std::mutex> lock(FftwPlannerMutex());
  return Plan(fftw_plan_dft_c2r_1d(static_cast<int>(T), spec, time, FFTW_ESTIMATE));
}

// The inverse plan on a helper thread (the same planner call as on the caller's, after the
// forward plan as before: the same plan, the same bits). Planning does not touch the arrays
// (FFTW_ESTIMATE), which the caller keeps using; a planner call never overlaps another (the
// mutex). If no thread can be started, the plan is made here.
void StartInversePlan(VmdSpectrum& sp) {
  const std::size_t T = sp.T;
  fftw_complex* spec = sp.spec_buf.get();
  double* time = sp.time_buf.get();
  try {
    sp.inverse_pending = std::async(std::launch::async, [T, spec, time] { return PlanInverse(T, spec, time); });
  } catch (const std::system_error&) {
    sp.inverse = PlanInverse(T, spec, time);
  }
}

}  // namespace

fftw_plan_s* VmdSpectrum::InversePlan() {
  if (inverse_pending.valid()) inverse = inverse_pending.get();
  return inverse.get();
}

// Even working length, mirror extension f[ltemp-1..0], f, f[N-1..N-ltemp], forward FFT, and the
// one-sided spectrum with vmdpy's frequency grid.
Result<VmdSpectrum> MirrorAndTransform(std::span<const double> signal, bool mirror_extension) {
  VmdSpectrum sp;
  // Even working length (odd input: repeat the last sample; the reference drops it).
  // Normalise by a power of two (exact: every later operation commutes with it bit for bit, so
  // results are unchanged) so that extreme but finite inputs (|x| near 1e308 or 1e-300) neither
  // overflow in the transforms and squared sums nor lose precision to underflow.
  double max_abs = 0.0;
  for (double v : signal) max_abs = std::max(max_abs, std::abs(v));
  sp.scale_exp = max_abs > 0 ? std::ilogb(max_abs) : 0;
  std::vector<double> f(signal.size());
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = std::ldexp(signal[i], -sp.scale_exp);
  if (f.size() % 2) f.push_back(f.back());
  sp.n_in = signal.size();
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
  }
  if (!sp.forward) return InternalError("VMD: FFTW planning failed");
  StartInversePlan(sp);
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

// Reconstruction (vmdpy): Hermitian spectrum with X[0] = Re U_0, X[j] = U_j, and the Nyquist
// bin = Re U_{H-1} (the reference copies conj(U_{H-1}) there; real(ifft) keeps its real part);
// inverse FFT / T, keep the middle N samples (unmirror). Consumes the spectrum's buffers.
Result<std::vector<std::vector<double>>> ReconstructModes(VmdSpectrum& sp, const double* out_re,
                                                          const double* out_im, std::size_t stride, int K,
                                                          std::size_t n_in, int threads) {
  const std::size_t T = sp.T, H = sp.H;
  fftw_plan_s* inverse = sp.InversePlan();
  if (!inverse) return InternalError("VMD: FFTW planning failed");
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
  const double scale = std::ldexp(1.0, sp.scale_exp);
  RunThreads(ifft_threads, [&](int t) {
    fftw_complex* X = s_bufs[t].get();
    double* y = t_bufs[t].get();
    for (int k = t; k < K; k += ifft_threads) {
      const double* ur = out_re + static_cast<std::size_t>(k) * stride;
      const double* ui = out_im + static_cast<std::size_t>(k) * stride;
      for (std::size_t j = 0; j < H; ++j) {
        X[j][0] = ur[j];
        X[j][1] = ui[j];
      }
      X[0][1] = 0.0;
      X[H][0] = ur[H - 1];
      X[H][1] = 0.0;
      fftw_execute_dft_c2r(inverse, X, y);
      std::vector<double>& mode = modes[k];
      // Undo the normalisation: a multiplication by a power of two (exact).
      for (std::size_t i = 0; i < n_in; ++i) mode[i] = (y[sp.offset + i] * sp.inv_T) * scale;
    }
  });
  return modes;
}

}  // namespace gyrocomp::vmd_internal
