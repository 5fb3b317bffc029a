#include "validation_report.h"

#include <cstdio>

#include "report_builder.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

std::string TauLabel(double tau_s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "ADEV at tau = %.4g s, compensated / raw (deg/s)", tau_s);
  return buf;
}

std::string Pair(double compensated, double raw) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.4g / %.4g", compensated, raw);
  return buf;
}

std::string Percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g%%", 100.0 * fraction);
  return buf;
}

}  // namespace

nlohmann::json ValidationReportTable(const std::vector<ValidationSection>& sections, const std::string& title) {
  nlohmann::json columns = {"quantity"};
  for (const ValidationSection& s : sections) columns.push_back(s.label);
  std::vector<nlohmann::json> rows;
  auto add = [&](const std::string& name, auto cell) {
    nlohmann::json row = {name};
    for (const ValidationSection& s : sections) row.push_back(cell(*s.validation));
    rows.push_back(row);
  };
  add("residual drift RMS, compensated (deg/s)", [](const DriftValidation& v) { return Num(v.residual_drift_rms); });
  add("drift RMS, raw (deg/s)", [](const DriftValidation& v) { return Num(v.raw_drift_rms); });
  add("residual mean (deg/s)", [](const DriftValidation& v) { return Num(v.residual_mean); });
  add("residual slope vs T (deg/s per deg C)", [](const DriftValidation& v) { return Num(v.slope_vs_temp); });
  add("residual slope vs dT/dt (deg/s per deg C/s)", [](const DriftValidation& v) { return Num(v.slope_vs_dtemp); });
  add("RMSE vs true drift (deg/s)", [](const DriftValidation& v) {
    return v.rmse_vs_true_drift ? Num(*v.rmse_vs_true_drift) : nlohmann::json("no truth column");
  });
  // The prediction band: its width and how much of the truth / the block means it held.
  add("90% band half-width RMS (deg/s)", [](const DriftValidation& v) {
    return v.band_half_width_rms ? Num(*v.band_half_width_rms) : nlohmann::json("no band in the model file");
  });
  add("band coverage of the true drift", [](const DriftValidation& v) {
    return v.band_coverage_truth ? nlohmann::json(Percent(*v.band_coverage_truth)) : nlohmann::json("-");
  });
  add("band coverage of the rate's block means", [](const DriftValidation& v) {
    return v.band_coverage_blocks ? nlohmann::json(Percent(*v.band_coverage_blocks)) : nlohmann::json("-");
  });
  add("samples with T outside the fitted range", [](const DriftValidation& v) { return Percent(v.fraction_temp_outside); });
  add("samples with dT/dt outside the fitted range",
      [](const DriftValidation& v) { return Percent(v.fraction_dtemp_outside); });
  add("block means (residual drift)", [](const DriftValidation& v) { return nlohmann::json(v.num_blocks); });
  // ADEV rows: the taus of the first section (every section of one run shares them).
  const DriftValidation& first = *sections.front().validation;
  for (std::size_t i = 0; i < first.tau_s.size(); ++i) {
    add(TauLabel(first.tau_s[i]), [i](const DriftValidation& v) {
      return i < v.tau_s.size() ? nlohmann::json(Pair(v.adev_compensated[i], v.adev_raw[i])) : nlohmann::json();
    });
  }
  std::string note =
      "Residual drift: the compensated rate in block means, about its mean (raw: the same for the raw rate); "
      "slopes: least squares of the residual block means on T and dT/dt (what the model missed; 0 = nothing "
      "left); ADEV: overlapping, tau >= the validation's min tau. Keys: docs/reference/cli-contract.md (validate).";
  for (const ValidationSection& s : sections) {
    if (s.model) note += " " + s.label + ": " + s.model->selection_reason;
  }
  return {{"title", title}, {"columns", columns}, {"rows", rows}, {"note", note}};
}

ReportData BuildValidationReport(const std::vector<ValidationSection>& sections, const std::string& title,
                                 const std::string& subtitle, const nlohmann::json& parameters) {
  ReportData data;
  nlohmann::json& c = data.content;
  c["title"] = title;
  c["subtitle"] = subtitle;
  nlohmann::json allan = nlohmann::json::array();
  for (const ValidationSection& s : sections) {
    const DriftValidation& v = *s.validation;
    if (v.tau_s.empty()) continue;
    allan.push_back({{"name", s.label + ": raw"}, {"tau_s", v.tau_s}, {"adev_dps", v.adev_raw}});
    allan.push_back({{"name", s.label + ": compensated"}, {"tau_s", v.tau_s}, {"adev_dps", v.adev_compensated}});
  }
  if (!allan.empty()) c["allan"] = allan;
  c["tables"] = nlohmann::json::array({ValidationReportTable(sections, "Validation on a run the model was not fitted on")});
  c["parameters"] = parameters;
  c["versions"] = SoftwareVersions();
  return data;
}

}  // namespace gyrocomp::cli
