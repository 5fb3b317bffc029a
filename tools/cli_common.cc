#include "cli_common.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "gyrocomp/io/bag_log.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/core/units.h"

namespace gyrocomp::cli {

void AddLogOptions(CLI::App* app, LogOptions* o, bool input_required) {
  auto* in = AddInputOption(app, "-i,--input", &o->input,
                            "Input log: CSV (header row; .gz read directly; '-' = stdin), PX4 ULog, ArduPilot "
                            "DataFlash, ROS bag (ROS 1, MCAP, rosbag2 .db3 or folder; recognised by their first bytes)");
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
  app->add_option("--topic", o->topic, "ROS bag: the sensor_msgs/Imu topic (default: the only one)");
  app->add_option("--time", o->time_source,
                  "ROS bag: row time from the message header stamp (header) or the bag's receive time (receive)")
      ->check(CLI::IsMember({"header", "receive"}))
      ->capture_default_str();
  app->add_option("--resample", o->resample_hz,
                  "Resample an irregularly sampled log onto this uniform rate (Hz, linear interpolation)")
      ->check(CLI::PositiveNumber);
  app->add_option("--max-memory", o->max_memory_gb,
                  "Memory the log may take when read or resampled, GB (refused with what it needs beyond)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app->add_flag("--strict", o->strict,
                "ULog / DataFlash / ROS 1 bag / MCAP / rosbag2 .db3: refuse a damaged log at its first bad record (exit 2, "
                "naming the byte offset or message id) instead of skipping to the next valid record with a warning");
}

CLI::Validator IntegerRange(std::int64_t lo, std::int64_t hi, const std::string& source) {
  std::ostringstream range;
  range << "[" << static_cast<double>(lo) << ", " << static_cast<double>(hi) << "]";
  const std::string range_text = range.str();
  return CLI::Validator(
      [lo, hi, range_text, source](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(text.c_str(), &end, 10);
        const bool integer = !text.empty() && end == text.c_str() + text.size() && errno == 0;
        if (integer && v >= lo && v <= hi) return "";
        return text + ": must be an integer in " + range_text + " (" + source + ")";
      },
      range_text, "gyrocomp-integer-range");
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
  spec.max_memory_bytes = static_cast<std::size_t>(std::min(o.max_memory_gb, 1e9) * 1e9);
  const auto unit = ParseRateUnit(o.rate_unit);
  if (!unit) return InvalidArgument("--rate-unit " + o.rate_unit + ": must be dps, rads or dph");
  spec.rate_unit = *unit;
  spec.instance = o.instance;
  spec.topic = o.topic;
  spec.bag_time = o.time_source == "receive" ? BagTimeSource::kReceive : BagTimeSource::kHeader;
  spec.on_warning = [](const std::string& w) { std::cerr << "gyrocomp: " << w << "\n"; };
  return spec;
}

Result<LoadedLog> LoadLog(const std::string& command, const LogOptions& options, LogSpec spec) {
  if (options.rate_unit_given && options.rate_unit != "rads" && DetectLogFormat(options.input) != LogFormat::kCsv) {
    return InvalidArgument("--rate-unit " + options.rate_unit + ": " + options.input +
                           " is a flight-controller log, whose rates are rad/s (drop --rate-unit)");
  }
  // A ROS bag is read here so that --strict reaches its reader (BagReadOptions::strict).
  Result<LogTableRead> read = DetectLogFormat(options.input) == LogFormat::kRosBag
                                  ? ReadBagLogTable(options.input, spec, options.strict)
                                  : ReadLogTable(options.input, spec, options.strict);
  if (!read) return read.error();
  spec = read->spec;
  // A CSV read for some of its columns only (LogSpec::keep_cols): the log's columns move out of
  // the table (what stays are the ones the command named); otherwise the table stays whole.
  // (A ROS bag's table keeps its accelerometer columns for allan: never taken apart.)
  const bool take = spec.keep_cols.has_value() && read->format != LogFormat::kRosBag;
  Result<GyroLog> log = take ? TakeGyroLog(&read->table, spec) : LoadGyroLog(read->table, spec);
  if (!log) return log.error();
  AttachFlightLogInfo(*read, &*log);
  LoadedLog out{std::move(read->table), std::move(*log), {}};
  if (read->flight) out.damage = read->flight->damage;
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

void SetColumn(const std::string& command, Table* table, std::string name, std::vector<double> values) {
  const std::string shown = name;
  if (table->Set(std::move(name), std::move(values))) {
    Note(command, "warning: the input already has a column '" + shown + "' (an earlier run's output?): replaced by this run's");
  }
}

void WarnIfTemperatureFlat(const std::string& command, const GyroLog& log) {
  if (log.temp_c.empty()) return;
  const auto [lo, hi] = std::minmax_element(log.temp_c.begin(), log.temp_c.end());
  if (*hi - *lo >= kMinTemperatureSpanC) return;
  char msg[320];
  std::snprintf(msg, sizeof msg,
                "warning: the temperature spans only %.3g C (%.6g .. %.6g C), below %.3g C: there is no temperature "
                "variation to learn drift from; the model is then a bias for this one temperature (plus fitted "
                "noise), not a temperature compensation",
                *hi - *lo, *lo, *hi, kMinTemperatureSpanC);
  Note(command, msg);
}

void Note(const std::string& command, const std::string& message) {
  std::cerr << "gyrocomp " << command << ": " << message << "\n";
}

namespace {

struct FileOption {
  const CLI::App* app;
  CLI::Option* option;
  std::string* path;
  bool output;
  std::vector<std::string>* paths = nullptr;  // an input option that takes several files
};

std::vector<FileOption>& FileOptions() {
  static std::vector<FileOption> options;
  return options;
}

// Length of the valid UTF-8 sequence at s[i], or 0.
std::size_t Utf8Length(const std::string& s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 && c >= 0xc2 ? 2 : (c >> 4) == 0xe ? 3 : (c >> 3) == 0x1e && c <= 0xf4 ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return 0;
  }
  const auto c1 = static_cast<unsigned char>(s[i + 1 < s.size() ? i + 1 : i]);
  if ((c == 0xe0 && c1 < 0xa0) || (c == 0xed && c1 >= 0xa0) || (c == 0xf0 && c1 < 0x90) || (c == 0xf4 && c1 >= 0x90)) {
    return 0;  // overlong, surrogate, beyond U+10FFFF
  }
  return n;
}

// `s` with every byte that is not part of valid UTF-8 written as the four characters \xNN.
std::string EscapeNonUtf8(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = Utf8Length(s, i);
    if (n > 0) {
      out.append(s, i, n);
      i += n;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", static_cast<unsigned char>(s[i]));
      out += buf;
      ++i;
    }
  }
  return out;
}

// Escapes non-UTF-8 strings in place and refuses non-finite numbers, naming their JSON pointer.
Status CleanJson(nlohmann::json& j, const std::string& where) {
  if (j.is_number_float() && !std::isfinite(j.get<double>())) {
    return InternalError("JSON value at '" + where + "' would be " + (std::isnan(j.get<double>()) ? "NaN" : "an infinity") +
                         ": refusing to write a non-finite number");
  }
  if (j.is_string()) {
    const std::string& s = j.get_ref<const std::string&>();
    if (EscapeNonUtf8(s) != s) j = EscapeNonUtf8(s);
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      if (Status s = CleanJson(j[i], where + "/" + std::to_string(i)); !s) return s;
    }
  } else if (j.is_object()) {
    nlohmann::json clean = nlohmann::json::object();
    for (auto& [key, value] : j.items()) {
      const std::string k = EscapeNonUtf8(key);
      if (Status s = CleanJson(value, where + "/" + k); !s) return s;
      clean[k] = std::move(value);
    }
    j = std::move(clean);
  }
  return Status::Ok();
}

// What a destination resolves to, so that two options writing the same place are refused
// before any work: "-" is standard output (so it matches /dev/stdout or a link to
// it), an existing file its device and inode, a new name its canonical path. "" for what may
// take several outputs: /dev/null and a terminal.
std::string OutputIdentity(const std::string& path) {
  struct stat st;
  const bool is_stdout = path == "-";
  if (is_stdout ? ::fstat(STDOUT_FILENO, &st) == 0 : ::stat(path.c_str(), &st) == 0) {
    struct stat null_st;
    if (::stat("/dev/null", &null_st) == 0 && st.st_dev == null_st.st_dev && st.st_ino == null_st.st_ino) return "";
    if (S_ISCHR(st.st_mode) && (is_stdout ? ::isatty(STDOUT_FILENO) : 1) != 0) {
      const int fd = is_stdout ? STDOUT_FILENO : ::open(path.c_str(), O_WRONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
      const bool tty = fd >= 0 && ::isatty(fd) != 0;
      if (fd >= 0 && !is_stdout) ::close(fd);
      if (tty) return is_stdout ? "stdout" : "";
    }
    return std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
  }
  if (is_stdout) return "stdout";
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
  return "new:" + (ec ? path : canonical.string());
}

}  // namespace

CLI::Option* AddInputOption(CLI::App* app, const std::string& flags, std::string* path, const std::string& help) {
  CLI::Option* option = app->add_option(flags, *path, help);
  FileOptions().push_back({app, option, path, false});
  return option;
}

CLI::Option* AddInputOption(CLI::App* app, const std::string& flags, std::vector<std::string>* paths,
                            const std::string& help) {
  CLI::Option* option = app->add_option(flags, *paths, help);
  FileOptions().push_back({app, option, nullptr, false, paths});
  return option;
}

CLI::Option* AddOutputOption(CLI::App* app, const std::string& flags, std::string* path, const std::string& help) {
  CLI::Option* option = app->add_option(flags, *path, help);
  FileOptions().push_back({app, option, path, true});
  return option;
}

OutputSet& Outputs() {
  static OutputSet outputs;
  return outputs;
}

Status PrepareFiles(const CLI::App* app) {
  for (const FileOption& f : FileOptions()) {
    if (f.app != app || f.output) continue;
    if (f.paths != nullptr) {
      for (const std::string& p : *f.paths) Outputs().AddInput(p);
    } else {
      Outputs().AddInput(*f.path);
    }
  }
  std::vector<std::pair<std::string, const FileOption*>> written;  // (identity, option)
  for (const FileOption& f : FileOptions()) {
    if (f.app != app || !f.output || (f.option->count() == 0 && f.path->empty())) continue;
    if (f.path->empty()) return InvalidArgument(f.option->get_name() + ": the file name is empty");
    const std::string id = OutputIdentity(*f.path);
    for (const auto& [other_id, other] : written) {
      if (!id.empty() && (id == other_id || *other->path == *f.path)) {
        return InvalidArgument(other->option->get_name() + " '" + *other->path + "' and " + f.option->get_name() +
                               " '" + *f.path + "' are the same destination: give each output its own file");
      }
    }
    written.emplace_back(id, &f);
    if (Status s = Outputs().Declare(*f.path); !s) return s;
  }
  return Status::Ok();
}

Status WriteCsv(const std::string& path, const Table& table) { return Outputs().StageCsv(path, table); }

Status WriteText(const std::string& path, const std::string& text) { return Outputs().StageText(path, text); }

Result<std::string> JsonText(const nlohmann::json& j) {
  nlohmann::json copy = j;
  if (Status s = CleanJson(copy, ""); !s) return s.error();
  return copy.dump(1) + "\n";
}

Status WriteJson(const std::string& path, const nlohmann::json& j) {
  Result<std::string> text = JsonText(j);
  if (!text) return Status(Error{text.error().kind, path + ": " + text.error().message});
  return WriteText(path, *text);
}

double Rms(std::span<const double> a, std::span<const double> b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = a[i] - (b.empty() ? 0.0 : b[i]);
    s += d * d;
  }
  return a.empty() ? 0.0 : std::sqrt(s / static_cast<double>(a.size()));
}

}  // namespace gyrocomp::cli
