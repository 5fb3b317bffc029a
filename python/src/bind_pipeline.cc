// gyrocomp.run_parallel_model: the paper's VMD-SE-WFLP-CS-SVR model on one record, with the HTML
// report of `gyrocomp process --report` (report=...); gyrocomp.compare_methods: the paper's
// comparisons on it (`gyrocomp compare`).
#include "bindings.h"

#include "gyrocomp/io/io.h"
#include "gyrocomp/pipeline/compare.h"
#include "gyrocomp/pipeline/pipeline.h"
#include "gyrocomp/report/pipeline_report.h"

namespace gyrocomp::python {
namespace {

PipelineOptions ReadPipelineOptions(Kwargs& kw) {
  PipelineOptions o;
  o.vmd = ReadAll(kw.Nested("vmd"), kw.function() + "(vmd=...)", ReadVmdOptions);
  o.drift = ReadAll(kw.Nested("drift"), kw.function() + "(drift=...)", ReadFitOptions);
  o.allan = ReadAll(kw.Nested("allan"), kw.function() + "(allan=...)", ReadAllanOptions);
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

py::object Optional(const std::optional<double>& v) { return v ? py::object(py::float_(*v)) : py::object(py::none()); }

py::dict MethodRowDict(const MethodRow& r) {
  return py::dict(py::arg("group") = r.group, py::arg("method") = r.method,
                  py::arg("arw_deg_per_sqrt_h") = Optional(r.arw_deg_per_sqrt_h),
                  py::arg("adev_min_deg_per_h") = Optional(r.adev_min_deg_per_h),
                  py::arg("bias_instability_deg_per_h") = Optional(r.bias_instability_deg_per_h),
                  py::arg("bandwidth_hz") = Optional(r.bandwidth_hz),
                  py::arg("rmse_vs_true_rate_dps") = Optional(r.rmse_vs_true_rate_dps),
                  py::arg("drift_rmse_vs_truth_dps") = Optional(r.drift_rmse_vs_truth_dps),
                  py::arg("drift_cv_rmse_dps") = Optional(r.drift_cv_rmse_dps), py::arg("seconds") = r.seconds,
                  py::arg("note") = r.note);
}

// The long call of the pipeline: every stage's options poll its token; progress(stage, fraction).
class PipelineCall {
 public:
  PipelineCall(PipelineOptions* o, py::object progress, const CancellationToken* cancel)
      : call_(cancel), hooks_(std::move(progress), call_.token()) {
    o->vmd.cancel = o->entropy.cancel = o->allan.cancel = call_.token();
    o->drift.cancel = o->drift.search.cuckoo.cancel = o->drift.svr.cancel = call_.token();
  }
  PipelineResult Run(const PipelineInput& input, const PipelineOptions& o) {
    const ProgressCallback callback = [this](const std::string& stage, double fraction) { hooks_.Poll(stage, fraction); };
    return Unwrap(call_.Run([&] { return RunParallelModel(input, o, callback); }));
  }
  LongCall& call() { return call_; }

 private:
  LongCall call_;
  Hooks hooks_;
};

PipelineInput Input(const DoubleArray& rate_dps, const DoubleArray& temp_c, double fs_hz) {
  PipelineInput input;
  input.rate_dps = AsSpan(rate_dps, "rate_dps");
  input.temp_c = AsSpan(temp_c, "temp_c");
  input.fs_hz = fs_hz;
  return input;
}

// report=: the HTML report `gyrocomp process --report` writes, a path or dict(path, source, axis,
// title, time_s). source names the record in the subtitle (process: the input file), axis its rate
// column, title defaults to "gyrocomp: <source>", time_s to i / fs_hz.
struct ReportRequest {
  std::string path;
  std::string source = "Python arrays";
  std::string axis = "rate_dps";
  std::optional<std::string> title;
  std::optional<DoubleArray> time_s;
};

std::optional<ReportRequest> ReadReportRequest(Kwargs& kw) {
  py::object v = kw.Take("report");
  if (v.is_none()) return std::nullopt;
  ReportRequest q;
  if (py::isinstance<py::str>(v) || py::hasattr(v, "__fspath__")) {
    q.path = py::str(v);
    return q;
  }
  if (!py::isinstance<py::dict>(v)) throw py::type_error(kw.function() + "(): report must be a path or a dict");
  Kwargs rk(v.cast<py::dict>(), kw.function() + "(report=...)");
  rk.Get("path", &q.path);
  rk.Get("source", &q.source);
  rk.Get("axis", &q.axis);
  rk.Get("title", &q.title);
  rk.Get("time_s", &q.time_s);
  rk.Done();
  if (q.path.empty()) throw py::value_error(kw.function() + "(): report=dict(...) needs a path");
  return q;
}

// The report's time axis: time_s as given (checked against the rate's length before the run), else
// i / fs_hz.
std::vector<double> ReportTime(const ReportRequest& q, const PipelineInput& input) {
  if (!q.time_s) {
    std::vector<double> t(input.rate_dps.size());
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = static_cast<double>(i) / input.fs_hz;
    return t;
  }
  const std::span<const double> t = AsSpan(*q.time_s, "report time_s");
  if (t.size() != input.rate_dps.size())
    throw py::value_error("report time_s: " + std::to_string(t.size()) + " samples, the rate has " +
                          std::to_string(input.rate_dps.size()));
  return {t.begin(), t.end()};
}

// Builds the report of run `r` (BuildPipelineReport; with the comparison's tables when given) and
// writes it (atomic).
void WriteReport(const ReportRequest& q, std::span<const double> time_s, const PipelineResult& r,
                 const PipelineInput& input, const PipelineOptions& o, const ComparisonResult* comparison = nullptr) {
  PipelineReportContext ctx;
  ctx.title = q.title ? *q.title : "gyrocomp: " + q.source;
  ctx.source = q.source;
  ctx.axis = q.axis;
  ctx.time_s = time_s;
  ctx.rate_dps = input.rate_dps;
  ctx.temp_c = input.temp_c;
  ctx.parameters = PipelineOptionsJson(o);
  ctx.comparison = comparison;
  Check(WithoutGil([&] { return WriteTextAtomic(q.path, RenderReportHtml(BuildPipelineReport(r, ctx))); }));
}

py::dict CompareMethodsCall(const DoubleArray& rate_dps, const DoubleArray& temp_c, double fs_hz,
                            std::optional<DoubleArray> true_rate_dps, std::optional<DoubleArray> true_drift_dps,
                            py::object progress, const CancellationToken* cancel, const py::kwargs& kwargs) {
  Kwargs kw(kwargs, "compare_methods");
  ComparisonOptions co;
  co.pipeline = ReadPipelineOptions(kw);
  kw.Get("denoising", &co.denoising);
  kw.Get("drift_models", &co.drift_models);
  kw.Get("grid_search", &co.grid_search);
  kw.Get("schemes", &co.schemes);
  kw.Get("serial_reuses_parallel_parameters", &co.serial_reuses_parallel_parameters);
  const std::optional<ReportRequest> report = ReadReportRequest(kw);
  kw.Done();
  if (std::string why; !co.IsValid(&why)) throw py::value_error(why);
  const PipelineInput input = Input(rate_dps, temp_c, fs_hz);
  const std::vector<double> time_s = report ? ReportTime(*report, input) : std::vector<double>{};
  ComparisonTruth truth;
  if (true_rate_dps) truth.true_rate_dps = AsSpan(*true_rate_dps, "true_rate_dps");
  if (true_drift_dps) truth.true_drift_dps = AsSpan(*true_drift_dps, "true_drift_dps");
  PipelineCall call(&co.pipeline, std::move(progress), cancel);
  // As `gyrocomp compare`: the parallel model first, then the comparisons that reuse it.
  PipelineResult parallel = call.Run(input, co.pipeline);
  const ComparisonResult r = Unwrap(call.call().Run([&] { return CompareMethods(input, parallel, truth, co); }));
  if (report) WriteReport(*report, time_s, parallel, input, co.pipeline, &r);
  py::dict d;
  py::list rows;
  for (const MethodRow& row : r.rows) rows.append(MethodRowDict(row));
  d["rows"] = rows;
  d["brief_report"] = r.BriefReport();
  d["parallel"] = ResultDict(std::move(parallel));
  return d;
}

py::dict RunParallelModelCall(const DoubleArray& rate_dps, const DoubleArray& temp_c, double fs_hz,
                              std::optional<DoubleArray> known_rate_dps, py::object progress,
                              const CancellationToken* cancel, const py::kwargs& kwargs) {
  Kwargs kw(kwargs, "run_parallel_model");
  PipelineOptions o = ReadPipelineOptions(kw);
  const std::optional<ReportRequest> report = ReadReportRequest(kw);
  kw.Done();
  PipelineInput input = Input(rate_dps, temp_c, fs_hz);
  if (known_rate_dps) input.known_rate_dps = AsSpan(*known_rate_dps, "known_rate_dps");
  const std::vector<double> time_s = report ? ReportTime(*report, input) : std::vector<double>{};
  PipelineCall call(&o, std::move(progress), cancel);
  PipelineResult r = call.Run(input, o);
  if (report) WriteReport(*report, time_s, r, input, o);
  return ResultDict(std::move(r));
}

}  // namespace

void BindPipeline(py::module_& m) {
  m.def("compare_methods", &CompareMethodsCall, py::arg("rate_dps"), py::arg("temp_c"), py::arg("fs_hz"),
        py::kw_only(), py::arg("true_rate_dps") = py::none(), py::arg("true_drift_dps") = py::none(),
        py::arg("progress") = py::none(), py::arg("cancel") = nullptr,
        "The paper's comparisons on one record (gyrocomp compare): the parallel model, then denoisers, drift "
        "models and schemes (ComparisonOptions: denoising, drift_models, grid_search, schemes, "
        "serial_reuses_parallel_parameters; PipelineOptions as run_parallel_model's). rows: one MethodRow dict "
        "per method (the rows of compare --json); errors against the truth when true_rate_dps / "
        "true_drift_dps are given; parallel: the run_parallel_model result. report: as run_parallel_model's, with "
        "the comparison tables (gyrocomp process --compare --report).");
  m.def("run_parallel_model", &RunParallelModelCall, py::arg("rate_dps"), py::arg("temp_c"), py::arg("fs_hz"),
        py::kw_only(), py::arg("known_rate_dps") = py::none(), py::arg("progress") = py::none(),
        py::arg("cancel") = nullptr,
        "The parallel VMD-SE-WFLP-CS-SVR model (PipelineOptions as keywords; vmd=, drift=, allan= as dicts). "
        "progress(stage, fraction); cancel: a CancellationToken. report: a path, or dict(path, source, axis, "
        "title, time_s): writes the HTML report of gyrocomp process --report.");
}

}  // namespace gyrocomp::python
