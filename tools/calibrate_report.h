// The HTML report of `gyrocomp calibrate --report`: the report stage's tables and
// chart (gyrocomp/report/report.h) filled from the command's JSON summary (docs/reference/cli-contract.md,
// calibrate), so the report shows exactly what the JSON says.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gyrocomp/export/thermal_cubic.h"
#include "gyrocomp/report/report.h"

namespace gyrocomp::cli {

// One exported cubic drawn against temperature, in deg/s (gyro axes).
struct CalibrateCurve {
  std::string name;         // e.g. "gyro 0 x_rad_s"
  TemperatureCubic cubic;   // firmware unit
  double to_display = 1.0;  // firmware unit -> deg/s
};

// Tables: the sensors (status, span, model, projection cost, expected next-run error per
// condition), the exported coefficients, and with --validation the scores on the validation run;
// the chart: the gyro cubics over the union of their ranges (flat outside each range: the
// firmware clamps T). `summary`: the JSON calibrate writes with --json.
ReportData BuildCalibrateReport(const nlohmann::json& summary, const std::vector<CalibrateCurve>& gyro_curves);

}  // namespace gyrocomp::cli
