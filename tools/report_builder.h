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
// ARW and RRW follow the not-applicable rule (gyrocomp/report/applicability.h; bandwidth before
// = the raw record's Nyquist frequency, after = the measured one): a figure the processing makes
// meaningless has its value cleared and the reason in before_na / after_na.
struct SummaryRow {
  std::string metric;
  std::optional<double> before, after;
  std::string unit;
  std::string before_na, after_na;  // not-applicable reasons ("" = applicable)
};
std::vector<SummaryRow> BeforeAfterRows(const PipelineResult& r);

// The rule on one Allan result's terms JSON (AllanTermsJson / AllanJson): a non-applicable ARW
// or RRW becomes null and "arw_not_applicable" / "rrw_not_applicable" carry the reason (cli.md).
void MarkNotApplicable(const AllanResult& allan, std::optional<double> bandwidth_hz, nlohmann::json* terms);
// Both of a pipeline run: j["before"] (raw, bandwidth fs/2) and j["after"] (measured bandwidth).
void MarkNotApplicable(const PipelineResult& r, nlohmann::json* j);
// The bandwidth the rule uses for the processed output (nullopt when not measured).
std::optional<double> ProcessedBandwidth(const PipelineResult& r);

// Plain-language caveats on the after-processing figures (slope at 1 s not -1/2, ADEV minimum
// at the shortest tau), for the console, the JSON and the report.
std::vector<std::string> HonestyNotes(const PipelineResult& r);

// Minimum of the ADEV curve over tau >= tau_min_s, deg/h (nullopt when no such tau).
std::optional<double> AdevMinAbove(const AllanCurve& c, double tau_min_s);

// Versions of gyrocomp and of the libraries it was built with.
nlohmann::json SoftwareVersions();

}  // namespace gyrocomp::cli
