// Command-line options for every stage of the pipeline, in one place, so that `process`,
// `compare` and `demo` expose the same parameters under the same names ("Every stage's
// parameters are reachable from the command line"). Defaults shown in --help are the library's.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "gyrocomp/pipeline/pipeline.h"
#include "gyrocomp/report/pipeline_report.h"
#include "cli_common.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp::cli {

// Holds PipelineOptions plus the text form of its enum-valued options until Resolve().
struct PipelineCliOptions {
  PipelineOptions options;
  std::string vmd_init = "uniform";
  std::string vmd_stop = "absolute";
  std::string vmd_accel = "auto";  // VmdOptions::omega_extrapolation_period: auto (library default) | off
  std::string rule = "standard";
  std::optional<double> drift_max_se, noise_min_se;
  std::string wavelet_extension = "symmetric";
  std::string details = "threshold";
  std::string threshold_mode = "soft";
  std::string model = "auto";
  std::string inputs = "temp";
  std::string scale = "standard";
  std::optional<double> svr_C, svr_gamma, svr_sigma;
  std::string taus = "octave";
  bool no_bandwidth = false;
};

// Adds the option groups "VMD", "Sample entropy", "Classification", "WFLP", "Drift model",
// "Allan" and "Bandwidth" to `app`.
void AddPipelineOptions(CLI::App* app, PipelineCliOptions* o);

// Parses the text options into o->options and validates; kInvalidArgument naming the option.
Status ResolvePipelineOptions(PipelineCliOptions* o);

// What `process` and `compare` do first: resolve the stage options (into *pipe), then read the
// log with its temperature required (`LoadLog`). Errors name the option or the file.
// `keep_cols`: LogSpec::keep_cols (nullopt: every column of a CSV stays in the table).
Result<LoadedLog> LoadPipelineLog(const std::string& command, const LogOptions& log, PipelineCliOptions* pipe,
                                  std::optional<std::vector<std::string>> keep_cols = std::nullopt);

// Every parameter, for the JSON output and the report: PipelineOptionsJson
// (gyrocomp/report/pipeline_report.h).

}  // namespace gyrocomp::cli
