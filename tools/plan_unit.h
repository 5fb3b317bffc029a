// gyrocomp plan: the drift family of a pilot run's fitted model in the simulator's terms
// ("its noise from an Allan run or from datasheet numbers, its drift structure from a
// pilot run or a stated family"; docs/explanation/calibration-design.md).
#pragma once

#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp::cli {

// The simulator's drift family (BiasModelOptions, deg/s) that `m`'s structured polynomial
// describes: its temperature polynomial re-expanded about bias->reference_temp_c; a dT/dt gain
// as dtemp_coeff; a lag state (T - T_lag ~ tau dT/dt on a ramp) as the gain c tau; a memory
// (m in [-1, 1], width w) as the play hysteresis of width w and coefficient 2 h / w (the same
// +-h at saturation). What the simulator cannot represent (a kernel residual, dT/dt powers > 1)
// is left out and named in *notes. Errors: no structured part, a unit other than deg/s or rad/s.
Status FamilyFromModel(const DriftModel& m, BiasModelOptions* bias, std::vector<std::string>* notes);

}  // namespace gyrocomp::cli
