// Shared by the calibrate stage's files (not installed).
#pragma once

#include <string>
#include <vector>

#include "gyrocomp/calibrate/calibrate.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp::calibrate_internal {

using Sensor = CalibratedSensor;

// The options with the logs they apply to: input = inputs[0], the primary run.
struct Args : CalibrateOptions {
  std::string input;
  std::vector<std::string> inputs;
  std::vector<std::string>* notes = nullptr;  // the readers' notes, once each
};

// The parameter file's text (PX4 or ArduPilot, every sensor, disabled slots included).
Result<std::string> ParameterText(const Args& a, const std::vector<Sensor>& all);

}  // namespace gyrocomp::calibrate_internal
