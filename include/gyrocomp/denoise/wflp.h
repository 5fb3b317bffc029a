// WFLP: wavelet transform + forward linear prediction (paper Section 3.3, steps (1)-(3);
// method.md section 3).
//
//   (1) multi-level DWT of the signal (the mixed feature C2 in the pipeline);
//   (2) the approximation cA_L is filtered by the variable-step FLP (Eqs. 14-16, flp.h); the
//       detail coefficients are thresholded (universal threshold, soft: the golden rule of
//       wavelet_denoise.h) by default, or kept untouched, or zeroed;
//   (3) reconstruction with the same wavelet, cut to the input length.
// The FLP runs at the approximation's rate fs / 2^L, so its causal lag is multiplied by 2^L in
// the output: measure it (bandwidth.h) rather than guess it.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/denoise/flp.h"
#include "gyrocomp/core/status.h"
#include "gyrocomp/denoise/wavelet.h"
#include "gyrocomp/denoise/wavelet_denoise.h"

namespace gyrocomp {

// What WFLP does with the detail coefficients.
enum class DetailHandling {
  kThreshold,  // threshold rule of WflpOptions (default: universal, soft)
  kKeep,       // details untouched: only the approximation is filtered
  kZero,       // details removed: output = reconstruction of the filtered approximation only
};

// "threshold" | "keep" | "zero".
std::optional<DetailHandling> ParseDetailHandling(std::string_view name);
// DetailHandling -> "threshold" | "keep" | "zero".
const char* DetailHandlingName(DetailHandling handling);

// Wavelet, depth, FLP and detail handling of RunWflp.
struct WflpOptions {
  // Wavelet and depth (see WaveletDenoiseOptions for the meaning). Default db4, level 4.
  std::string wavelet = "db4";
  std::optional<int> level = 4;  // decomposition depth L; nullopt = DwtMaxLevel
  ExtensionMode extension = ExtensionMode::kSymmetric;  // signal extension (pywt "symmetric")
  // FLP on the approximation coefficients (its defaults: flp.h).
  FlpOptions flp;
  // What happens to the detail coefficients.
  DetailHandling details = DetailHandling::kThreshold;
  ThresholdRule threshold = ThresholdRule::kUniversal;  // rule when details = kThreshold
  ThresholdMode threshold_mode = ThresholdMode::kSoft;  // soft or hard, when kThreshold
  std::optional<double> noise_sigma;  // known white-noise SD; nullopt = MAD of cD1
  bool IsValid(std::string* error) const;  // checks flp too: "WflpOptions::flp.beta = 3: ..."
};

// What a WFLP run did.
struct WflpSummary {
  std::string wavelet;                                  // wavelet name used
  int level = 0;                                        // decomposition depth L used
  std::size_t num_samples = 0;                          // input length N
  std::size_t approximation_length = 0;                 // length of cA_L, the FLP's input
  DetailHandling details = DetailHandling::kThreshold;  // detail handling used
  FlpSummary flp;                       // FLP on cA_L
  WaveletDenoiseSummary thresholds;     // per-level sigma / threshold (when kThreshold)
  // "WFLP db4 level 4 (N samples, approximation M), details threshold; FLP ...; wavelet ..."
  std::string BriefReport() const;
};

// The denoised record and what happened.
struct WflpResult {
  std::vector<double> denoised;  // same length as the input
  WflpSummary summary;           // FLP and threshold details
};

// Errors: invalid options (kInvalidArgument), empty input or non-finite samples (kInvalidInput),
// level deeper than DwtMaxLevel for this length (kInvalidArgument).
Result<WflpResult> RunWflp(std::span<const double> x, const WflpOptions& options = {});
// Convenience: the denoised signal only (what the pipeline calls on the mixed feature).
Result<std::vector<double>> WflpDenoise(std::span<const double> x, const WflpOptions& options = {});

}  // namespace gyrocomp
