// Classification of VMD modes into drift / mixed / noise features: see
// include/gyrocomp/feature_classifier.h and docs/explanation/classification.md (design and evidence).
#include "gyrocomp/decompose/feature_classifier.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "gyrocomp/core/format.h"
#include "gyrocomp/core/parallel.h"

namespace gyrocomp {
namespace {

std::span<const double> MiddleWindow(const std::vector<double>& x, std::optional<std::size_t> max_samples) {
  if (!max_samples || x.size() <= *max_samples) return x;
  const std::size_t start = (x.size() - *max_samples) / 2;
  return std::span<const double>(x).subspan(start, *max_samples);
}

}  // namespace

const char* FeatureClassName(FeatureClass feature) {
  switch (feature) {
    case FeatureClass::kDrift: return "drift";
    case FeatureClass::kMixed: return "mixed";
    case FeatureClass::kNoise: return "noise";
  }
  return "mixed";
}

ClassifierOptions ClassifierOptions::Paper() {
  ClassifierOptions o;
  o.rule_name = "paper";
  o.drift_max_se = 2.0;  // paper Section 4.2: "lower than 2 ... drift feature"
  o.noise_min_se = 4.2;  // "bigger than 4.2 ... nearly completely noise"
  o.drift_max_frequency_hz.reset();
  o.keep_lowest_mode = false;
  return o;
}

ClassifierOptions ClassifierOptions::Standard() {
  // Calibrated on the standard SE scale (m = 2, r = 0.2 SD of each mode) with VMD's reference
  // defaults (alpha = 2000): see docs/explanation/classification.md for the measurements behind each number.
  ClassifierOptions o;
  o.rule_name = "standard";
  o.drift_max_se = 0.3;
  o.noise_min_se = 0.5;
  o.drift_max_frequency_hz.reset();
  o.keep_lowest_mode = true;
  return o;
}

bool ClassifierOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = "ClassifierOptions::" + what;
    return false;
  };
  if (!std::isfinite(drift_max_se) || drift_max_se < 0) {
    return fail("drift_max_se = " + FormatNumber(drift_max_se) + ": must be finite and >= 0");
  }
  if (!std::isfinite(noise_min_se)) return fail("noise_min_se = " + FormatNumber(noise_min_se) + ": must be finite");
  if (noise_min_se < drift_max_se) {
    return fail("noise_min_se = " + FormatNumber(noise_min_se) + ": must be >= drift_max_se = " + FormatNumber(drift_max_se));
  }
  if (drift_max_frequency_hz && !(*drift_max_frequency_hz > 0)) {
    return fail("drift_max_frequency_hz = " + FormatNumber(*drift_max_frequency_hz) + ": must be > 0 when set");
  }
  return true;
}

std::string ClassifierOptions::Describe() const {
  std::ostringstream os;
  os << rule_name << ": SE < " << drift_max_se << " drift";
  if (drift_max_frequency_hz) os << " (if centre frequency < " << *drift_max_frequency_hz << " Hz)";
  os << ", " << drift_max_se << "..." << noise_min_se << " mixed, SE > " << noise_min_se << " noise";
  if (keep_lowest_mode) os << "; the lowest-frequency mode is never noise";
  return os.str();
}

std::string ClassificationResult::BriefReport() const {
  std::ostringstream os;
  for (FeatureClass c : {FeatureClass::kDrift, FeatureClass::kMixed, FeatureClass::kNoise}) {
    os << FeatureClassName(c) << ":";
    bool any = false;
    for (const ModeClassification& m : modes) {
      if (m.feature == c) {
        os << " " << m.index;
        any = true;
      }
    }
    if (!any) os << " -";
    os << "; ";
  }
  os << "(" << rule_text << ")";
  return os.str();
}

Result<ClassificationResult> ClassifyModes(std::span<const ModeFeature> modes, const ClassifierOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  ClassificationResult out;
  out.rule = options;
  out.rule_text = options.Describe();
  std::size_t lowest = 0;
  for (std::size_t k = 1; k < modes.size(); ++k) {
    if (modes[k].center_frequency_cycles_per_sample < modes[lowest].center_frequency_cycles_per_sample) lowest = k;
  }
  for (std::size_t k = 0; k < modes.size(); ++k) {
    const ModeFeature& f = modes[k];
    if (std::isnan(f.sample_entropy)) {
      return InvalidInput("mode " + std::to_string(k + 1) + ": sample entropy is undefined (NaN)");
    }
    ModeClassification c;
    c.index = static_cast<int>(k) + 1;
    c.sample_entropy = f.sample_entropy;
    c.center_frequency_cycles_per_sample = f.center_frequency_cycles_per_sample;
    c.center_frequency_hz = f.center_frequency_hz;
    // Section 4.2 of the paper: SE above the noise threshold -> noise-only, below the drift
    // threshold -> drift, in between -> mixed (thresholds: `options`).
    if (f.sample_entropy > options.noise_min_se) {
      c.feature = (options.keep_lowest_mode && k == lowest) ? FeatureClass::kMixed : FeatureClass::kNoise;
    } else if (f.sample_entropy < options.drift_max_se) {
      const bool slow = !options.drift_max_frequency_hz || f.center_frequency_hz < *options.drift_max_frequency_hz;
      c.feature = slow ? FeatureClass::kDrift : FeatureClass::kMixed;
    } else {
      c.feature = FeatureClass::kMixed;
    }
    out.modes.push_back(c);
  }
  return out;
}

Result<ClassificationResult> ClassifyVmdModes(const VmdResult& vmd, const SampleEntropyOptions& se_options,
                                              const ClassifierOptions& options,
                                              std::optional<std::size_t> entropy_max_samples) {
  std::string why;
  if (!se_options.IsValid(&why)) return InvalidArgument(why);
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (entropy_max_samples && *entropy_max_samples < 16) {
    return InvalidArgument("entropy_max_samples = " + std::to_string(*entropy_max_samples) + ": must be >= 16");
  }
  const std::size_t K = vmd.modes.size();
  if (vmd.summary.center_frequency_hz.size() != K || vmd.summary.center_frequency_cycles_per_sample.size() != K) {
    return InvalidArgument("ClassifyVmdModes: the VMD summary does not have one centre frequency per mode");
  }
  // Modes are measured in parallel, one SE per thread at a time (each SE single-threaded).
  const int threads = se_options.num_threads.value_or(DefaultItemThreads());
  SampleEntropyOptions one = se_options;
  one.num_threads = 1;
  std::vector<std::optional<Result<SampleEntropyResult>>> se(K);
  // SampleEntropyOptions::cancel: a Cancelled thrown on a worker reaches the caller
  // after the join (ParallelFor).
  ParallelFor(K, threads, [&](std::size_t k) { se[k] = SampleEntropy(MiddleWindow(vmd.modes[k], entropy_max_samples), one); });
  std::vector<ModeFeature> features(K);
  for (std::size_t k = 0; k < K; ++k) {
    const Result<SampleEntropyResult>& r = *se[k];
    if (!r.ok()) return Error{r.error().kind, "mode " + std::to_string(k + 1) + ": " + r.error().message};
    if (!r->defined) {
      return InvalidInput("mode " + std::to_string(k + 1) + ": sample entropy is undefined (no template match of length m)");
    }
    features[k].sample_entropy = r->sample_entropy;
    features[k].center_frequency_cycles_per_sample = vmd.summary.center_frequency_cycles_per_sample[k];
    features[k].center_frequency_hz = vmd.summary.center_frequency_hz[k];
  }
  return ClassifyModes(features, options);
}

FeatureSignals SumFeatures(const VmdResult& vmd, const ClassificationResult& classes) {
  const std::size_t n = vmd.modes.empty() ? 0 : vmd.modes.front().size();
  FeatureSignals out;
  out.drift.assign(n, 0.0);
  out.mixed.assign(n, 0.0);
  out.noise.assign(n, 0.0);
  for (const ModeClassification& m : classes.modes) {
    const std::size_t k = static_cast<std::size_t>(m.index - 1);
    assert(k < vmd.modes.size());
    std::vector<double>& dst = m.feature == FeatureClass::kDrift ? out.drift
                               : m.feature == FeatureClass::kMixed ? out.mixed
                                                                   : out.noise;
    const std::vector<double>& u = vmd.modes[k];
    for (std::size_t i = 0; i < n; ++i) dst[i] += u[i];
  }
  return out;
}

}  // namespace gyrocomp
