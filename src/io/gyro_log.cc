// GyroLog extraction and sampling checks (include/gyrocomp/gyro_log.h).
#include "gyrocomp/io/gyro_log.h"

#include "gyrocomp/core/format.h"
#include "gyrocomp/io/flight_log.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

namespace gyrocomp {

namespace {

std::string Where(const std::string& file, std::size_t line, std::size_t column) {
  return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
}

// %.*g formatting for messages.
// Shortest round-trip text of a value: what the file most likely says.
std::string Shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string SourceOf(const Table& table) {
  return table.source.empty() ? std::string("<table>") : table.source;
}

// "no column 'x' (what) in the header; columns are: a, b, c; did you mean 'X'?"
Error MissingColumn(const Table& table, const std::string& name, const std::string& what,
                    const std::string& hint) {
  std::string list;
  std::string guess;
  for (const std::string& n : table.FileNames()) {
    list += (list.empty() ? "" : ", ") + n;
    if (guess.empty() && Lower(n) == Lower(name)) guess = n;
  }
  std::string msg = Where(SourceOf(table), 1, 1) + "missing column '" + name + "' (" + what +
                    ") in the header; columns are: " + list;
  if (!guess.empty()) msg += "; did you mean '" + guess + "'?";
  if (!hint.empty()) msg += "; " + hint;
  return InvalidInput(msg);
}

// Data row i is line i + 2 (the header is line 1; ReadCsv rejects blank lines inside the data).
std::size_t LineOf(std::size_t row) { return row + 2; }

// Strictly increasing time, or an error naming both lines and values.
std::optional<Error> CheckMonotonic(const Table& table, int time_index) {
  const std::vector<double>& t = table.columns[static_cast<std::size_t>(time_index)];
  const std::string& col = table.names[static_cast<std::size_t>(time_index)];
  const std::size_t file_col = table.FileColumn(static_cast<std::size_t>(time_index));
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (t[i] > t[i - 1]) continue;
    const std::string at = Where(SourceOf(table), LineOf(i), file_col);
    const std::string here = col + " = " + Shortest(t[i]) + " at line " + std::to_string(LineOf(i));
    const std::string prev = Shortest(t[i - 1]) + " at line " + std::to_string(LineOf(i - 1));
    if (t[i] == t[i - 1]) {
      return InvalidInput(at + "time repeats: " + here + " equals the previous row's " + prev +
                          " (column " + std::to_string(file_col) + "); timestamps must be "
                          "strictly increasing");
    }
    return InvalidInput(at + "time goes backwards: " + here + " is before the previous row's " +
                        prev + " (column " + std::to_string(file_col) + ")");
  }
  return std::nullopt;
}

// Linear interpolation of the columns `which` of `table` (time = column `time_index`, strictly
// increasing) onto t0 + k / fs_hz. Returns the grid and fills `out` (one vector per entry of
// `which`); counts grid points that fall strictly inside a gap interval.
std::vector<double> Interpolate(const std::vector<double>& t, const std::vector<const std::vector<double>*>& which,
                                double fs_hz, double gap_dt_s, std::vector<std::vector<double>>* out,
                                std::size_t* in_gaps) {
  const double t0 = t.front();
  const double span = t.back() - t0;
  // floor with a relative guard so that an end time that is an exact multiple of 1/fs in
  // decimal (e.g. 9.99 at 100 Hz) keeps its last grid point despite rounding.
  const auto m = static_cast<std::size_t>(std::floor(span * fs_hz * (1.0 + 1e-12) + 1e-9)) + 1;
  std::vector<double> grid(m);
  out->assign(which.size(), std::vector<double>(m));
  *in_gaps = 0;
  std::size_t i = 0;  // t[i] <= tk < t[i+1]
  for (std::size_t k = 0; k < m; ++k) {
    double tk = t0 + static_cast<double>(k) / fs_hz;
    if (tk > t.back()) tk = t.back();  // the guard above may step past the end by an ulp
    grid[k] = tk;
    while (i + 2 < t.size() && t[i + 1] <= tk) ++i;
    const double dt = t[i + 1] - t[i];
    double w = (tk - t[i]) / dt;  // Linear interpolation weight in [0, 1].
    w = std::clamp(w, 0.0, 1.0);
    if (dt > gap_dt_s && tk > t[i] && tk < t[i + 1]) ++*in_gaps;
    for (std::size_t c = 0; c < which.size(); ++c) {
      const std::vector<double>& y = *which[c];
      (*out)[c][k] = w == 0.0 ? y[i] : (w == 1.0 ? y[i + 1] : y[i] + w * (y[i + 1] - y[i]));
    }
  }
  return grid;
}

// Resampling `span_s` at `fs_hz` into `columns` columns must fit in `max_bytes`.
std::optional<Error> CheckResampleMemory(double span_s, double fs_hz, std::size_t columns, std::size_t max_bytes,
                                         const std::string& src) {
  const double samples = std::floor(span_s * fs_hz) + 1.0;
  const double bytes = samples * static_cast<double>(columns) * sizeof(double);
  if (bytes <= static_cast<double>(max_bytes)) return std::nullopt;
  char msg[240];
  std::snprintf(msg, sizeof msg,
                "--resample %.6g Hz over %.6g s needs %.3g GB for %.3g samples of %zu columns; at most %.3g GB "
                "allowed (--max-memory)", fs_hz, span_s, bytes / 1e9, samples, columns,
                static_cast<double>(max_bytes) / 1e9);
  return InvalidArgument(src + ": " + msg);
}

}  // namespace

bool LogSpec::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = "LogSpec::" + m;
    return false;
  };
  if (rates_required && rate_cols.empty()) return fail("rate_cols is empty: name at least one rate column");
  for (std::size_t a = 0; a < rate_cols.size(); ++a) {
    if (rate_cols[a].empty()) return fail("rate_cols[" + std::to_string(a) + "] is empty");
    for (std::size_t b = 0; b < a; ++b) {
      if (rate_cols[a] == rate_cols[b]) return fail("rate_cols names '" + rate_cols[a] + "' twice");
    }
  }
  const std::string fs_range = " Hz: must be in [" + FormatNumber(kMinFsHz) + ", " + FormatNumber(kMaxFsHz) + "] Hz";
  if (fs_hz && !(*fs_hz >= kMinFsHz && *fs_hz <= kMaxFsHz)) return fail("fs_hz = " + FormatNumber(*fs_hz) + fs_range);
  if (resample_hz && !(*resample_hz >= kMinFsHz && *resample_hz <= kMaxFsHz)) {
    return fail("resample_hz = " + FormatNumber(*resample_hz) + fs_range);
  }
  if (!(max_abs_rate_dps > 0)) return fail("max_abs_rate_dps = " + FormatNumber(max_abs_rate_dps) + ": must be > 0");
  if (!(min_temp_c < max_temp_c)) return fail("min_temp_c must be below max_temp_c");
  if (max_memory_bytes == 0) return fail("max_memory_bytes = 0: must be > 0");
  if (min_samples < 1) return fail("min_samples = 0: must be >= 1");
  if (!(jitter_tolerance > 0 && jitter_tolerance < 1)) {
    return fail("jitter_tolerance = " + FormatNumber(jitter_tolerance) + ": must be in (0, 1) (fraction of the median dt)");
  }
  if (!(max_irregular_fraction >= 0 && max_irregular_fraction <= 1)) {
    return fail("max_irregular_fraction = " + FormatNumber(max_irregular_fraction) + ": must be in [0, 1]");
  }
  if (!(gap_factor > 1)) return fail("gap_factor = " + FormatNumber(gap_factor) + ": must be > 1 (multiple of the median dt)");
  return true;
}

std::string SamplingReport::BriefReport() const {
  std::string s;
  if (time_from_fs) {
    s = "no time column: " + std::to_string(rows_in) + " samples at the given " + FormatNumber(fs_hz) + " Hz";
    return s;
  }
  s = std::to_string(rows_in) + " samples, " + std::to_string(num_intervals) + " intervals: median dt " +
      FormatNumber(median_dt_s) + " s, min " + FormatNumber(min_dt_s) + " s, max " + FormatNumber(max_dt_s) + " s; " +
      std::to_string(num_irregular) + " outside the jitter tolerance, " + std::to_string(num_gaps) +
      " gaps (longest " + FormatNumber(longest_gap_s) + " s); " + (irregular ? "IRREGULAR" : "regular");
  if (resampled) {
    s += "; resampled by linear interpolation to " + FormatNumber(fs_hz) + " Hz: " + std::to_string(rows_in) +
         " -> " + std::to_string(rows_out) + " rows, " + std::to_string(rows_in_gaps) +
         " of them interpolated across gaps (no anti-alias filter)";
  } else {
    s += "; " + FormatNumber(fs_hz) + " Hz";
  }
  return s;
}

SamplingReport MeasureSampling(const std::vector<double>& time_s, const LogSpec& spec) {
  SamplingReport r;
  r.rows_in = r.rows_out = time_s.size();
  if (time_s.size() < 2) return r;
  // One vector of intervals, partly sorted for the median; the other statistics take the
  // intervals from time_s again (the same differences, so the same bits).
  const auto interval = [&time_s](std::size_t i) { return time_s[i + 1] - time_s[i]; };
  r.num_intervals = time_s.size() - 1;
  r.min_dt_s = r.max_dt_s = interval(0);
  for (std::size_t i = 1; i < r.num_intervals; ++i) {
    r.min_dt_s = std::min(r.min_dt_s, interval(i));
    r.max_dt_s = std::max(r.max_dt_s, interval(i));
  }
  {
    std::vector<double> sorted(r.num_intervals);
    for (std::size_t i = 0; i < r.num_intervals; ++i) sorted[i] = interval(i);
    const std::size_t mid = sorted.size() / 2;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(mid), sorted.end());
    r.median_dt_s = sorted[mid];
    if (sorted.size() % 2 == 0) {
      const double lower = *std::max_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(mid));
      r.median_dt_s = 0.5 * (r.median_dt_s + lower);
    }
  }
  const double lo = (1.0 - spec.jitter_tolerance) * r.median_dt_s;
  const double hi = (1.0 + spec.jitter_tolerance) * r.median_dt_s;
  const double gap = spec.gap_factor * r.median_dt_s;
  for (std::size_t i = 0; i < r.num_intervals; ++i) {
    const double d = interval(i);
    if (d < lo || d > hi) ++r.num_irregular;
    if (d > gap) {
      ++r.num_gaps;
      r.longest_gap_s = std::max(r.longest_gap_s, d);
    }
  }
  r.irregular = r.num_gaps > 0 ||
                static_cast<double>(r.num_irregular) > spec.max_irregular_fraction * static_cast<double>(r.num_intervals);
  // Mean rate over the record: the best estimate of fs for a regular log.
  r.fs_hz = static_cast<double>(r.num_intervals) / (time_s.back() - time_s.front());
  return r;
}

Result<Table> ResampleTable(const Table& table, const std::string& time_col, double fs_hz) {
  if (!(std::isfinite(fs_hz) && fs_hz > 0)) return InvalidArgument("resample rate = " + FormatNumber(fs_hz) + " Hz: must be > 0");
  const int ti = table.Find(time_col);
  if (ti < 0) return MissingColumn(table, time_col, "time, s", "");
  if (table.num_rows() < 2) {
    return InvalidInput(Where(SourceOf(table), table.num_rows() + 1, 1) + "too few samples to resample: " +
                        std::to_string(table.num_rows()));
  }
  if (auto e = CheckMonotonic(table, ti)) return *e;
  const std::vector<double>& t = table.columns[static_cast<std::size_t>(ti)];
  if (auto e = CheckResampleMemory(t.back() - t.front(), fs_hz, table.columns.size(), LogSpec{}.max_memory_bytes,
                                   SourceOf(table))) {
    return *e;
  }
  std::vector<const std::vector<double>*> which;
  for (const auto& c : table.columns) which.push_back(&c);
  std::vector<std::vector<double>> cols;
  std::size_t in_gaps = 0;
  const SamplingReport s = MeasureSampling(table.columns[static_cast<std::size_t>(ti)], LogSpec{});
  const std::vector<double> grid = Interpolate(table.columns[static_cast<std::size_t>(ti)], which, fs_hz,
                                               LogSpec{}.gap_factor * s.median_dt_s, &cols, &in_gaps);
  Table out;
  out.source = table.source;
  out.names = table.names;
  out.header = table.header;
  out.columns = std::move(cols);
  out.columns[static_cast<std::size_t>(ti)] = grid;
  return out;
}

namespace {

// Where the log's columns are in the table (-1: absent) and the names of the rate axes found.
struct LogColumns {
  std::vector<int> rate;
  std::vector<std::string> axis_names;
  int temp = -1;
  int time = -1;
};

// Step 1: find the rate, temperature and time columns; a required one that is missing is an
// error naming the header's columns and the option that chooses it.
Result<LogColumns> FindLogColumns(const Table& table, const LogSpec& spec) {
  LogColumns cols;
  for (const std::string& name : spec.rate_cols) {
    const int j = table.Find(name);
    if (j < 0) {
      if (!spec.rates_required) continue;
      return MissingColumn(table, name, std::string("rate, ") + std::string(RateUnitName(spec.rate_unit)),
                           "choose the rate column(s) with --rate-col");
    }
    cols.rate.push_back(j);
    cols.axis_names.push_back(name);
  }
  cols.temp = table.Find(spec.temp_col);
  if (cols.temp < 0 && spec.temp_required) {
    return MissingColumn(table, spec.temp_col, "temperature, deg C", "choose it with --temp-col");
  }
  cols.time = table.Find(spec.time_col);
  if (cols.time < 0 && !spec.fs_hz) {
    return MissingColumn(table, spec.time_col, "time, s",
                         "name the time column with --time-col, or give the sample rate with --fs HZ");
  }
  return cols;
}

// Hands the table's columns to the log: copies (LoadGyroLog), or, for TakeGyroLog, the columns
// themselves, moved, when nothing else needs them: a column that serves two roles (time and
// temperature named alike) is copied for all but its last, one LogSpec::keep_cols names is
// copied (the caller reads it from the table too). RemoveMoved then drops the moved columns.
class ColumnTaker {
 public:
  ColumnTaker(const Table& table, Table* movable, const LogSpec& spec, const LogColumns& cols)
      : table_(table), movable_(movable), uses_(table.columns.size(), 0), moved_(table.columns.size(), false) {
    if (cols.time >= 0) ++uses_[static_cast<std::size_t>(cols.time)];
    for (int j : cols.rate) ++uses_[static_cast<std::size_t>(j)];
    if (cols.temp >= 0) ++uses_[static_cast<std::size_t>(cols.temp)];
    if (spec.keep_cols) {
      for (const std::string& name : *spec.keep_cols) {
        const int j = table.Find(name);
        if (j >= 0) uses_[static_cast<std::size_t>(j)] += 1000;  // never the last use
      }
    }
  }
  // Column j: moved out when this is its last use and the table may give it up, else copied.
  std::vector<double> Take(int j) {
    const auto k = static_cast<std::size_t>(j);
    if (movable_ != nullptr && --uses_[k] == 0) {
      moved_[k] = true;
      return std::move(movable_->columns[k]);
    }
    return table_.columns[k];
  }
  void RemoveMoved() {
    if (movable_ == nullptr) return;
    for (std::size_t k = moved_.size(); k-- > 0;) {
      if (moved_[k]) movable_->Remove(k);
    }
  }

 private:
  const Table& table_;
  Table* movable_;
  std::vector<int> uses_;
  std::vector<bool> moved_;
};

// Step 1b: values no instrument produces (LogSpec::max_abs_rate_dps, min_temp_c, max_temp_c).
std::optional<Error> CheckValueRanges(const Table& table, const LogSpec& spec, const LogColumns& cols) {
  const double to_dps = units::ToDegPerSec(spec.rate_unit);
  for (int j : cols.rate) {
    const std::vector<double>& v = table.columns[static_cast<std::size_t>(j)];
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (std::abs(v[i] * to_dps) <= spec.max_abs_rate_dps) continue;
      return InvalidInput(Where(SourceOf(table), LineOf(i), table.FileColumn(static_cast<std::size_t>(j))) + "rate " +
                          table.names[static_cast<std::size_t>(j)] + " = " + Shortest(v[i]) +
                          " is beyond any gyroscope (|rate| <= " + FormatNumber(spec.max_abs_rate_dps) + " deg/s)");
    }
  }
  if (cols.temp >= 0) {
    const std::vector<double>& v = table.columns[static_cast<std::size_t>(cols.temp)];
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (v[i] >= spec.min_temp_c && v[i] <= spec.max_temp_c) continue;
      return InvalidInput(Where(SourceOf(table), LineOf(i), table.FileColumn(static_cast<std::size_t>(cols.temp))) +
                          "temperature " + table.names[static_cast<std::size_t>(cols.temp)] + " = " +
                          Shortest(v[i]) + " C is outside [" + FormatNumber(spec.min_temp_c) + ", " +
                          FormatNumber(spec.max_temp_c) + "] C");
    }
  }
  return std::nullopt;
}

// Step 2a (no time column): uniform by construction, time = i / fs.
Result<GyroLog> LoadUniformLog(const Table& table, const LogSpec& spec, const LogColumns& cols, GyroLog log,
                               ColumnTaker* taker) {
  const std::string& src = log.source;
  const std::size_t n = table.num_rows();
  const double to_dps = units::ToDegPerSec(spec.rate_unit);
  const double fs = *spec.fs_hz;
  log.time_s.resize(n);
  for (std::size_t i = 0; i < n; ++i) log.time_s[i] = static_cast<double>(i) / fs;
  log.sampling.time_from_fs = true;
  log.sampling.fs_hz = fs;
  log.sampling.median_dt_s = log.sampling.min_dt_s = log.sampling.max_dt_s = 1.0 / fs;
  log.sampling.num_intervals = n > 0 ? n - 1 : 0;
  log.sampling.rows_in = log.sampling.rows_out = n;
  if (spec.resample_hz) {
    return InvalidInput(Where(src, 1, 1) + "--resample needs a time column ('" + spec.time_col +
                        "' is missing); a log without one is uniform at --fs already");
  }
  for (int j : cols.rate) {
    std::vector<double> r = taker->Take(j);
    if (to_dps != 1.0) for (double& v : r) v *= to_dps;
    log.rate_dps.push_back(std::move(r));
  }
  if (cols.temp >= 0) log.temp_c = taker->Take(cols.temp);
  log.fs_hz = fs;
  return log;
}

// Step 2b: a given --fs must agree with the time column's median interval within 1%.
std::optional<Error> CheckFsAgreesWithTime(const LogSpec& spec, const SamplingReport& rep, const std::string& src,
                                           std::size_t tcol) {
  if (!spec.fs_hz) return std::nullopt;
  const double fs_t = 1.0 / rep.median_dt_s;
  if (std::abs(*spec.fs_hz / fs_t - 1.0) > 0.01) {
    return InvalidInput(Where(src, 2, tcol) + "--fs " + FormatNumber(*spec.fs_hz) + " Hz disagrees with the time column '" +
                        spec.time_col + "' (median dt " + FormatNumber(rep.median_dt_s) + " s = " + FormatNumber(fs_t) +
                        " Hz) by more than 1%; the time column wins: drop --fs or fix the time column");
  }
  return std::nullopt;
}

// Step 2c: the error for irregular timestamps without --resample, with the sampling statistics.
Error IrregularTimestamps(const std::vector<double>& t, const LogSpec& spec, const SamplingReport& rep,
                          const std::string& src, std::size_t tcol) {
  const std::size_t n = t.size();
  // Point at the longest gap, or else at the first interval outside the tolerance.
  std::size_t worst = 0;
  double worst_dev = -1;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double dev = std::abs((t[i + 1] - t[i]) / rep.median_dt_s - 1.0);
    if (dev > worst_dev) {
      worst_dev = dev;
      worst = i + 1;
    }
  }
  // Burst signature (FIFO read times: many reads ~1/median apart, then a long wait): the mean
  // rate is far below 1/median dt. The samples themselves may well be uniform then.
  std::string burst_hint;
  if (rep.fs_hz < 0.5 / rep.median_dt_s) {
    burst_hint = " (the times look like bursts of reads: mean rate " + FormatNumber(rep.fs_hz, 4) + " Hz vs " +
                 FormatNumber(1.0 / rep.median_dt_s, 4) + " Hz within bursts; if the sensor sampled uniformly, "
                 "use --time-col none --fs " + FormatNumber(rep.fs_hz, 4) + " to take time = i / fs instead)";
  }
  const double pct = 100.0 * static_cast<double>(rep.num_irregular) / static_cast<double>(rep.num_intervals);
  return InvalidInput(
      Where(src, LineOf(worst), tcol) + "irregular timestamps in '" + spec.time_col + "': " +
      std::to_string(rep.num_intervals) + " intervals, median dt " + FormatNumber(rep.median_dt_s, 4) + " s (" +
      FormatNumber(1.0 / rep.median_dt_s, 4) + " Hz), min " + FormatNumber(rep.min_dt_s, 4) + " s, max " + FormatNumber(rep.max_dt_s, 4) +
      " s, mean rate " + FormatNumber(rep.fs_hz, 4) + " Hz; " + std::to_string(rep.num_irregular) + " intervals (" +
      FormatNumber(pct, 3) + "%) outside +-" + FormatNumber(100 * spec.jitter_tolerance) + "% of the median; " +
      std::to_string(rep.num_gaps) + " gaps > " + FormatNumber(spec.gap_factor) + " x median, longest " +
      FormatNumber(rep.longest_gap_s, 4) + " s; worst interval ends at line " + std::to_string(LineOf(worst)) +
      ". Pass --resample HZ to interpolate linearly onto a uniform grid" + burst_hint);
}

// Step 3: the rate (converted to deg/s) and temperature columns on the time column's grid, or
// linearly interpolated onto a uniform grid at --resample HZ.
Result<GyroLog> TakeTimedColumns(const Table& table, const LogSpec& spec, const LogColumns& cols,
                                 SamplingReport rep, GyroLog log, ColumnTaker* taker) {
  const std::vector<double>& t = table.columns[static_cast<std::size_t>(cols.time)];
  const std::size_t tcol = table.FileColumn(static_cast<std::size_t>(cols.time));
  const std::size_t n = table.num_rows();
  const double to_dps = units::ToDegPerSec(spec.rate_unit);
  std::vector<const std::vector<double>*> which;
  for (int j : cols.rate) which.push_back(&table.columns[static_cast<std::size_t>(j)]);
  if (cols.temp >= 0) which.push_back(&table.columns[static_cast<std::size_t>(cols.temp)]);
  std::vector<std::vector<double>> taken;
  if (spec.resample_hz) {
    // The log's columns, and the CLI's resampled copy of every table column (ResampleTable).
    if (auto e = CheckResampleMemory(t.back() - t.front(), *spec.resample_hz, which.size() + 1 + table.columns.size(),
                                     spec.max_memory_bytes, log.source)) {
      return *e;
    }
    std::size_t in_gaps = 0;
    log.time_s = Interpolate(t, which, *spec.resample_hz, spec.gap_factor * rep.median_dt_s, &taken, &in_gaps);
    rep.resampled = true;
    rep.rows_in_gaps = in_gaps;
    rep.rows_out = log.time_s.size();
    rep.fs_hz = *spec.resample_hz;
    if (rep.rows_out < spec.min_samples) {
      return InvalidInput(Where(log.source, n + 1, tcol) + "too few samples after resampling to " + FormatNumber(rep.fs_hz) +
                          " Hz: " + std::to_string(rep.rows_out) + ", this analysis needs at least " +
                          std::to_string(spec.min_samples));
    }
  } else {
    log.time_s = taker->Take(cols.time);  // (t is no longer used: it may have been moved)
    for (int j : cols.rate) taken.push_back(taker->Take(j));
    if (cols.temp >= 0) taken.push_back(taker->Take(cols.temp));
  }
  for (std::size_t a = 0; a < cols.rate.size(); ++a) {
    if (to_dps != 1.0) for (double& v : taken[a]) v *= to_dps;
    log.rate_dps.push_back(std::move(taken[a]));
  }
  if (cols.temp >= 0) log.temp_c = std::move(taken.back());
  log.fs_hz = rep.fs_hz;
  log.sampling = rep;
  return log;
}

// LoadGyroLog, or TakeGyroLog when `movable` (== &table) is given.
Result<GyroLog> LoadGyroLogFrom(const Table& table, Table* movable, const LogSpec& spec) {
  std::string why;
  if (!spec.IsValid(&why)) return InvalidArgument(why);
  const std::string src = SourceOf(table);
  const std::size_t n = table.num_rows();

  GyroLog log;
  log.source = src;
  Result<LogColumns> cols = FindLogColumns(table, spec);
  if (!cols) return cols.error();
  log.axis_names = cols->axis_names;
  if (auto e = CheckValueRanges(table, spec, *cols)) return *e;
  if (n < spec.min_samples) {
    return InvalidInput(Where(src, n + 1, 1) + "too few samples: " + std::to_string(n) +
                        " data row(s), this analysis needs at least " + std::to_string(spec.min_samples));
  }
  ColumnTaker taker(table, movable, spec, *cols);
  if (cols->time < 0) {
    Result<GyroLog> out = LoadUniformLog(table, spec, *cols, std::move(log), &taker);
    if (out) taker.RemoveMoved();
    return out;
  }

  const std::vector<double>& t = table.columns[static_cast<std::size_t>(cols->time)];
  const std::size_t tcol = table.FileColumn(static_cast<std::size_t>(cols->time));
  if (n < 2) {
    return InvalidInput(Where(src, n + 1, tcol) + "too few samples: 1 data row; at least 2 are needed "
                        "to measure the sampling interval");
  }
  if (auto e = CheckMonotonic(table, cols->time)) return *e;
  SamplingReport rep = MeasureSampling(t, spec);
  // (With --resample, the memory the new grid needs is what bounds it, in TakeTimedColumns.)
  if (!spec.resample_hz && !(rep.fs_hz >= LogSpec::kMinFsHz && rep.fs_hz <= LogSpec::kMaxFsHz)) {
    return InvalidInput(Where(src, 2, tcol) + "the time column '" + spec.time_col + "' gives a sample rate of " +
                        FormatNumber(rep.fs_hz) + " Hz (" + FormatNumber(t.back() - t.front()) + " s for " +
                        std::to_string(n - 1) + " intervals): outside [" + FormatNumber(LogSpec::kMinFsHz) + ", " +
                        FormatNumber(LogSpec::kMaxFsHz) + "] Hz");
  }
  if (auto e = CheckFsAgreesWithTime(spec, rep, src, tcol)) return *e;
  if (rep.irregular && !spec.resample_hz) return IrregularTimestamps(t, spec, rep, src, tcol);
  Result<GyroLog> out = TakeTimedColumns(table, spec, *cols, rep, std::move(log), &taker);
  if (out) taker.RemoveMoved();
  return out;
}

}  // namespace

Result<GyroLog> LoadGyroLog(const Table& table, const LogSpec& spec) { return LoadGyroLogFrom(table, nullptr, spec); }

Result<GyroLog> TakeGyroLog(Table* table, const LogSpec& spec) { return LoadGyroLogFrom(*table, table, spec); }

Result<GyroLog> ReadGyroLog(const std::string& path, const LogSpec& spec) {
  std::string why;
  if (!spec.IsValid(&why)) return InvalidArgument(why);
  // CSV, PX4 ULog or ArduPilot DataFlash, by the file's first bytes (flight_log.h). Only the
  // log's columns of a CSV are kept, and they move into the log (no copy).
  LogSpec only_log = spec;
  if (!only_log.keep_cols) only_log.keep_cols.emplace();
  Result<LogTableRead> read = ReadLogTable(path, only_log);
  if (!read) return read.error();
  Result<GyroLog> log = TakeGyroLog(&read->table, read->spec);
  if (!log) return log.error();
  AttachFlightLogInfo(*read, &*log);
  return log;
}

}  // namespace gyrocomp
