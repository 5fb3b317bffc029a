// gyrocomp validate: a saved drift model on a run it was not fitted on (docs/explanation/drift-models.md,
// drift_validate.h): residual drift, what the model missed, ADEV at long taus, errors against
// the truth when present, and how far the run leaves the calibration's conditions.
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "console.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/drift/drift_validate.h"
#include "gyrocomp/report/report.h"
#include "result_json.h"
#include "validation_report.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kValidateName = "validate";

struct ValidateArgs {
  LogOptions log;
  std::string model_path;
  std::string json_path;
  std::string report_path;
  std::string truth_col = "true_drift_dps";
  bool verbose = false;
  DriftValidationOptions options;
};

// One axis on stdout: the residual drift beside the uncompensated one, the error against the truth
// when given, the band's coverage and how far the run leaves the fitted range. --verbose: the
// validation's full BriefReport (slopes, block counts).
void PrintAxis(const std::string& axis, const DriftValidation& v, bool verbose) {
  if (verbose) {
    std::cout << axis << ": " << v.BriefReport() << "\n";
    return;
  }
  std::cout << axis << ": residual drift " << RateDps(v.residual_drift_rms) << " RMS against "
            << RateDps(v.raw_drift_rms) << " uncompensated";
  if (v.raw_drift_rms > 0.0) std::cout << " (" << Figure(v.residual_drift_rms / v.raw_drift_rms, 2) << "x)";
  if (v.rmse_vs_true_drift) std::cout << "; error against the true drift " << RateDps(*v.rmse_vs_true_drift);
  std::cout << "\n";
  if (v.band_level) {
    std::cout << "  " << Figure(100.0 * *v.band_level) << "% band: half-width " << RateDps(v.band_half_width_rms.value_or(NAN))
              << " RMS";
    if (v.band_coverage_truth) std::cout << ", holds " << Figure(100.0 * *v.band_coverage_truth) << "% of the true drift";
    else if (v.band_coverage_blocks)
      std::cout << ", holds " << Figure(100.0 * *v.band_coverage_blocks) << "% of the block means (noise included)";
    std::cout << "\n";
  } else {
    std::cout << "  band: n/a (the model file has none; refit with gyrocomp fit to get one)\n";
  }
  // A temperature excursion was already said once, as the warning on stderr.
  if (!v.excursion.outside && v.fraction_dtemp_outside > 0.0) {
    std::cout << "  outside the fitted range: T " << Figure(100.0 * v.fraction_temp_outside) << "% of samples, dT/dt "
              << Figure(100.0 * v.fraction_dtemp_outside) << "%\n";
  }
}

int Run(const ValidateArgs& a) {
  Result<DriftModelSet> set = LoadDriftModelSet(a.model_path);
  if (!set.ok()) return ReportError(kValidateName, set.error());
  Result<LogSpec> spec = ToLogSpec(a.log);
  if (!spec.ok()) return ReportError(kValidateName, spec.error());
  spec->temp_required = true;
  spec->keep_cols = std::vector<std::string>{a.truth_col};  // the log and the truth only: memory
  Result<LoadedLog> loaded = LoadLog(kValidateName, a.log, *spec);
  if (!loaded.ok()) return ReportError(kValidateName, loaded.error());
  const GyroLog& log = loaded->log;
  const int truth = loaded->table.Find(a.truth_col);
  nlohmann::json axes = nlohmann::json::array();
  std::vector<DriftValidation> validations;  // per axis, for the report
  std::vector<const DriftModel*> models;
  for (std::size_t k = 0; k < log.axis_names.size(); ++k) {
    const DriftModel* model = set->ForAxis(log.axis_names[k]);
    if (!model)
      return ReportError(kValidateName, InvalidInput(a.model_path + ": no model for rate column '" + log.axis_names[k] + "'"));
    std::vector<double> none;
    auto v = ValidateDriftModel(*model, log.rate_dps[k], log.temp_c, log.fs_hz,
                                truth >= 0 ? loaded->table.columns[truth] : none, a.options);
    if (!v.ok()) return ReportError(kValidateName, v.error());
    if (v->excursion.outside && a.json_path != "-") Note(kValidateName, "warning: " + v->excursion.Message());
    if (a.json_path != "-") PrintAxis(log.axis_names[k], *v, a.verbose);
    nlohmann::json j = DriftValidationJson(*v);
    j["rate_col"] = log.axis_names[k];
    j["model"] = DriftSummaryJson(model->summary);
    axes.push_back(j);
    validations.push_back(std::move(*v));
    models.push_back(model);
  }
  if (!a.json_path.empty()) {
    nlohmann::json j = axes[0];
    j["model_file"] = a.model_path;
    j["input"] = loaded->table.source;
    j["causal"] = a.options.causal;
    j["axes"] = axes;
    if (Status s = WriteJson(a.json_path, j); !s.ok()) return ReportError(kValidateName, s.error());
  }
  if (!a.report_path.empty()) {
    std::vector<ValidationSection> sections;
    for (std::size_t k = 0; k < validations.size(); ++k) {
      sections.push_back({log.axis_names[k] + ": " + DriftModelKindName(models[k]->kind) + "(" +
                              DriftInputSetName(models[k]->summary.inputs) + ")",
                          &validations[k], &models[k]->summary});
    }
    const nlohmann::json params = {{"model_file", a.model_path}, {"input", loaded->table.source},
                                   {"block_s", a.options.block_s}, {"min_tau_s", a.options.min_tau_s},
                                   {"causal", a.options.causal}, {"truth_col", truth >= 0 ? a.truth_col : ""}};
    const ReportData report = BuildValidationReport(
        sections, "gyrocomp validate: " + loaded->table.source,
        "Drift model " + a.model_path + " on " + loaded->table.source + ", a run it was not fitted on: " +
            std::to_string(log.rate_dps[0].size()) + " samples at " + std::to_string(log.fs_hz) + " Hz.",
        params);
    if (Status s = WriteText(a.report_path, RenderReportHtml(report)); !s.ok()) return ReportError(kValidateName, s.error());
  }
  return kExitOk;
}

Command MakeValidate(CLI::App& app) {
  auto a = std::make_shared<ValidateArgs>();
  CLI::App* sub = app.add_subcommand(kValidateName, "Validate a saved drift model on another run (residual drift, what it missed)");
  sub->footer(
      "Reports, per axis: residual drift RMS (the compensated rate in --block means, about its mean)\n"
      "beside the raw rate's; the residual's least-squares slopes against T and dT/dt (what the\n"
      "model missed); ADEV of compensated and raw rates at tau >= --min-tau; RMSE against the truth\n"
      "column when present; the share of samples with T and dT/dt outside the fitted ranges.\n"
      "JSON keys: docs/reference/cli-contract.md (validate).\n"
      "Example: gyrocomp validate -m model.json -i other_run.csv --json validate.json --report validate.html");
  AddInputOption(sub, "-m,--model", &a->model_path, "Model file written by gyrocomp fit")->required();
  AddLogOptions(sub, &a->log);
  AddOutputOption(sub, "--json", &a->json_path, "Write the validation as JSON to FILE ('-' = stdout)");
  AddOutputOption(sub, "--report", &a->report_path,
                  "Write an HTML report of the validation to FILE (self-contained, opens offline)");
  sub->add_option("--truth-col", a->truth_col, "Column with the true drift, scored when present")->capture_default_str();
  sub->add_option("--block", a->options.block_s, "Block length of the residual drift, s")->capture_default_str();
  sub->add_option("--min-tau", a->options.min_tau_s, "Smallest tau of the ADEV comparison, s")->capture_default_str();
  sub->add_flag("--causal", a->options.causal, "Evaluate the model one sample at a time (as firmware)");
  sub->add_flag("-v,--verbose", a->verbose, "The full validation per axis (slopes against T and dT/dt, block counts)");
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kValidateRegistrar(kValidateName, 66, &MakeValidate);

}  // namespace
}  // namespace gyrocomp::cli
