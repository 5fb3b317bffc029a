// Wavelet-threshold denoising (the baseline of the paper's Section 4.3.2) and the threshold rules
// WFLP shares with it.
//
// Default rule (exactly ../golden/wavelet/wavedec.json "denoise_rule", VisuShrink):
//   sigma = median(|cD1|) / 0.6745                      (MAD of the finest details)
//   thr   = sigma * sqrt(2 ln N)                        (N = signal length)
//   soft threshold on every detail level, approximation untouched, WaveRec, cut to N.
// Extras: hard thresholding; a level-dependent universal threshold (sigma estimated from each
// level's own details, for coloured noise); SURE (Donoho & Johnstone 1995, SureShrink with the
// hybrid fallback to the universal threshold when the level is sparse).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/denoise/wavelet.h"

namespace gyrocomp {

// Soft (shrink towards 0) or hard (keep or zero) thresholding; see ApplyThreshold.
enum class ThresholdMode { kSoft, kHard };
// How the threshold of each detail level is chosen.
enum class ThresholdRule {
  kUniversal,                // one threshold sigma * sqrt(2 ln N), sigma from cD1 (golden rule)
  kUniversalLevelDependent,  // sigma_l from each level's details, thr_l = sigma_l sqrt(2 ln N)
  kSure,                     // SureShrink per level (hybrid), sigma_l from each level's details
};

// "soft" | "hard"; "universal" | "universal-level" | "sure".
std::optional<ThresholdMode> ParseThresholdMode(std::string_view name);
// ThresholdMode -> "soft" | "hard".
const char* ThresholdModeName(ThresholdMode mode);
// "universal" | "universal-level" | "sure" -> ThresholdRule; nullopt otherwise.
std::optional<ThresholdRule> ParseThresholdRule(std::string_view name);
// ThresholdRule -> "universal" | "universal-level" | "sure".
const char* ThresholdRuleName(ThresholdRule rule);

// Soft: sign(x) max(|x| - thr, 0) (as pywt: x (1 - thr/|x|) clipped at 0). Hard: x where
// |x| >= thr, else 0. In place.
void ApplyThreshold(std::span<double> coefficients, double threshold, ThresholdMode mode);

// Robust noise SD of detail coefficients: median(|d|) / 0.6745 (0 for an empty span).
double MadSigma(std::span<const double> detail);

// Wavelet, depth and threshold rule of RunWaveletDenoise; the defaults are the golden rule.
struct WaveletDenoiseOptions {
  // Wavelet name (MakeWavelet): Daubechies 4 by default (the golden case and a common choice for
  // gyro signals: 4 vanishing moments, 8 taps).
  std::string wavelet = "db4";
  // Decomposition depth. nullopt = DwtMaxLevel (pywt's wavedec default). Default 4: at a sample
  // rate fs, details of levels 1-4 cover fs/32 .. fs/2, the approximation 0 .. fs/32.
  std::optional<int> level = 4;
  ExtensionMode extension = ExtensionMode::kSymmetric;  // signal extension (pywt "symmetric")
  ThresholdRule threshold = ThresholdRule::kUniversal;  // threshold rule (VisuShrink)
  ThresholdMode threshold_mode = ThresholdMode::kSoft;  // soft or hard thresholding
  // Known noise SD of the signal's white noise (signal units). nullopt = estimate by MAD.
  std::optional<double> noise_sigma;
  bool IsValid(std::string* error) const;  // "WaveletDenoiseOptions::level = -1: must be >= 0"
};

// What a wavelet denoising did, level by level.
struct WaveletDenoiseSummary {
  std::string wavelet;                                  // wavelet name used
  ExtensionMode extension = ExtensionMode::kSymmetric;  // extension used
  int level = 0;                                        // decomposition depth L used
  ThresholdRule rule = ThresholdRule::kUniversal;       // threshold rule used
  ThresholdMode mode = ThresholdMode::kSoft;            // soft or hard
  std::size_t num_samples = 0;                          // input length N
  // Per detail level l = 1..L (index l-1): noise SD used and threshold applied, and the fraction
  // of that level's coefficients set to zero.
  std::vector<double> sigma;
  std::vector<double> threshold;        // threshold applied to level l, signal units
  std::vector<double> fraction_zeroed;  // fraction of level l's coefficients set to 0
  // "wavelet db4/symmetric level 4, universal soft threshold, N samples; D1 sigma .. thr .. ..."
  std::string BriefReport() const;
};

// The denoised record and what happened.
struct WaveletDenoiseResult {
  std::vector<double> denoised;   // same length as the input
  WaveletDenoiseSummary summary;  // per-level sigma, threshold, fraction zeroed
};

// Thresholds the detail coefficients of `d` in place by the rule (signal length d.signal_length).
// Fills sigma/threshold/fraction_zeroed of *summary when given. Used by WaveletDenoise and WFLP.
Status ThresholdDetails(WaveletDecomposition* d, ThresholdRule rule, ThresholdMode mode,
                        std::optional<double> noise_sigma, WaveletDenoiseSummary* summary);

// Errors: invalid options (kInvalidArgument), empty or too-short signal for the level
// (kInvalidArgument naming the level and DwtMaxLevel), non-finite samples (kInvalidInput).
Result<WaveletDenoiseResult> RunWaveletDenoise(std::span<const double> x,
                                               const WaveletDenoiseOptions& options = {});
// Convenience: the denoised signal only.
Result<std::vector<double>> WaveletDenoise(std::span<const double> x,
                                           const WaveletDenoiseOptions& options = {});

}  // namespace gyrocomp
