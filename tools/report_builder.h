// Fills the HTML report (gyrocomp/report.h) from a pipeline run: shared by `process` and `demo`.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gyrocomp/pipeline/compare.h"
#include "gyrocomp/pipeline/pipeline.h"
#include "gyrocomp/report/report.h"

namespace gyrocomp::cli {

struct ReportContext {
  std::string title;
  std::string source;             // input file (or "simulated ...")
  std::string axis;               // rate column
  std::vector<double> time_s;     // of the record
  std::vector<double> rate_dps;   // raw
  std::vector<double> temp_c;
  nlohmann::json parameters;      // every option, for repeating the run
  const ComparisonResult* comparison = nullptr;  // optional tables
};

ReportData BuildPipelineReport(const PipelineResult& r, const ReportContext& ctx);

// The before/after rows: ARW, ADEV min, bias instability, RRW, bandwidth; as strings and numbers
// for the console table and the report. Columns: metric, before, after, change (%).
struct SummaryRow {
  std::string metric;
  std::optional<double> before, after;
  std::string unit;
};
std::vector<SummaryRow> BeforeAfterRows(const PipelineResult& r);

// Plain-language caveats on the after-processing figures (slope at 1 s not -1/2, ADEV minimum
// at the shortest tau), for the console, the JSON and the report.
std::vector<std::string> HonestyNotes(const PipelineResult& r);

// Versions of gyrocomp and of the libraries it was built with.
nlohmann::json SoftwareVersions();

}  // namespace gyrocomp::cli
