// Numeric CSV reading (include/gyrocomp/io.h); writing is in io_write.cc.
//
// Reading: zlib's gzread reads gzip and plain files alike (it detects the gzip magic bytes
// 1f 8b itself), so plain, .gz and stdin share one path. The decompressed stream is processed in
// large chunks; every cell is parsed in place with std::from_chars (no iostream, no strtod on
// the hot path). Any problem stops the read with "<file>:<line>:<column>: <what>".
#include "gyrocomp/io/io.h"

#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cassert>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>

namespace gyrocomp {

int Table::Find(const std::string& name) const {
  for (std::size_t j = 0; j < names.size(); ++j) {
    if (names[j] == name) return static_cast<int>(j);
  }
  return -1;
}

void Table::Add(std::string name, std::vector<double> values) {
  assert(columns.empty() || values.size() == num_rows());
  names.push_back(std::move(name));
  columns.push_back(std::move(values));
}

std::size_t Table::FileColumn(std::size_t j) const {
  if (header.empty() || j >= names.size()) return j + 1;
  for (std::size_t k = 0; k < header.size(); ++k) {
    if (header[k] == names[j]) return k + 1;
  }
  return j + 1;
}

void Table::Remove(std::size_t j) {
  assert(j < names.size());
  if (header.empty()) header = names;
  names.erase(names.begin() + static_cast<std::ptrdiff_t>(j));
  columns.erase(columns.begin() + static_cast<std::ptrdiff_t>(j));
}

bool Table::Set(std::string name, std::vector<double> values) {
  const int j = Find(name);
  if (j < 0) {
    Add(std::move(name), std::move(values));
    return false;
  }
  assert(values.size() == num_rows());
  columns[static_cast<std::size_t>(j)] = std::move(values);
  return true;
}

namespace {

constexpr std::size_t kChunkBytes = std::size_t{1} << 22;  // 4 MiB per read
constexpr unsigned kGzBufferBytes = 1u << 20;              // zlib's internal buffer
// Rows to read before the columns are reserved for the whole file, and the margin over the
// estimate (bytes per row so far; for gzip, decompressed bytes per compressed byte so far). A
// reservation costs address space only: the pages a column never reaches are never touched, so
// the margin costs no resident memory, while an estimate short of the file makes every kept
// column copy itself once (old and new both resident for a moment).
constexpr std::size_t kRowsBeforeReserve = 1000;
constexpr double kReserveMarginPlain = 1.05;
constexpr double kReserveMarginGzip = 1.25;

std::string Where(const std::string& file, std::size_t line, std::size_t column) {
  return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
}

// A cell shown in a message: at most 40 bytes, non-printable bytes as \xNN.
std::string Quote(std::string_view cell) {
  std::string out = "'";
  std::size_t n = 0;
  for (unsigned char c : cell) {
    if (++n > 40) {
      out += "...";
      break;
    }
    if (c >= 0x20 && c < 0x7f) {
      out.push_back(static_cast<char>(c));
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    }
  }
  return out + "'";
}

// zlib's gzerror text without the "<path>: " it prepends (the path is already in the message).
std::string ZlibMessage(const char* msg) {
  if (msg == nullptr) return "?";
  const std::string m = msg;
  const std::size_t colon = m.rfind(": ");
  return colon == std::string::npos ? m : m.substr(colon + 2);
}

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

std::string_view Trim(std::string_view s) {
  while (!s.empty() && IsBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsBlank(s.back())) s.remove_suffix(1);
  return s;
}

// Offset of the first byte of `s` that is not clean text (a control character other than tab,
// DEL, or invalid UTF-8), or npos.
std::size_t FirstUncleanByte(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      if ((c < 0x20 && c != '\t') || c == 0x7f) return i;
      ++i;
      continue;
    }
    int extra = 0;
    if ((c & 0xe0) == 0xc0 && c >= 0xc2) extra = 1;
    else if ((c & 0xf0) == 0xe0) extra = 2;
    else if ((c & 0xf8) == 0xf0 && c <= 0xf4) extra = 3;
    else return i;
    if (i + extra >= s.size()) return i;
    for (int k = 1; k <= extra; ++k) {
      if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return i;
    }
    i += extra + 1;
  }
  return std::string_view::npos;
}

// True when `s` is valid UTF-8 without control characters other than tab.
bool IsCleanText(std::string_view s) { return FirstUncleanByte(s) == std::string_view::npos; }

// For a file named like a flight log or bag that reached the CSV reader: its first bytes are not
// that format's header (DetectLogFormat reads the bytes, not the name), so say so.
std::string LogNameHint(const std::string& source) {
  std::string ext = std::filesystem::path(source).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* log : {".ulg", ".ulog", ".bin", ".bag", ".mcap", ".db3"}) {
    if (ext == log) {
      return "; named like a flight log or bag, but its first bytes are not a ULog, DataFlash or ROS bag "
             "header (a log cut at its start cannot be read)";
    }
  }
  return "";
}

bool HasBinaryByte(std::string_view s) {
  for (unsigned char c : s) {
    if (c == 0 || (c < 0x20 && c != '\t' && c != '\r')) return true;
  }
  return false;
}

// Parses a whole cell (surrounding blanks allowed, optional '+') as a double. Returns false when
// the cell is not exactly one number.
bool ParseCell(std::string_view cell, double* value, bool* out_of_range) {
  cell = Trim(cell);
  const char* b = cell.data();
  const char* e = b + cell.size();
  if (b != e && *b == '+' && b + 1 != e && *(b + 1) != '-') ++b;
  const auto r = std::from_chars(b, e, *value);
  *out_of_range = false;
  if (r.ec == std::errc::result_out_of_range && r.ptr == e) {
    // Underflow (e.g. 1e-400) reads as 0 or a subnormal, as strtod does; overflow is an error.
    const std::string copy(b, e);
    *value = std::strtod(copy.c_str(), nullptr);
    if (std::isinf(*value)) {
      *out_of_range = true;
      return false;
    }
    return true;
  }
  return r.ec == std::errc() && r.ptr == e;
}

// The reader: a gzFile and a growing buffer of complete lines.
class CsvParser {
 public:
  CsvParser(std::string source, const CsvReadOptions& options)
      : source_(std::move(source)), opt_(options) {}

  // `file_size` is the file size when known (0 for stdin/pipes): used to reserve the columns once
  // the first rows show the bytes per row, and for the --max-memory check.
  Result<Table> Run(gzFile in, std::size_t file_size);

 private:
  // Handles one line (without its '\n').
  std::optional<Error> Line(std::string_view line);
  std::optional<Error> Header(std::string_view line);
  std::optional<Error> Row(std::string_view line);
  Error RowError(std::string_view line);
  std::optional<double> EstimateRows(gzFile in, std::size_t file_size, std::size_t consumed) const;
  std::optional<Error> CheckMemory(std::optional<double> rows_estimate) const;
  void Reserve(double rows_estimate, bool gzip);
  void KeepColumns();
  std::string ColumnLabel(std::size_t j) const {
    return "column '" + header_[j] + "'";
  }

  std::string source_;
  CsvReadOptions opt_;
  Table table_;                     // the kept columns
  std::vector<std::string> header_; // every column name, in file order
  std::vector<int> slot_;           // slot_[j]: index in table_.columns of file column j, or -1
  std::size_t rows_ = 0;            // complete data rows read
  std::size_t line_no_ = 0;         // 1-based number of the line being handled
  bool have_header_ = false;
  std::size_t first_blank_line_ = 0; // a blank line seen after the header (0 = none yet)
};

Result<Table> CsvParser::Run(gzFile in, std::size_t file_size) {
  std::size_t consumed = 0;  // bytes of complete lines handled so far
  bool reserved = false;
  table_.source = source_;
  // (For gzip the file size bounds nothing; the buffer grows by doubling up to max_line_bytes.)
  std::vector<char> buf(file_size > 0 ? std::min(kChunkBytes, file_size + 1) : kChunkBytes);
  std::size_t filled = 0;
  bool eof = false;
  bool first = true;
  while (!eof) {
    if (filled == buf.size()) {  // a line longer than the buffer
      if (filled >= opt_.max_line_bytes) {
        return InvalidInput(Where(source_, line_no_ + 1, 1) + "line longer than " +
                            std::to_string(opt_.max_line_bytes) +
                            " bytes without a line break (binary data, or not a CSV file)");
      }
      buf.resize(buf.size() * 2);
    }
    const std::size_t want = std::min<std::size_t>(buf.size() - filled, 1u << 30);
    const int got = gzread(in, buf.data() + filled, static_cast<unsigned>(want));
    if (got < 0) {
      int errnum = 0;
      const char* msg = gzerror(in, &errnum);
      if (errnum == Z_ERRNO) {
        return IoError(source_ + ": cannot read: " + std::strerror(errno));
      }
      return InvalidInput(Where(source_, line_no_ + 1, 1) + "corrupt gzip data (" +
                          ZlibMessage(msg) + ")");
    }
    if (got == 0) {
      int errnum = 0;
      const char* msg = gzerror(in, &errnum);
      if (errnum != Z_OK) {  // e.g. Z_BUF_ERROR: truncated gzip stream
        return InvalidInput(Where(source_, line_no_ + 1, 1) + "truncated or corrupt gzip data (" +
                            ZlibMessage(msg) + ")");
      }
      eof = true;
    }
    filled += static_cast<std::size_t>(got);
    std::size_t start = 0;
    if (first && filled >= 3 && std::memcmp(buf.data(), "\xEF\xBB\xBF", 3) == 0) start = 3;  // BOM
    if (first && (filled >= 3 || eof)) first = false;
    else if (first) continue;
    // Complete lines in [start, filled).
    while (true) {
      const void* nl = std::memchr(buf.data() + start, '\n', filled - start);
      if (nl == nullptr) break;
      const std::size_t end = static_cast<const char*>(nl) - buf.data();
      if (auto err = Line(std::string_view(buf.data() + start, end - start))) return *err;
      start = end + 1;
    }
    if (eof && start < filled) {
      if (auto err = Line(std::string_view(buf.data() + start, filled - start))) return *err;
      start = filled;
    }
    consumed += start;
    const std::optional<double> rows_estimate = EstimateRows(in, file_size, consumed);
    if (auto err = CheckMemory(rows_estimate)) return *err;
    if (!reserved && rows_estimate) {
      Reserve(*rows_estimate, !gzdirect(in));
      reserved = true;
    }
    std::memmove(buf.data(), buf.data() + start, filled - start);
    filled -= start;
  }
  if (!have_header_) {
    return InvalidInput(Where(source_, 1, 1) + "empty file: expected a header row of column names");
  }
  if (table_.num_rows() == 0) {
    return InvalidInput(Where(source_, 2, 1) +
                        "header only: no data rows after the header (columns: " +
                        [&] {
                          std::string s;
                          for (std::size_t j = 0; j < header_.size(); ++j) s += (j ? ", " : "") + header_[j];
                          return s;
                        }() + ")");
  }
  return std::move(table_);
}

// The file's rows at the bytes per row seen so far, once kRowsBeforeReserve rows are in and the
// size of the file is known: for plain text, file size / bytes per row; for gzip, the rows so
// far times the compressed bytes still to come over those read (zlib's gzoffset: the compressed
// input consumed, without its read-ahead). nullopt before that, or for stdin / a pipe.
std::optional<double> CsvParser::EstimateRows(gzFile in, std::size_t file_size, std::size_t consumed) const {
  if (file_size == 0 || rows_ < kRowsBeforeReserve || consumed == 0) return std::nullopt;
  const double rows = static_cast<double>(rows_);
  if (gzdirect(in)) return std::max(rows, static_cast<double>(file_size) / (static_cast<double>(consumed) / rows));
  const z_off_t compressed = gzoffset(in);
  if (compressed <= 0) return std::nullopt;
  return std::max(rows, rows * static_cast<double>(file_size) / static_cast<double>(compressed));
}

// Reserves every kept column for the estimated rows plus a margin (see kReserveMarginPlain), so
// that the columns are not regrown (each regrowth of a 5M-row column copies it).
void CsvParser::Reserve(double rows_estimate, bool gzip) {
  const double margin = gzip ? kReserveMarginGzip : kReserveMarginPlain;
  const double rows = rows_estimate * margin + 16.0;
  // Never more than the --max-memory bound allows (CheckMemory has passed the estimate itself).
  const double cap = static_cast<double>(opt_.max_memory_bytes) / sizeof(double) /
                     static_cast<double>(std::max<std::size_t>(1, table_.columns.size()));
  const auto n = static_cast<std::size_t>(std::min(rows, cap));
  for (auto& c : table_.columns) {
    if (n > c.capacity()) c.reserve(n);
  }
}

// The table so far, or (file of known size) the whole file at the bytes per row seen so far,
// must fit in opt_.max_memory_bytes. Only kept columns count (CsvReadOptions::columns).
std::optional<Error> CsvParser::CheckMemory(std::optional<double> rows_estimate) const {
  const double cells_per_row = static_cast<double>(table_.names.size());
  const double rows = std::max(static_cast<double>(rows_), rows_estimate.value_or(0.0));
  const double bytes = rows * cells_per_row * sizeof(double);
  if (bytes <= static_cast<double>(opt_.max_memory_bytes)) return std::nullopt;
  char msg[200];
  std::snprintf(msg, sizeof msg, "needs %.3g GB for %.3g rows of %zu columns; at most %.3g GB allowed (--max-memory)",
                bytes / 1e9, rows, table_.names.size(), static_cast<double>(opt_.max_memory_bytes) / 1e9);
  return InvalidInput(Where(source_, line_no_, 1) + msg);
}

std::optional<Error> CsvParser::Line(std::string_view line) {
  ++line_no_;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);  // CRLF
  if (Trim(line).empty()) {
    // Blank lines: allowed before the header and at the very end of the file only (a blank line
    // in the middle would make the line numbers of later messages lie).
    if (have_header_ && first_blank_line_ == 0) first_blank_line_ = line_no_;
    return std::nullopt;
  }
  if (!have_header_) return Header(line);
  if (first_blank_line_ != 0) {
    return InvalidInput(Where(source_, first_blank_line_, 1) +
                        "blank line in the middle of the data (data continues at line " +
                        std::to_string(line_no_) + ")");
  }
  return Row(line);
}

std::optional<Error> CsvParser::Header(std::string_view line) {
  const std::string_view raw = line;
  if (const std::size_t bad = FirstUncleanByte(raw); bad != std::string_view::npos) {
    // Old Mac line ends only when the CRs are all that is wrong: random bytes hold 0x0d too.
    std::string without_cr(raw);
    without_cr.erase(std::remove(without_cr.begin(), without_cr.end(), '\r'), without_cr.end());
    if (raw[bad] == '\r' && IsCleanText(without_cr)) {
      return InvalidInput(Where(source_, line_no_, 1) +
                          "carriage returns inside the header line: old Mac (CR-only) line endings are "
                          "not supported");
    }
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02x", static_cast<unsigned>(static_cast<unsigned char>(raw[bad])));
    return InvalidInput(Where(source_, line_no_, 1) +
                        "binary garbage, not a text CSV header (NUL bytes, control characters or invalid "
                        "UTF-8 in the first line; the first is " + byte + " at byte " +
                        std::to_string(bad) + " of the line)" + LogNameHint(source_));
  }
  std::vector<std::string> names;
  std::size_t pos = 0;
  while (true) {
    const std::size_t d = line.find(opt_.delimiter, pos);
    std::string_view name = Trim(line.substr(pos, d == std::string_view::npos ? line.npos : d - pos));
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"') {
      name = Trim(name.substr(1, name.size() - 2));
    }
    names.emplace_back(name);
    if (d == std::string_view::npos) break;
    pos = d + 1;
  }
  if (names.size() == 1) {
    for (char other : {';', '\t', ' '}) {
      if (other != opt_.delimiter && names[0].find(other) != std::string::npos) {
        const std::string shown = other == '\t' ? "tab" : std::string("'") + other + "'";
        return InvalidInput(Where(source_, line_no_, 1) + "the header " + Quote(names[0]) +
                            " has one column and looks " + shown + "-separated; columns must be "
                            "separated by '" + std::string(1, opt_.delimiter) + "'");
      }
    }
  }
  bool all_numeric = true;
  std::unordered_map<std::string, std::size_t> seen;
  for (std::size_t j = 0; j < names.size(); ++j) {
    if (names[j].empty()) {
      return InvalidInput(Where(source_, line_no_, j + 1) + "empty column name in the header (column " +
                          std::to_string(j + 1) + " of " + std::to_string(names.size()) + ")");
    }
    const auto [it, fresh] = seen.emplace(names[j], j);
    if (!fresh) {
      return InvalidInput(Where(source_, line_no_, j + 1) + "duplicate column name '" + names[j] +
                          "' (also column " + std::to_string(it->second + 1) + ")");
    }
    double v = 0;
    bool oor = false;
    if (!ParseCell(names[j], &v, &oor)) all_numeric = false;
  }
  if (all_numeric) {
    return InvalidInput(Where(source_, line_no_, 1) +
                        "the first line is numbers, not a header: a header row of column names is "
                        "required (e.g. time_s,rate_dps,temp_c)");
  }
  header_ = std::move(names);
  KeepColumns();
  have_header_ = true;
  return std::nullopt;
}

// The kept columns (CsvReadOptions::columns) and where each file column goes (slot_).
void CsvParser::KeepColumns() {
  slot_.assign(header_.size(), -1);
  std::vector<bool> keep(header_.size(), !opt_.columns.has_value());
  if (opt_.columns) {
    bool any = false;
    for (std::size_t j = 0; j < header_.size(); ++j) {
      keep[j] = std::find(opt_.columns->begin(), opt_.columns->end(), header_[j]) != opt_.columns->end();
      any = any || keep[j];
    }
    if (!any) keep[0] = true;  // one column, so that num_rows() counts the rows
  }
  for (std::size_t j = 0; j < header_.size(); ++j) {
    if (!keep[j]) continue;
    slot_[j] = static_cast<int>(table_.names.size());
    table_.names.push_back(header_[j]);
  }
  table_.columns.assign(table_.names.size(), {});
  if (table_.names.size() != header_.size()) table_.header = header_;
}

// Hot path: one data row, every field parsed in place.
std::optional<Error> CsvParser::Row(std::string_view line) {
  const char* p = line.data();
  const char* const end = p + line.size();
  const std::size_t ncols = slot_.size();
  const char delim = opt_.delimiter;
  for (std::size_t j = 0; j < ncols; ++j) {
    while (p != end && IsBlank(*p)) ++p;
    if (p != end && *p == '+' && p + 1 != end && p[1] != '-') ++p;
    double v;
    const auto r = std::from_chars(p, end, v);
    if (r.ec == std::errc::result_out_of_range) {
      // Underflow (1e-400) reads as 0 / subnormal like strtod; overflow is reported.
      const std::string copy(p, r.ptr);
      v = std::strtod(copy.c_str(), nullptr);
      if (std::isinf(v)) return RowError(line);
    } else if (r.ec != std::errc()) {
      return RowError(line);
    }
    p = r.ptr;
    while (p != end && IsBlank(*p)) ++p;
    if (j + 1 < ncols) {
      if (p == end || *p != delim) return RowError(line);
      ++p;
    } else if (p != end) {
      return RowError(line);
    }
    if (opt_.reject_non_finite && !std::isfinite(v)) return RowError(line);
    if (slot_[j] >= 0) table_.columns[static_cast<std::size_t>(slot_[j])].push_back(v);
  }
  ++rows_;
  return std::nullopt;
}

// Slow path: the row failed somewhere; find the first problem and describe it. Columns already
// appended for this row are rolled back (the read stops anyway, but keep the table consistent).
Error CsvParser::RowError(std::string_view line) {
  for (auto& c : table_.columns) c.resize(rows_);
  const std::size_t ncols = header_.size();
  std::vector<std::string_view> cells;
  std::size_t pos = 0;
  while (true) {
    const std::size_t d = line.find(opt_.delimiter, pos);
    cells.push_back(line.substr(pos, d == std::string_view::npos ? line.npos : d - pos));
    if (d == std::string_view::npos) break;
    pos = d + 1;
  }
  if (std::memchr(line.data(), '\0', line.size()) != nullptr) {
    std::size_t j = 0;
    while (j + 1 < cells.size() && std::memchr(cells[j].data(), '\0', cells[j].size()) == nullptr) ++j;
    return InvalidInput(Where(source_, line_no_, j + 1) +
                        "binary garbage (NUL bytes) in a data row, column " + std::to_string(j + 1));
  }
  for (std::size_t j = 0; j < std::min(cells.size(), ncols); ++j) {
    double v = 0;
    bool out_of_range = false;
    const std::string_view cell = Trim(cells[j]);
    const std::string at = Where(source_, line_no_, j + 1);
    const std::string col = " in " + ColumnLabel(j) + " (line " + std::to_string(line_no_) +
                            ", column " + std::to_string(j + 1) + ")";
    if (cell.empty()) return InvalidInput(at + "empty cell" + col);
    if (!ParseCell(cell, &v, &out_of_range)) {
      if (out_of_range) return InvalidInput(at + "value " + Quote(cell) + " overflows a double" + col);
      if (HasBinaryByte(cell) || !IsCleanText(cell)) {
        return InvalidInput(at + "binary garbage " + Quote(cell) + col);
      }
      return InvalidInput(at + "non-numeric value " + Quote(cell) + col);
    }
    if (opt_.reject_non_finite && !std::isfinite(v)) {
      return InvalidInput(at + (std::isnan(v) ? "NaN" : "infinite value") + " " + Quote(cell) + col);
    }
  }
  if (cells.size() != ncols) {
    const std::size_t j = std::min(cells.size(), ncols) + 1;
    return InvalidInput(Where(source_, line_no_, j) + "ragged row: " + std::to_string(cells.size()) +
                        " fields, the header has " + std::to_string(ncols) + " (line " +
                        std::to_string(line_no_) + ", column " + std::to_string(j) + ")");
  }
  return InvalidInput(Where(source_, line_no_, 1) + "malformed row " + Quote(line));
}

}  // namespace

Result<Table> ReadCsv(const std::string& path, const CsvReadOptions& options) {
  const bool is_stdin = path == "-";
  const std::string source = is_stdin ? "<stdin>" : path;
  if (options.delimiter == '\n' || options.delimiter == '\r' || options.delimiter == '"' ||
      options.delimiter == '.' || options.delimiter == '-' || options.delimiter == '+' ||
      (options.delimiter >= '0' && options.delimiter <= '9')) {
    return InvalidArgument("CsvReadOptions::delimiter = '" + std::string(1, options.delimiter) +
                           "': must not be a digit, sign, '.', quote or line break");
  }
  gzFile in = nullptr;
  if (is_stdin) {
    const int fd = ::dup(STDIN_FILENO);
    if (fd >= 0) in = gzdopen(fd, "rb");
    if (in == nullptr && fd >= 0) ::close(fd);
  } else {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
      return IoError(path + ": cannot read: is a directory");
    }
    in = gzopen(path.c_str(), "rb");
  }
  if (in == nullptr) {
    return IoError(source + ": cannot open: " + std::string(errno ? std::strerror(errno) : "out of memory"));
  }
  std::size_t plain_size = 0;
  if (!is_stdin) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) plain_size = static_cast<std::size_t>(st.st_size);
  }
  // A small file gets small buffers (the fuzzers read thousands of 1 kB files a second).
  gzbuffer(in, plain_size > 0 ? static_cast<unsigned>(std::clamp<std::size_t>(plain_size, 8192, kGzBufferBytes))
                              : kGzBufferBytes);
  CsvParser parser(source, options);
  Result<Table> result = parser.Run(in, plain_size);
  gzclose(in);
  return result;
}

Result<std::string> ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return IoError(path + ": cannot open");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  if (size < 0) return IoError(path + ": cannot tell its size (not a regular file?)");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (!in.read(bytes.data(), size)) return IoError(path + ": read error");
  return bytes;
}

}  // namespace gyrocomp
