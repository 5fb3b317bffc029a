// One Bind* function per binding file; module.cc calls them all.
#pragma once

#include "convert.h"
#include "gyrocomp/allan/allan.h"
#include "gyrocomp/decompose/vmd.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp::python {

void BindAllan(py::module_& m);
void BindSimulator(py::module_& m);
void BindStages(py::module_& m);    // VMD, sample entropy, wavelet / FLP / WFLP
void BindDrift(py::module_& m);
void BindPipeline(py::module_& m);
void BindExport(py::module_& m);      // the export stage
void BindIo(py::module_& m);          // the log and bag readers
void BindCalibrate(py::module_& m);   // the calibrate stage
void BindPlan(py::module_& m);        // the plan stage (gyrocomp plan)
void BindInspect(py::module_& m);     // what a flight log or bag holds (gyrocomp inspect)

// Options structs from keyword arguments (each reads its own fields; the caller calls Done()).
AllanOptions ReadAllanOptions(Kwargs& kw);
VmdOptions ReadVmdOptions(Kwargs& kw);
DriftFitOptions ReadFitOptions(Kwargs& kw);
LogSpec ReadLogSpec(Kwargs& kw);  // read_log's keywords (time_col, rate_cols, rate_unit, temp_col, ...)
py::dict FitSummaryDict(const DriftFitSummary& s);
// The simulator's nested options (simulate(profile=..., bias=..., noise=...)); `function` names the
// caller in errors.
void ReadProfile(py::dict d, ThermalProfileOptions* p, const std::string& function);
void ReadBias(py::dict d, BiasModelOptions* b, const std::string& function);
void ReadNoise(py::dict d, NoiseOptions* n, const std::string& function);

// An AllanResult as a dict of numpy arrays and figures (shared by compute_allan and the pipeline).
py::dict AllanDict(AllanResult&& r);

}  // namespace gyrocomp::python
