// gyrocomp apply: predict the drift of a record from its temperature with a saved model and
// subtract it (cli.md). Warns, with the amounts, when the record leaves the fitted range.
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/causal_drift.h"
#include "gyrocomp/io/io.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kName = "apply";

struct ApplyArgs {
  LogOptions log;
  std::string model_path;
  std::string output;
  std::string json_path;
  std::string truth_col = "true_drift_dps";
  bool causal = false;           // issue 12: firmware-equivalent prediction
  std::optional<double> tau_s;   // causal dT/dt lag time constant
};

double Rmse(const std::vector<double>& a, const std::vector<double>& b) {
  double ss = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) ss += (a[i] - b[i]) * (a[i] - b[i]);
  return a.empty() ? 0.0 : std::sqrt(ss / static_cast<double>(a.size()));
}

int Run(const ApplyArgs& a) {
  Result<DriftModel> model = LoadDriftModel(a.model_path);
  if (!model.ok()) return ReportError(kName, model.error());
  Result<LogSpec> spec = ToLogSpec(a.log);
  if (!spec.ok()) return ReportError(kName, spec.error());
  spec->temp_required = true;
  Result<LoadedLog> loaded = LoadLog(kName, a.log, *spec);
  if (!loaded.ok()) return ReportError(kName, loaded.error());
  const GyroLog& log = loaded->log;
  Table out = loaded->table;

  const DriftInputs inputs{log.temp_c, log.fs_hz};
  // --causal (issue 12): what the generated C computes (causal_drift.h); else the centred model.
  CausalPredictionSummary causal;
  Result<std::vector<double>> predicted =
      a.causal ? PredictDriftCausal(*model, inputs, CausalRateOptions{a.tau_s}, &causal) : model->Predict(inputs);
  if (!predicted.ok()) return ReportError(kName, predicted.error());
  if (a.causal) Note(kName, causal.BriefReport());
  for (std::size_t i = 0; i < predicted->size(); ++i) {  // issue 15: never an absurd or non-finite drift
    if (std::abs((*predicted)[i]) <= LogSpec{}.max_abs_rate_dps) continue;
    return ReportError(kName, InvalidInput(a.model_path + ": predicts a drift of " + std::to_string((*predicted)[i]) +
                                           " deg/s at " + log.source + " row " + std::to_string(i + 1) + " (temp " +
                                           std::to_string(log.temp_c[i]) + " C): beyond any gyroscope"));
  }
  const TemperatureExcursion range = model->CheckTemperatureRange(log.temp_c);
  if (range.outside) Note(kName, "warning: " + range.Message());

  // One axis: predicted_drift_dps, compensated_dps. Several: <axis>_predicted_drift /
  // <axis>_compensated (the same temperature model applied to each).
  const bool one = log.axis_names.size() == 1;
  SetColumn(kName, &out, "predicted_drift_dps", *predicted);
  nlohmann::json axes = nlohmann::json::object();
  for (std::size_t k = 0; k < log.axis_names.size(); ++k) {
    std::vector<double> comp(log.num_samples());
    for (std::size_t i = 0; i < comp.size(); ++i) comp[i] = log.rate_dps[k][i] - (*predicted)[i];
    SetColumn(kName, &out, one ? "compensated_dps" : log.axis_names[k] + "_compensated", std::move(comp));
  }
  if (Status s = WriteCsv(a.output, out); !s.ok()) return ReportError(kName, s.error());

  nlohmann::json j;
  j["model_file"] = a.model_path;
  j["model"] = DriftSummaryJson(model->summary);
  j["input"] = out.source;
  j["n_samples"] = log.num_samples();
  j["fs_hz"] = log.fs_hz;
  j["temp_outside_fitted_range"] = range.outside;
  j["temp_below_fitted_c"] = range.below_c;
  j["temp_above_fitted_c"] = range.above_c;
  j["fraction_outside_fitted_range"] = range.fraction_outside;
  if (a.causal)
    j["causal"] = {{"tau_s", causal.tau_s}, {"delay_s", causal.delay_s}, {"samples_clamped", causal.num_clamped}};
  // When the record carries the true drift (simulator output), score the prediction.
  const int truth = out.Find(a.truth_col);
  if (truth >= 0) j["rmse_vs_" + a.truth_col] = Rmse(*predicted, out.columns[truth]);
  if (!a.json_path.empty()) {
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kName, s.error());
  }
  if (a.json_path != "-") {
    std::cout << "applied " << DriftModelKindName(model->kind) << " model (" << DriftInputSetName(model->inputs)
              << ") to " << log.num_samples() << " samples; wrote " << a.output;
    if (truth >= 0) std::cout << "; RMSE vs " << a.truth_col << " = " << j["rmse_vs_" + a.truth_col].get<double>() << " deg/s";
    std::cout << "\n";
  }
  return kExitOk;
}

Command Make(CLI::App& app) {
  auto a = std::make_shared<ApplyArgs>();
  CLI::App* sub = app.add_subcommand(kName, "Apply a saved drift model: predict the drift from temperature and subtract it");
  sub->footer(
      "OUT.csv: the input columns plus predicted_drift_dps and compensated_dps (= rate -\n"
      "predicted); with several --rate-col axes, <axis>_compensated for each. dT/dt, when the model\n"
      "uses it, is computed from this record with the model's own window. Temperatures outside the\n"
      "range the model was fitted on are reported (how far, what share of samples).\n"
      "JSON: model summary, n_samples, fs_hz, temp_outside_fitted_range, temp_below_fitted_c,\n"
      "  temp_above_fitted_c, fraction_outside_fitted_range, and rmse_vs_true_drift_dps when the\n"
      "  record has a true_drift_dps column (simulator output).\n"
      "Example: gyrocomp apply -m model.json -i run2.csv -o compensated.csv");
  AddInputOption(sub, "-m,--model", &a->model_path, "Model file written by gyrocomp fit")->required();
  AddLogOptions(sub, &a->log);
  AddOutputOption(sub, "-o,--output", &a->output, "Output CSV")->required();
  AddOutputOption(sub, "--json", &a->json_path, "Write a summary as JSON to FILE ('-' = stdout)");
  sub->add_flag("--causal", a->causal,
                "Firmware form: causal dT/dt (double lag, delay 2 tau), inputs clamped to the fitted range; "
                "equals the C of 'export --format c'");
  sub->add_option("--tau", a->tau_s, "With --causal: dT/dt lag time constant, s (default: model window / 48^(1/3))");
  sub->add_option("--truth-col", a->truth_col, "Column with the true drift, scored when present")->capture_default_str();
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kReg(kName, 65, &Make);

}  // namespace
}  // namespace gyrocomp::cli
