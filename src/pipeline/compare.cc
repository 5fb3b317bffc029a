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
  const PipelineOptions& po = options.pipeline;
  ComparisonResult result;
  const std::vector<double>& drift = parallel.features.drift;
  const std::vector<double>& predicted = parallel.predicted_drift_dps;
  // The denoisers are compared on the mixed feature C2 (the paper). When no mode was classified
  // mixed, C2 is empty and the comparison would be void: they get C2 + C3 (everything but the
  // drift feature) instead, and every row says so.
  const bool mixed_empty = std::all_of(parallel.features.mixed.begin(), parallel.features.mixed.end(),
                                       [](double v) { return v == 0.0; });
  std::vector<double> mixed = parallel.features.mixed;
  if (mixed_empty) {
    for (std::size_t i = 0; i < n; ++i) mixed[i] += parallel.features.noise[i];
  }

  if (options.denoising) {
    WaveletDenoiseOptions wavelet;
    wavelet.wavelet = po.wflp.wavelet;
    wavelet.level = po.wflp.level;
    wavelet.extension = po.wflp.extension;
    wavelet.threshold = po.wflp.threshold;
    wavelet.threshold_mode = po.wflp.threshold_mode;
    struct Denoiser {
      std::string name;
      SignalProcessing run;  // empty: the mixed feature as is
    };
    const std::string level = po.wflp.level ? std::to_string(*po.wflp.level) : std::string("max");
    std::vector<Denoiser> denoisers = {
        {"none (mixed feature kept as is)", {}},
        {"wavelet threshold (" + po.wflp.wavelet + ", level " + level + ", universal " +
             (po.wflp.threshold_mode == ThresholdMode::kSoft ? "soft" : "hard") + ")",
         [wavelet](std::span<const double> x) { return WaveletDenoise(x, wavelet); }},
        {"FLP (order " + std::to_string(po.wflp.flp.order) + ")",
         [flp = po.wflp.flp](std::span<const double> x) { return FlpDenoise(x, flp); }},
        {"WFLP (" + po.wflp.wavelet + ", level " + level + ", FLP order " +
             std::to_string(po.wflp.flp.order) + ")",
         [wflp = po.wflp](std::span<const double> x) { return WflpDenoise(x, wflp); }},
    };
    const std::size_t seg = std::min(n, options.bandwidth_segment_samples);
    const std::span<const double> background = std::span<const double>(mixed).subspan((n - seg) / 2, seg);
    for (const Denoiser& d : denoisers) {
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
      if (Status s = AddOutputMetrics(Combine(denoised, drift, predicted), input, truth, po.allan, &row); !s) {
        return s.error();
      }
      if (d.run) {
        BandwidthOptions bw;
        bw.fs_hz = input.fs_hz;
        bw.num_frequencies = po.bandwidth_frequencies;
        Result<BandwidthResult> b = MeasureBandwidth(d.run, background, bw);
        if (b) {
          row.bandwidth_hz = b->bandwidth_hz;
          if (!b->bandwidth_hz) row.note = "gain above -3 dB up to " + std::to_string(b->max_frequency_hz) + " Hz";
        } else {
          row.note = "bandwidth not measured: " + b.error().message;
        }
      } else {
        row.note = "denoiser bandwidth: the full band";
      }
      row.note += row.note.empty() ? "" : "; ";
      row.note += mixed_empty ? "no mixed mode: denoiser applied to mixed + noise features; output = that + "
                                "compensated drift feature"
                              : "output = denoised mixed feature + compensated drift feature";
      result.rows.push_back(std::move(row));
    }
  }

  if (options.drift_models) {
    struct Candidate {
      std::string name;
      DriftFitOptions fit;
    };
    std::vector<Candidate> candidates;
    DriftFitOptions base = po.drift;
    base.target_name = "drift-mode";
    {
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
      if (options.grid_search) {
        f = base;
        f.model = DriftModelKind::kGridSvr;
        candidates.push_back({"SVR, grid search (same budget as CS)", f});
      }
    }
    std::vector<double> target = drift;
    if (!input.known_rate_dps.empty()) {
      for (std::size_t i = 0; i < n; ++i) target[i] -= input.known_rate_dps[i];
    }
    const DriftInputs drift_inputs{input.temp_c, input.fs_hz};
    // `parallel_run`: the row of the parallel run's own model, whose output and Allan analysis
    // the run already has.
    auto add_model_row = [&](const std::string& name, const DriftModel& model,
                             const std::vector<double>& pred, double seconds, bool parallel_run) -> Status {
      MethodRow row;
      row.group = "drift";
      row.method = name;
      row.seconds = seconds;
      row.drift_cv_rmse_dps = model.summary.cv_rmse;
      if (!truth.true_drift_dps.empty()) row.drift_rmse_vs_truth_dps = Rms(pred, truth.true_drift_dps);
      row.note = "in-sample (fitted on this record)";
      if (parallel_run) {
        SetOutputMetrics(parallel.allan_after, parallel.compensated_dps, truth, &row);
      } else if (Status s = AddOutputMetrics(Combine(parallel.mixed_denoised, drift, pred), input, truth,
                                             po.allan, &row);
                 !s) {
        return s;
      }
      result.rows.push_back(std::move(row));
      return Status::Ok();
    };
    for (const Candidate& c : candidates) {
      const auto start = Clock::now();
      Result<DriftModel> model = FitDriftModel(drift_inputs, target, c.fit);
      if (!model) return model.error();
      Result<std::vector<double>> pred = model->Predict(drift_inputs);
      if (!pred) return pred.error();
      if (Status s = add_model_row(c.name, *model, *pred, SecondsSince(start), false); !s) return s.error();
    }
    if (parallel.drift_model) {
      if (Status s = add_model_row(std::string(DriftModelKindName(parallel.drift_model->kind)) +
                                       " (the parallel run's model)",
                                   *parallel.drift_model, predicted,
                                   parallel.timings_s.count("drift_fit") ? parallel.timings_s.at("drift_fit") : 0.0,
                                   true);
          !s) {
        return s.error();
      }
    }
  }

  if (options.schemes) {
    MethodRow raw;
    raw.group = "scheme";
    raw.method = "raw (no processing)";
    SetOutputMetrics(parallel.allan_before, input.rate_dps, truth, &raw);
    raw.note = "full band";
    result.rows.push_back(std::move(raw));

    MethodRow serial;
    serial.group = "scheme";
    serial.method = "serial: WFLP on the record, then " + std::string(DriftModelKindName(po.drift.model));
    PipelineOptions serial_options = po;
    const bool reuse = options.serial_reuses_parallel_parameters && parallel.drift_model &&
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
    Result<SerialResult> s = RunSerialModel(input, serial_options);
    if (!s) return s.error();
    serial.seconds = s->seconds;
    {  // The serial scheme's bandwidth is WFLP's on the raw record.
      BandwidthOptions bw;
      bw.fs_hz = input.fs_hz;
      bw.num_frequencies = po.bandwidth_frequencies;
      const std::size_t seg = std::min(n, options.bandwidth_segment_samples);
      Result<BandwidthResult> b = MeasureBandwidth(
          [wflp = po.wflp](std::span<const double> x) { return WflpDenoise(x, wflp); },
          input.rate_dps.subspan((n - seg) / 2, seg), bw);
      if (b) serial.bandwidth_hz = b->bandwidth_hz;
    }
    if (!truth.true_drift_dps.empty()) serial.drift_rmse_vs_truth_dps = Rms(s->predicted_drift_dps, truth.true_drift_dps);
    if (Status st = AddOutputMetrics(s->compensated_dps, input, truth, po.allan, &serial); !st) return st.error();
    result.rows.push_back(std::move(serial));

    MethodRow par;
    par.group = "scheme";
    par.method = "parallel: VMD-SE, WFLP | " + std::string(DriftModelKindName(po.drift.model)) + " (the paper)";
    par.seconds = parallel.timings_s.count("total") ? parallel.timings_s.at("total") : 0.0;
    if (parallel.bandwidth) par.bandwidth_hz = parallel.bandwidth->bandwidth_hz;
    if (!truth.true_drift_dps.empty()) par.drift_rmse_vs_truth_dps = Rms(predicted, truth.true_drift_dps);
    SetOutputMetrics(parallel.allan_after, parallel.compensated_dps, truth, &par);
    result.rows.push_back(std::move(par));
  }
  return result;
}

}  // namespace gyrocomp
