// The HTML report of `gyrocomp calibrate --report`: the report stage's tables and charts
// (gyrocomp/report/report.h). The tables are filled from the command's JSON summary
// (docs/reference/cli-contract.md, calibrate), so they show exactly what the JSON says; the
// per-sensor charts from the sensors' fit rows and bands (calibrate.h, FitRows, CurveBand).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gyrocomp/calibrate/calibrate.h"
#include "gyrocomp/report/report.h"

namespace gyrocomp::cli {

// Tables: the sensors (status, span, model, projection cost, expected next-run error per
// condition), the exported coefficients, and with --validation the scores on the validation run.
// Then one section per sensor (docs/guides/calibrate-board.md, "What the report shows"): per
// axis the rows the fit saw against temperature with the exported cubic and its band over them,
// the residual after the cubic, and a table of the error before and after compensation beside
// the expected next-run error; a skipped sensor's section says why and has no chart. `summary`:
// the JSON calibrate writes with --json; `sensors`: the same sensors (their fit rows and bands).
ReportData BuildCalibrateReport(const nlohmann::json& summary, const std::vector<CalibratedSensor>& sensors);

}  // namespace gyrocomp::cli
