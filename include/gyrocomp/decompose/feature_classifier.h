// Classification of VMD modes into drift, mixed and noise-only features (paper Sections 3.2
// and 3.5): the end of step 2 of the pipeline.
//
// Each mode gets its sample entropy (SE) and centre frequency; a rule sorts it:
//   SE < drift_max_se                     -> drift   (C1: to the CS-SVR temperature model)
//   drift_max_se <= SE <= noise_min_se    -> mixed   (C2: to WFLP)
//   SE > noise_min_se                     -> noise   (discarded)
// optionally with a centre-frequency guard (a drift mode must also lie below
// drift_max_frequency_hz; otherwise it is mixed), and (keep_lowest_mode, default) the mode of
// lowest centre frequency is never noise.
//
// Two presets (docs/explanation/classification.md gives the design and the evidence):
//   - Paper(): the paper's thresholds 2 / 4.2. On the standard SE scale (m = 2, r = 0.2 SD of
//     each mode) white noise scores about 2.18, so "noise" (> 4.2) never fires: kept for
//     comparison with the paper only.
//   - Standard() (the default): thresholds calibrated on the standard SE scale.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/decompose/sample_entropy.h"
#include "gyrocomp/core/status.h"
#include "gyrocomp/decompose/vmd.h"

namespace gyrocomp {

// The class of a VMD mode, and the feature it is summed into: kDrift (C1, low sample entropy: to
// the temperature drift model), kMixed (C2: to WFLP), kNoise (C3, high sample entropy: discarded).
enum class FeatureClass { kDrift, kMixed, kNoise };

// "drift" | "mixed" | "noise".
const char* FeatureClassName(FeatureClass feature);

// The thresholds that sort modes into classes; Standard() by default, Paper() for comparison.
struct ClassifierOptions {
  // Name reported with the results ("standard", "paper", or "custom" when edited).
  std::string rule_name = "standard";
  // SE strictly below this: drift (dimensionless SE units). Paper: 2.0. Standard: 0.3.
  double drift_max_se = 0.3;
  // SE strictly above this: noise. Paper: 4.2. Standard: 0.5. >= drift_max_se.
  double noise_min_se = 0.5;
  // When set, a mode classed drift by SE whose centre frequency is at or above this (Hz) is
  // classed mixed instead (drift is slow by nature). nullopt: SE alone decides.
  std::optional<double> drift_max_frequency_hz;
  // The mode with the lowest centre frequency holds the mean of the signal (the bias, any
  // constant true rate) and the slowest drift: when true it is never classed noise (an SE above
  // noise_min_se makes it mixed), so that the classification cannot discard them. Standard: true;
  // paper: false (SE alone, as published).
  bool keep_lowest_mode = true;

  // The paper's preset: SE < 2 drift, 2..4.2 mixed, > 4.2 noise; no frequency guard.
  static ClassifierOptions Paper();
  // The default, calibrated on the standard SE scale (m = 2, r = 0.2 SD of each mode).
  static ClassifierOptions Standard();

  // "drift_max_se = 5 > noise_min_se = 4.2" etc.
  bool IsValid(std::string* error) const;
  // "standard: SE < 0.3 drift, 0.3...0.5 mixed, SE > 0.5 noise"
  std::string Describe() const;
};

// Input per mode.
struct ModeFeature {
  double sample_entropy = 0.0;                     // +inf allowed (no m+1 match): noise
  double center_frequency_cycles_per_sample = 0.0;  // picks the lowest mode (keep_lowest_mode)
  double center_frequency_hz = 0.0;  // compared with drift_max_frequency_hz
};

// The class given to one mode, with the features it was given from.
struct ModeClassification {
  int index = 0;  // 1-based mode number, algorithm order
  double sample_entropy = 0.0;                      // SE of the mode, as given
  double center_frequency_cycles_per_sample = 0.0;  // centre frequency, cycles per sample
  double center_frequency_hz = 0.0;                 // centre frequency, Hz
  FeatureClass feature = FeatureClass::kMixed;      // the class the rule gave
};

// The classes of all modes and the rule that gave them.
struct ClassificationResult {
  std::vector<ModeClassification> modes;  // one per input mode, in input order
  ClassifierOptions rule;   // the rule used (thresholds, name)
  std::string rule_text;    // rule.Describe()
  // "drift: modes 1; mixed: 2 3; noise: 4 5 6 (standard: SE < ...)"
  std::string BriefReport() const;
};

// Classifies modes from their SE and centre frequency. Errors: invalid options, a NaN SE.
Result<ClassificationResult> ClassifyModes(std::span<const ModeFeature> modes,
                                           const ClassifierOptions& options = ClassifierOptions::Standard());

// Convenience: SE of every mode of `vmd` (modes measured in parallel), then ClassifyModes.
// entropy_max_samples: measure SE on at most this many samples of each mode (its middle
// window; nullopt = all). A mode whose SE is undefined (B = 0, e.g. an all-zero mode) is an
// error.
Result<ClassificationResult> ClassifyVmdModes(const VmdResult& vmd,
                                              const SampleEntropyOptions& se_options = {},
                                              const ClassifierOptions& options = ClassifierOptions::Standard(),
                                              std::optional<std::size_t> entropy_max_samples = std::nullopt);

// The three features of Section 3.5: the sums of the modes of each class (same length as the
// modes; all-zero when a class is empty).
struct FeatureSignals {
  std::vector<double> drift;  // C1
  std::vector<double> mixed;  // C2
  std::vector<double> noise;  // C3
};
// Sums the modes of `vmd` into the three features by `classes` (mode index k+1 of `classes` is
// vmd.modes[k]).
FeatureSignals SumFeatures(const VmdResult& vmd, const ClassificationResult& classes);

}  // namespace gyrocomp
