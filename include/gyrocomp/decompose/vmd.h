// Variational mode decomposition (paper Section 3.1, Eqs. 1-7): step 1 of the pipeline.
//
// The algorithm is Dragomiretskiy & Zosso (IEEE TSP 62(3), 2014) exactly as in their reference
// code and its Python port vmdpy (vrcarva/vmdpy), which made tests/golden/vmd/:
//   - the signal (even length) is mirror-extended by half its length on each side (T = 2N);
//   - the modes live on the one-sided spectrum (bins 0 .. T/2-1 of the extended signal; the
//     Nyquist bin and the negative half stay zero);
//   - Eq. (4) mode update (Wiener filter of the residual), Gauss-Seidel over modes;
//   - Eq. (5) centre frequency = power-weighted mean frequency of the mode's positive half;
//   - Eq. (6) dual ascent with step tau (tau = 0: no Lagrangian update);
//   - stop when sum_k ||u_k^{n} - u_k^{n-1}||^2 / T (+ machine epsilon) <= tol, or after
//     max_iterations - 1 updates (the reference's Niter convention);
//   - the first update always runs (vmdpy runs none when tol >= ~1 squared signal unit absorbs
//     its eps, and returns all-zero modes);
//   - like the reference, the modes and centre frequencies returned are those of update n-1
//     (the iterate *before* the one that met the criterion); VmdOptions::return_last_iterate
//     returns update n instead.
// Extreme but finite inputs: the signal is normalised internally by a power of two 2^e (max |x|
// in [1, 2); exact, so results are those of the unnormalised arithmetic wherever that does not
// overflow or underflow), tol of the absolute rule is scaled by 2^-2e and the machine epsilon of
// the rule is taken relative to the signal's scale (eps 2^2e squared units; vmdpy's eps for
// max |x| in [1, 2)). A signal scaled by 2^k with tol scaled by 2^2k gives the same iterations
// and exactly the scaled modes, up to |x| ~ 1e308 and down to subnormal values.
// Unlike vmdpy, memory is O(K x N) (no per-iteration history), FFTs are FFTW real transforms,
// and the per-bin work is split over threads (bit-identical results for any thread count).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/core/cancel.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp {

// Initial centre frequencies (vmdpy's `init`).
enum class VmdInit {
  kZero,     // 0: all omega_k = 0
  kUniform,  // 1: omega_k = k * 0.5 / K, k = 0..K-1 (cycles per sample)
  kRandom,   // 2: sorted exp(log(1/N) + (log 0.5 - log(1/N)) * U(0,1)), U from MT19937(seed)
             //    drawn as numpy's legacy np.random.rand (53-bit doubles from two 32-bit words)
};

// Stopping rule.
enum class VmdStoppingRule {
  // The reference code: eps + sum_k ||u_k^{n} - u_k^{n-1}||^2 / T <= tol, with the spectra
  // unnormalised (numpy FFT convention) and T the extended length.
  kAbsolute,
  // The paper's Eq. (7): sum_k ||u_k^{n} - u_k^{n-1}||^2 / ||u_k^{n-1}||^2 < tol (modes whose
  // previous norm is zero contribute 0).
  kRelative,
};

// Parameters of DecomposeVmd; the defaults are the paper's experiment and the reference code's.
struct VmdOptions {
  // Number of modes K (paper Section 3.1; K = 6 in its experiment). >= 1.
  int num_modes = 6;
  // Bandwidth penalty alpha of the reference code (Eq. 4 read with the correct denominator
  // 1 + alpha (w - w_k)^2, w in cycles per sample). Larger alpha: narrower modes. > 0.
  // (MATLAB's own `vmd` scales its penalty differently.)
  double alpha = 2000.0;
  // Dual-ascent time step tau of Eq. (6). 0 = no Lagrangian update (noise-slack). In [0, kMaxTau]
  // (larger steps diverge: vmd_options.cc).
  double tau = 0.0;
  static constexpr double kMaxTau = 2.0;  // largest tau accepted by IsValid
  // Convergence tolerance of the stopping rule (dimensionless for kRelative; squared signal
  // units for kAbsolute). > 0.
  double tol = 1e-7;
  // Keep mode 1 at 0 frequency (DC mode).
  bool dc = false;
  // Initial centre frequencies.
  VmdInit init = VmdInit::kUniform;
  // Warm start: the initial centre frequencies themselves (cycles per sample, K values in
  // [0, 0.5]), e.g. those of a VMD of an excerpt of the record. Set: overrides `init`.
  std::optional<std::vector<double>> initial_center_frequencies;
  // Seed of the MT19937 stream for VmdInit::kRandom (numpy np.random.seed semantics, 32 bits).
  std::uint32_t seed = 0;
  // The reference's Niter: at most max_iterations - 1 updates are run. >= 2.
  int max_iterations = 500;
  // Stopping rule: kAbsolute (the reference code's, default) or kRelative (the paper's Eq. 7).
  VmdStoppingRule stopping_rule = VmdStoppingRule::kAbsolute;
  // Mirror-extend the signal by N/2 samples on each side (reference behaviour). Off: the
  // signal is decomposed as is (T = N), which wraps its ends around.
  bool mirror_extension = true;
  // Return update n (the last) instead of update n-1 (reference behaviour).
  bool return_last_iterate = false;
  // Acceleration of the centre frequencies for long records (the reference iteration stalls above
  // ~100k samples; docs/explanation/performance.md, "Long records: centre-frequency extrapolation"). Every
  // `omega_extrapolation_period` updates (>= 3), each w_k whose last three values w0, w1, w2
  // approach a limit geometrically (r = (w2 - w1) / (w1 - w0) in (0, 0.995)) is moved to the Aitken
  // limit w2 + (w2 - w1) r / (1 - r), clamped to [0, 0.5]; the modes follow in the next updates. A
  // fixed point of the reference iteration is one of this one too (there the differences vanish),
  // so it converges to the same decomposition, in ~4.5x fewer updates (docs/explanation/performance.md), but
  // its path, iteration count and where within tol it stops differ from vmdpy's. Applied only to
  // records of at least `omega_extrapolation_min_samples` samples, so shorter ones follow the
  // reference exactly. nullopt = never (the reference iteration at every length).
  std::optional<int> omega_extrapolation_period = 5;
  // Shortest record (samples N) the extrapolation is applied to; shorter ones follow vmdpy.
  std::size_t omega_extrapolation_min_samples = 100000;
  // Sample rate in Hz, used only to express the centre frequencies in Hz. > 0.
  double fs_hz = 1.0;
  // Worker threads for the per-bin updates and the final inverse FFTs. nullopt = automatic
  // (hardware concurrency, at most 2 here, and 1 for small problems where threads cost more
  // than they save). Results are bit-identical for any value.
  std::optional<int> num_threads;
  // Called after every update with the update count and the stopping quantity (for progress
  // displays), or NaN on updates that skip the stopping-rule sums (far from tol, K <= 8, without
  // the centre-frequency extrapolation: the sums are computed only where the rule could be met).
  // Each update is reported once; when a run is repeated internally, updates past the returned
  // count may have been reported. Empty: not called. Does not change the result.
  std::function<void(int iteration, double update)> on_iteration;
  // Polled before every ADMM update on the calling thread: once cancelled,
  // DecomposeVmd throws Cancelled (the worker pool joins in its destructor). nullptr: not polled.
  const CancellationToken* cancel = nullptr;
  // Largest working set DecomposeVmd may allocate, bytes (K modes x N bins x two complex iterates
  // and the accumulator, ~48 K N bytes, plus the modes returned). Checked before allocating: a
  // larger problem is refused with the estimate, never a std::bad_alloc. 8 GiB.
  std::size_t max_memory_bytes = std::size_t{8} << 30;

  // Returns false and a message naming the field ("VmdOptions::alpha = -1: must be > 0").
  bool IsValid(std::string* error) const;
};

// What happened.
struct VmdSummary {
  int num_modes = 0;               // K
  std::size_t num_samples = 0;     // N of the input
  std::size_t extended_length = 0; // T: length of the (mirror-extended, even) working signal
  // Number of updates run (vmdpy's final loop counter n; the golden `iterations`).
  int iterations = 0;
  // True when the stopping rule was met before max_iterations.
  bool converged = false;
  // The last value of the stopping quantity (the one compared with tol), in tol's units; for the
  // absolute rule it saturates at the largest double when the squared signal scale is not
  // representable (|x| above ~1e154).
  double final_update = 0.0;
  // Centre frequency of each returned mode, in the algorithm's order (mode k started from the
  // k-th initial frequency): cycles per sample (0 .. 0.5) and Hz (= cycles per sample * fs_hz).
  // Eq. (5) of the returned modes, never an extrapolated value (omega_extrapolation_period).
  std::vector<double> center_frequency_cycles_per_sample;
  std::vector<double> center_frequency_hz;  // the same in Hz
  double fs_hz = 1.0;    // VmdOptions::fs_hz used for the Hz values
  int threads_used = 1;  // worker threads of the per-bin updates and inverse FFTs
  // The centre-frequency extrapolation period applied (VmdOptions::omega_extrapolation_period;
  // nullopt: the reference iteration, e.g. for a record shorter than its min_samples).
  std::optional<int> omega_extrapolation_period;
  double elapsed_s = 0.0;  // wall-clock time of DecomposeVmd
  // "VMD K=6 N=4000: converged after 193 iterations (update 8.1e-08 <= tol 1e-07) in 0.021 s;
  //  centre frequencies [Hz]: 0.0003 0.0736 ..."
  std::string BriefReport() const;
};

// The modes and what happened.
struct VmdResult {
  // modes[k][i]: mode k (algorithm order), sample i; K vectors of N samples.
  std::vector<std::vector<double>> modes;
  VmdSummary summary;  // iterations, convergence, centre frequencies, timing
};

// Decomposes `signal` (deg/s or any unit; the modes carry the same unit) into K modes.
// Errors (kInvalidArgument / kInvalidInput): invalid options, fewer than 4 samples, a
// non-finite sample. An odd-length input is decomposed with its last sample repeated once (the
// reference drops it instead) and the modes are cut back to N samples. Not converging within
// max_iterations is not an error: see summary.converged.
Result<VmdResult> DecomposeVmd(std::span<const double> signal, const VmdOptions& options = {});

}  // namespace gyrocomp
