// Numeric CSV reading and atomic writing (include/gyrocomp/io.h).
//
// Reading: zlib's gzread reads gzip and plain files alike (it detects the gzip magic bytes
// 1f 8b itself), so plain, .gz and stdin share one path. The decompressed stream is processed in
// large chunks; every cell is parsed in place with std::from_chars (no iostream, no strtod on
// the hot path). Any problem stops the read with "<file>:<line>:<column>: <what>".
//
// Writing: cells are formatted with std::to_chars (shortest round-trip), streamed into a
// temporary file created next to the target (O_EXCL, so umask applies), then renamed over it.
#include "gyrocomp/io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <random>
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

namespace {

constexpr std::size_t kChunkBytes = std::size_t{1} << 22;  // 4 MiB per read
constexpr unsigned kGzBufferBytes = 1u << 20;              // zlib's internal buffer

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

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

std::string_view Trim(std::string_view s) {
  while (!s.empty() && IsBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsBlank(s.back())) s.remove_suffix(1);
  return s;
}

// True when `s` is valid UTF-8 without control characters other than tab.
bool IsCleanText(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      if ((c < 0x20 && c != '\t') || c == 0x7f) return false;
      ++i;
      continue;
    }
    int extra = 0;
    if ((c & 0xe0) == 0xc0 && c >= 0xc2) extra = 1;
    else if ((c & 0xf0) == 0xe0) extra = 2;
    else if ((c & 0xf8) == 0xf0 && c <= 0xf4) extra = 3;
    else return false;
    if (i + extra >= s.size()) return false;
    for (int k = 1; k <= extra; ++k) {
      if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return false;
    }
    i += extra + 1;
  }
  return true;
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

  // `plain_size` is the file size when known (0 for stdin/pipes): used, for plain text only, to
  // reserve the columns once the first chunk shows the bytes per row.
  Result<Table> Run(gzFile in, std::size_t plain_size);

 private:
  // Handles one line (without its '\n').
  std::optional<Error> Line(std::string_view line);
  std::optional<Error> Header(std::string_view line);
  std::optional<Error> Row(std::string_view line);
  Error RowError(std::string_view line);
  std::string ColumnLabel(std::size_t j) const {
    return "column '" + table_.names[j] + "'";
  }

  std::string source_;
  CsvReadOptions opt_;
  Table table_;
  std::size_t line_no_ = 0;         // 1-based number of the line being handled
  bool have_header_ = false;
  std::size_t first_blank_line_ = 0; // a blank line seen after the header (0 = none yet)
};

Result<Table> CsvParser::Run(gzFile in, std::size_t plain_size) {
  std::size_t consumed = 0;  // bytes of complete lines handled so far
  bool reserved = false;
  table_.source = source_;
  std::vector<char> buf(kChunkBytes);
  std::size_t filled = 0;
  bool eof = false;
  bool first = true;
  while (!eof) {
    if (filled == buf.size()) buf.resize(buf.size() * 2);  // a line longer than the buffer
    const std::size_t want = std::min<std::size_t>(buf.size() - filled, 1u << 30);
    const int got = gzread(in, buf.data() + filled, static_cast<unsigned>(want));
    if (got < 0) {
      int errnum = 0;
      const char* msg = gzerror(in, &errnum);
      if (errnum == Z_ERRNO) {
        return IoError(source_ + ": cannot read: " + std::strerror(errno));
      }
      return InvalidInput(Where(source_, line_no_ + 1, 1) + "corrupt gzip data (" +
                          std::string(msg ? msg : "?") + ")");
    }
    if (got == 0) {
      int errnum = 0;
      const char* msg = gzerror(in, &errnum);
      if (errnum != Z_OK) {  // e.g. Z_BUF_ERROR: truncated gzip stream
        return InvalidInput(Where(source_, line_no_ + 1, 1) + "truncated or corrupt gzip data (" +
                            std::string(msg ? msg : "?") + ")");
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
    if (!reserved && plain_size > 0 && gzdirect(in) && table_.num_rows() >= 1000) {
      // Avoids regrowing 5M-row columns; over-reserves by at most ~2 %.
      const double per_row = static_cast<double>(consumed) / static_cast<double>(table_.num_rows());
      const auto rows = static_cast<std::size_t>(static_cast<double>(plain_size) / per_row * 1.02) + 16;
      for (auto& c : table_.columns) c.reserve(rows);
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
                          for (std::size_t j = 0; j < table_.names.size(); ++j) {
                            s += (j ? ", " : "") + table_.names[j];
                          }
                          return s;
                        }() + ")");
  }
  return std::move(table_);
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
  if (std::memchr(raw.data(), '\0', raw.size()) != nullptr || !IsCleanText(raw)) {
    const bool cr = raw.find('\r') != std::string_view::npos;
    return InvalidInput(Where(source_, line_no_, 1) +
                        (cr ? std::string("carriage returns inside the header line: old Mac (CR-only) "
                                          "line endings are not supported")
                            : "binary garbage, not a text CSV header (NUL bytes, control characters "
                              "or invalid UTF-8 in the first line)"));
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
  table_.names = std::move(names);
  table_.columns.assign(table_.names.size(), {});
  have_header_ = true;
  return std::nullopt;
}

// Hot path: one data row, every field parsed in place.
std::optional<Error> CsvParser::Row(std::string_view line) {
  const char* p = line.data();
  const char* const end = p + line.size();
  const std::size_t ncols = table_.columns.size();
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
    table_.columns[j].push_back(v);
  }
  return std::nullopt;
}

// Slow path: the row failed somewhere; find the first problem and describe it. Columns already
// appended for this row are rolled back (the read stops anyway, but keep the table consistent).
Error CsvParser::RowError(std::string_view line) {
  const std::size_t rows = table_.columns.back().size();
  for (auto& c : table_.columns) c.resize(rows);
  const std::size_t ncols = table_.columns.size();
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

// ---- writing ------------------------------------------------------------------------------

// A temporary file beside the target, removed unless committed.
class AtomicFile {
 public:
  ~AtomicFile() {
    if (gz_ != nullptr) gzclose(gz_);
    if (fd_ >= 0) ::close(fd_);
    if (!tmp_.empty() && !committed_) std::remove(tmp_.c_str());
  }

  Status Open(const std::string& path) {
    path_ = path;
    const bool gz = path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0;
    if (path == "-") {
      fd_ = ::dup(STDOUT_FILENO);
      if (fd_ < 0) return IoError("stdout: cannot write: " + std::string(std::strerror(errno)));
      stdout_ = true;
      return Status::Ok();
    }
    const std::size_t slash = path.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
    const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
    if (base.empty()) return IoError(path + ": not a file name");
    std::random_device rd;
    for (int attempt = 0; attempt < 16 && fd_ < 0; ++attempt) {
      tmp_ = dir + "." + base + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(rd());
      fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd_ < 0 && errno != EEXIST) break;
    }
    if (fd_ < 0) {
      const std::string why = std::strerror(errno);
      tmp_.clear();
      return IoError(path + ": cannot create a temporary file in '" + (dir.empty() ? "." : dir) +
                     "': " + why);
    }
    if (gz) {
      const int fd2 = ::dup(fd_);
      // Level 1: on gyro CSVs ~6x faster than level 6 for ~25 % more bytes (measured with
      // gzip -1/-6 on adis16405_run1: 7.0 vs 5.5 MB, 0.24 vs 1.50 s).
      gz_ = fd2 >= 0 ? gzdopen(fd2, "wb1") : nullptr;
      if (gz_ == nullptr) {
        if (fd2 >= 0) ::close(fd2);
        return IoError(path + ": cannot start gzip output");
      }
      gzbuffer(gz_, kGzBufferBytes);
    }
    return Status::Ok();
  }

  Status Write(const char* data, std::size_t n) {
    if (gz_ != nullptr) {
      while (n > 0) {
        const unsigned part = static_cast<unsigned>(std::min<std::size_t>(n, 1u << 30));
        if (gzwrite(gz_, data, part) != static_cast<int>(part)) {
          int errnum = 0;
          return IoError(path_ + ": write failed: " + gzerror(gz_, &errnum));
        }
        data += part;
        n -= part;
      }
      return Status::Ok();
    }
    while (n > 0) {
      const ssize_t w = ::write(fd_, data, n);
      if (w < 0) {
        if (errno == EINTR) continue;
        return IoError(path_ + ": write failed: " + std::strerror(errno));
      }
      data += w;
      n -= static_cast<std::size_t>(w);
    }
    return Status::Ok();
  }

  Status Commit() {
    if (gz_ != nullptr) {
      const int rc = gzclose(gz_);
      gz_ = nullptr;
      if (rc != Z_OK) return IoError(path_ + ": write failed (gzip close)");
    }
    if (stdout_) {
      ::close(fd_);
      fd_ = -1;
      return Status::Ok();
    }
    if (::fsync(fd_) != 0 && errno != EINVAL && errno != EROFS) {
      return IoError(path_ + ": fsync failed: " + std::strerror(errno));
    }
    if (::close(fd_) != 0) {
      fd_ = -1;
      return IoError(path_ + ": close failed: " + std::strerror(errno));
    }
    fd_ = -1;
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
      return IoError(path_ + ": cannot rename the temporary file over it: " + std::strerror(errno));
    }
    committed_ = true;
    return Status::Ok();
  }

 private:
  std::string path_;
  std::string tmp_;
  int fd_ = -1;
  gzFile gz_ = nullptr;
  bool stdout_ = false;
  bool committed_ = false;
};

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
  gzbuffer(in, kGzBufferBytes);
  std::size_t plain_size = 0;
  if (!is_stdin) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) plain_size = static_cast<std::size_t>(st.st_size);
  }
  CsvParser parser(source, options);
  Result<Table> result = parser.Run(in, plain_size);
  gzclose(in);
  return result;
}

Status WriteCsvAtomic(const std::string& path, const Table& table) {
  const std::size_t rows = table.num_rows();
  if (table.names.size() != table.columns.size()) {
    return InvalidArgument(path + ": table has " + std::to_string(table.names.size()) + " names and " +
                           std::to_string(table.columns.size()) + " columns");
  }
  for (std::size_t j = 0; j < table.names.size(); ++j) {
    const std::string& n = table.names[j];
    if (n.empty() || n.find_first_of(",\"\r\n") != std::string::npos) {
      return InvalidArgument(path + ": column name " + Quote(n) +
                             " cannot be written (empty, or contains a comma, quote or line break)");
    }
    if (table.columns[j].size() != rows) {
      return InvalidArgument(path + ": column '" + n + "' has " +
                             std::to_string(table.columns[j].size()) + " rows, expected " +
                             std::to_string(rows));
    }
  }
  AtomicFile out;
  if (Status s = out.Open(path); !s) return s;
  std::string buf;
  buf.reserve(kChunkBytes + 4096);
  for (std::size_t j = 0; j < table.names.size(); ++j) {
    if (j) buf.push_back(',');
    buf += table.names[j];
  }
  buf.push_back('\n');
  const std::size_t ncols = table.columns.size();
  char cell[64];
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t j = 0; j < ncols; ++j) {
      const auto r = std::to_chars(cell, cell + sizeof cell, table.columns[j][i]);  // shortest round trip
      if (j) buf.push_back(',');
      buf.append(cell, r.ptr);
    }
    buf.push_back('\n');
    if (buf.size() >= kChunkBytes) {
      if (Status s = out.Write(buf.data(), buf.size()); !s) return s;
      buf.clear();
    }
  }
  if (Status s = out.Write(buf.data(), buf.size()); !s) return s;
  return out.Commit();
}

Status WriteTextAtomic(const std::string& path, const std::string& text) {
  AtomicFile out;
  if (Status s = out.Open(path); !s) return s;
  if (Status s = out.Write(text.data(), text.size()); !s) return s;
  return out.Commit();
}

}  // namespace gyrocomp
