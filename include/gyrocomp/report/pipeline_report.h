// The report of a parallel-model run (RunParallelModel): the content of the HTML report
// (report.h schema) built from the PipelineResult and the raw record, and the figures the console,
// the JSON and the report share (the before/after rows, the caveats on the processed figures, the
// parameters of the run). `gyrocomp process --report`, `gyrocomp demo` and the Python
// run_parallel_model(report=...) all build their report here, so the three agree.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gyrocomp/allan/allan.h"
#include "gyrocomp/pipeline/compare.h"
#include "gyrocomp/pipeline/pipeline.h"
#include "gyrocomp/report/report.h"

namespace gyrocomp {

// What the report shows besides the PipelineResult: the record as read, and where it came from.
struct PipelineReportContext {
  std::string title;               // page title ("gyrocomp: run.csv")
  std::string source;              // the input file, or a description ("simulated ...")
  std::string axis;                // the rate column processed ("" leaves the axis out of the subtitle)
  std::span<const double> time_s;  // time of each sample, s (same length as the rate)
  std::span<const double> rate_dps;  // the raw rate, deg/s
  std::span<const double> temp_c;    // the temperature, deg C
  nlohmann::json parameters;         // every option of the run, printed verbatim (PipelineOptionsJson)
  const ComparisonResult* comparison = nullptr;  // the comparison tables (CompareMethods); nullptr: none
};

// The report's content (report.h schema): subtitle, before/after summary, rate and temperature,
// the VMD modes, the ADEV curves before and after with their noise-term lines, drift against
// temperature with the model's prediction band, and the tables (classification rule, drift model,
// comparisons, timings, warnings), parameters and versions.
ReportData BuildPipelineReport(const PipelineResult& r, const PipelineReportContext& ctx);

// One row of the before/after table: ARW, ADEV minimum, bias instability, RRW, bandwidth. ARW and
// RRW follow the not-applicable rule (applicability.h; bandwidth before = the raw record's Nyquist
// frequency, after = the measured one): a figure the processing makes meaningless has its value
// cleared and the reason in before_na / after_na.
struct BeforeAfterRow {
  std::string metric;                 // "ARW", "ADEV minimum (bias stability)", ...
  std::optional<double> before;       // the raw record's figure, in `unit`
  std::optional<double> after;        // the compensated output's figure, in `unit`
  std::string unit;                   // "deg/sqrt(h)", "deg/h", "deg/h/sqrt(h)", "Hz"
  std::string before_na;  // why `before` is not applicable ("" = applicable)
  std::string after_na;   // why `after` is not applicable ("" = applicable)
};
// The rows of the before/after table, in the order the console and the report print them.
std::vector<BeforeAfterRow> BeforeAfterRows(const PipelineResult& r);

// Plain-language caveats on the after-processing figures (slope at 1 s not -1/2, ADEV minimum at
// the shortest tau, minimum at the longest tau), for the console, the JSON and the report.
std::vector<std::string> HonestyNotes(const PipelineResult& r);

// Minimum of the ADEV curve over tau >= tau_min_s, deg/h (nullopt when no such tau).
std::optional<double> AdevMinAbove(const AllanCurve& c, double tau_min_s);

// The -3 dB bandwidth of the processed output, Hz (nullopt when not measured).
std::optional<double> ProcessedBandwidth(const PipelineResult& r);

// Versions of gyrocomp and of the libraries it was built with ({name: version}).
nlohmann::json SoftwareVersions();

// Every parameter of a parallel-model run, grouped by stage (vmd, sample_entropy, classification,
// wflp, drift_model, allan, bandwidth), so that a run can be repeated: the "parameters" of the
// report and of `process --json` / `compare --json`.
nlohmann::json PipelineOptionsJson(const PipelineOptions& o);

}  // namespace gyrocomp
