// Pieces every gyrocomp subcommand shares: the log-reading options of cli.md ("Reading a log"),
// error reporting with the exit-status contract, and the output transaction.
//
// Files: a subcommand adds the options naming files it reads with AddInputOption and those naming
// files it writes with AddOutputOption. main() then, before the command runs, registers every
// input and declares every output in one OutputSet (gyrocomp/io/output.h): an empty name, an
// output that is an input (any spelling, symbolic or hard link), a missing or read-only folder
// are refused with exit 2 before any work. The command writes with WriteCsv / WriteText /
// WriteJson, which only stage the content in temporaries; main() commits them together when the
// command returns 0 (a failed commit, e.g. ENOSPC, is exit 1) and discards them otherwise, and
// its SIGINT / SIGTERM handler removes them.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/io/log_damage.h"
#include "gyrocomp/io/output.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp::cli {

// Exit statuses (cli.md): 0 success, 2 bad usage or bad input, 1 internal failure.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitBadInput = 2;

// A registered subcommand: its CLI11 app and what runs it when it was parsed.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

// The log-reading options shared by every subcommand that takes -i.
struct LogOptions {
  std::string input;
  std::string time_col = "time_s";
  std::string rate_col = "rate_dps";  // comma-separated for several axes
  std::string temp_col = "temp_c";
  std::optional<double> fs_hz;
  std::string rate_unit = "dps";
  std::optional<double> resample_hz;
  // ULog / DataFlash: gyro instance (sensor_gyro multi_id, IMU instance); nullopt = the only one.
  std::optional<int> instance;
  // ROS bags: the sensor_msgs/Imu topic (nullopt = the only one) and the row time,
  // "header" (header.stamp) or "receive" (the bag's record time).
  std::optional<std::string> topic;
  std::string time_source = "header";
  bool rate_unit_given = false;  // --rate-unit was on the command line
  bool strict = false;  // --strict: a damaged ULog / DataFlash / bag record is an error (ReadLogTable's, BagReadOptions' strict)
  double max_memory_gb = 8.0;  // LogSpec::max_memory_bytes, CsvReadOptions::max_memory_bytes
};

// Adds -i/--input, --time-col, --rate-col, --temp-col, --fs, --rate-unit, --resample, --instance,
// --max-memory, --strict
// to `app`.
void AddLogOptions(CLI::App* app, LogOptions* options, bool input_required = true);

// Converts the CLI options to a LogSpec (rate columns split on ','), or an kInvalidArgument error.
// Flight-log reader warnings are printed to stderr as "gyrocomp: <warning>".
Result<LogSpec> ToLogSpec(const LogOptions& options);

// A log read for a command whose output is "the input columns plus ...": the table (resampled
// onto the log's grid when --resample was given, so its rows line up with the log) and the log.
struct LoadedLog {
  Table table;
  GyroLog log;
  std::vector<LogDamage> damage;  // byte ranges of a damaged ULog / DataFlash log or bag skipped (--json "damage")
};
// ReadLogTable (CSV, ULog or DataFlash by magic bytes) + (ResampleTable) + LoadGyroLog. Prints
// what resampling did, as a note, when it did. With spec.keep_cols set, a CSV is read for the
// log's columns and those only (TakeGyroLog moves the log's out: the table then holds just the
// keep_cols columns the file has, plus the log's when resampled); without, the table is whole. A --rate-unit other than rads given for a ULog or
// DataFlash log is an error (their rates are rad/s).
Result<LoadedLog> LoadLog(const std::string& command, const LogOptions& options, LogSpec spec);

// Prints "gyrocomp <command>: error: <message>" (one line) to stderr and returns the exit status
// for the error's kind.
int ReportError(const std::string& command, const Error& error);

// Prints a one-line note to stderr (warnings, what resampling did), prefixed with the command.
void Note(const std::string& command, const std::string& message);

// Adds an option naming a file the command reads (never written, see above).
CLI::Option* AddInputOption(CLI::App* app, const std::string& flags, std::string* path, const std::string& help);

// The same for an option that takes several files (-m x.json -m y.json).
CLI::Option* AddInputOption(CLI::App* app, const std::string& flags, std::vector<std::string>* paths,
                            const std::string& help);

// Adds an option naming a file the command writes (checked before the command runs, see above).
CLI::Option* AddOutputOption(CLI::App* app, const std::string& flags, std::string* path, const std::string& help);

// The outputs of this run (one per process).
OutputSet& Outputs();

// For main(): registers the inputs and declares the outputs given to the parsed subcommand `app`.
Status PrepareFiles(const CLI::App* app);

// Stage content for an output (declared by AddOutputOption, or declared now); see above.
Status WriteCsv(const std::string& path, const Table& table);
Status WriteText(const std::string& path, const std::string& text);
// JSON, pretty-printed. A NaN or infinity anywhere is refused (kInternal, naming its key), never
// written as null; strings that are not UTF-8 (file names are bytes) have those bytes escaped.
Status WriteJson(const std::string& path, const nlohmann::json& j);

// `j` as text, with the checks of WriteJson.
Result<std::string> JsonText(const nlohmann::json& j);

// Adds the column `name` to an output table built from the input's columns; when the input
// already had it (the command run on its own output), replaces it and says so on stderr.
void SetColumn(const std::string& command, Table* table, std::string name, std::vector<double> values);

// A temperature that hardly varies (span below kMinTemperatureSpanC) gives a model in T nothing
// to learn: warns on stderr with the span and what the model then is.
inline constexpr double kMinTemperatureSpanC = 1.0;
void WarnIfTemperatureFlat(const std::string& command, const GyroLog& log);

// A validator for an integer option that counts something (samples, frequencies, points, modes):
// refused at parse time, before any work (exit 2), unless it is an integer in [lo, hi]; the
// message names the range and what states it ("0: must be an integer in [1, 1e+09]
// (BandwidthOptions::num_frequencies)"; CLI11 prefixes the option). `denoise
// --bandwidth-segment 0` ran and exited 0.
CLI::Validator IntegerRange(std::int64_t lo, std::int64_t hi, const std::string& source);

// Splits "a,b,c" on commas, trimming spaces; empty items are dropped.
std::vector<std::string> SplitList(const std::string& text);

// Root mean square of a - b, element by element (b empty: of a alone); 0 for an empty a.
double Rms(std::span<const double> a, std::span<const double> b);

}  // namespace gyrocomp::cli
