#include "gyrocomp/pipeline/compare.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <sstream>

#include "gyrocomp/denoise/flp.h"
#include "gyrocomp/denoise/wavelet_denoise.h"

namespace gyrocomp {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double Rms(std::span<const double> a, std::span<const double> b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s / static_cast<double>(a.size()));
}

// Allan figures of a full output record (already analysed: `a`), and its error against the true
// rate when known.
void SetOutputMetrics(const AllanResult& a, std::span<const double> out, const ComparisonTruth& truth,
                      MethodRow* row) {
  row->arw_deg_per_sqrt_h = a.terms.arw_deg_per_sqrt_h;
  row->adev_min_deg_per_h = a.terms.adev_min_deg_per_h;
  row->bias_instability_deg_per_h = a.terms.bias_instability_deg_per_h;
  if (!truth.true_rate_dps.empty()) row->rmse_vs_true_rate_dps = Rms(out, truth.true_rate_dps);
}

// The same for an output not analysed yet.
Status AddOutputMetrics(std::span<const double> out, const PipelineInput& input,
                        const ComparisonTruth& truth, const AllanOptions& allan, MethodRow* row) {
  Result<AllanResult> a = ComputeAllan(out, input.fs_hz, allan);
  if (!a) return a.error();
  SetOutputMetrics(*a, out, truth, row);
  return Status::Ok();
}

std::vector<double> Combine(std::span<const double> mixed_part, std::span<const double> drift,
                            std::span<const double> predicted) {
  std::vector<double> out(mixed_part.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = mixed_part[i] + (drift[i] - predicted[i]);
  return out;
}

// What every comparison reads: CompareMethods' arguments, validated.
struct CompareArgs {
  const PipelineInput& input;
  const PipelineResult& parallel;
  const ComparisonTruth& truth;
  const ComparisonOptions& options;
  const PipelineOptions& po;  // options.pipeline
};

// The background a processing's bandwidth is measured on: the middle segment of `x`.
std::span<const double> MiddleSegment(std::span<const double> x, std::size_t max_samples) {
  const std::size_t n = x.size();
  const std::size_t seg = std::min(n, max_samples);
  return x.subspan((n - seg) / 2, seg);
}

struct Denoiser {
  std::string name;
  SignalProcessing run;  // empty: the mixed feature as is
};

// Section 4.3.2 (Figs. 14-15): nothing, wavelet threshold, FLP and WFLP, with the run's settings.
std::vector<Denoiser> DenoisersToCompare(const WflpOptions& wflp) {
  WaveletDenoiseOptions wavelet;
  wavelet.wavelet = wflp.wavelet;
  wavelet.level = wflp.level;
  wavelet.extension = wflp.extension;
  wavelet.threshold = wflp.threshold;
  wavelet.threshold_mode = wflp.threshold_mode;
  const std::string level = wflp.level ? std::to_string(*wflp.level) : std::string("max");
  return {
      {"none (mixed feature kept as is)", {}},
      {"wavelet threshold (" + wflp.wavelet + ", level " + level + ", universal " +
           (wflp.threshold_mode == ThresholdMode::kSoft ? "soft" : "hard") + ")",
       [wavelet](std::span<const double> x) { return WaveletDenoise(x, wavelet); }},
      {"FLP (order " + std::to_string(wflp.flp.order) + ")",
       [flp = wflp.flp](std::span<const double> x) { return FlpDenoise(x, flp); }},
      {"WFLP (" + wflp.wavelet + ", level " + level + ", FLP order " +
           std::to_string(wflp.flp.order) + ")",
       [wflp](std::span<const double> x) { return WflpDenoise(x, wflp); }},
  };
}

// The denoiser's effective bandwidth (or why it has none) into row->bandwidth_hz / row->note.
void SetDenoiserBandwidth(const Denoiser& d, std::span<const double> background, const CompareArgs& a,
                          MethodRow* row) {
  if (!d.run) {
    row->note = "denoiser bandwidth: the full band";
    return;
  }
  BandwidthOptions bw;
  bw.fs_hz = a.input.fs_hz;
  bw.num_frequencies = a.po.bandwidth_frequencies;
  Result<BandwidthResult> b = MeasureBandwidth(d.run, background, bw);
  if (b) {
    row->bandwidth_hz = b->bandwidth_hz;
    if (!b->bandwidth_hz) row->note = "gain above -3 dB up to " + std::to_string(b->max_frequency_hz) + " Hz";
  } else {
    row->note = "bandwidth not measured: " + b.error().message;
  }
}

// The denoisers on the mixed feature C2, each output recombined with the compensated drift feature.
Status CompareDenoisers(const CompareArgs& a, ComparisonResult* result) {
  const PipelineResult& parallel = a.parallel;
  // The denoisers are compared on the mixed feature C2 (the paper). When no mode was classified
  // mixed, C2 is empty and the comparison would be void: they get C2 + C3 (everything but the
  // drift feature) instead, and every row says so.
  const bool mixed_empty = std::all_of(parallel.features.mixed.begin(), parallel.features.mixed.end(),
                                       [](double v) { return v == 0.0; });
  std::vector<double> mixed = parallel.features.mixed;
  if (mixed_empty) {
    for (std::size_t i = 0; i < mixed.size(); ++i) mixed[i] += parallel.features.noise[i];
  }
  const std::span<const double> background = MiddleSegment(mixed, a.options.bandwidth_segment_samples);
  for (const Denoiser& d : DenoisersToCompare(a.po.wflp)) {
    MethodRow row;
    row.group = "denoising";
    row.method = d.name;
    const auto start = Clock::now();
    std::vector<double> denoised = mixed;
    if (d.run) {
      Result<std::vector<double>> r = d.run(mixed);
      if (!r) return r.error();
      denoised = std::move(*r);
    }
    row.seconds = SecondsSince(start);
    if (Status s = AddOutputMetrics(Combine(denoised, parallel.features.drift, parallel.predicted_drift_dps),
                                    a.input, a.truth, a.po.allan, &row);
        !s) {
      return s.error();
    }
    SetDenoiserBandwidth(d, background, a, &row);
    row.note += row.note.empty() ? "" : "; ";
    row.note += mixed_empty ? "no mixed mode: denoiser applied to mixed + noise features; output = that + "
                              "compensated drift feature"
                            : "output = denoised mixed feature + compensated drift feature";
    result->rows.push_back(std::move(row));
  }
  return Status::Ok();
}

struct DriftCandidate {
  std::string name;
  DriftFitOptions fit;
};

// Section 4.3.3 (Fig. 16) and the baselines: poly(T), poly(T, dT/dt), SVR with LIBSVM's defaults
// and (optionally) grid-searched SVR, besides the run's own model.
std::vector<DriftCandidate> DriftModelsToCompare(const DriftFitOptions& drift, bool grid_search) {
  std::vector<DriftCandidate> candidates;
  DriftFitOptions base = drift;
  base.target_name = "drift-mode";
  DriftFitOptions f = base;
  f.model = DriftModelKind::kPolynomial;
  f.inputs = DriftInputSet::kTemp;
  candidates.push_back({"poly(T), degree " + std::to_string(f.polynomial.degree), f});
  f.inputs = DriftInputSet::kTempAndRate;
  candidates.push_back({"poly(T, dT/dt), degree " + std::to_string(f.polynomial.degree) + " + " +
                            std::to_string(f.polynomial.dtemp_degree),
                        f});
  f = base;
  f.model = DriftModelKind::kSvr;
  f.svr = SvrOptions{};  // LIBSVM's defaults (C = 1, gamma = 1/num_inputs, epsilon = 0.1)
  f.svr.scaling = base.svr.scaling;
  candidates.push_back({"SVR, LIBSVM defaults", f});
  if (grid_search) {
    f = base;
    f.model = DriftModelKind::kGridSvr;
    candidates.push_back({"SVR, grid search (same budget as CS)", f});
  }
  return candidates;
}

// One drift model's row. `parallel_run`: the row of the parallel run's own model, whose output
// and Allan analysis the run already has.
Status AddDriftModelRow(const std::string& name, const DriftModel& model, const std::vector<double>& pred,
                        double seconds, bool parallel_run, const CompareArgs& a, ComparisonResult* result) {
  MethodRow row;
  row.group = "drift";
  row.method = name;
  row.seconds = seconds;
  row.drift_cv_rmse_dps = model.summary.cv_rmse;
  if (!a.truth.true_drift_dps.empty()) row.drift_rmse_vs_truth_dps = Rms(pred, a.truth.true_drift_dps);
  row.note = "in-sample (fitted on this record)";
  if (parallel_run) {
    SetOutputMetrics(a.parallel.allan_after, a.parallel.compensated_dps, a.truth, &row);
  } else if (Status s = AddOutputMetrics(Combine(a.parallel.mixed_denoised, a.parallel.features.drift, pred),
                                         a.input, a.truth, a.po.allan, &row);
             !s) {
    return s;
  }
  result->rows.push_back(std::move(row));
  return Status::Ok();
}

// The drift models of the drift feature C1 (less any known applied rate) against temperature,
// each fitted and compensated in-sample, then the parallel run's own model.
Status CompareDriftModels(const CompareArgs& a, ComparisonResult* result) {
  const PipelineResult& parallel = a.parallel;
  std::vector<double> target = parallel.features.drift;
  if (!a.input.known_rate_dps.empty()) {
    for (std::size_t i = 0; i < target.size(); ++i) target[i] -= a.input.known_rate_dps[i];
  }
  const DriftInputs drift_inputs{a.input.temp_c, a.input.fs_hz};
  for (const DriftCandidate& c : DriftModelsToCompare(a.po.drift, a.options.grid_search)) {
    const auto start = Clock::now();
    Result<DriftModel> model = FitDriftModel(drift_inputs, target, c.fit);
    if (!model) return model.error();
    Result<std::vector<double>> pred = model->Predict(drift_inputs);
    if (!pred) return pred.error();
    if (Status s = AddDriftModelRow(c.name, *model, *pred, SecondsSince(start), false, a, result); !s) {
      return s.error();
    }
  }
  if (!parallel.drift_model) return Status::Ok();
  return AddDriftModelRow(
      std::string(DriftModelKindName(parallel.drift_model->kind)) + " (the parallel run's model)",
      *parallel.drift_model, parallel.predicted_drift_dps,
      parallel.timings_s.count("drift_fit") ? parallel.timings_s.at("drift_fit") : 0.0, true, a, result);
}

MethodRow RawSchemeRow(const CompareArgs& a) {
  MethodRow raw;
  raw.group = "scheme";
  raw.method = "raw (no processing)";
  SetOutputMetrics(a.parallel.allan_before, a.input.rate_dps, a.truth, &raw);
  raw.note = "full band";
  return raw;
}

// The serial scheme the paper argues against: WFLP on the whole record, then one drift model.
Result<MethodRow> SerialSchemeRow(const CompareArgs& a) {
  const PipelineResult& parallel = a.parallel;
  MethodRow serial;
  serial.group = "scheme";
  serial.method = "serial: WFLP on the record, then " + std::string(DriftModelKindName(a.po.drift.model));
  PipelineOptions serial_options = a.po;
  const bool reuse = a.options.serial_reuses_parallel_parameters && parallel.drift_model &&
                     parallel.drift_model->summary.C && parallel.drift_model->summary.gamma;
  if (reuse) {
    const DriftFitSummary& ps = parallel.drift_model->summary;
    serial_options.drift.model = DriftModelKind::kSvr;
    serial_options.drift.svr.C = *ps.C;
    serial_options.drift.svr.gamma = *ps.gamma;
    serial_options.drift.svr.sigma.reset();
    if (ps.epsilon) serial_options.drift.svr.epsilon = *ps.epsilon;
    serial.note = "SVR with the parameters the parallel run's search chose (no second search)";
  }
  Result<SerialResult> s = RunSerialModel(a.input, serial_options);
  if (!s) return s.error();
  serial.seconds = s->seconds;
  {  // The serial scheme's bandwidth is WFLP's on the raw record.
    BandwidthOptions bw;
    bw.fs_hz = a.input.fs_hz;
    bw.num_frequencies = a.po.bandwidth_frequencies;
    Result<BandwidthResult> b = MeasureBandwidth(
        [wflp = a.po.wflp](std::span<const double> x) { return WflpDenoise(x, wflp); },
        MiddleSegment(a.input.rate_dps, a.options.bandwidth_segment_samples), bw);
    if (b) serial.bandwidth_hz = b->bandwidth_hz;
  }
  if (!a.truth.true_drift_dps.empty()) {
    serial.drift_rmse_vs_truth_dps = Rms(s->predicted_drift_dps, a.truth.true_drift_dps);
  }
  if (Status st = AddOutputMetrics(s->compensated_dps, a.input, a.truth, a.po.allan, &serial); !st) {
    return st.error();
  }
  return serial;
}

// The paper's parallel model (Section 3.5): the run itself.
MethodRow ParallelSchemeRow(const CompareArgs& a) {
  const PipelineResult& parallel = a.parallel;
  MethodRow par;
  par.group = "scheme";
  par.method = "parallel: VMD-SE, WFLP | " + std::string(DriftModelKindName(a.po.drift.model)) + " (the paper)";
  par.seconds = parallel.timings_s.count("total") ? parallel.timings_s.at("total") : 0.0;
  if (parallel.bandwidth) par.bandwidth_hz = parallel.bandwidth->bandwidth_hz;
  if (!a.truth.true_drift_dps.empty()) {
    par.drift_rmse_vs_truth_dps = Rms(parallel.predicted_drift_dps, a.truth.true_drift_dps);
  }
  SetOutputMetrics(parallel.allan_after, parallel.compensated_dps, a.truth, &par);
  return par;
}

// Raw vs serial vs parallel.
Status CompareSchemes(const CompareArgs& a, ComparisonResult* result) {
  result->rows.push_back(RawSchemeRow(a));
  Result<MethodRow> serial = SerialSchemeRow(a);
  if (!serial) return serial.error();
  result->rows.push_back(std::move(*serial));
  result->rows.push_back(ParallelSchemeRow(a));
  return Status::Ok();
}

}  // namespace

bool ComparisonOptions::IsValid(std::string* error) const {
  if (!pipeline.IsValid(error)) return false;
  if (bandwidth_segment_samples < 1024) {
    *error = "ComparisonOptions::bandwidth_segment_samples = " +
             std::to_string(bandwidth_segment_samples) + ": must be >= 1024";
    return false;
  }
  return true;
}

std::string ComparisonResult::BriefReport() const {
  std::ostringstream s;
  for (const MethodRow& r : rows) {
    s << r.group << " | " << r.method << " | ARW " << r.arw_deg_per_sqrt_h.value_or(NAN)
      << " | ADEV min " << r.adev_min_deg_per_h.value_or(NAN) << " | BW "
      << r.bandwidth_hz.value_or(NAN) << " Hz\n";
  }
  return s.str();
}

Result<ComparisonResult> CompareMethods(const PipelineInput& input, const PipelineResult& parallel,
                                        const ComparisonTruth& truth,
                                        const ComparisonOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  const std::size_t n = input.rate_dps.size();
  if (parallel.compensated_dps.size() != n || parallel.features.mixed.size() != n) {
    return InvalidArgument("CompareMethods: `parallel` is not a run of this record");
  }
  if ((!truth.true_rate_dps.empty() && truth.true_rate_dps.size() != n) ||
      (!truth.true_drift_dps.empty() && truth.true_drift_dps.size() != n)) {
    return InvalidInput("ground-truth columns differ in length from the record");
  }
  const CompareArgs args{input, parallel, truth, options, options.pipeline};
  ComparisonResult result;
  if (options.denoising) {
    if (Status s = CompareDenoisers(args, &result); !s) return s.error();
  }
  if (options.drift_models) {
    if (Status s = CompareDriftModels(args, &result); !s) return s.error();
  }
  if (options.schemes) {
    if (Status s = CompareSchemes(args, &result); !s) return s.error();
  }
  return result;
}

}  // namespace gyrocomp
