#include "gyrocomp/report/pipeline_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Core>
#include <fftw3.h>
#include <libsvm/svm.h>

#include "gyrocomp/core/format.h"
#include "gyrocomp/core/units.h"
#include "gyrocomp/denoise/wavelet.h"
#include "gyrocomp/denoise/wavelet_denoise.h"
#include "gyrocomp/report/applicability.h"

namespace gyrocomp {
namespace {

// A JSON number, or null for NaN / Inf / absent (as the CLI's JSON writes them).
nlohmann::json Num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }
nlohmann::json Num(const std::optional<double>& v) { return v ? Num(*v) : nlohmann::json(); }

// Three significant digits, "n/a" when not finite: the EDF in a row's name.
std::string EdfText(double edf) { return std::isfinite(edf) ? FormatNumber(edf, 3) : "n/a"; }

std::vector<double> Hours(std::span<const double> t_s) {
  std::vector<double> h(t_s.size());
  for (std::size_t i = 0; i < h.size(); ++i) h[i] = t_s[i] / units::kSecondsPerHour;
  return h;
}

// The ADEV curve with its confidence band and the fitted noise-term lines (ARW and RRW only where
// the not-applicable rule accepts them: a line the processing made would contradict the table).
nlohmann::json AllanCurveJson(const AllanResult& a, const std::string& name, std::optional<double> bandwidth_hz) {
  const AllanCurve& c = a.curve;
  nlohmann::json j = {{"name", name}, {"tau_s", c.tau_s}, {"adev_dps", c.adev_dps},
                      {"lo_dps", c.adev_lo_dps}, {"hi_dps", c.adev_hi_dps}};
  nlohmann::json lines = nlohmann::json::array();
  if (!c.tau_s.empty()) {
    const double t0 = c.tau_s.front(), t1 = c.tau_s.back();
    if (a.terms.arw_deg_per_sqrt_h && ArwApplicability(a, bandwidth_hz).applicable) {  // sigma = N / sqrt(tau)
      const double n_dps = units::DegPerSqrtHourToDegPerSqrtSec(*a.terms.arw_deg_per_sqrt_h);
      lines.push_back({{"name", "ARW"}, {"tau_s", {t0, t1}}, {"adev_dps", {n_dps / std::sqrt(t0), n_dps / std::sqrt(t1)}}});
    }
    const double floor_dps = units::DphToDps(a.terms.adev_min_deg_per_h);
    lines.push_back({{"name", "ADEV min"}, {"tau_s", {t0, t1}}, {"adev_dps", {floor_dps, floor_dps}}});
    if (a.terms.rrw_deg_per_h_per_sqrt_h && RrwApplicability(a, bandwidth_hz).applicable) {  // K sqrt(tau / 3)
      const double k = units::DphPerSqrtHourToDpsPerSqrtSec(*a.terms.rrw_deg_per_h_per_sqrt_h);
      lines.push_back({{"name", "RRW"}, {"tau_s", {t0, t1}}, {"adev_dps", {k * std::sqrt(t0 / 3.0), k * std::sqrt(t1 / 3.0)}}});
    }
  }
  j["lines"] = lines;
  return j;
}

nlohmann::json ChangeCell(const std::optional<double>& before, const std::optional<double>& after) {
  if (!before || !after || *before == 0.0) return nullptr;
  return std::round(1000.0 * (*after - *before) / *before) / 10.0;
}

// Local log-log slope of the curve at the tau nearest tau_s.
std::optional<double> SlopeNear(const AllanCurve& c, double tau_s) {
  std::optional<double> slope;
  double best = 1e300;
  for (std::size_t i = 0; i < c.size() && i < c.slope.size(); ++i) {
    const double d = std::abs(std::log(c.tau_s[i] / tau_s));
    if (d < best) { best = d; slope = c.slope[i]; }
  }
  return slope;
}

}  // namespace

std::optional<double> AdevMinAbove(const AllanCurve& c, double tau_min_s) {
  std::optional<double> best;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c.tau_s[i] >= tau_min_s && (!best || c.adev_dps[i] < *best)) best = c.adev_dps[i];
  }
  if (best) *best = units::DpsToDph(*best);
  return best;
}

std::vector<std::string> HonestyNotes(const PipelineResult& r) {
  std::vector<std::string> notes;
  const auto slope = SlopeNear(r.allan_after.curve, 1.0);
  if (slope && std::abs(*slope + 0.5) > 0.2) {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "After processing the ADEV slope at tau = 1 s is %+.2f, not -1/2: the output is no longer "
                  "white at 1 s, so 'ARW after' is sigma(1 s) of a low-passed signal (bandwidth %s Hz), "
                  "not an angle random walk coefficient.",
                  *slope, r.bandwidth && r.bandwidth->bandwidth_hz ? std::to_string(*r.bandwidth->bandwidth_hz).c_str() : "n/a");
    notes.emplace_back(buf);
  }
  if (!r.allan_after.curve.tau_s.empty() &&
      r.allan_after.terms.tau_at_min_s <= r.allan_after.curve.tau_s.front() * 1.0001) {
    notes.emplace_back("After processing the ADEV minimum is at the shortest tau, where the filter removed the "
                       "signal; the 'ADEV minimum over tau >= 10 s' row is the bias-stability figure to compare, "
                       "and the +1/2 region that 'RRW after' is fitted on is made by the filter, not by a rate "
                       "random walk.");
  }
  for (const auto& [when, terms] : {std::pair{"before", &r.allan_before.terms}, std::pair{"after", &r.allan_after.terms}}) {
    if (terms->min_at_longest_tau) {
      notes.push_back(std::string("The ADEV minimum ") + when + " processing is at the longest tau: the floor was "
                      "not reached and the figure is an upper bound (a point with few degrees of freedom).");
    }
  }
  return notes;
}

std::optional<double> ProcessedBandwidth(const PipelineResult& r) {
  if (r.bandwidth) return r.bandwidth->bandwidth_hz;
  return std::nullopt;
}

namespace {
BeforeAfterRow Row(std::string metric, std::optional<double> before, std::optional<double> after, std::string unit) {
  BeforeAfterRow row;
  row.metric = std::move(metric);
  row.before = before;
  row.after = after;
  row.unit = std::move(unit);
  return row;
}
}  // namespace

std::vector<BeforeAfterRow> BeforeAfterRows(const PipelineResult& r) {
  const AllanNoiseTerms& b = r.allan_before.terms;
  const AllanNoiseTerms& a = r.allan_after.terms;
  const std::optional<double> bw_before = r.fs_hz / 2.0, bw_after = ProcessedBandwidth(r);
  BeforeAfterRow arw = Row("ARW", b.arw_deg_per_sqrt_h, a.arw_deg_per_sqrt_h, "deg/sqrt(h)");
  BeforeAfterRow rrw = Row("RRW", b.rrw_deg_per_h_per_sqrt_h, a.rrw_deg_per_h_per_sqrt_h, "deg/h/sqrt(h)");
  const std::pair<BeforeAfterRow*, TermApplicability (*)(const AllanResult&, std::optional<double>,
                                                      const TermApplicabilityOptions&)>
      checked[] = {{&arw, &ArwApplicability}, {&rrw, &RrwApplicability}};
  for (const auto& [row, rule] : checked) {
    if (const TermApplicability t = rule(r.allan_before, bw_before, {}); !t.applicable) {
      row->before.reset();
      row->before_na = t.reason;
    }
    if (const TermApplicability t = rule(r.allan_after, bw_after, {}); !t.applicable) {
      row->after.reset();
      row->after_na = t.reason;
    }
  }
  std::vector<BeforeAfterRow> rows = {
      arw,
      Row("ADEV minimum (bias stability)", b.adev_min_deg_per_h, a.adev_min_deg_per_h, "deg/h"),
      Row("bias instability (min / 0.664)", b.bias_instability_deg_per_h, a.bias_instability_deg_per_h, "deg/h"),
      Row("ADEV minimum over taus with EDF >= " + EdfText(b.min_edf), b.adev_min_usable_deg_per_h,
          a.adev_min_usable_deg_per_h, "deg/h"),
      Row("ADEV minimum over tau >= 10 s", AdevMinAbove(r.allan_before.curve, 10.0),
          AdevMinAbove(r.allan_after.curve, 10.0), "deg/h"),
      rrw,
  };
  rows.push_back(Row("bandwidth (-3 dB)", bw_before, bw_after, "Hz"));
  return rows;
}

nlohmann::json SoftwareVersions() {
  return {{"gyrocomp", GYROCOMP_VERSION},
          {"FFTW", std::string(fftw_version)},
          {"LIBSVM", std::to_string(libsvm_version)},
          {"Eigen", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                        std::to_string(EIGEN_MINOR_VERSION)},
          {"nlohmann_json", std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." +
                                std::to_string(NLOHMANN_JSON_VERSION_MINOR) + "." +
                                std::to_string(NLOHMANN_JSON_VERSION_PATCH)},
          {"uPlot", "1.6.32 (MIT), bundled"}};
}

namespace {

// Before/after table (BeforeAfterRows) with the bandwidth caveat and HonestyNotes.
nlohmann::json SummaryJson(const PipelineResult& r) {
  nlohmann::json rows = nlohmann::json::array();
  std::string na_note;
  for (const BeforeAfterRow& row : BeforeAfterRows(r)) {
    const nlohmann::json before = row.before_na.empty() ? Num(row.before) : nlohmann::json("not applicable");
    const nlohmann::json after = row.after_na.empty() ? Num(row.after) : nlohmann::json("not applicable");
    rows.push_back({row.metric + " (" + row.unit + ")", before, after, ChangeCell(row.before, row.after)});
    if (!row.before_na.empty()) na_note += " Before: " + row.before_na + ".";
    if (!row.after_na.empty()) na_note += " After: " + row.after_na + ".";
  }
  std::string note = "Bandwidth 'before' is the Nyquist frequency of the raw record. A lower ARW "
                     "obtained by narrowing the bandwidth is low-pass filtering: read the two together.";
  if (!na_note.empty()) {
    note += " Not applicable (rule: bandwidth known, taus >= 1/(2 bandwidth), ADEV slope within 0.2 of "
            "-1/2 for ARW, +1/2 for RRW):" + na_note;
  }
  for (const std::string& s : HonestyNotes(r)) note += " " + s;
  return {{"columns", {"metric", "before", "after", "change (%)"}}, {"rows", rows}, {"note", note}};
}

// The VMD modes (Fig. 8) with their sample entropy and class (Fig. 9).
nlohmann::json ModesJson(const PipelineResult& r, const std::vector<double>& hours) {
  nlohmann::json modes = nlohmann::json::array();
  for (std::size_t k = 0; k < r.mode_reports.size() && k < r.modes.size(); ++k) {
    const ModeReport& m = r.mode_reports[k];
    const DisplaySeries d = MinMaxEnvelope(hours, r.modes[k], 400);
    modes.push_back({{"index", m.index}, {"sample_entropy", Num(m.sample_entropy)},
                     {"center_frequency_hz", Num(m.center_frequency_hz)},
                     {"class", FeatureClassName(m.feature)}, {"x", d.x}, {"y", d.y}});
  }
  return modes;
}

// The model's prediction band (DriftModel::PredictBand) over the record, as block means
// of its lower and upper edges on the same blocks as the prediction: model_lo_dps / model_hi_dps,
// band_level. A model without a band (or a band that cannot be evaluated) adds nothing.
void AddDriftBand(const DriftModel& m, const PipelineResult& r, const PipelineReportContext& ctx, std::size_t points,
                  nlohmann::json* drift) {
  if (!m.band || ctx.temp_c.size() != r.num_samples || points == 0) return;
  auto band = m.PredictBand({ctx.temp_c, r.fs_hz});
  if (!band.ok() || band->lo.size() != r.num_samples) return;
  const std::size_t n = r.num_samples;
  std::vector<double> lo_mean, hi_mean;
  for (std::size_t b = 0; b < points; ++b) {
    const std::size_t lo = b * n / points, hi = (b + 1) * n / points;
    double sl = 0, sh = 0;
    for (std::size_t i = lo; i < hi; ++i) sl += band->lo[i], sh += band->hi[i];
    lo_mean.push_back(sl / static_cast<double>(hi - lo));
    hi_mean.push_back(sh / static_cast<double>(hi - lo));
  }
  (*drift)["model_lo_dps"] = lo_mean;
  (*drift)["model_hi_dps"] = hi_mean;
  (*drift)["band_level"] = band->level;
}

// Drift against temperature: block means (about 1500 points) of the drift feature and of the
// model's prediction along the record.
nlohmann::json DriftVsTemperatureJson(const PipelineResult& r, const PipelineReportContext& ctx) {
  const std::size_t n = r.num_samples, points = std::min<std::size_t>(n, 1500);
  std::vector<double> t_mean, d_mean, p_mean;
  for (std::size_t b = 0; b < points; ++b) {
    const std::size_t lo = b * n / points, hi = (b + 1) * n / points;
    double st = 0, sd = 0, sp = 0;
    for (std::size_t i = lo; i < hi; ++i) {
      st += ctx.temp_c[i];
      sd += r.features.drift[i];
      sp += r.predicted_drift_dps[i];
    }
    const double w = static_cast<double>(hi - lo);
    t_mean.push_back(st / w);
    d_mean.push_back(sd / w);
    p_mean.push_back(sp / w);
  }
  nlohmann::json drift = {{"temp_c", t_mean}, {"drift_dps", d_mean}};
  if (r.drift_model) {
    drift["model_temp_c"] = t_mean;
    drift["model_dps"] = p_mean;
    AddDriftBand(*r.drift_model, r, ctx, points, &drift);
  }
  return drift;
}

// The model's summary, with the expected drift error on the next run (the band's RMS standard
// deviation over this record, DriftBandModel::expected_rms) and the terms the run left out.
nlohmann::json DriftModelTable(const DriftModel& m) {
  const DriftFitSummary& s = m.summary;
  std::string left_out;
  for (const ExcludedTerm& e : s.excluded_terms) left_out += (left_out.empty() ? "" : ", ") + e.term;
  nlohmann::json expected = nullptr;
  if (m.band) expected = Num(m.band->expected_rms);
  return {{"title", "Drift model"},
          {"columns", {"model", "inputs", "C", "sigma", "epsilon", "support vectors", "CV RMSE (deg/s)",
                       "train RMSE (deg/s)", "expected next-run error RMS (deg/s)", "left out", "T range (deg C)",
                       "fit time (s)"}},
          {"rows", {{DriftModelKindName(s.model), DriftInputSetName(s.inputs), Num(s.C), Num(s.sigma),
                     Num(s.epsilon), s.num_support, Num(s.cv_rmse), Num(s.train_rmse), expected,
                     left_out.empty() ? "-" : left_out,
                     std::to_string(s.temp_min_c).substr(0, 6) + " .. " + std::to_string(s.temp_max_c).substr(0, 6),
                     Num(s.fit_time_s)}}},
          {"note", "C and sigma in the SVR's scaled units (standardised inputs by default). "
                   "Expected next-run error: RMS of the 90% prediction band's standard deviation over this record "
                   "(parameter uncertainty under the measured noise, model-form spread, left-out dT/dt gain; "
                   "docs/explanation/drift-models.md \"Prediction bands\"); empty when the model has no band."}};
}

// One table per comparison group (Section 4.3): denoising, drift models, serial vs parallel.
void AddComparisonTables(const ComparisonResult& comparison, nlohmann::json* tables) {
  for (const char* group : {"denoising", "drift", "scheme"}) {
    nlohmann::json rows = nlohmann::json::array();
    for (const MethodRow& m : comparison.rows) {
      if (m.group != group) continue;
      rows.push_back({m.method, Num(m.arw_deg_per_sqrt_h), Num(m.adev_min_deg_per_h), Num(m.bandwidth_hz),
                      Num(m.rmse_vs_true_rate_dps), Num(m.drift_rmse_vs_truth_dps), Num(m.seconds), m.note});
    }
    const std::string title = std::string(group) == "denoising" ? "Comparison: denoising of the mixed feature"
                            : std::string(group) == "drift"     ? "Comparison: drift models"
                                                                : "Comparison: serial vs parallel";
    tables->push_back({{"title", title},
                       {"columns", {"method", "ARW (deg/sqrt(h))", "ADEV min (deg/h)", "bandwidth (Hz)",
                                    "RMSE vs true rate (deg/s)", "drift RMSE vs truth (deg/s)", "time (s)", "note"}},
                       {"rows", rows}});
  }
}

// Classification rule, drift model, comparisons, timings, warnings.
nlohmann::json TablesJson(const PipelineResult& r, const PipelineReportContext& ctx) {
  nlohmann::json tables = nlohmann::json::array();
  tables.push_back({{"title", "Classification rule"},
                    {"columns", {"rule"}},
                    {"rows", {{r.classification_rule + (r.drift_mode_forced ? " (drift mode forced: see warnings)" : "")}}}});
  if (r.drift_model) tables.push_back(DriftModelTable(*r.drift_model));
  if (ctx.comparison) AddComparisonTables(*ctx.comparison, &tables);
  nlohmann::json timing_rows = nlohmann::json::array();
  for (const auto& [stage, seconds] : r.timings_s) timing_rows.push_back({stage, seconds});
  tables.push_back({{"title", "Timings"}, {"columns", {"stage", "seconds"}}, {"rows", timing_rows}});
  if (!r.warnings.empty()) {
    nlohmann::json w = nlohmann::json::array();
    for (const std::string& s : r.warnings) w.push_back({s});
    tables.push_back({{"title", "Warnings"}, {"columns", {"warning"}}, {"rows", w}});
  }
  return tables;
}

}  // namespace

nlohmann::json PipelineOptionsJson(const PipelineOptions& o) {
  nlohmann::json j;
  j["vmd"] = {{"K", o.vmd.num_modes}, {"alpha", o.vmd.alpha}, {"tau", o.vmd.tau}, {"tol", o.vmd.tol},
              {"dc", o.vmd.dc}, {"init", static_cast<int>(o.vmd.init)}, {"seed", o.vmd.seed},
              {"max_iterations", o.vmd.max_iterations},
              {"stopping_rule", o.vmd.stopping_rule == VmdStoppingRule::kAbsolute ? "absolute" : "relative"},
              {"mirror_extension", o.vmd.mirror_extension},
              {"omega_extrapolation_period", o.vmd.omega_extrapolation_period ? nlohmann::json(*o.vmd.omega_extrapolation_period) : nlohmann::json()},
              {"omega_extrapolation_min_samples", o.vmd.omega_extrapolation_min_samples}};
  j["sample_entropy"] = {{"m", o.entropy.m}, {"r_factor", o.entropy.r_factor},
                         {"max_samples", o.entropy_max_samples ? nlohmann::json(*o.entropy_max_samples) : nlohmann::json()}};
  j["classification"] = {{"rule", o.classifier.rule_name}, {"description", o.classifier.Describe()},
                         {"drift_max_se", o.classifier.drift_max_se}, {"noise_min_se", o.classifier.noise_min_se},
                         {"force_drift_mode", o.force_drift_mode}};
  j["wflp"] = {{"wavelet", o.wflp.wavelet}, {"level", o.wflp.level ? nlohmann::json(*o.wflp.level) : nlohmann::json()},
               {"extension", ExtensionModeName(o.wflp.extension)}, {"details", DetailHandlingName(o.wflp.details)},
               {"threshold_mode", o.wflp.threshold_mode == ThresholdMode::kSoft ? "soft" : "hard"},
               {"flp_order", o.wflp.flp.order}, {"flp_beta", o.wflp.flp.beta}, {"flp_alpha", o.wflp.flp.alpha},
               {"flp_power_forgetting", o.wflp.flp.power_forgetting}};
  const auto& cs = o.drift.search.cuckoo;
  j["drift_model"] = {{"model", DriftModelKindName(o.drift.model)}, {"inputs", DriftInputSetName(o.drift.inputs)},
                      {"svr_C", o.drift.svr.C}, {"svr_gamma", Num(o.drift.svr.gamma)}, {"svr_sigma", Num(o.drift.svr.sigma)},
                      {"svr_epsilon", o.drift.svr.epsilon}, {"svr_tol", o.drift.svr.tolerance},
                      {"scale", o.drift.svr.scaling == SvrScaling::kStandard ? "standard" : "none"},
                      {"polynomial_degree", o.drift.polynomial.degree},
                      {"search_C", {o.drift.search.C.lower, o.drift.search.C.upper}},
                      {"search_sigma", {o.drift.search.sigma.lower, o.drift.search.sigma.upper}},
                      {"nests", cs.num_nests}, {"generations", cs.max_generations},
                      {"pa", cs.discovery_probability}, {"levy_beta", cs.levy_beta}, {"step_scale", cs.step_scale},
                      {"seed", cs.seed}, {"cv_folds", o.drift.cv_folds},
                      {"train_period_s", Num(o.drift.train_period_s)},
                      {"dtemp_window_s", o.drift.rate.window_s}};
  j["allan"] = {{"confidence", o.allan.confidence}, {"points_per_decade", o.allan.points_per_decade},
                {"grid", static_cast<int>(o.allan.grid)}};
  j["bandwidth"] = {{"measured", o.measure_bandwidth}, {"segment_samples", o.bandwidth_segment_samples},
                    {"frequencies", o.bandwidth_frequencies}};
  return j;
}


ReportData BuildPipelineReport(const PipelineResult& r, const PipelineReportContext& ctx) {
  ReportData data;
  nlohmann::json& c = data.content;
  c["title"] = ctx.title;
  c["subtitle"] = ctx.source + (ctx.axis.empty() ? "" : ", axis " + ctx.axis) + ": " +
                  std::to_string(r.num_samples) + " samples at " + std::to_string(r.fs_hz) +
                  " Hz. Parallel VMD-SE-WFLP-" + (r.drift_model ? DriftModelKindName(r.drift_model->kind) : "none") +
                  " model (Chang, Cao & Shen 2020).";
  c["summary"] = SummaryJson(r);
  const std::vector<double> hours = Hours(ctx.time_s);
  const auto env = MinMaxEnvelopes(hours, {ctx.rate_dps, r.compensated_dps, ctx.temp_c}, 1500);
  c["timeseries"] = {{"x_label", "time (h)"},
                     {"x", env[0].x},
                     {"series", {{{"name", "raw rate (deg/s)"}, {"y", env[0].y}, {"axis", "rate"}},
                                 {{"name", "compensated (deg/s)"}, {"y", env[1].y}, {"axis", "rate"}},
                                 {{"name", "temperature (deg C)"}, {"y", env[2].y}, {"axis", "temp"}}}}};
  c["modes"] = ModesJson(r, hours);
  c["allan"] = {AllanCurveJson(r.allan_before, "raw", r.fs_hz / 2.0),
                AllanCurveJson(r.allan_after, "compensated", ProcessedBandwidth(r))};
  c["drift"] = DriftVsTemperatureJson(r, ctx);
  c["tables"] = TablesJson(r, ctx);
  c["parameters"] = ctx.parameters;
  c["versions"] = SoftwareVersions();
  return data;
}

}  // namespace gyrocomp
