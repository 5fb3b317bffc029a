// Orthogonal wavelet filter banks: haar, db1-db20 (Daubechies), sym2-sym20 (symlets),
// coif1-coif5 (coiflets).
//
// Source of the numbers: transcribed from PyWavelets (pywt/_extensions/c/
// wavelets_coeffs.template.h, MIT licence, Copyright (c) 2006-2012 Filip Wasilewski, 2012- The
// PyWavelets Developers), the implementation ../golden/wavelet/ was made with: db and coif from its
// 60-digit tables (Hatano / Niemitalo), sym from its 17-digit table (see src/wavelet_filters.cc).
// One low-pass filter is stored per wavelet; the other three follow from the orthogonal
// quadrature-mirror relations, exactly as PyWavelets builds them:
//     rec_lo[k] = dec_lo[F-1-k]
//     dec_hi[k] = (-1)^(k+1) rec_lo[k]
//     rec_hi[k] = dec_hi[F-1-k]
// How the table is verified (src/wavelet_test.cc): every filter is checked for
//   sum(dec_lo) = sqrt(2), orthonormality sum_k h[k] h[k+2m] = delta(m), and the number of
//   vanishing moments of the high-pass filter (db N / sym N: N, coif N: 2N), to 1e-15 (db, coif)
//   and 1e-10 (sym: PyWavelets' own accuracy); the Daubechies filters are recomputed
//   independently by spectral factorisation in long double (agree to <= 7e-16); symlets have the
//   autocorrelation of the Daubechies filter of the same order; and haar, db2, db4, db8, sym8 and
//   coif3 reproduce ../golden/wavelet/ to 1e-12 (measured: <= 3e-17).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/status.h"

namespace gyrocomp {

// One orthogonal wavelet: its names and its four filters.
struct Wavelet {
  std::string name;          // "db4", "sym8", "coif3", "haar"
  std::string family;        // "db" | "sym" | "coif" | "haar"
  int order = 0;             // N of dbN / symN / coifN (haar: 1)
  int vanishing_moments = 0; // of the wavelet (high-pass): db/sym N, coif 2N, haar 1
  // Filters in PyWavelets' convention (convolution, not correlation); all have length
  // filter_length(). Decomposition low-pass.
  std::vector<double> dec_lo;
  std::vector<double> dec_hi;  // decomposition high-pass
  std::vector<double> rec_lo;  // reconstruction low-pass
  std::vector<double> rec_hi;  // reconstruction high-pass
  // F, the length of every filter.
  std::size_t filter_length() const { return dec_lo.size(); }
};

// The named wavelet, or kInvalidArgument naming the valid names. Names are case-sensitive as in
// PyWavelets; "haar" is db1 under another name.
Result<Wavelet> MakeWavelet(std::string_view name);

// Every name MakeWavelet accepts, in family order (haar, db1..db20, sym2..sym20, coif1..coif5).
std::vector<std::string> WaveletNames();

}  // namespace gyrocomp
