#include "gyrocomp/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <sstream>

namespace gyrocomp {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Status CheckInput(const PipelineInput& in, std::size_t min_samples) {
  const std::size_t n = in.rate_dps.size();
  if (!(in.fs_hz > 0.0) || !std::isfinite(in.fs_hz)) {
    return InvalidInput("sample rate " + std::to_string(in.fs_hz) + " Hz: must be > 0");
  }
  if (in.temp_c.size() != n) {
    return InvalidInput("rate has " + std::to_string(n) + " samples but temperature has " +
                        std::to_string(in.temp_c.size()) + ": the pipeline needs a temperature "
                        "for every rate sample");
  }
  if (!in.known_rate_dps.empty() && in.known_rate_dps.size() != n) {
    return InvalidInput("known rate has " + std::to_string(in.known_rate_dps.size()) +
                        " samples, rate has " + std::to_string(n));
  }
  if (n < min_samples) {
    return InvalidInput("record has " + std::to_string(n) + " samples; the parallel model needs "
                        "at least " + std::to_string(min_samples));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(in.rate_dps[i]) || !std::isfinite(in.temp_c[i])) {
      return InvalidInput("non-finite rate or temperature at sample " + std::to_string(i));
    }
  }
  return Status::Ok();
}

}  // namespace

bool PipelineOptions::IsValid(std::string* error) const {
  std::string e;
  if (!vmd.IsValid(&e)) { *error = "PipelineOptions::vmd: " + e; return false; }
  if (!entropy.IsValid(&e)) { *error = "PipelineOptions::entropy: " + e; return false; }
  if (!classifier.IsValid(&e)) { *error = "PipelineOptions::classifier: " + e; return false; }
  if (!wflp.IsValid(&e)) { *error = "PipelineOptions::wflp: " + e; return false; }
  if (!drift.IsValid(&e)) { *error = "PipelineOptions::drift: " + e; return false; }
  if (!allan.IsValid(&e)) { *error = "PipelineOptions::allan: " + e; return false; }
  if (entropy_max_samples && *entropy_max_samples < 100) {
    *error = "PipelineOptions::entropy_max_samples = " + std::to_string(*entropy_max_samples) +
             ": must be >= 100";
    return false;
  }
  if (num_threads && *num_threads < 1) {
    *error = "PipelineOptions::num_threads = " + std::to_string(*num_threads) + ": must be >= 1 when set";
    return false;
  }
  if (measure_bandwidth && bandwidth_segment_samples < 1024) {
    *error = "PipelineOptions::bandwidth_segment_samples = " +
             std::to_string(bandwidth_segment_samples) + ": must be >= 1024";
    return false;
  }
  if (measure_bandwidth && bandwidth_frequencies < 4) {
    *error = "PipelineOptions::bandwidth_frequencies = " + std::to_string(bandwidth_frequencies) +
             ": must be >= 4";
    return false;
  }
  return true;
}

std::string PipelineResult::BriefReport() const {
  std::ostringstream s;
  s << "parallel model, N=" << num_samples << " at " << fs_hz << " Hz; " << vmd.BriefReport()
    << "\nclasses:";
  for (const ModeReport& m : mode_reports) {
    s << " " << m.index << "=" << FeatureClassName(m.feature) << "(SE " << m.sample_entropy << ")";
  }
  if (drift_model) s << "\ndrift model: " << drift_model->summary.BriefReport();
  s << "\nARW " << allan_before.terms.arw_deg_per_sqrt_h.value_or(NAN) << " -> "
    << allan_after.terms.arw_deg_per_sqrt_h.value_or(NAN) << " deg/sqrt(h); ADEV min "
    << allan_before.terms.adev_min_deg_per_h << " -> " << allan_after.terms.adev_min_deg_per_h
    << " deg/h";
  if (bandwidth && bandwidth->bandwidth_hz) s << "; bandwidth " << *bandwidth->bandwidth_hz << " Hz";
  return s.str();
}

namespace {

void Report(const ProgressCallback& progress, const char* stage, double fraction) {
  if (progress) progress(stage, fraction);
}

bool AnyNonZero(std::span<const double> x) {
  return std::any_of(x.begin(), x.end(), [](double v) { return v != 0.0; });
}

// Step 1: VMD of the rate into K modes (Section 3.1, Eqs. 1-7).
Result<VmdResult> DecomposeIntoModes(const PipelineInput& input, const PipelineOptions& options,
                                     const ProgressCallback& progress, PipelineResult* out) {
  Report(progress, "vmd", 0.0);
  const auto t = Clock::now();
  VmdOptions vmd_options = options.vmd;
  vmd_options.fs_hz = input.fs_hz;
  if (progress) {
    vmd_options.on_iteration = [&](int iteration, double) {
      if (iteration % 10 == 0) {
        progress("vmd", static_cast<double>(iteration) / static_cast<double>(options.vmd.max_iterations));
      }
    };
  }
  Result<VmdResult> vmd = DecomposeVmd(input.rate_dps, vmd_options);
  if (!vmd) return vmd.error();
  out->timings_s["vmd"] = SecondsSince(t);
  out->vmd = vmd->summary;
  if (!vmd->summary.converged) {
    out->warnings.push_back("VMD stopped at max_iterations without meeting its tolerance (" +
                            vmd->summary.BriefReport() + ")");
  }
  Report(progress, "vmd", 1.0);
  return vmd;
}

// PipelineOptions::force_drift_mode: with no drift-like mode, the mode of lowest centre frequency
// becomes the drift feature C1.
void ForceDriftModeIfNone(const PipelineOptions& options, ClassificationResult* classes,
                          PipelineResult* out) {
  const bool has_drift = std::any_of(classes->modes.begin(), classes->modes.end(),
      [](const ModeClassification& m) { return m.feature == FeatureClass::kDrift; });
  if (has_drift || !options.force_drift_mode || classes->modes.empty()) return;
  auto lowest = std::min_element(classes->modes.begin(), classes->modes.end(),
      [](const ModeClassification& a, const ModeClassification& b) {
        return a.center_frequency_hz < b.center_frequency_hz;
      });
  lowest->feature = FeatureClass::kDrift;
  out->drift_mode_forced = true;
  out->warnings.push_back("no mode had a drift-like sample entropy; mode " +
                          std::to_string(lowest->index) +
                          " (lowest centre frequency) was taken as the drift feature");
}

// Step 2: sample entropy of each mode (Section 3.2, Eqs. 8-13, modes measured in parallel)
// and the drift (C1) / mixed (C2) / noise (C3) classes; the features are the sums of their modes.
Status ClassifyModesBySampleEntropy(const VmdResult& vmd, const PipelineOptions& options,
                                    const ProgressCallback& progress, PipelineResult* out) {
  Report(progress, "entropy", 0.0);
  const auto t = Clock::now();
  Result<ClassificationResult> classes =
      ClassifyVmdModes(vmd, options.entropy, options.classifier, options.entropy_max_samples);
  if (!classes) return classes.error();
  out->timings_s["entropy"] = SecondsSince(t);
  ForceDriftModeIfNone(options, &*classes, out);
  out->classification_rule = classes->rule_text;
  for (const ModeClassification& m : classes->modes) {
    out->mode_reports.push_back({m.index, m.center_frequency_hz, m.center_frequency_cycles_per_sample,
                                 m.sample_entropy, m.feature});
  }
  out->features = SumFeatures(vmd, *classes);
  Report(progress, "entropy", 1.0);
  return Status::Ok();
}

// Step 3, denoising branch (Section 3.3): WFLP on the mixed feature C2. `seconds` stays 0 when
// there is no mixed feature.
Result<WflpResult> DenoiseMixedFeature(std::span<const double> mixed, const WflpOptions& options,
                                       double* seconds) {
  const auto start = Clock::now();
  if (!AnyNonZero(mixed)) {  // no mixed mode: nothing to denoise
    WflpResult r;
    r.denoised.assign(mixed.size(), 0.0);
    return r;
  }
  Result<WflpResult> r = RunWflp(mixed, options);
  *seconds = SecondsSince(start);
  return r;
}

// Step 3, compensation branch (Section 3.4): the drift model (CS-SVR by default) of the drift
// feature C1, less any known applied rate, against temperature; its prediction model(T).
Status CompensateDriftFeature(const PipelineInput& input, const PipelineOptions& options,
                              const ProgressCallback& progress, PipelineResult* out) {
  const std::size_t n = input.rate_dps.size();
  Report(progress, "drift-fit", 0.0);
  auto t = Clock::now();
  std::vector<double> target = out->features.drift;
  if (!input.known_rate_dps.empty()) {
    for (std::size_t i = 0; i < n; ++i) target[i] -= input.known_rate_dps[i];
  }
  DriftFitOptions drift_options = options.drift;
  if (progress) {
    const int generations = drift_options.search.cuckoo.max_generations;
    drift_options.search.cuckoo.on_generation = [&progress, generations](int generation, double) {
      progress("drift-fit (cuckoo search)", static_cast<double>(generation) / generations);
    };
  }
  if (drift_options.target_name.empty() || drift_options.target_name == "rate_dps") {
    drift_options.target_name = "drift-mode";
  }
  const DriftInputs drift_inputs{input.temp_c, input.fs_hz};
  Result<DriftModel> model = FitDriftModel(drift_inputs, target, drift_options);
  out->timings_s["drift_fit"] = SecondsSince(t);
  Status status;
  if (!model) {
    status = model.error();
  } else {
    t = Clock::now();
    Result<std::vector<double>> predicted = model->Predict(drift_inputs);
    out->timings_s["drift_predict"] = SecondsSince(t);
    if (!predicted) {
      status = predicted.error();
    } else {
      out->predicted_drift_dps = std::move(*predicted);
      out->drift_model = std::move(*model);
    }
  }
  Report(progress, "drift-fit", 1.0);
  return status;
}

// Step 3 (Section 3.5, step 2): the mixed feature C2 denoised and the drift feature C1
// compensated, the two branches concurrently; the noise feature C3 is not used (discarded).
Status ProcessFeaturesInParallel(const PipelineInput& input, const PipelineOptions& options,
                                 const ProgressCallback& progress, PipelineResult* out) {
  // The task touches only its own locals and reads out->features.mixed, which nothing writes
  // until it is joined.
  double wflp_seconds = 0.0;
  const std::launch policy = options.num_threads == 1 ? std::launch::deferred : std::launch::async;
  auto wflp_task = std::async(policy, [&]() -> Result<WflpResult> {
    return DenoiseMixedFeature(out->features.mixed, options.wflp, &wflp_seconds);
  });

  out->predicted_drift_dps.assign(input.rate_dps.size(), 0.0);
  Status drift_status;
  if (AnyNonZero(out->features.drift)) {
    drift_status = CompensateDriftFeature(input, options, progress, out);
  } else {
    out->warnings.push_back("no drift feature: no temperature compensation was applied");
  }
  Result<WflpResult> wflp = wflp_task.get();
  out->timings_s["wflp"] = wflp_seconds;
  if (!drift_status) return drift_status.error();
  if (!wflp) return wflp.error();
  out->mixed_denoised = std::move(wflp->denoised);
  out->wflp = std::move(wflp->summary);
  return Status::Ok();
}

// Step 4: reconstruction. Output = WFLP(C2) + (C1 - model(T)); C3 discarded.
void Reconstruct(PipelineResult* out) {
  const std::size_t n = out->features.drift.size();
  out->compensated_dps.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    out->compensated_dps[i] =
        out->mixed_denoised[i] + (out->features.drift[i] - out->predicted_drift_dps[i]);
  }
}

// Step 5: Allan variance before and after (Section 4.3.1).
Status AnalyseAllanBeforeAfter(const PipelineInput& input, const PipelineOptions& options,
                               PipelineResult* out) {
  const auto t = Clock::now();
  Result<AllanResult> before = ComputeAllan(input.rate_dps, input.fs_hz, options.allan);
  if (!before) return before.error();
  Result<AllanResult> after = ComputeAllan(out->compensated_dps, input.fs_hz, options.allan);
  if (!after) return after.error();
  out->allan_before = std::move(*before);
  out->allan_after = std::move(*after);
  out->allan_before.axis = "raw";
  out->allan_after.axis = "compensated";
  out->timings_s["allan"] = SecondsSince(t);
  return Status::Ok();
}

// The processing the bandwidth is measured on: VMD of a segment, the run's mode classes (by mode
// index), WFLP on the mixed part (when the run had one), drift + denoised mixed; noise dropped.
SignalProcessing ReplayParallelModel(const VmdOptions& seg_vmd, std::vector<FeatureClass> class_of_mode,
                                     bool any_mixed, const WflpOptions& wflp_options) {
  return [seg_vmd, class_of_mode = std::move(class_of_mode), any_mixed,
          wflp_options](std::span<const double> x) -> Result<std::vector<double>> {
    Result<VmdResult> v = DecomposeVmd(x, seg_vmd);
    if (!v) return v.error();
    std::vector<double> drift(x.size(), 0.0), mixed(x.size(), 0.0);
    for (std::size_t k = 0; k < v->modes.size() && k < class_of_mode.size(); ++k) {
      std::vector<double>* dst = class_of_mode[k] == FeatureClass::kDrift ? &drift
                               : class_of_mode[k] == FeatureClass::kMixed ? &mixed : nullptr;
      if (!dst) continue;
      for (std::size_t i = 0; i < x.size(); ++i) (*dst)[i] += v->modes[k][i];
    }
    if (any_mixed) {
      Result<std::vector<double>> d = WflpDenoise(mixed, wflp_options);
      if (!d) return d.error();
      mixed = std::move(*d);
    }
    for (std::size_t i = 0; i < x.size(); ++i) drift[i] += mixed[i];
    return drift;
  };
}

// Effective bandwidth: replay VMD + the same classes + WFLP on a segment with test sines.
// A failure is a warning, not an error.
void MeasureEffectiveBandwidth(const PipelineInput& input, const PipelineOptions& options,
                               const ProgressCallback& progress, PipelineResult* out) {
  Report(progress, "bandwidth", 0.0);
  const auto t = Clock::now();
  const std::size_t n = input.rate_dps.size();
  const std::size_t seg = std::min(n, options.bandwidth_segment_samples);
  const std::span<const double> background = input.rate_dps.subspan((n - seg) / 2, seg);
  std::vector<FeatureClass> class_of_mode;
  for (const ModeReport& m : out->mode_reports) class_of_mode.push_back(m.feature);
  VmdOptions seg_vmd = options.vmd;
  seg_vmd.fs_hz = input.fs_hz;
  seg_vmd.on_iteration = nullptr;
  const SignalProcessing processing = ReplayParallelModel(
      seg_vmd, std::move(class_of_mode), AnyNonZero(out->features.mixed), options.wflp);
  BandwidthOptions bw;
  bw.fs_hz = input.fs_hz;
  bw.num_frequencies = options.bandwidth_frequencies;
  Result<BandwidthResult> measured = MeasureBandwidth(processing, background, bw);
  if (measured) {
    out->bandwidth = std::move(*measured);
  } else {
    out->warnings.push_back("bandwidth not measured: " + measured.error().message);
  }
  out->timings_s["bandwidth"] = SecondsSince(t);
  Report(progress, "bandwidth", 1.0);
}

// PipelineOptions::num_threads handed to every stage that has its own.
PipelineOptions WithThreads(const PipelineOptions& options) {
  PipelineOptions o = options;
  if (o.num_threads) {
    o.vmd.num_threads = *o.num_threads;
    o.entropy.num_threads = *o.num_threads;
    o.drift.search.cuckoo.num_threads = *o.num_threads;
  }
  return o;
}

}  // namespace

// The parallel model of Section 3.5 (Fig. 5), one named step per stage.
Result<PipelineResult> RunParallelModel(const PipelineInput& input, const PipelineOptions& given,
                                        const ProgressCallback& progress) {
  std::string why;
  if (!given.IsValid(&why)) return InvalidArgument(why);
  const PipelineOptions options = WithThreads(given);
  const std::size_t min_samples = std::max<std::size_t>(64, 4 * static_cast<std::size_t>(options.vmd.num_modes));
  if (Status s = CheckInput(input, min_samples); !s) return s.error();
  const auto t_total = Clock::now();

  PipelineResult out;
  out.fs_hz = input.fs_hz;
  out.num_samples = input.rate_dps.size();
  Result<VmdResult> vmd = DecomposeIntoModes(input, options, progress, &out);          // Step 1
  if (!vmd) return vmd.error();
  if (Status s = ClassifyModesBySampleEntropy(*vmd, options, progress, &out); !s) {   // Step 2
    return s.error();
  }
  if (Status s = ProcessFeaturesInParallel(input, options, progress, &out); !s) {     // Step 3
    return s.error();
  }
  Reconstruct(&out);                                                                  // Step 4
  if (Status s = AnalyseAllanBeforeAfter(input, options, &out); !s) return s.error();  // Step 5
  if (options.measure_bandwidth) MeasureEffectiveBandwidth(input, options, progress, &out);
  out.modes = std::move(vmd->modes);
  out.timings_s["total"] = SecondsSince(t_total);
  return out;
}

Result<SerialResult> RunSerialModel(const PipelineInput& input, const PipelineOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (Status s = CheckInput(input, 64); !s) return s.error();
  const auto start = Clock::now();
  SerialResult out;
  Result<std::vector<double>> denoised = WflpDenoise(input.rate_dps, options.wflp);
  if (!denoised) return denoised.error();
  out.denoised = std::move(*denoised);
  std::vector<double> target = out.denoised;
  if (!input.known_rate_dps.empty()) {
    for (std::size_t i = 0; i < target.size(); ++i) target[i] -= input.known_rate_dps[i];
  }
  const DriftInputs drift_inputs{input.temp_c, input.fs_hz};
  Result<DriftModel> model = FitDriftModel(drift_inputs, target, options.drift);
  if (!model) return model.error();
  Result<std::vector<double>> predicted = model->Predict(drift_inputs);
  if (!predicted) return predicted.error();
  out.predicted_drift_dps = std::move(*predicted);
  out.drift_model = std::move(*model);
  out.compensated_dps.resize(out.denoised.size());
  for (std::size_t i = 0; i < out.denoised.size(); ++i) {
    out.compensated_dps[i] = out.denoised[i] - out.predicted_drift_dps[i];
  }
  out.seconds = SecondsSince(start);
  return out;
}

}  // namespace gyrocomp
