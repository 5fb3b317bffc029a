// gyrocomp.run_parallel_model: the paper's VMD-SE-WFLP-CS-SVR model on one record.
#include "bindings.h"

#include "gyrocomp/pipeline/pipeline.h"

namespace gyrocomp::python {
namespace {

PipelineOptions ReadPipelineOptions(Kwargs& kw) {
  PipelineOptions o;
  {
    Kwargs vmd(kw.Nested("vmd"), "run_parallel_model(vmd=...)");
    o.vmd = ReadVmdOptions(vmd);
    vmd.Done();
  }
  {
    Kwargs drift(kw.Nested("drift"), "run_parallel_model(drift=...)");
    o.drift = ReadFitOptions(drift);
    drift.Done();
  }
  {
    Kwargs allan(kw.Nested("allan"), "run_parallel_model(allan=...)");
    o.allan = ReadAllanOptions(allan);
    allan.Done();
  }
  kw.Get("entropy_max_samples", &o.entropy_max_samples);
  kw.Get("force_drift_mode", &o.force_drift_mode);
  kw.Get("measure_bandwidth", &o.measure_bandwidth);
  kw.Get("bandwidth_segment_samples", &o.bandwidth_segment_samples);
  kw.Get("bandwidth_frequencies", &o.bandwidth_frequencies);
  return o;
}

py::dict ResultDict(PipelineResult&& r) {
  py::dict d;
  d["fs_hz"] = r.fs_hz;
  d["num_samples"] = r.num_samples;
  d["compensated_dps"] = ToNumpy(std::move(r.compensated_dps));
  d["predicted_drift_dps"] = ToNumpy(std::move(r.predicted_drift_dps));
  d["mixed_denoised_dps"] = ToNumpy(std::move(r.mixed_denoised));
  d["drift_feature_dps"] = ToNumpy(std::move(r.features.drift));
  d["mixed_feature_dps"] = ToNumpy(std::move(r.features.mixed));
  d["noise_feature_dps"] = ToNumpy(std::move(r.features.noise));
  d["modes"] = ToNumpy2d(r.modes);
  py::list modes;
  for (const ModeReport& m : r.mode_reports) {
    modes.append(py::dict(py::arg("index") = m.index, py::arg("center_frequency_hz") = m.center_frequency_hz,
                          py::arg("center_frequency_cycles_per_sample") = m.center_frequency_cycles_per_sample,
                          py::arg("sample_entropy") = m.sample_entropy,
                          py::arg("class") = FeatureClassName(m.feature)));
  }
  d["mode_reports"] = modes;
  d["classification_rule"] = r.classification_rule;
  d["drift_mode_forced"] = r.drift_mode_forced;
  d["vmd_iterations"] = r.vmd.iterations;
  d["vmd_converged"] = r.vmd.converged;
  d["wflp"] = r.wflp.BriefReport();
  d["drift_model"] = r.drift_model ? py::cast(std::move(*r.drift_model)) : py::none();
  d["bandwidth_hz"] = r.bandwidth ? py::cast(r.bandwidth->bandwidth_hz) : py::none();
  d["timings_s"] = r.timings_s;
  d["warnings"] = r.warnings;
  d["brief_report"] = r.BriefReport();
  d["allan_before"] = AllanDict(std::move(r.allan_before));
  d["allan_after"] = AllanDict(std::move(r.allan_after));
  return d;
}

}  // namespace

void BindPipeline(py::module_& m) {
  m.def(
      "run_parallel_model",
      [](const DoubleArray& rate_dps, const DoubleArray& temp_c, double fs_hz, std::optional<DoubleArray> known_rate_dps,
         py::object progress, const CancellationToken* cancel, const py::kwargs& kwargs) {
        Kwargs kw(kwargs, "run_parallel_model");
        PipelineOptions o = ReadPipelineOptions(kw);
        kw.Done();
        PipelineInput input;
        input.rate_dps = AsSpan(rate_dps, "rate_dps");
        input.temp_c = AsSpan(temp_c, "temp_c");
        input.fs_hz = fs_hz;
        if (known_rate_dps) input.known_rate_dps = AsSpan(*known_rate_dps, "known_rate_dps");
        LongCall call(cancel);
        o.vmd.cancel = o.entropy.cancel = o.allan.cancel = call.token();
        o.drift.cancel = o.drift.search.cuckoo.cancel = o.drift.svr.cancel = call.token();
        const Hooks hooks(std::move(progress), call.token());
        const ProgressCallback callback = [&hooks](const std::string& stage, double fraction) {
          hooks.Poll(stage, fraction);
        };
        return ResultDict(Unwrap(call.Run([&] { return RunParallelModel(input, o, callback); })));
      },
      py::arg("rate_dps"), py::arg("temp_c"), py::arg("fs_hz"), py::kw_only(), py::arg("known_rate_dps") = py::none(),
      py::arg("progress") = py::none(), py::arg("cancel") = nullptr,
      "The parallel VMD-SE-WFLP-CS-SVR model (PipelineOptions as keywords; vmd=, drift=, allan= as dicts). "
      "progress(stage, fraction); cancel: a CancellationToken.");
}

}  // namespace gyrocomp::python
