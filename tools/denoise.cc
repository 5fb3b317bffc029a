// gyrocomp denoise: wavelet thresholding, FLP or WFLP on the rate column(s) (paper Section 3.3 and
// the comparison of Section 4.3.2), with optional honest metrics: RMSE against a known truth, ARW
// before/after, and the processing's measured -3 dB bandwidth and delay.
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "gyrocomp/io/bag_log.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/allan/allan.h"
#include "gyrocomp/denoise/bandwidth.h"
#include "gyrocomp/denoise/flp.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/denoise/wavelet_denoise.h"
#include "gyrocomp/denoise/wflp.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kDenoiseName = "denoise";

struct DenoiseArgs {
  LogOptions log;
  std::string method;
  std::string output;
  std::string json_path;
  // Wavelet part (wavelet and wflp).
  std::string wavelet = WflpOptions{}.wavelet;
  std::optional<int> level;  // unset: the library default (4)
  bool max_level = false;
  std::string extension = "symmetric";
  std::string threshold = "universal";
  std::string threshold_mode = "soft";
  std::string details = "threshold";
  std::optional<double> noise_sigma;
  // FLP part (flp and wflp): library defaults.
  FlpOptions flp;
  std::string flp_init = FlpInitialWeightsName(FlpOptions{}.initial_weights);
  // Metrics.
  std::string truth_cols;
  bool bandwidth = false;
  std::size_t bandwidth_segment = 1u << 15;
  int bandwidth_frequencies = 24;
  std::optional<double> bandwidth_amplitude;
};

struct Method {
  std::string name;
  WaveletDenoiseOptions wavelet;
  FlpOptions flp;
  WflpOptions wflp;
  Result<std::vector<double>> Apply(std::span<const double> x, std::string* report) const {
    if (name == "wavelet") {
      Result<WaveletDenoiseResult> r = RunWaveletDenoise(x, wavelet);
      if (!r.ok()) return r.error();
      if (report) *report = r->summary.BriefReport();
      return std::move(r->denoised);
    }
    if (name == "flp") {
      Result<FlpResult> r = RunFlp(x, flp);
      if (!r.ok()) return r.error();
      if (report) *report = r->summary.BriefReport();
      return std::move(r->filtered);
    }
    Result<WflpResult> r = RunWflp(x, wflp);
    if (!r.ok()) return r.error();
    if (report) *report = r->summary.BriefReport();
    return std::move(r->denoised);
  }
};

Result<Method> MakeMethod(const DenoiseArgs& a) {
  Method m;
  m.name = a.method;
  const auto ext = ParseExtensionMode(a.extension);
  if (!ext) return InvalidArgument("--extension " + a.extension + ": must be symmetric, reflect, periodic, zero, constant or periodization");
  const auto rule = ParseThresholdRule(a.threshold);
  if (!rule) return InvalidArgument("--threshold " + a.threshold + ": must be universal, universal-level or sure");
  const auto tmode = ParseThresholdMode(a.threshold_mode);
  if (!tmode) return InvalidArgument("--threshold-mode " + a.threshold_mode + ": must be soft or hard");
  const auto details = ParseDetailHandling(a.details);
  if (!details) return InvalidArgument("--details " + a.details + ": must be threshold, keep or zero");
  const auto init = ParseFlpInitialWeights(a.flp_init);
  if (!init) return InvalidArgument("--flp-init " + a.flp_init + ": must be moving-average, zero or last-sample");
  std::optional<int> level = WaveletDenoiseOptions{}.level;
  if (a.level) level = *a.level;
  if (a.max_level) level = std::nullopt;
  m.wavelet.wavelet = a.wavelet;
  m.wavelet.level = level;
  m.wavelet.extension = *ext;
  m.wavelet.threshold = *rule;
  m.wavelet.threshold_mode = *tmode;
  m.wavelet.noise_sigma = a.noise_sigma;
  m.flp = a.flp;
  m.flp.initial_weights = *init;
  m.wflp.wavelet = a.wavelet;
  m.wflp.level = level;
  m.wflp.extension = *ext;
  m.wflp.flp = m.flp;
  m.wflp.details = *details;
  m.wflp.threshold = *rule;
  m.wflp.threshold_mode = *tmode;
  m.wflp.noise_sigma = a.noise_sigma;
  std::string why;
  if (m.name == "wavelet" && !m.wavelet.IsValid(&why)) return InvalidArgument(why);
  if (m.name == "flp" && !m.flp.IsValid(&why)) return InvalidArgument(why);
  if (m.name == "wflp" && !m.wflp.IsValid(&why)) return InvalidArgument(why);
  return m;
}

nlohmann::json OptionalNumber(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(); }

int Run(const DenoiseArgs& a) {
  if (a.output.empty() && a.json_path.empty()) {
    return ReportError(kDenoiseName, InvalidArgument("nothing to write: give -o OUT.csv and/or --json FILE"));
  }
  Result<Method> method = MakeMethod(a);
  if (!method.ok()) return ReportError(kDenoiseName, method.error());
  Result<LogSpec> spec = ToLogSpec(a.log);
  if (!spec.ok()) return ReportError(kDenoiseName, spec.error());
  // CSV, ULog, DataFlash or ROS bag, with --strict (a bag read here so that it reaches the bag reader).
  Result<LogTableRead> read = DetectLogFormat(a.log.input) == LogFormat::kRosBag
                                  ? ReadBagLogTable(a.log.input, *spec, a.log.strict)
                                  : ReadLogTable(a.log.input, *spec, a.log.strict);
  if (!read.ok()) return ReportError(kDenoiseName, read.error());
  Result<Table> table = std::move(read->table);
  Result<GyroLog> log = LoadGyroLog(*table, read->spec);
  if (!log.ok()) return ReportError(kDenoiseName, log.error());
  if (log->sampling.resampled) Note(kDenoiseName, log->sampling.BriefReport());

  // Truth (for RMSE): the sum of the named columns, in deg/s, on the log's rows.
  std::vector<double> truth;
  if (!a.truth_cols.empty()) {
    if (log->sampling.resampled) {
      return ReportError(kDenoiseName, InvalidArgument("--truth-col cannot be used with --resample (the truth is not resampled)"));
    }
    truth.assign(log->num_samples(), 0.0);
    for (const std::string& name : SplitList(a.truth_cols)) {
      const int c = table->Find(name);
      if (c < 0) return ReportError(kDenoiseName, InvalidInput(table->source + ": no column '" + name + "' (--truth-col)"));
      for (std::size_t i = 0; i < truth.size(); ++i) truth[i] += table->columns[static_cast<std::size_t>(c)][i];
    }
  }

  // Output table: the input columns (or the resampled log's) plus one denoised column per axis.
  Table out;
  if (log->sampling.resampled) {
    out.source = log->source;
    out.Add("time_s", log->time_s);
    for (std::size_t k = 0; k < log->axis_names.size(); ++k) out.Add(log->axis_names[k], log->rate_dps[k]);
    if (log->has_temperature()) out.Add("temp_c", log->temp_c);
  } else {
    out = *table;
  }
  const bool single = log->axis_names.size() == 1;
  nlohmann::json axes = nlohmann::json::object();
  for (std::size_t k = 0; k < log->axis_names.size(); ++k) {
    const std::string& axis = log->axis_names[k];
    const std::vector<double>& x = log->rate_dps[k];
    std::string report;
    Result<std::vector<double>> y = method->Apply(x, &report);
    if (!y.ok()) return ReportError(kDenoiseName, Error{y.error().kind, axis + ": " + y.error().message});
    nlohmann::json j;
    j["method"] = method->name;
    j["summary"] = report;
    j["n_samples"] = x.size();
    j["fs_hz"] = log->fs_hz;
    if (!truth.empty()) {
      j["rmse_before_dps"] = Rms(x, truth);
      j["rmse_after_dps"] = Rms(*y, truth);
    }
    if (!a.json_path.empty() && x.size() >= 3) {
      Result<AllanResult> before = ComputeAllan(x, log->fs_hz);
      Result<AllanResult> after = ComputeAllan(*y, log->fs_hz);
      if (!before.ok()) return ReportError(kDenoiseName, before.error());
      if (!after.ok()) return ReportError(kDenoiseName, after.error());
      j["arw_before_deg_per_sqrt_h"] = OptionalNumber(before->terms.arw_deg_per_sqrt_h);
      j["arw_after_deg_per_sqrt_h"] = OptionalNumber(after->terms.arw_deg_per_sqrt_h);
      j["adev_min_before_deg_per_h"] = before->terms.adev_min_deg_per_h;
      j["adev_min_after_deg_per_h"] = after->terms.adev_min_deg_per_h;
    }
    if (a.bandwidth) {
      // Background: the record itself (its first segment), so that thresholds and the adaptive
      // FLP see the noise they see in use.
      const std::size_t n = std::min(a.bandwidth_segment, x.size());
      BandwidthOptions bo;
      bo.fs_hz = log->fs_hz;
      bo.num_frequencies = a.bandwidth_frequencies;
      bo.amplitude = a.bandwidth_amplitude;
      const Method& m = *method;
      SignalProcessing p = [&m](std::span<const double> s) { return m.Apply(s, nullptr); };
      Result<BandwidthResult> bw = MeasureBandwidth(p, std::span<const double>(x.data(), n), bo);
      if (!bw.ok()) return ReportError(kDenoiseName, Error{bw.error().kind, axis + ": bandwidth: " + bw.error().message});
      j["bandwidth_hz"] = OptionalNumber(bw->bandwidth_hz);
      j["bandwidth_below_range"] = bw->bandwidth_below_range;
      j["bandwidth_max_tested_hz"] = bw->max_frequency_hz;
      j["delay_s"] = bw->delay_s;
      j["bandwidth_report"] = bw->BriefReport();
      j["bandwidth_segment_samples"] = n;
      j["bandwidth_test_amplitude_dps"] = bw->amplitude;
    }
    if (a.json_path != "-") std::cout << axis << ": " << report << "\n";
    axes[axis] = j;
    SetColumn(kDenoiseName, &out, single ? "denoised_dps" : axis + "_denoised", std::move(*y));
  }
  if (!a.output.empty()) {
    if (Status s = WriteCsv(a.output, out); !s.ok()) return ReportError(kDenoiseName, s.error());
  }
  if (!a.json_path.empty()) {
    nlohmann::json j = single ? axes.begin().value() : nlohmann::json{{"axes", axes}};
    j["input"] = log->source;
    j["sampling"] = log->sampling.BriefReport();
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kDenoiseName, s.error());
  }
  return kExitOk;
}

Command MakeDenoise(CLI::App& app) {
  auto args = std::make_shared<DenoiseArgs>();
  DenoiseArgs& a = *args;
  CLI::App* sub = app.add_subcommand(
      kDenoiseName, "Denoise the rate column(s): wavelet thresholding, FLP (variable-step LMS predictor) or WFLP "
             "(paper Section 3.3)");
  AddLogOptions(sub, &a.log);
  sub->add_option("--method", a.method, "wavelet | flp | wflp")
      ->required()
      ->check(CLI::IsMember({"wavelet", "flp", "wflp"}));
  AddOutputOption(sub, "-o,--output", &a.output,
                  "Output CSV: the input columns plus denoised_dps (several axes: <col>_denoised)");
  AddOutputOption(sub, "--json", &a.json_path, "Write a summary (and the metrics below) as JSON ('-' = stdout)");
  std::string g = "Wavelet (wavelet, wflp)";
  sub->add_option("--wavelet", a.wavelet, "haar, db1-db20, sym2-sym20, coif1-coif5")->group(g)->capture_default_str();
  sub->add_option("--level", a.level, "Decomposition level (default 4)")->check(CLI::NonNegativeNumber)->group(g);
  sub->add_flag("--max-level", a.max_level, "Use the deepest level for the record length (pywt dwt_max_level)")->group(g);
  sub->add_option("--extension", a.extension, "symmetric | periodization | periodic | zero | reflect | constant")
      ->group(g)
      ->capture_default_str();
  sub->add_option("--threshold", a.threshold,
                  "universal (sigma from MAD of cD1, one threshold) | universal-level | sure")
      ->group(g)
      ->capture_default_str();
  sub->add_option("--threshold-mode", a.threshold_mode, "soft | hard")->group(g)->capture_default_str();
  sub->add_option("--details", a.details, "wflp: detail coefficients threshold | keep | zero")
      ->group(g)
      ->capture_default_str();
  sub->add_option("--noise-sigma", a.noise_sigma, "Known white-noise SD, deg/s (default: MAD estimate)")
      ->check(CLI::NonNegativeNumber)
      ->group(g);
  g = "FLP (flp, wflp)";
  sub->add_option("--flp-order", a.flp.order, "Prediction order N (Eq. 14)")->group(g)->capture_default_str();
  sub->add_option("--flp-beta", a.flp.beta, "Maximum step beta of Eq. 16 (normalised, 0 < beta < 2)")
      ->group(g)
      ->capture_default_str();
  sub->add_option("--flp-alpha", a.flp.alpha, "alpha of Eq. 16 (per normalised squared error)")
      ->group(g)
      ->capture_default_str();
  sub->add_option("--flp-forgetting", a.flp.power_forgetting, "Forgetting factor of the power estimate")
      ->group(g)
      ->capture_default_str();
  sub->add_option("--flp-init", a.flp_init, "Initial weights: moving-average | zero | last-sample")
      ->group(g)
      ->capture_default_str();
  g = "Metrics (JSON)";
  sub->add_option("--truth-col", a.truth_cols,
                  "Column(s) holding the true signal, deg/s, summed (e.g. true_rate_dps,true_drift_dps): "
                  "RMSE before/after")
      ->group(g);
  sub->add_flag("--bandwidth", a.bandwidth,
                "Measure the -3 dB bandwidth and delay by adding test sines to a segment of the record")
      ->group(g);
  // 0 would run the measurement on an all-zero background and exited 0. The floor is
  // BandwidthOptions::num_samples's (>= 256; MeasureBandwidth's window is 80% of it, >= 128).
  sub->add_option("--bandwidth-segment", a.bandwidth_segment, "Samples of the record used as background")
      ->check(IntegerRange(256, 1'000'000'000, "BandwidthOptions::num_samples"))
      ->group(g)
      ->capture_default_str();
  // At least 2 (BandwidthOptions::num_frequencies); above 10000 the log-spaced frequencies,
  // rounded to whole cycles, are duplicates dropped anyway.
  sub->add_option("--bandwidth-frequencies", a.bandwidth_frequencies, "Number of test frequencies")
      ->check(IntegerRange(2, 10'000, "BandwidthOptions::num_frequencies"))
      ->group(g)
      ->capture_default_str();
  sub->add_option("--bandwidth-amplitude", a.bandwidth_amplitude,
                  "Amplitude of the test sines, deg/s (default: the segment's SD). Adaptive methods (flp, wflp) "
                  "pass strong tones better than weak ones: try both")
      ->check(CLI::PositiveNumber)
      ->group(g);
  sub->footer(
      "Methods:\n"
      "  wavelet: DWT, soft/hard threshold of every detail level, approximation untouched, inverse DWT.\n"
      "    --threshold universal --threshold-mode soft is the rule of tests/golden/wavelet/wavedec.json:\n"
      "    sigma = median(|cD1|)/0.6745, thr = sigma*sqrt(2 ln N).\n"
      "  flp: causal one-step predictor, weights adapted by normalised LMS with the variable step of\n"
      "    Eq. 16; the output is the prediction (sample by sample, as in firmware).\n"
      "  wflp: DWT; FLP on the approximation; details thresholded (--details); inverse DWT.\n"
      "JSON (--json): per axis method, summary, rmse_before/after_dps (with --truth-col),\n"
      "  arw_before/after_deg_per_sqrt_h (sigma(1 s) x 60), adev_min_before/after_deg_per_h,\n"
      "  bandwidth_hz and delay_s (with --bandwidth). A lower ARW bought by a narrower bandwidth is\n"
      "  low-pass filtering: read the two together (docs/explanation/denoising.md).");
  return {sub, [args] { return Run(*args); }};
}

const CommandRegistrar kDenoiseRegistrar(kDenoiseName, 50, &MakeDenoise);

}  // namespace
}  // namespace gyrocomp::cli
