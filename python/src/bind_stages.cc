// gyrocomp.vmd, decompose, sample_entropy, wavelet_denoise, flp_denoise, wflp_denoise.
#include "bindings.h"

#include "gyrocomp/decompose/feature_classifier.h"
#include "gyrocomp/decompose/sample_entropy.h"
#include "gyrocomp/decompose/vmd.h"
#include "gyrocomp/denoise/bandwidth.h"
#include "gyrocomp/denoise/flp.h"
#include "gyrocomp/denoise/wavelet_denoise.h"
#include "gyrocomp/denoise/wflp.h"
#include "gyrocomp/pipeline/pipeline.h"  // kDefaultEntropyMaxSamples, the default of `decompose` and `process`

namespace gyrocomp::python {
namespace {

// The wavelet fields WaveletDenoiseOptions and WflpOptions share.
template <class Options>
void ReadWaveletFields(Kwargs& kw, Options* o) {
  kw.Get("wavelet", &o->wavelet);
  kw.Get("level", &o->level);
  kw.GetParsed("extension", &o->extension, ParseExtensionMode, "must be symmetric, periodization, periodic or zero");
  kw.GetParsed("threshold", &o->threshold, ParseThresholdRule, "must be a threshold rule name (docs/explanation/denoising.md)");
  kw.GetParsed("threshold_mode", &o->threshold_mode, ParseThresholdMode, "must be soft or hard");
  kw.Get("noise_sigma", &o->noise_sigma);
}

WaveletDenoiseOptions ReadWaveletOptions(Kwargs& kw) {
  WaveletDenoiseOptions o;
  ReadWaveletFields(kw, &o);
  return o;
}

FlpOptions ReadFlpOptions(Kwargs& kw) {
  FlpOptions o;
  kw.Get("order", &o.order);
  kw.Get("beta", &o.beta);
  kw.Get("alpha", &o.alpha);
  kw.Get("power_forgetting", &o.power_forgetting);
  kw.Get("regularization", &o.regularization);
  kw.GetParsed("initial_weights", &o.initial_weights, ParseFlpInitialWeights, "must be an FlpInitialWeights name");
  return o;
}

WflpOptions ReadWflpOptions(Kwargs& kw) {
  WflpOptions o;
  ReadWaveletFields(kw, &o);
  o.flp = ReadAll(kw.Nested("flp"), kw.function() + "(flp=...)", ReadFlpOptions);
  kw.GetParsed("details", &o.details, ParseDetailHandling, "must be a DetailHandling name");
  return o;
}

py::dict FlpSummaryDict(const FlpSummary& s) {
  return py::dict(py::arg("num_samples") = s.num_samples, py::arg("order") = s.order, py::arg("beta") = s.beta,
                  py::arg("alpha") = s.alpha, py::arg("final_weights") = s.final_weights,
                  py::arg("mean_step") = s.mean_step, py::arg("final_step") = s.final_step,
                  py::arg("rms_error") = s.rms_error, py::arg("rms_error_second_half") = s.rms_error_second_half,
                  py::arg("brief_report") = s.BriefReport());
}

py::dict ThresholdsDict(const WaveletDenoiseSummary& s) {
  return py::dict(py::arg("wavelet") = s.wavelet, py::arg("level") = s.level, py::arg("sigma") = s.sigma,
                  py::arg("threshold") = s.threshold, py::arg("fraction_zeroed") = s.fraction_zeroed,
                  py::arg("brief_report") = s.BriefReport());
}

py::dict VmdDict(VmdResult&& r) {
  const VmdSummary& s = r.summary;
  py::dict d;
  d["modes"] = ToNumpy2d(r.modes);
  d["num_modes"] = s.num_modes;
  d["num_samples"] = s.num_samples;
  d["iterations"] = s.iterations;
  d["converged"] = s.converged;
  d["final_update"] = s.final_update;
  d["center_frequency_cycles_per_sample"] = s.center_frequency_cycles_per_sample;
  d["center_frequency_hz"] = s.center_frequency_hz;
  d["fs_hz"] = s.fs_hz;
  d["threads_used"] = s.threads_used;
  d["elapsed_s"] = s.elapsed_s;
  d["brief_report"] = s.BriefReport();
  return d;
}

// VMD's progress: the fraction of max_iterations done, each iteration (and its cancellation).
void PollEachIteration(VmdOptions* o, const Hooks& hooks) {
  const int max_iterations = o->max_iterations;
  o->on_iteration = [&hooks, max_iterations](int iteration, double) {
    hooks.Poll("vmd", static_cast<double>(iteration) / max_iterations);
  };
}

py::dict Vmd(const DoubleArray& signal, py::object progress, const CancellationToken* cancel, const py::kwargs& kwargs) {
  VmdOptions o = ReadAll(kwargs, "vmd", ReadVmdOptions);
  LongCall call(cancel);
  o.cancel = call.token();
  const Hooks hooks(std::move(progress), call.token());
  PollEachIteration(&o, hooks);
  const std::span<const double> x = AsSpan(signal, "signal");
  return VmdDict(Unwrap(call.Run([&] { return DecomposeVmd(x, o); })));
}

SampleEntropyOptions ReadEntropyOptions(Kwargs& kw) {
  SampleEntropyOptions o;
  kw.Get("m", &o.m);
  kw.Get("r_factor", &o.r_factor);
  return o;
}

// decompose's rule: 'standard' | 'paper', with drift_max_se, noise_min_se, drift_max_frequency_hz
// over it (then named "custom").
ClassifierOptions ReadClassifierRule(Kwargs& kw) {
  std::string rule_name = "standard";
  kw.Get("rule", &rule_name);
  if (rule_name != "standard" && rule_name != "paper")
    throw py::value_error("decompose(): rule=" + rule_name + ": must be standard or paper");
  ClassifierOptions rule = rule_name == "paper" ? ClassifierOptions::Paper() : ClassifierOptions::Standard();
  std::optional<double> drift_max_se, noise_min_se, drift_max_frequency_hz;
  kw.Get("drift_max_se", &drift_max_se);
  kw.Get("noise_min_se", &noise_min_se);
  kw.Get("drift_max_frequency_hz", &drift_max_frequency_hz);
  if (drift_max_se) rule.drift_max_se = *drift_max_se;
  if (noise_min_se) rule.noise_min_se = *noise_min_se;
  if (drift_max_frequency_hz) rule.drift_max_frequency_hz = *drift_max_frequency_hz;
  if (drift_max_se || noise_min_se || drift_max_frequency_hz) rule.rule_name = "custom";
  return rule;
}

// Sample entropy on at most this many samples of each mode (None: all), as `process`.
std::optional<std::size_t> ReadEntropyMaxSamples(Kwargs& kw, const py::kwargs& kwargs) {
  if (!kwargs.contains("entropy_max_samples")) return kDefaultEntropyMaxSamples;
  py::object v = kw.Take("entropy_max_samples");
  return v.is_none() ? std::nullopt : std::optional<std::size_t>(v.cast<std::size_t>());
}

// The classes of decompose's result: one dict per mode, the rule and its text.
void AddClasses(const ClassificationResult& c, py::dict* d) {
  py::list modes;
  for (const ModeClassification& m : c.modes) {
    modes.append(py::dict(py::arg("index") = m.index, py::arg("sample_entropy") = m.sample_entropy,
                          py::arg("center_frequency_cycles_per_sample") = m.center_frequency_cycles_per_sample,
                          py::arg("center_frequency_hz") = m.center_frequency_hz,
                          py::arg("feature") = FeatureClassName(m.feature)));
  }
  (*d)["classes"] = modes;
  const ClassifierOptions& r = c.rule;
  (*d)["rule"] = py::dict(py::arg("rule_name") = r.rule_name, py::arg("drift_max_se") = r.drift_max_se,
                          py::arg("noise_min_se") = r.noise_min_se,
                          py::arg("drift_max_frequency_hz") = r.drift_max_frequency_hz,
                          py::arg("keep_lowest_mode") = r.keep_lowest_mode);
  (*d)["rule_text"] = c.rule_text;
  (*d)["classification_report"] = c.BriefReport();
}

// gyrocomp.decompose: VMD, sample entropy of each mode, the drift / mixed / noise classes
// (DecomposeVmd + ClassifyVmdModes), the work of `gyrocomp decompose` on one axis.
py::dict Decompose(const DoubleArray& signal, py::object progress, const CancellationToken* cancel,
                   const py::kwargs& kwargs) {
  Kwargs kw(kwargs, "decompose");
  VmdOptions o = ReadVmdOptions(kw);
  SampleEntropyOptions se = ReadAll(kw.Nested("entropy"), "decompose(entropy=...)", ReadEntropyOptions);
  const ClassifierOptions rule = ReadClassifierRule(kw);
  const std::optional<std::size_t> entropy_max_samples = ReadEntropyMaxSamples(kw, kwargs);
  kw.Done();
  std::string why;
  if (!se.IsValid(&why) || !rule.IsValid(&why)) throw py::value_error(why);
  LongCall call(cancel);
  o.cancel = call.token();
  se.cancel = call.token();
  const Hooks hooks(std::move(progress), call.token());
  PollEachIteration(&o, hooks);
  const std::span<const double> x = AsSpan(signal, "signal");
  // Two runs of the worker, each result unwrapped here (a Python error is raised with the GIL held).
  VmdResult v = Unwrap(call.Run([&] { return DecomposeVmd(x, o); }));
  const ClassificationResult c = Unwrap(call.Run([&] { return ClassifyVmdModes(v, se, rule, entropy_max_samples); }));
  py::dict d = VmdDict(std::move(v));
  AddClasses(c, &d);
  return d;
}

py::dict SampleEntropyCall(const DoubleArray& x, const CancellationToken* cancel, const py::kwargs& kwargs) {
  SampleEntropyOptions o = ReadAll(kwargs, "sample_entropy", [](Kwargs& kw) {
    SampleEntropyOptions e = ReadEntropyOptions(kw);
    kw.Get("reference_sd", &e.reference_sd);
    kw.Get("r_absolute", &e.r_absolute);
    kw.Get("num_threads", &e.num_threads);
    return e;
  });
  const std::span<const double> s = AsSpan(x, "x");
  LongCall call(cancel);
  o.cancel = call.token();
  SampleEntropyResult r = Unwrap(call.Run([&] { return SampleEntropy(s, o); }));
  return py::dict(py::arg("sample_entropy") = r.defined ? py::cast(r.sample_entropy) : py::none(),
                  py::arg("defined") = r.defined, py::arg("m") = r.m, py::arg("r") = r.r, py::arg("n") = r.n,
                  py::arg("a_matches") = r.a_matches, py::arg("b_matches") = r.b_matches,
                  py::arg("elapsed_s") = r.elapsed_s, py::arg("brief_report") = r.BriefReport());
}

py::dict WaveletDenoiseCall(const DoubleArray& x, const py::kwargs& kwargs) {
  const WaveletDenoiseOptions o = ReadAll(kwargs, "wavelet_denoise", ReadWaveletOptions);
  const std::span<const double> s = AsSpan(x, "x");
  WaveletDenoiseResult r = Unwrap(WithoutGil([&] { return RunWaveletDenoise(s, o); }));
  return py::dict(py::arg("denoised") = ToNumpy(std::move(r.denoised)), py::arg("summary") = ThresholdsDict(r.summary));
}

py::dict FlpDenoiseCall(const DoubleArray& x, const py::kwargs& kwargs) {
  const FlpOptions o = ReadAll(kwargs, "flp_denoise", ReadFlpOptions);
  const std::span<const double> s = AsSpan(x, "x");
  FlpResult r = Unwrap(WithoutGil([&] { return RunFlp(s, o); }));
  return py::dict(py::arg("denoised") = ToNumpy(std::move(r.filtered)), py::arg("summary") = FlpSummaryDict(r.summary));
}

py::dict WflpDenoiseCall(const DoubleArray& x, const py::kwargs& kwargs) {
  const WflpOptions o = ReadAll(kwargs, "wflp_denoise", ReadWflpOptions);
  const std::span<const double> s = AsSpan(x, "x");
  WflpResult r = Unwrap(WithoutGil([&] { return RunWflp(s, o); }));
  py::dict summary = py::dict(py::arg("wavelet") = r.summary.wavelet, py::arg("level") = r.summary.level,
                              py::arg("flp") = FlpSummaryDict(r.summary.flp),
                              py::arg("thresholds") = ThresholdsDict(r.summary.thresholds),
                              py::arg("brief_report") = r.summary.BriefReport());
  return py::dict(py::arg("denoised") = ToNumpy(std::move(r.denoised)), py::arg("summary") = summary);
}

// A denoiser's output as a SignalProcessing (what MeasureBandwidth drives).
template <class Options, class Run, class Member>
SignalProcessing Denoiser(Options o, Run run, Member output) {
  return [o, run, output](std::span<const double> x) -> Result<std::vector<double>> {
    auto r = run(x, o);
    if (!r.ok()) return r.error();
    return std::move((*r).*output);
  };
}

// The denoiser under test of measure_bandwidth with its options, as wavelet_denoise / flp_denoise /
// wflp_denoise take them (`gyrocomp denoise --method M --bandwidth`).
SignalProcessing DenoiserUnderTest(const std::string& method, py::dict options) {
  const std::string fn = "measure_bandwidth(options=...)";
  if (method == "wavelet")
    return Denoiser(ReadAll(options, fn, ReadWaveletOptions), RunWaveletDenoise, &WaveletDenoiseResult::denoised);
  if (method == "flp") return Denoiser(ReadAll(options, fn, ReadFlpOptions), RunFlp, &FlpResult::filtered);
  if (method == "wflp") return Denoiser(ReadAll(options, fn, ReadWflpOptions), RunWflp, &WflpResult::denoised);
  throw py::value_error("measure_bandwidth(): method=" + method + ": must be wavelet, flp or wflp");
}

py::dict BandwidthDict(BandwidthResult&& r) {
  py::dict d;
  d["brief_report"] = r.BriefReport();  // before the vectors move out (it reads them)
  d["frequency_hz"] = ToNumpy(std::move(r.frequency_hz));
  d["gain"] = ToNumpy(std::move(r.gain));
  d["phase_rad"] = ToNumpy(std::move(r.phase_rad));
  d["bandwidth_hz"] = r.bandwidth_hz;
  d["bandwidth_below_range"] = r.bandwidth_below_range;
  d["max_frequency_hz"] = r.max_frequency_hz;
  d["delay_s"] = r.delay_s;
  d["dc_gain"] = r.dc_gain;
  d["amplitude"] = r.amplitude;
  d["num_runs"] = r.num_runs;
  return d;
}

py::dict MeasureBandwidthCall(const std::string& method, const DoubleArray& background, double fs_hz,
                              const py::kwargs& kwargs) {
  Kwargs kw(kwargs, "measure_bandwidth");
  BandwidthOptions bo;
  bo.fs_hz = fs_hz;
  kw.Get("num_frequencies", &bo.num_frequencies);
  kw.Get("min_frequency_hz", &bo.min_frequency_hz);
  kw.Get("max_frequency_hz", &bo.max_frequency_hz);
  kw.Get("amplitude", &bo.amplitude);
  kw.Get("edge_fraction", &bo.edge_fraction);
  const py::dict options = kw.Nested("options");
  kw.Done();
  const SignalProcessing p = DenoiserUnderTest(method, options);
  const std::span<const double> b = AsSpan(background, "background");
  return BandwidthDict(Unwrap(WithoutGil([&] { return MeasureBandwidth(p, b, bo); })));
}

}  // namespace

VmdOptions ReadVmdOptions(Kwargs& kw) {
  VmdOptions o;
  kw.Get("num_modes", &o.num_modes);
  kw.Get("alpha", &o.alpha);
  kw.Get("tau", &o.tau);
  kw.Get("tol", &o.tol);
  kw.Get("dc", &o.dc);
  kw.Get("seed", &o.seed);
  kw.Get("max_iterations", &o.max_iterations);
  kw.Get("mirror_extension", &o.mirror_extension);
  kw.Get("return_last_iterate", &o.return_last_iterate);
  kw.Get("fs_hz", &o.fs_hz);
  kw.Get("num_threads", &o.num_threads);
  return o;
}

void BindStages(py::module_& m) {
  m.def("vmd", &Vmd, py::arg("signal"), py::kw_only(), py::arg("progress") = py::none(),
        py::arg("cancel") = nullptr,
        "Variational mode decomposition (VmdOptions as keywords). progress(stage, fraction) is called "
        "every iteration; cancel: a CancellationToken.");
  m.def("decompose", &Decompose, py::arg("signal"), py::kw_only(), py::arg("progress") = py::none(),
        py::arg("cancel") = nullptr,
        "VMD, sample entropy per mode and the drift / mixed / noise classes (gyrocomp decompose): VmdOptions "
        "as keywords, entropy={m, r_factor}, entropy_max_samples (None: all), rule ('standard' | 'paper'), "
        "drift_max_se, noise_min_se, drift_max_frequency_hz. classes: one dict per mode.");
  m.def("sample_entropy", &SampleEntropyCall, py::arg("x"), py::kw_only(), py::arg("cancel") = nullptr,
        "Sample entropy (SampleEntropyOptions as keywords: m, r_factor, r_absolute, ...); cancel: a "
        "CancellationToken. Ctrl-C stops it (KeyboardInterrupt).");
  m.def("wavelet_denoise", &WaveletDenoiseCall, py::arg("x"), "Wavelet threshold denoising (WaveletDenoiseOptions as keywords).");
  m.def("flp_denoise", &FlpDenoiseCall, py::arg("x"), "Fuzzy linear prediction (FlpOptions as keywords).");
  m.def("wflp_denoise", &WflpDenoiseCall, py::arg("x"),
        "Wavelet + FLP denoising of the paper (WflpOptions as keywords; flp={...}).");
  m.def("measure_bandwidth", &MeasureBandwidthCall, py::arg("method"), py::arg("background"), py::arg("fs_hz"),
        "The -3 dB bandwidth and delay of a denoiser (MeasureBandwidth; gyrocomp denoise --bandwidth): test sines "
        "added to `background` (the CLI uses the record's first 32768 samples). method: wavelet | flp | wflp, "
        "options={...} its keywords; BandwidthOptions as keywords (num_frequencies: 32 here, the CLI's default "
        "is 24; min_frequency_hz, max_frequency_hz, amplitude, edge_fraction).");
}

}  // namespace gyrocomp::python
