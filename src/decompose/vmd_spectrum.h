// The VMD's transforms (internal to src/decompose/): the mirror-extended record's one-sided
// spectrum and the reconstruction of the modes from theirs (FFTW real transforms). Split from
// vmd.cc, which keeps the iteration.
#pragma once

#include <fftw3.h>

#include <cstddef>
#include <future>
#include <memory>
#include <mutex>
#include <new>
#include <span>
#include <vector>

#include "gyrocomp/core/status.h"

namespace gyrocomp::vmd_internal {

// Arrays the kernel streams start on a 64-byte boundary (a cache line, one 512-bit vector):
// std::vector's large blocks come from mmap at 16 bytes past a page, so every 512-bit access
// straddled two lines (measured: 0.59 vs 0.51 ns per bin-update without the stopping sums).
template <class T>
struct CacheAlignedAllocator {
  using value_type = T;
  static constexpr std::align_val_t kAlign{64};
  CacheAlignedAllocator() = default;
  template <class U>
  CacheAlignedAllocator(const CacheAlignedAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), kAlign)); }
  void deallocate(T* p, std::size_t) { ::operator delete(p, kAlign); }
  friend bool operator==(const CacheAlignedAllocator&, const CacheAlignedAllocator&) { return true; }
};
using AlignedVector = std::vector<double, CacheAlignedAllocator<double>>;

// FFTW planning is not thread-safe; execution of an existing plan is.
std::mutex& FftwPlannerMutex();

template <class T>
struct FftwFree {
  void operator()(T* p) const { fftw_free(p); }
};
using RealBuffer = std::unique_ptr<double, FftwFree<double>>;
using ComplexBuffer = std::unique_ptr<fftw_complex, FftwFree<fftw_complex>>;

inline RealBuffer AllocReal(std::size_t n) { return RealBuffer(fftw_alloc_real(n)); }
inline ComplexBuffer AllocComplex(std::size_t n) { return ComplexBuffer(fftw_alloc_complex(n)); }

struct PlanDeleter {
  void operator()(fftw_plan_s* p) const {
    std::lock_guard<std::mutex> lock(FftwPlannerMutex());
    fftw_destroy_plan(p);
  }
};
using Plan = std::unique_ptr<fftw_plan_s, PlanDeleter>;

// The mirror-extended, even-length signal's one-sided spectrum (f_hat_plus), its frequency grid
// and the FFT plans and buffers (reused for the inverse transforms).
struct VmdSpectrum {
  std::size_t n_in = 0;    // samples of the record
  std::size_t n_even = 0;  // even working length (odd input: the last sample repeated)
  std::size_t offset = 0;  // mirrored samples before the signal (ltemp)
  std::size_t T = 0;       // extended length
  std::size_t H = 0;       // one-sided bins 0..H-1
  int scale_exp = 0;       // the working signal is signal / 2^scale_exp (max |x| in [1, 2))
  double inv_T = 0.0;
  RealBuffer time_buf;
  ComplexBuffer spec_buf;
  Plan forward;
  // The inverse plan, made on a helper thread while the forward transform and the iterations run
  // (FFTW_ESTIMATE planning at T = 40,000 costs 3-4 ms, ~40x the transform; docs/explanation/performance.md):
  // InversePlan() waits for it. The future's destructor waits too, on every return path.
  std::future<Plan> inverse_pending;
  Plan inverse;
  fftw_plan_s* InversePlan();
  AlignedVector f_re, f_im;  // f_hat_plus
  AlignedVector freq;        // cycles per sample
};

// Even working length, mirror extension f[ltemp-1..0], f, f[N-1..N-ltemp], forward FFT, and the
// one-sided spectrum with vmdpy's frequency grid.
Result<VmdSpectrum> MirrorAndTransform(std::span<const double> signal, bool mirror_extension);

// Reconstruction (vmdpy): Hermitian spectrum with X[0] = Re U_0, X[j] = U_j, and the Nyquist
// bin = Re U_{H-1} (the reference copies conj(U_{H-1}) there; real(ifft) keeps its real part);
// inverse FFT / T, keep the middle N samples (unmirror). Consumes the spectrum's buffers.
// Mode k is read at out_* + k * stride (H bins).
Result<std::vector<std::vector<double>>> ReconstructModes(VmdSpectrum& sp, const double* out_re,
                                                          const double* out_im, std::size_t stride, int K,
                                                          std::size_t n_in, int threads);

}  // namespace gyrocomp::vmd_internal
