#include "cli_common.h"

#include <iostream>

#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/core/units.h"

namespace gyrocomp::cli {

void AddLogOptions(CLI::App* app, LogOptions* o, bool input_required) {
  auto* in = app->add_option("-i,--input", o->input,
                             "Input log: CSV (header row; .gz read directly; '-' = stdin), PX4 ULog or ArduPilot "
                             "DataFlash (recognised by their first bytes)");
  if (input_required) in->required();
  app->add_option("--time-col", o->time_col, "Time column, seconds")->capture_default_str();
  app->add_option("--rate-col", o->rate_col, "Rate column(s), comma-separated for several axes")
      ->capture_default_str();
  app->add_option("--temp-col", o->temp_col, "Temperature column, deg C")->capture_default_str();
  app->add_option("--fs", o->fs_hz, "Sample rate in Hz when the file has no time column")
      ->check(CLI::PositiveNumber);
  app->add_option("--rate-unit", o->rate_unit, "Unit of the rate column(s) (ULog, DataFlash: rads, from the log)")
      ->check(CLI::IsMember({"dps", "rads", "dph"}))
      ->each([o](const std::string&) { o->rate_unit_given = true; })
      ->capture_default_str();
  app->add_option("--instance", o->instance,
                  "ULog / DataFlash: gyro instance (sensor_gyro multi_id, IMU instance); default: the only one")
      ->check(CLI::NonNegativeNumber);
  app->add_option("--resample", o->resample_hz,
                  "Resample an irregularly sampled log onto this uniform rate (Hz, linear interpolation)")
      ->check(CLI::PositiveNumber);
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::string item;
  auto flush = [&] {
    const auto b = item.find_first_not_of(" \t");
    const auto e = item.find_last_not_of(" \t");
    if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
    item.clear();
  };
  for (char c : text) {
    if (c == ',') flush(); else item.push_back(c);
  }
  flush();
  return out;
}

Result<LogSpec> ToLogSpec(const LogOptions& o) {
  LogSpec spec;
  spec.time_col = o.time_col;
  spec.rate_cols = SplitList(o.rate_col);
  if (spec.rate_cols.empty()) return InvalidArgument("--rate-col: no column named");
  spec.temp_col = o.temp_col;
  spec.fs_hz = o.fs_hz;
  spec.resample_hz = o.resample_hz;
  const auto unit = ParseRateUnit(o.rate_unit);
  if (!unit) return InvalidArgument("--rate-unit " + o.rate_unit + ": must be dps, rads or dph");
  spec.rate_unit = *unit;
  spec.instance = o.instance;
  spec.on_warning = [](const std::string& w) { std::cerr << "gyrocomp: " << w << "\n"; };
  return spec;
}

Result<LoadedLog> LoadLog(const std::string& command, const LogOptions& options, LogSpec spec) {
  if (options.rate_unit_given && options.rate_unit != "rads" && DetectLogFormat(options.input) != LogFormat::kCsv) {
    return InvalidArgument("--rate-unit " + options.rate_unit + ": " + options.input +
                           " is a flight-controller log, whose rates are rad/s (drop --rate-unit)");
  }
  Result<LogTableRead> read = ReadLogTable(options.input, spec);
  if (!read) return read.error();
  spec = read->spec;
  Result<GyroLog> log = LoadGyroLog(read->table, spec);
  if (!log) return log.error();
  AttachFlightLogInfo(*read, &*log);
  LoadedLog out{std::move(read->table), std::move(*log)};
  if (out.log.sampling.resampled) {
    Result<Table> resampled = ResampleTable(out.table, spec.time_col, out.log.fs_hz);
    if (!resampled) return resampled.error();
    out.table = std::move(*resampled);
    Note(command, out.log.sampling.BriefReport());
  }
  return out;
}

int ReportError(const std::string& command, const Error& error) {
  std::cerr << "gyrocomp " << command << ": error: " << error.message << "\n";
  switch (error.kind) {
    // A file that cannot be opened, read or created is a bad input or a bad -o path: the
    // user's to fix (cli.md: exit 2), not an internal failure.
    case ErrorKind::kInvalidInput:
    case ErrorKind::kInvalidArgument:
    case ErrorKind::kUnsupported:
    case ErrorKind::kIo:
      return kExitBadInput;
    default:
      return kExitFailure;
  }
}

void Note(const std::string& command, const std::string& message) {
  std::cerr << "gyrocomp " << command << ": " << message << "\n";
}

Status WriteJson(const std::string& path, const nlohmann::json& j) {
  return WriteTextAtomic(path, j.dump(1) + "\n");
}

}  // namespace gyrocomp::cli
