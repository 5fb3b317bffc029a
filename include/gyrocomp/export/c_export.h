// A generated, dependency-free C99 evaluator of drift models: the firmware form that keeps the
// whole model (docs/explanation/flight-controller-export.md).
//
// With prefix = CExportOptions::prefix and PREFIX = it in upper case, the generated prefix.h /
// prefix.c hold the model's numbers as constant tables and
//     void prefix_init(prefix_state *state);
//     void prefix_step(prefix_state *state, prefix_real dt_s, prefix_real temp_c,
//                      const prefix_real rate_in[PREFIX_NUM_AXES],
//                      prefix_real rate_out[PREFIX_NUM_AXES]);
// step() runs each axis's thermal state update (thermal_state.h Eqs. TS-1..3: rate, lag or
// memory), applies the model's out-of-range policy to the temperature, evaluates the model
// (structured polynomial + RBF SVR kernel, either or both: poly, svr, hybrid) and returns
// rate_out = rate_in - drift; state->drift[a] keeps the last drift. No allocation, no globals
// written, no libm except exp (expf in the float build) for the SVR and the state updates.
// Compile with -DPREFIX_USE_FLOAT for MCUs without double: then every constant and every
// operation is float (no double promotion).
//
// It computes what DriftModel::Predict(inputs, causal = true) computes (same formulas; the states
// carried as small numbers, see docs/explanation/flight-controller-export.md):
// in double within rounding (tests: 1e-12 of the drift span); in float within 1e-5 of the span
// plus the model's own conditioning (an SVR whose terms cancel: its sum is compensated, Kahan,
// but each term keeps its float rounding; docs/explanation/flight-controller-export.md gives the measured figures).
#pragma once

#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/causal_drift.h"

namespace gyrocomp {

// One axis: its name (a comment in the generated code) and its model.
struct AxisDriftModel {
  std::string axis;  // name, a comment in the generated code
  DriftModel model;  // the axis's model
};

// What GenerateCEvaluator names and how it scales the output.
struct CExportOptions {
  // C identifier prefix of every generated name, and the file stem: prefix.h, prefix.c.
  std::string prefix = "gyrocomp_drift";
  // Unit of rate_in / rate_out relative to the model's unit: drift_out = model * output_scale
  // (1: the model's deg/s; pi/180 for rad/s).
  double output_scale = 1.0;
  std::string output_unit = "deg/s";  // unit of rate_in / rate_out, for the comments
  // Free text for the header comment (where the model came from).
  std::vector<std::string> comments;
  // False with the reason in `error` when prefix is not a C identifier or output_scale not > 0.
  bool IsValid(std::string* error) const;
};

// The generated header and source: file names and texts.
struct GeneratedC {
  std::string header_name;  // "prefix.h"
  std::string header;       // text of prefix.h
  std::string source_name;  // "prefix.c"
  std::string source;       // text of prefix.c
};

// Errors: no axes, invalid options (prefix not a C identifier), non-finite model numbers.
Result<GeneratedC> GenerateCEvaluator(const std::vector<AxisDriftModel>& axes, const CExportOptions& options = {});

}  // namespace gyrocomp
