// gyrocomp apply: predict the drift of a record from its temperature with a saved model and
// subtract it (cli.md). Warns, with the amounts, when the record leaves the fitted range.
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/core/units.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/io.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kApplyName = "apply";

struct ApplyArgs {
  LogOptions log;
  std::string model_path;
  std::string output;
  std::string json_path;
  std::string truth_col = "true_drift_dps";
  bool causal = false;
  std::string out_of_range;  // "" = the model file's policy
};

double Rmse(const std::vector<double>& a, const std::vector<double>& b) {
  double ss = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) ss += (a[i] - b[i]) * (a[i] - b[i]);
  return a.empty() ? 0.0 : std::sqrt(ss / static_cast<double>(a.size()));
}

// Never an absurd or non-finite drift (a model far outside its range, coefficients at
// the edge of double): refused with the row and temperature, never written with exit 0.
Status CheckPlausibleDrift(const std::string& model_path, const GyroLog& log, const std::vector<double>& predicted) {
  for (std::size_t i = 0; i < predicted.size(); ++i) {
    if (std::abs(predicted[i]) <= LogSpec{}.max_abs_rate_dps) continue;
    return InvalidInput(model_path + ": predicts a drift of " + std::to_string(predicted[i]) + " deg/s at " +
                        log.source + " row " + std::to_string(i + 1) + " (temp " + std::to_string(log.temp_c[i]) +
                        " C): beyond any gyroscope");
  }
  return {};
}

int Run(const ApplyArgs& a) {
  Result<DriftModelSet> set = LoadDriftModelSet(a.model_path);
  if (!set.ok()) return ReportError(kApplyName, set.error());
  if (!a.out_of_range.empty())
    for (DriftModel& m : set->axes) m.out_of_range = *ParseOutOfRangePolicy(a.out_of_range);
  Result<LogSpec> spec = ToLogSpec(a.log);
  if (!spec.ok()) return ReportError(kApplyName, spec.error());
  spec->temp_required = true;
  Result<LoadedLog> loaded = LoadLog(kApplyName, a.log, *spec);
  if (!loaded.ok()) return ReportError(kApplyName, loaded.error());
  const GyroLog& log = loaded->log;
  Table out = loaded->table;
  const DriftInputs inputs{log.temp_c, log.fs_hz};

  // One axis: predicted_drift_dps, compensated_dps. Several: <axis>_predicted_drift /
  // <axis>_compensated, each with its own model when the file has one per axis.
  const bool one = log.axis_names.size() == 1;
  // <axis>_predicted_drift / <axis>_compensated are in the unit of the rate column they are named
  // after (ULog / DataFlash: rad/s; CSV: --rate-unit); the _dps columns stay deg/s.
  const RateUnit col_unit = DetectLogFormat(a.log.input) == LogFormat::kCsv ? spec->rate_unit : RateUnit::kRadPerSec;
  const double to_col_unit = one ? 1.0 : 1.0 / units::ToDegPerSec(col_unit);
  const int truth = out.Find(a.truth_col);
  nlohmann::json axes = nlohmann::json::array();
  std::vector<double> first_prediction;
  for (std::size_t k = 0; k < log.axis_names.size(); ++k) {
    const DriftModel* model = set->ForAxis(log.axis_names[k]);
    if (!model)
      return ReportError(kApplyName, InvalidInput(a.model_path + ": no model for rate column '" + log.axis_names[k] + "'"));
    Result<std::vector<double>> predicted = model->Predict(inputs, a.causal);
    if (!predicted.ok()) return ReportError(kApplyName, predicted.error());
    if (Status s = CheckPlausibleDrift(a.model_path, log, *predicted); !s.ok()) return ReportError(kApplyName, s.error());
    const TemperatureExcursion range = model->CheckTemperatureRange(log.temp_c);
    if (range.outside && k == 0) Note(kApplyName, "warning: " + range.Message());
    std::vector<double> comp(log.num_samples());
    for (std::size_t i = 0; i < comp.size(); ++i) comp[i] = log.rate_dps[k][i] - (*predicted)[i];
    nlohmann::json j;
    j["rate_col"] = log.axis_names[k];
    j["model"] = DriftSummaryJson(model->summary);
    j["out_of_range"] = OutOfRangePolicyName(model->out_of_range);
    j["temp_outside_fitted_range"] = range.outside;
    j["temp_below_fitted_c"] = range.below_c;
    j["temp_above_fitted_c"] = range.above_c;
    j["fraction_outside_fitted_range"] = range.fraction_outside;
    // When the record carries the true drift (simulator output), score the prediction.
    if (truth >= 0) j["rmse_vs_" + a.truth_col] = Rmse(*predicted, out.columns[truth]);
    // The 90% band (cli.md "apply (bands)"): a model file written before it has none.
    if (model->band) {
      Result<DriftBand> band = model->PredictBand(inputs, a.causal);
      if (!band.ok()) return ReportError(kApplyName, band.error());
      if (truth >= 0) {
        std::size_t inside = 0;
        for (std::size_t i = 0; i < band->lo.size(); ++i)
          inside += out.columns[truth][i] >= band->lo[i] && out.columns[truth][i] <= band->hi[i] ? 1 : 0;
        j["band_coverage_of_" + a.truth_col] = band->lo.empty() ? 0.0 : static_cast<double>(inside) / band->lo.size();
      }
      double half2 = 0.0;
      for (std::size_t i = 0; i < band->lo.size(); ++i) half2 += std::pow(0.5 * (band->hi[i] - band->lo[i]), 2);
      j["band_level"] = band->level;
      j["band_half_width_rms"] = band->lo.empty() ? 0.0 : std::sqrt(half2 / band->lo.size());
      // In the unit of the rate column they are named after, as the prediction below.
      for (double& v : band->lo) v *= to_col_unit;
      for (double& v : band->hi) v *= to_col_unit;
      SetColumn(kApplyName, &out, one ? "predicted_drift_lo_dps" : log.axis_names[k] + "_predicted_drift_lo", band->lo);
      SetColumn(kApplyName, &out, one ? "predicted_drift_hi_dps" : log.axis_names[k] + "_predicted_drift_hi", band->hi);
    } else {
      j["band_level"] = nullptr;
      j["band_level_reason"] = "model_has_no_band";
      j["band_level_why"] = "the model file holds no prediction band (written before bands existed): refit it "
                            "with gyrocomp fit to get one";
      if (k == 0) Note(kApplyName, "note: " + a.model_path + " has no prediction band (a schema-1 model file, written before prediction bands); "
                                  "no _lo/_hi columns: refit it to get one");
    }
    axes.push_back(j);
    std::vector<double> predicted_col = *predicted;
    for (double& v : predicted_col) v *= to_col_unit;
    for (double& v : comp) v *= to_col_unit;
    SetColumn(kApplyName, &out, one ? "predicted_drift_dps" : log.axis_names[k] + "_predicted_drift", std::move(predicted_col));
    SetColumn(kApplyName, &out, one ? "compensated_dps" : log.axis_names[k] + "_compensated", std::move(comp));
  }
  if (Status s = WriteCsv(a.output, out); !s.ok()) return ReportError(kApplyName, s.error());

  // The first axis's keys at the top level (as before), every axis under "axes".
  nlohmann::json j = axes[0];
  j.erase("rate_col");
  j["model_file"] = a.model_path;
  j["input"] = out.source;
  j["n_samples"] = log.num_samples();
  j["fs_hz"] = log.fs_hz;
  j["causal"] = a.causal;
  j["axes"] = axes;
  if (!a.json_path.empty()) {
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kApplyName, s.error());
  }
  if (a.json_path != "-") {
    std::cout << "applied " << set->axes.size() << " model(s) (" << DriftModelKindName(set->axes[0].kind) << ", "
              << DriftInputSetName(set->axes[0].inputs) << (a.causal ? ", causal" : "") << ") to "
              << log.num_samples() << " samples; wrote " << a.output;
    if (truth >= 0) std::cout << "; RMSE vs " << a.truth_col << " = " << j["rmse_vs_" + a.truth_col].get<double>() << " deg/s";
    std::cout << "\n";
  }
  return kExitOk;
}

Command MakeApply(CLI::App& app) {
  auto a = std::make_shared<ApplyArgs>();
  CLI::App* sub = app.add_subcommand(kApplyName, "Apply a saved drift model: predict the drift from temperature and subtract it");
  sub->footer(
      "OUT.csv: the input columns plus predicted_drift_dps and compensated_dps (= rate -\n"
      "predicted); with several --rate-col axes, <axis>_predicted_drift and <axis>_compensated, each\n"
      "with the model file's model for that rate column (or its only model). The 90% prediction band\n"
      "of the drift: predicted_drift_lo_dps / predicted_drift_hi_dps (<axis>_predicted_drift_lo / _hi);\n"
      "a model file written before the bands existed has none (a note says so). Thermal states, when the\n"
      "model uses one, are computed from this record with the model's own parameters. Temperatures outside the\n"
      "range the model was fitted on are reported (how far, what share of samples).\n"
      "JSON: model summary, n_samples, fs_hz, causal, out_of_range, axes[], temp_outside_fitted_range, temp_below_fitted_c,\n"
      "  temp_above_fitted_c, fraction_outside_fitted_range, and rmse_vs_true_drift_dps when the\n"
      "  record has a true_drift_dps column (simulator output); band_level, band_half_width_rms and\n"
      "  band_coverage_of_true_drift_dps (share of samples whose true drift lies in the band).\n"
      "Example: gyrocomp apply -m model.json -i run2.csv -o compensated.csv");
  AddInputOption(sub, "-m,--model", &a->model_path, "Model file written by gyrocomp fit")->required();
  AddLogOptions(sub, &a->log);
  AddOutputOption(sub, "-o,--output", &a->output, "Output CSV")->required();
  AddOutputOption(sub, "--json", &a->json_path, "Write a summary as JSON to FILE ('-' = stdout)");
  sub->add_flag("--causal", a->causal,
                "Evaluate thermal states one sample at a time as firmware does (dT/dt by two lags instead of the "
                "centred slope; lag and memory are causal either way)");
  sub->add_option("--out-of-range", a->out_of_range, "Override the model's policy: extrapolate | clamp")
      ->check(CLI::IsMember({"extrapolate", "clamp"}));
  sub->add_option("--truth-col", a->truth_col, "Column with the true drift, scored when present")->capture_default_str();
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kApplyRegistrar(kApplyName, 65, &MakeApply);

}  // namespace
}  // namespace gyrocomp::cli
