// Record-level mutator and recovery invariant for fuzz_ulog / fuzz_dataflash (fuzz_records.h).
#include "fuzz_records.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <set>
#include <unordered_set>

#include "fuzz_support.h"
#include "log_rows.h"
#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/ulog.h"

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

namespace gyrocomp::fuzz {
namespace {

// Every sensor row a reader gives, under one series (a record moved by a damaged id is still a
// row of the log); `ok` false when the reader refuses the bytes.
test::LogRows Rows(LogKind kind, const std::uint8_t* data, std::size_t size, bool* ok) {
  *ok = false;
  if (kind == LogKind::kULog) {
    Result<ULogContents> log = ParseULog(data, size, "fuzz");
    if (!log) return {};
    *ok = true;
    return test::AnySeries(test::ULogRows(*log));
  }
  Result<DataFlashContents> log = ParseDataFlash(data, size, "fuzz");
  if (!log) return {};
  *ok = true;
  return test::AnySeries(test::DataFlashRows(*log));
}

// The intact records of a log: its record byte strings, and for DataFlash the length of each
// type from its FMT records (a mutated log's own FMTs may be the damaged ones).
struct RecordBook {
  std::unordered_set<std::string> records;
  std::map<int, std::size_t> dataflash_length = {{0x80, 89}};
  std::set<std::pair<char, std::size_t>> ulog_headers;  // (type, size with header) of its records
};

struct Original {
  std::string name;
  std::string bytes;
  test::LogRows rows;
  RecordBook book;  // filled by InitOriginals
};
std::vector<Original>& Originals() {
  static std::vector<Original> o;
  return o;
}

std::string BuiltIn(LogKind kind) {
  if (kind == LogKind::kULog) {
    ULogWriteInput in;
    for (int k = 0; k < 3; ++k) {
      ULogSensorWriteSeries s;
      s.topic = k == 2 ? "sensor_accel" : "sensor_gyro";
      s.multi_id = k == 2 ? 0 : k;
      s.device_id = 2424842u + static_cast<std::uint32_t>(k);
      for (int i = 0; i < 40; ++i) {
        s.timestamp_us.push_back(1000000 + 4000 * static_cast<std::uint64_t>(i) + static_cast<std::uint64_t>(k));
        s.x.push_back(0.001f * static_cast<float>(i + k));
        s.y.push_back(-0.02f * static_cast<float>(k));
        s.z.push_back(0.5f);
        s.temperature_c.push_back(30.0f + 0.05f * static_cast<float>(i));
      }
      in.series.push_back(s);
    }
    Result<std::string> b = EncodeULog(in);
    return b ? *b : std::string();
  }
  DataFlashWriteInput in;
  for (int k = 0; k < 2; ++k) {
    DataFlashImuWriteInput imu;
    imu.instance = k;
    for (int i = 0; i < 40; ++i) {
      imu.time_us.push_back(1000000 + 2500 * static_cast<std::uint64_t>(i));
      imu.gyr_x_rad_s.push_back(0.001f * static_cast<float>(i));
      imu.gyr_y_rad_s.push_back(0.1f * static_cast<float>(k));
      imu.gyr_z_rad_s.push_back(-0.3f);
      imu.temp_c.push_back(25.0f + 0.1f * static_cast<float>(i));
    }
    in.imus.push_back(imu);
  }
  Result<std::string> b = EncodeDataFlash(in);
  return b ? *b : std::string();
}

// The length (header included) that the record at `pos` declares: ULog, 3 + its size field;
// DataFlash, the FMT length of its type when it starts with A3 95 and the type is in `book`.
// 0 when no record is declared there (fewer than 3 bytes left, no A3 95, a type with no FMT).
std::size_t DeclaredLength(LogKind kind, const RecordBook& book, const std::uint8_t* d, std::size_t n,
                           std::size_t pos) {
  if (pos + 3 > n) return 0;
  if (kind == LogKind::kULog) return 3 + (d[pos] | (d[pos + 1] << 8));
  if (d[pos] != 0xA3 || d[pos + 1] != 0x95) return 0;
  const auto it = book.dataflash_length.find(d[pos + 2]);
  return it == book.dataflash_length.end() ? 0 : it->second;
}

std::size_t FirstRecord(LogKind kind) { return kind == LogKind::kULog ? 16 : 0; }  // after the ULog file header

// Record boundaries (offset, size with header) of the original's records still intact in a
// mutated log. Damaged bytes (a cut record, a broken header) are skipped byte by byte until an
// intact record starts again, so every mutation splits and joins the log only where a record of
// the original begins or ends. Walking the damaged bytes by their declared sizes instead would
// give boundaries inside records, and a delete between two of them splices the head of one
// record onto the tail of another: a well-formed record holding a row the original never had,
// which no reader could tell apart.
std::vector<std::pair<std::size_t, std::size_t>> Records(LogKind kind, const RecordBook& book, const std::uint8_t* d,
                                                         std::size_t n) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  const auto intact = [&](std::size_t pos, std::size_t len) {
    return pos + len <= n && book.records.count(std::string(reinterpret_cast<const char*>(d) + pos, len)) > 0;
  };
  std::size_t pos = FirstRecord(kind);
  while (pos + 3 <= n) {
    const std::size_t len = DeclaredLength(kind, book, d, n, pos);
    if (len >= 3 && intact(pos, len)) {
      out.emplace_back(pos, len);
      pos += len;
    } else {
      ++pos;
    }
  }
  return out;
}

// Whether a chain of records starts somewhere in [from, end of s) and ends exactly at the end,
// each header one the original has (ULog: its type with that size; DataFlash: a type of its
// FMTs). From the end backwards, so the tail is walked once: a chain from p reaches the end when
// its first record does or the chain from where that record ends does.
bool ChainEndsAtEnd(LogKind kind, const RecordBook& book, const std::string& s, std::size_t from) {
  const auto* d = reinterpret_cast<const std::uint8_t*>(s.data());
  const std::size_t n = s.size();
  if (from >= n) return false;
  std::vector<char> reaches(n - from + 1, 0);  // reaches[p - from]: a chain from p ends at n
  reaches[n - from] = 1;
  for (std::size_t p = n; p-- > from;) {
    const std::size_t len = DeclaredLength(kind, book, d, n, p);
    const auto known = [&] {
      return kind == LogKind::kDataFlash || book.ulog_headers.count({static_cast<char>(d[p + 2]), len}) > 0;
    };
    reaches[p - from] = len >= 3 && p + len <= n && known() && reaches[p + len - from];
    if (reaches[p - from]) return true;
  }
  return false;
}

// A damaged record (cut short, its size now reaching into what followed) that the end of the file
// cuts exactly where its declared size ends looks like an intact last record: nothing follows it
// to refuse it by, and no reader can tell (ulog_recovery.cc decodes a record only when what
// follows is a record or the end). The mutator keeps that one case out by dropping the last byte,
// so that the record is a truncated one; every other damage stays. A chain of records from any
// offset after the last intact record, each header one the original has, ending exactly at the
// end, is that case. Records() runs once: a byte is dropped only when a chain starts after the
// last intact record, so that record ends before the new end and the intact records stay the
// same; only the tail after it is looked at again.
void KeepUndecidableEndOut(LogKind kind, const RecordBook& book, std::string& s) {
  const auto intact = Records(kind, book, reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
  const std::size_t from = intact.empty() ? FirstRecord(kind) : intact.back().first + intact.back().second;
  for (int guard = 0; guard < 64 && !s.empty() && ChainEndsAtEnd(kind, book, s, from); ++guard) s.pop_back();
}

// The original's own records, walked by their declared sizes (an original is undamaged).
RecordBook BookOf(LogKind kind, const std::string& bytes) {
  RecordBook book;
  const auto* d = reinterpret_cast<const std::uint8_t*>(bytes.data());
  const std::size_t n = bytes.size();
  std::size_t pos = FirstRecord(kind);
  while (pos + 3 <= n) {
    const std::size_t len = DeclaredLength(kind, book, d, n, pos);  // the FMTs read so far
    if (len < 3) break;
    if (kind == LogKind::kDataFlash && d[pos + 2] == 0x80 && pos + 5 <= n) book.dataflash_length[d[pos + 3]] = d[pos + 4];
    if (pos + len > n) break;
    book.records.insert(bytes.substr(pos, len));
    if (kind == LogKind::kULog) book.ulog_headers.insert({static_cast<char>(d[pos + 2]), len});
    pos += len;
  }
  return book;
}

bool Tagged(const std::uint8_t* d, std::size_t n) {
  return n >= kTagBytes && std::memcmp(d, kTag, kTagBytes - 1) == 0 && d[kTagBytes - 1] < Originals().size();
}

std::size_t Emit(const std::string& s, std::uint8_t* out, std::size_t max) {
  const std::size_t n = std::min(s.size(), max);
  std::memcpy(out, s.data(), n);
  return n;
}

std::string WithTag(std::uint8_t id, const std::string& log) {
  std::string s(kTag, kTagBytes - 1);
  s.push_back(static_cast<char>(id));
  return s + log;
}

}  // namespace

void InitOriginals(LogKind kind) {
  auto& o = Originals();
  if (!o.empty()) return;
  std::vector<std::pair<std::string, std::string>> logs = {{"built-in", BuiltIn(kind)}};
  if (const char* dir = std::getenv("GYROCOMP_FUZZ_ORIGINALS")) {
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec)) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      std::ifstream in(f, std::ios::binary);
      logs.emplace_back(f.string(), std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()));
    }
  }
  for (auto& [name, bytes] : logs) {
    bool ok = false;
    test::LogRows rows = Rows(kind, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), &ok);
    if (!ok || o.size() >= 255) continue;  // an original must read
    RecordBook book = BookOf(kind, bytes);
    o.push_back({name, std::move(bytes), std::move(rows), std::move(book)});
  }
}

void RunRecordHarness(LogKind kind, const std::uint8_t* data, std::size_t size) {
  InitOriginals(kind);
  const bool tagged = Tagged(data, size);
  const std::uint8_t* log = tagged ? data + kTagBytes : data;
  const std::size_t n = tagged ? size - kTagBytes : size;
  if (kind == LogKind::kULog) {
    (void)ParseULog(log, n, "fuzz");
  } else {
    (void)ParseDataFlash(log, n, "fuzz");
  }
  MemoryFile file(log, n);
  ReadFlightLog(file.path());
  if (!tagged) return;
  const Original& orig = Originals()[data[kTagBytes - 1]];
  bool ok = false;
  const test::LogRows rows = Rows(kind, log, n, &ok);
  // A log cut inside its definitions / header may be refused; the rows never invented (a
  // duplicated record repeats its row).
  if (const std::string bad = test::NotASubset(rows, orig.rows, /*allow_repeats=*/true); !bad.empty()) {
    std::fprintf(stderr, "recovery invariant broken: %s, against %s\n", bad.c_str(), orig.name.c_str());
    std::abort();
  }
}

std::size_t MutateRecords(LogKind kind, std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed) {
  InitOriginals(kind);
  std::minstd_rand rng(seed);
  if (!Tagged(data, size)) {
    // Now and then start again from a tagged original; otherwise byte-level mutation.
    if (rng() % 8 == 0) {
      const auto id = static_cast<std::uint8_t>(rng() % Originals().size());
      return Emit(WithTag(id, Originals()[id].bytes), data, max_size);
    }
    // Byte-level mutation; its result must not pass for a tagged original (libFuzzer learns the
    // tag from the comparison in Tagged() and may insert it), or the invariant would be checked
    // against bytes the record mutator never changed that way.
    const std::size_t n = LLVMFuzzerMutate(data, size, max_size);
    if (Tagged(data, n)) data[0] = 'g';
    return n;
  }
  std::string s(reinterpret_cast<const char*>(data + kTagBytes), size - kTagBytes);
  const std::string tag(reinterpret_cast<const char*>(data), kTagBytes);
  const Original& orig = Originals()[data[kTagBytes - 1]];
  const auto recs = Records(kind, orig.book, reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
  if (recs.size() < 2) return Emit(tag + orig.bytes, data, max_size);
  const std::size_t i = rng() % recs.size();
  const auto [off, len] = recs[i];
  switch (rng() % 6) {
    case 0:  // delete
      s.erase(off, len);
      break;
    case 1:  // duplicate
      s.insert(off, s.substr(off, len));
      break;
    case 2:  // swap with the next record ("flip")
      if (i + 1 < recs.size()) {
        const auto [off2, len2] = recs[i + 1];
        s = s.substr(0, off) + s.substr(off2, len2) + s.substr(off, len) + s.substr(off2 + len2);
      }
      break;
    case 3:  // truncate inside the record
      s.resize(off + rng() % len);
      break;
    case 4:  // cut the record short (its tail deleted): its size then runs into the next
      if (len > 3) s.erase(off + 3 + rng() % (len - 3), 1 + rng() % std::min<std::size_t>(8, len - 3));
      break;
    default:  // damage the header so the record must be refused
      if (kind == LogKind::kULog) {
        if (s[off + 2] == 'D' && len >= 5) {
          s[off + 3] = s[off + 4] = static_cast<char>(0xFF);  // msg_id 65535: no subscription
        } else {
          s[off + 2] = static_cast<char>(0x01);  // not a ULog message type
        }
      } else {
        s[off + (rng() % 2)] = 0x00;  // A3 95 broken
      }
      break;
  }
  KeepUndecidableEndOut(kind, orig.book, s);
  return Emit(tag + s, data, max_size);
}

std::size_t CrossOverRecords(LogKind kind, const std::uint8_t* a, std::size_t a_size, const std::uint8_t* b,
                             std::size_t b_size, std::uint8_t* out, std::size_t max_out, unsigned seed) {
  InitOriginals(kind);
  std::minstd_rand rng(seed);
  if (Tagged(a, a_size) && Tagged(b, b_size) && a[kTagBytes - 1] == b[kTagBytes - 1]) {
    // The records of a up to one of its boundaries, then b's from one of its boundaries.
    const RecordBook& book = Originals()[a[kTagBytes - 1]].book;
    const auto ra = Records(kind, book, a + kTagBytes, a_size - kTagBytes);
    const auto rb = Records(kind, book, b + kTagBytes, b_size - kTagBytes);
    if (!ra.empty() && !rb.empty()) {
      const std::size_t cut_a = ra[rng() % ra.size()].first + kTagBytes;
      const std::size_t cut_b = rb[rng() % rb.size()].first + kTagBytes;
      std::string s(reinterpret_cast<const char*>(a) + kTagBytes, cut_a - kTagBytes);
      s.append(reinterpret_cast<const char*>(b) + cut_b, b_size - cut_b);
      KeepUndecidableEndOut(kind, book, s);
      return Emit(std::string(reinterpret_cast<const char*>(a), kTagBytes) + s, out, max_out);
    }
  }
  if (Tagged(a, a_size)) return Emit(std::string(reinterpret_cast<const char*>(a), a_size), out, max_out);
  // Untagged: a's head and b's tail, byte level.
  const std::size_t cut_a = a_size ? rng() % (a_size + 1) : 0;
  const std::size_t cut_b = b_size ? rng() % (b_size + 1) : 0;
  std::string s(reinterpret_cast<const char*>(a), cut_a);
  s.append(reinterpret_cast<const char*>(b) + cut_b, b_size - cut_b);
  if (Tagged(reinterpret_cast<const std::uint8_t*>(s.data()), s.size())) s[0] = 'g';  // never tagged by chance
  return Emit(s, out, max_out);
}

}  // namespace gyrocomp::fuzz
