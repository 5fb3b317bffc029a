// The not-applicable rule on the CLI's JSON of a pipeline run (process, demo). The report itself
// and the figures it shares with the console (BuildPipelineReport, BeforeAfterRows, HonestyNotes,
// ...) are the library's: gyrocomp/report/pipeline_report.h.
#pragma once

#include <optional>

#include <nlohmann/json.hpp>

#include "gyrocomp/allan/allan.h"
#include "gyrocomp/pipeline/pipeline.h"
#include "gyrocomp/report/pipeline_report.h"

namespace gyrocomp::cli {

// The rule on one Allan result's terms JSON (AllanTermsJson / AllanJson): a non-applicable ARW
// or RRW becomes null and "arw_not_applicable" / "rrw_not_applicable" carry the reason (cli.md).
void MarkNotApplicable(const AllanResult& allan, std::optional<double> bandwidth_hz, nlohmann::json* terms);
// Both of a pipeline run: j["before"] (raw, bandwidth fs/2) and j["after"] (measured bandwidth).
void MarkNotApplicable(const PipelineResult& r, nlohmann::json* j);

}  // namespace gyrocomp::cli
