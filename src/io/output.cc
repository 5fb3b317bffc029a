// The output transaction of include/gyrocomp/io/output.h.
#include "gyrocomp/io/output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <thread>
#include <utility>
#include <vector>

namespace gyrocomp {

namespace {

// ---- process-wide table of live temporaries (read by signal handlers) ----------------------
constexpr int kMaxLiveTemporaries = 64;
constexpr std::size_t kMaxTemporaryPathBytes = 4096;
enum SlotState : int { kSlotFree = 0, kSlotFilling = 1, kSlotLive = 2 };
struct TemporarySlot {
  std::atomic<int> state{kSlotFree};
  char path[kMaxTemporaryPathBytes];
};
static_assert(std::atomic<int>::is_always_lock_free, "signal handlers need lock-free slots");
TemporarySlot g_slots[kMaxLiveTemporaries];

// Lists `path` as live in the first free of `n` slots; returns the slot, or -1 when the table is
// full or the path too long.
int ListIn(TemporarySlot* slots, int n, const std::string& path) {
  if (path.size() + 1 > kMaxTemporaryPathBytes) return -1;
  for (int i = 0; i < n; ++i) {
    int expected = kSlotFree;
    if (slots[i].state.compare_exchange_strong(expected, kSlotFilling)) {
      std::memcpy(slots[i].path, path.c_str(), path.size() + 1);
      slots[i].state.store(kSlotLive);
      return i;
    }
  }
  return -1;
}

int ListTemporary(const std::string& path) { return ListIn(g_slots, kMaxLiveTemporaries, path); }

void UnlistTemporary(int slot) {
  if (slot >= 0) g_slots[slot].state.store(kSlotFree);
}

// Folders created for outputs (ListCreatedFolder): few per process.
constexpr int kMaxCreatedFolders = 8;
TemporarySlot g_folder_slots[kMaxCreatedFolders];

// ---- paths ---------------------------------------------------------------------------------
constexpr std::size_t kChunkBytes = std::size_t{1} << 22;  // write in 4 MiB pieces
constexpr std::size_t kTempStemBytes = 64;  // keeps the temporary's name short: a legal
                                            // 255-byte target name must not be refused

std::string DirName(const std::string& path) {  // "" or "dir/"
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}
std::string BaseName(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}
bool EndsWith(const std::string& s, const char* suffix) {
  const std::size_t n = std::strlen(suffix);
  return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}
std::string Errno() { return std::strerror(errno); }

// Follows `path` through symbolic links (at most 40) to the name a write would reach.
Result<std::string> FollowLinks(std::string path) {
  for (int hop = 0; hop < 40; ++hop) {
    struct stat st;
    if (::lstat(path.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return path;
    std::string target(4096, '\0');
    const ssize_t n = ::readlink(path.c_str(), target.data(), target.size());
    if (n < 0) return IoError(path + ": cannot read the symbolic link: " + Errno());
    target.resize(static_cast<std::size_t>(n));
    path = target.front() == '/' ? target : DirName(path) + target;
  }
  return InvalidArgument(path + ": too many levels of symbolic links");
}

}  // namespace

// ---- one destination -------------------------------------------------------------------------
struct OutputSet::Entry {
  std::string path;        // as declared: messages and lookup
  std::string final_path;  // symbolic links followed: the file a rename replaces
  bool write_through = false;  // FIFO, device, stdout: buffered, written after the renames
  bool exists = false;
  unsigned long long dev = 0, ino = 0;
  std::string tmp_path;
  int fd = -1;
  int slot = -1;
  std::string buffer;  // write-through content
  bool staged = false;
  bool gzip = false;
  bool gzip_started = false;
  z_stream zs{};

  ~Entry() {
    if (gzip_started) deflateEnd(&zs);
    RemoveTemporary();
  }

  // Creates the temporary beside final_path (proving the folder exists and is writable) and lists
  // it for signal handlers. A replaced file's permissions `mode` are kept.
  Status CreateTemporary(mode_t mode) {
    const std::string dir = DirName(final_path);
    const std::string stem = BaseName(final_path).substr(0, kTempStemBytes);
    std::random_device rd;
    for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
      tmp_path = dir + "." + stem + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(rd());
      slot = ListTemporary(tmp_path);  // listed before it exists: no window for a signal
      fd = ::open(tmp_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd < 0) {
        const int err = errno;
        UnlistTemporary(slot);
        slot = -1;
        errno = err;
        if (errno != EEXIST) break;
      }
    }
    if (fd < 0) {
      const int err = errno;
      tmp_path.clear();
      if (err == ENOENT) return IoError(path + ": cannot write: folder '" + dir + "' does not exist");
      return IoError(path + ": cannot create a file in folder '" + (dir.empty() ? "." : dir) +
                     "': " + std::strerror(err));
    }
    if (exists) (void)::fchmod(fd, mode);
    return Status::Ok();
  }

  void RemoveTemporary() {
    if (fd >= 0) ::close(fd);
    fd = -1;
    if (!tmp_path.empty()) ::unlink(tmp_path.c_str());
    UnlistTemporary(slot);
    slot = -1;
    tmp_path.clear();
  }

  Status WriteRaw(const char* data, std::size_t n) {
    if (write_through) {
      buffer.append(data, n);
      return Status::Ok();
    }
    while (n > 0) {
      const ssize_t w = ::write(fd, data, n);
      if (w < 0) {
        if (errno == EINTR) continue;
        return IoError(path + ": write failed: " + Errno());
      }
      data += w;
      n -= static_cast<std::size_t>(w);
    }
    return Status::Ok();
  }

  // Runs deflate over the pending input with `flush`, passing its output to WriteRaw.
  Status Deflate(int flush) {
    char out[1 << 16];
    do {
      zs.next_out = reinterpret_cast<Bytef*>(out);
      zs.avail_out = sizeof out;
      const int rc = deflate(&zs, flush);
      if (rc == Z_STREAM_ERROR) return InternalError(path + ": gzip compression failed");
      if (Status s = WriteRaw(out, sizeof out - zs.avail_out); !s) return s;
    } while (zs.avail_out == 0);
    return Status::Ok();
  }

  // Content, gzip-compressed for a ".gz" name.
  Status Write(const char* data, std::size_t n) {
    if (!gzip) return WriteRaw(data, n);
    if (!gzip_started) {
      // Level 1: on gyro CSVs ~6x faster than level 6 for ~25 % more bytes (measured with
      // gzip -1/-6 on adis16405_run1: 7.0 vs 5.5 MB, 0.24 vs 1.50 s). windowBits 15 + 16: gzip.
      if (deflateInit2(&zs, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
        return InternalError(path + ": cannot start gzip output");
      }
      gzip_started = true;
    }
    while (n > 0) {
      const auto part = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
      zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data));
      zs.avail_in = part;
      if (Status s = Deflate(Z_NO_FLUSH); !s) return s;
      data += part;
      n -= part;
    }
    return Status::Ok();
  }

  Status Finish() {
    if (gzip) {
      if (!gzip_started) {
        if (Status s = Write(nullptr, 0); !s) return s;
      }
      zs.next_in = nullptr;
      zs.avail_in = 0;
      if (Status s = Deflate(Z_FINISH); !s) return s;
    }
    staged = true;
    return Status::Ok();
  }
};

// ---- the set ---------------------------------------------------------------------------------
OutputSet::OutputSet() = default;
OutputSet::~OutputSet() { Discard(); }

void OutputSet::Discard() { entries_.clear(); }

void OutputSet::AddInput(const std::string& path) {
  struct stat st;
  if (path.empty() || path == "-" || ::stat(path.c_str(), &st) != 0) return;
  inputs_.push_back({path, static_cast<unsigned long long>(st.st_dev),
                     static_cast<unsigned long long>(st.st_ino)});
}

OutputSet::Entry* OutputSet::Find(const std::string& path) {
  for (auto& e : entries_) {
    if (e->path == path) return e.get();
  }
  return nullptr;
}
const OutputSet::Entry* OutputSet::Find(const std::string& path) const {
  return const_cast<OutputSet*>(this)->Find(path);
}
bool OutputSet::IsDeclared(const std::string& path) const { return Find(path) != nullptr; }

Status OutputSet::CheckNotInput(const Entry& e) const {
  if (e.write_through) return Status::Ok();
  for (const InputId& in : inputs_) {
    if (e.exists && in.dev == e.dev && in.ino == e.ino) {
      return InvalidArgument("output '" + e.path + "' is the same file as input '" + in.path +
                             "': refusing to overwrite an input");
    }
  }
  for (const auto& other : entries_) {
    if (other.get() != &e && !other->write_through &&
        (other->final_path == e.final_path ||
         (other->exists && e.exists && other->dev == e.dev && other->ino == e.ino))) {
      return InvalidArgument("outputs '" + other->path + "' and '" + e.path + "' are the same file");
    }
  }
  return Status::Ok();
}

Status OutputSet::Declare(const std::string& path) {
  if (path.empty()) return InvalidArgument("an output file name is empty");
  if (Find(path) != nullptr) return Status::Ok();
  auto e = std::make_unique<Entry>();
  e->path = path;
  e->gzip = EndsWith(path, ".gz");
  if (path == "-" || path.rfind("/dev/", 0) == 0 || path.rfind("/proc/", 0) == 0) {
    e->write_through = true;
    e->final_path = path;
    entries_.push_back(std::move(e));
    return Status::Ok();
  }
  Result<std::string> final_path = FollowLinks(path);
  if (!final_path) return final_path.error();
  // The write-through rule is decided on what the name resolves to, not on its spelling: a link
  // to /dev/stdout (-> /proc/self/fd/1 -> "pipe:[...]", not a path) or to a FIFO is written
  // through the link itself.
  struct stat resolved;
  if (final_path->rfind("/dev/", 0) == 0 || final_path->rfind("/proc/", 0) == 0 ||
      (::stat(path.c_str(), &resolved) == 0 && (S_ISFIFO(resolved.st_mode) || S_ISCHR(resolved.st_mode)))) {
    e->write_through = true;
    e->final_path = path;
    entries_.push_back(std::move(e));
    return Status::Ok();
  }
  e->final_path = *final_path;
  struct stat st;
  mode_t mode = 0666;
  if (::stat(e->final_path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return InvalidArgument(path + ": is a folder, not a file name");
    if (S_ISFIFO(st.st_mode) || S_ISCHR(st.st_mode)) {
      e->write_through = true;
    } else if (!S_ISREG(st.st_mode)) {
      return InvalidArgument(path + ": not a regular file, FIFO or character device");
    }
    e->exists = true;
    e->dev = static_cast<unsigned long long>(st.st_dev);
    e->ino = static_cast<unsigned long long>(st.st_ino);
    mode = st.st_mode & 07777;
  } else if (errno != ENOENT) {
    return IoError(path + ": cannot write: " + Errno());
  }
  if (Status s = CheckNotInput(*e); !s) return s;
  if (!e->write_through) {
    if (Status s = e->CreateTemporary(mode); !s) return s;
  }
  entries_.push_back(std::move(e));
  return Status::Ok();
}

Result<OutputSet::Entry*> OutputSet::FindOrDeclare(const std::string& path) {
  if (Find(path) == nullptr) {
    if (Status s = Declare(path); !s) return s.error();
  }
  Entry* e = Find(path);
  if (e->staged && path == "/dev/null") {  // -o /dev/null --json /dev/null: both discarded
    e->buffer.clear();
    e->staged = false;
  }
  if (e->staged) return InternalError(path + ": written twice in one command");
  return e;
}

Status OutputSet::StageText(const std::string& path, std::string_view text) {
  Result<Entry*> e = FindOrDeclare(path);
  if (!e) return e.error();
  if (Status s = (*e)->Write(text.data(), text.size()); !s) return s;
  return (*e)->Finish();
}

namespace {

// Refuses what cannot be written as this CSV: a bad column name, a ragged column, a NaN or an
// infinity (named by column and line: a non-finite number never reaches a file with success).
Status CheckCsvTable(const std::string& path, const Table& table) {
  const std::size_t rows = table.num_rows();
  if (table.names.size() != table.columns.size()) {
    return InvalidArgument(path + ": table has " + std::to_string(table.names.size()) + " names and " +
                           std::to_string(table.columns.size()) + " columns");
  }
  for (std::size_t j = 0; j < table.names.size(); ++j) {
    const std::string& n = table.names[j];
    if (n.empty() || n.find_first_of(",\"\r\n") != std::string::npos) {
      return InvalidArgument(path + ": column name '" + n.substr(0, 40) +
                             "' cannot be written (empty, or contains a comma, quote or line break)");
    }
    for (std::size_t k = 0; k < j; ++k) {
      if (table.names[k] == n) {
        return InternalError(path + ": column name '" + n + "' twice (columns " + std::to_string(k + 1) + " and " +
                             std::to_string(j + 1) + "): a CSV that gyrocomp could not read back");
      }
    }
    if (table.columns[j].size() != rows) {
      return InvalidArgument(path + ": column '" + n + "' has " + std::to_string(table.columns[j].size()) +
                             " rows, expected " + std::to_string(rows));
    }
    for (std::size_t i = 0; i < rows; ++i) {
      if (!std::isfinite(table.columns[j][i])) {
        return InternalError(path + ":" + std::to_string(i + 2) + ": column '" + n + "' would hold " +
                             (std::isnan(table.columns[j][i]) ? "NaN" : "an infinity") +
                             ": refusing to write a non-finite number");
      }
    }
  }
  return Status::Ok();
}

}  // namespace

namespace {

// Rows [r0, r1) of `table` appended to `buf` as CSV lines, each number in its shortest
// round-trip form (std::to_chars).
void FormatCsvRows(const Table& table, std::size_t r0, std::size_t r1, std::string& buf) {
  char cell[64];
  for (std::size_t i = r0; i < r1; ++i) {
    for (std::size_t j = 0; j < table.columns.size(); ++j) {
      const auto r = std::to_chars(cell, cell + sizeof cell, table.columns[j][i]);
      if (j) buf.push_back(',');
      buf.append(cell, r.ptr);
    }
    buf.push_back('\n');
  }
}

// Formatting threads of StageCsv: 2 (the shortest round trip costs ~80 ns a number, the largest
// cost of writing a table) from kParallelCsvCells numbers on, when the machine has 2 cores.
constexpr std::size_t kParallelCsvCells = 1 << 15;
constexpr std::size_t kCsvBytesPerCell = 24;  // a typical "-0.0123456789012345678," for sizing

}  // namespace

Status OutputSet::StageCsv(const std::string& path, const Table& table) {
  if (Status s = CheckCsvTable(path, table); !s) return s;
  Result<Entry*> found = FindOrDeclare(path);
  if (!found) return found.error();
  Entry& e = **found;
  std::string header;
  for (std::size_t j = 0; j < table.names.size(); ++j) {
    if (j) header.push_back(',');
    header += table.names[j];
  }
  header.push_back('\n');
  if (Status s = e.Write(header.data(), header.size()); !s) return s;
  // Batches of rows cut in `threads` consecutive parts of at most ~kChunkBytes / 2 each, formatted
  // in parallel and written in order: the same bytes as one thread.
  const std::size_t rows = table.num_rows();
  const std::size_t cols = std::max<std::size_t>(1, table.columns.size());
  const std::size_t threads =
      rows * cols >= kParallelCsvCells && std::thread::hardware_concurrency() >= 2 ? 2 : 1;
  const std::size_t max_part_rows = std::max<std::size_t>(1, kChunkBytes / 2 / (kCsvBytesPerCell * cols));
  const std::size_t part_rows = std::min(max_part_rows, (rows + threads - 1) / threads);
  std::vector<std::string> parts(threads);
  for (std::size_t b0 = 0; b0 < rows; b0 += threads * part_rows) {
    auto part_range = [&](std::size_t t) {
      const std::size_t r0 = std::min(rows, b0 + t * part_rows);
      return std::pair<std::size_t, std::size_t>(r0, std::min(rows, r0 + part_rows));
    };
    std::vector<std::thread> helpers;
    for (std::size_t t = 1; t < threads; ++t) {
      helpers.emplace_back([&, t] {
        parts[t].clear();
        FormatCsvRows(table, part_range(t).first, part_range(t).second, parts[t]);
      });
    }
    parts[0].clear();
    FormatCsvRows(table, part_range(0).first, part_range(0).second, parts[0]);
    for (std::thread& h : helpers) h.join();
    for (const std::string& part : parts) {
      if (Status s = e.Write(part.data(), part.size()); !s) return s;
    }
  }
  return e.Finish();
}

namespace {

// Writes `data` to `fd`, retrying short writes; errno is kept on failure.
bool WriteAll(int fd, const std::string& data) {
  const char* p = data.data();
  std::size_t n = data.size();
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

}  // namespace

Status OutputSet::Commit() {
  // 1. Every temporary complete on disk.
  for (auto& e : entries_) {
    if (e->write_through || !e->staged) continue;
    if (::fsync(e->fd) != 0 && errno != EINVAL && errno != EROFS) {
      return IoError(e->path + ": fsync failed: " + Errno());
    }
    const int fd = e->fd;
    e->fd = -1;
    if (::close(fd) != 0) return IoError(e->path + ": close failed: " + Errno());
  }
  // 2. Renames: each atomic; the set is complete once the loop ends.
  for (auto& e : entries_) {
    if (e->write_through || !e->staged) continue;
    if (std::rename(e->tmp_path.c_str(), e->final_path.c_str()) != 0) {
      return IoError(e->path + ": cannot rename the temporary file over it: " + Errno());
    }
    UnlistTemporary(e->slot);
    e->slot = -1;
    e->tmp_path.clear();
  }
  // 3. Write-through destinations, after whatever the program printed itself.
  std::fflush(stdout);
  for (auto& e : entries_) {
    if (!e->write_through || !e->staged) continue;
    const bool is_stdout = e->path == "-";
    const int fd = is_stdout ? STDOUT_FILENO : ::open(e->final_path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) return IoError(e->path + ": cannot open for writing: " + Errno());
    const bool ok = WriteAll(fd, e->buffer);
    const std::string why = ok ? "" : Errno();
    if (!is_stdout && ::close(fd) != 0 && ok) return IoError(e->path + ": write failed: " + Errno());
    if (!ok) return IoError((is_stdout ? std::string("stdout") : e->path) + ": write failed: " + why);
    e->buffer.clear();
  }
  entries_.clear();  // nothing left to remove
  return Status::Ok();
}

void RemoveLiveTemporaryFiles() noexcept {
  for (TemporarySlot& slot : g_slots) {
    if (slot.state.load() == kSlotLive) ::unlink(slot.path);
  }
  for (TemporarySlot& slot : g_folder_slots) {
    if (slot.state.load() == kSlotLive) ::rmdir(slot.path);  // fails, harmlessly, unless empty
  }
}

int ListCreatedFolder(const std::string& path) { return ListIn(g_folder_slots, kMaxCreatedFolders, path); }

void UnlistCreatedFolder(int handle) {
  if (handle >= 0 && handle < kMaxCreatedFolders) g_folder_slots[handle].state.store(kSlotFree);
}

}  // namespace gyrocomp
