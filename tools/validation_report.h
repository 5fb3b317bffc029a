// The validation section of the HTML report: a drift model on a run it was
// not fitted on (DriftValidation, gyrocomp/drift/drift_validate.h). Shared by `validate --report`
// (a report of its own) and the held-out section of `demo`'s report.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/drift/drift_validate.h"
#include "gyrocomp/report/report.h"

namespace gyrocomp::cli {

// One validated model: what it is (label, e.g. "rate_dps: poly(temp,dtemp)") and its result.
struct ValidationSection {
  std::string label;
  const DriftValidation* validation = nullptr;
  const DriftFitSummary* model = nullptr;  // optional
};

// A report table {title, columns, rows, note}: residual drift RMS beside the raw's, residual slopes
// against T and dT/dt, ADEV of compensated vs raw at each tau >= min tau, RMSE against the truth
// (when present) and the out-of-range fractions. One value column per section.
nlohmann::json ValidationReportTable(const std::vector<ValidationSection>& sections, const std::string& title);

// A whole report for `validate --report`: the table above and, per section, the ADEV of the raw
// and compensated rates at tau >= min tau in the Allan chart. `parameters`: the command's options.
ReportData BuildValidationReport(const std::vector<ValidationSection>& sections, const std::string& title,
                                 const std::string& subtitle, const nlohmann::json& parameters);

}  // namespace gyrocomp::cli
