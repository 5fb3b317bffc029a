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

enum class ThresholdMode { kSoft, kHard };
enum class ThresholdRule {
  kUniversal,                // one threshold sigma * sqrt(2 ln N), sigma from cD1 (golden rule)
  kUniversalLevelDependent,  // sigma_l from each level's details, thr_l = sigma_l sqrt(2 ln N)
  kSure,                     // SureShrink per level (hybrid), sigma_l from each level's details
};

// "soft" | "hard"; "universal" | "universal-level" | "sure".
std::optional<ThresholdMode> ParseThresholdMode(std::string_view name);
const char* ThresholdModeName(ThresholdMode mode);
std::optional<ThresholdRule> ParseThresholdRule(std::string_view name);
const char* ThresholdRuleName(ThresholdRule rule);

// Soft: sign(x) max(|x| - thr, 0) (as pywt: x (1 - thr/|x|) clipped at 0). Hard: x where
// |x| >= thr, else 0. In place.
void ApplyThreshold(std::span<double> coefficients, double threshold, ThresholdMode mode);

// Robust noise SD of detail coefficients: median(|d|) / 0.6745 (0 for an empty span).
double MadSigma(std::span<const double> detail);

struct WaveletDenoiseOptions {
  // Wavelet name (MakeWavelet): Daubechies 4 by default (the golden case and a common choice for
  // gyro signals: 4 vanishing moments, 8 taps).
  std::string wavelet = "db4";
  // Decomposition depth. nullopt = DwtMaxLevel (pywt's wavedec default). Default 4: at a sample
  // rate fs, details of levels 1-4 cover fs/32 .. fs/2, the approximation 0 .. fs/32.
  std::optional<int> level = 4;
  ExtensionMode extension = ExtensionMode::kSymmetric;
  ThresholdRule threshold = ThresholdRule::kUniversal;
  ThresholdMode threshold_mode = ThresholdMode::kSoft;
  // Known noise SD of the signal's white noise (signal units). nullopt = estimate by MAD.
  std::optional<double> noise_sigma;
  bool IsValid(std::string* error) const;  // "WaveletDenoiseOptions::level = -1: must be >= 0"
};

struct WaveletDenoiseSummary {
  std::string wavelet;
  ExtensionMode extension = ExtensionMode::kSymmetric;
  int level = 0;
  ThresholdRule rule = ThresholdRule::kUniversal;
  ThresholdMode mode = ThresholdMode::kSoft;
  std::size_t num_samples = 0;
  // Per detail level l = 1..L (index l-1): noise SD used and threshold applied, and the fraction
  // of that level's coefficients set to zero.
  std::vector<double> sigma;
  std::vector<double> threshold;
  std::vector<double> fraction_zeroed;
  std::string BriefReport() const;
};

struct WaveletDenoiseResult {
  std::vector<double> denoised;
  WaveletDenoiseSummary summary;
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
