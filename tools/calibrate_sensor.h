// gyrocomp calibrate's options and outputs over the library's CalibratedSensor
// (gyrocomp/calibrate/calibrate.h fits it; tools/calibrate_output.cc writes the model files and the
// JSON). Internal to the CLI.
#pragma once

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calibrate_report.h"
#include "gyrocomp/calibrate/calibrate.h"
#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/static_weight.h"
#include "gyrocomp/export/thermal_cubic.h"

namespace gyrocomp::cli::calibrate {

constexpr const char* kCalibrateName = "calibrate";
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// The command's options: the library's (defaults there) and where its outputs go.
struct CalibrateArgs : CalibrateOptions {
  std::string input;                // the first -i (the primary run: models, bands, cost)
  std::vector<std::string> inputs;  // every -i: runs of one board
  std::string output;
  std::string models_dir;
  std::string json_path;
  std::string report_path;  // HTML report
  bool verbose = false;     // the full per-axis table instead of one line per sensor
  // --static-weight given on the command line (not its default): a pooled fit, which has no
  // static weighting, says once on stderr that it does not apply.
  bool static_weight_given = false;
};

using Sensor = CalibratedSensor;

// Each calibrated sensor's model file to --models (nothing without it).
Status WriteModels(const CalibrateArgs& a, const std::vector<Sensor>& all);
// One sensor's entry of --json.
nlohmann::json SensorJson(const CalibrateArgs& a, const Sensor& s);

}  // namespace gyrocomp::cli::calibrate
