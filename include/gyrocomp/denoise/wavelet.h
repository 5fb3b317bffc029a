// Discrete wavelet transform (DWT) and its inverse, single- and multi-level, for any signal length,
// with PyWavelets' signal-extension modes and coefficient lengths (../golden/wavelet/ was made by
// PyWavelets 1.1.1 wavedec/waverec).
//
// Single level, filter length F, signal length N:
//   modes other than periodization: the signal is extended beyond both ends by the mode, and
//     cA[o] = sum_{j<F} dec_lo[j] x_ext(2o + 1 - j),  o = 0 .. floor((N + F - 1) / 2) - 1
//     (cD the same with dec_hi); the inverse keeps the 2 * len(cA) - F + 2 samples of the
//     upsampled convolution where every filter tap meets a coefficient;
//   periodization: an odd-length signal is first extended by repeating its last sample, then the
//     convolution is circular: ceil(N / 2) coefficients per band, and the inverse returns
//     2 * len(cA) samples.
// Multi-level (WaveDec / WaveRec): the approximation is decomposed again; WaveRec drops the extra
// sample an odd-length level adds, as PyWavelets does, and cuts the result to the original length.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/denoise/wavelet_filters.h"

namespace gyrocomp {

// Signal extension beyond the ends (PyWavelets' names).
enum class ExtensionMode {
  kSymmetric,      // half-sample symmetric: ... x1 x0 | x0 x1 ... x(N-1) | x(N-1) x(N-2) ...
  kReflect,        // whole-sample symmetric: ... x2 x1 | x0 x1 ... x(N-1) | x(N-2) ...
  kPeriodic,       // ... x(N-1) | x0 ... x(N-1) | x0 ...  (coefficient lengths as symmetric)
  kZero,           // zeros outside
  kConstant,       // first / last sample repeated
  kPeriodization,  // circular transform, ceil(N/2) coefficients per band
};

// "symmetric" | "reflect" | "periodic" | "zero" | "constant" | "periodization"; nullopt otherwise.
std::optional<ExtensionMode> ParseExtensionMode(std::string_view name);
// ExtensionMode -> its PyWavelets name (the names ParseExtensionMode accepts).
const char* ExtensionModeName(ExtensionMode mode);

// Number of coefficients per band of one DWT level of an n-sample signal (pywt.dwt_coeff_len).
std::size_t DwtCoeffLength(std::size_t n, std::size_t filter_length, ExtensionMode mode);

// Deepest useful level (pywt.dwt_max_level): floor(log2(n / (F - 1))), 0 when n < F - 1.
int DwtMaxLevel(std::size_t n, std::size_t filter_length);

// The coefficients of one DWT level.
struct DwtLevel {
  std::vector<double> approximation;  // cA
  std::vector<double> detail;         // cD
};
// One DWT level of `x` (pywt.dwt). Errors: empty signal (kInvalidInput).
Result<DwtLevel> Dwt(std::span<const double> x, const Wavelet& wavelet, ExtensionMode mode);

// Inverse of one level. cA and cD must have the same length; modes other than periodization need
// len >= F / 2 (kInvalidArgument otherwise, as PyWavelets).
Result<std::vector<double>> Idwt(std::span<const double> approximation, std::span<const double> detail,
                                 const Wavelet& wavelet, ExtensionMode mode);

// A multi-level decomposition. details[l - 1] holds the detail coefficients of level l, so
// details[0] is cD1 (finest, highest frequencies) and details.back() is cD_L, which has the length
// of approximation (cA_L). (PyWavelets' wavedec list is [cA_L, cD_L, ..., cD1].)
struct WaveletDecomposition {
  std::string wavelet;                             // name for MakeWavelet, e.g. "db4"
  ExtensionMode mode = ExtensionMode::kSymmetric;  // extension used at every level
  std::size_t signal_length = 0;                   // N of the decomposed signal
  std::vector<double> approximation;               // cA_L
  std::vector<std::vector<double>> details;        // cD1 .. cD_L
  // L, the number of detail levels.
  int level() const { return static_cast<int>(details.size()); }
};

// Multi-level DWT. level: nullopt = DwtMaxLevel(x.size(), F); 0 is allowed (approximation = x).
// Errors: empty signal (kInvalidInput); level < 0 or > DwtMaxLevel (kInvalidArgument, naming both).
Result<WaveletDecomposition> WaveDec(std::span<const double> x, const Wavelet& wavelet,
                                     ExtensionMode mode, std::optional<int> level = std::nullopt);

// Reconstruction with the wavelet named in `d` (any coefficients may have been modified), cut to
// d.signal_length. Errors: inconsistent coefficient lengths (kInvalidArgument).
Result<std::vector<double>> WaveRec(const WaveletDecomposition& d);
// The same with `wavelet` given (d.wavelet is not read).
Result<std::vector<double>> WaveRec(const WaveletDecomposition& d, const Wavelet& wavelet);

}  // namespace gyrocomp
