// Little-endian byte cursors shared by the bag readers (src/io/mcap.cc, src/io/rosbag1.cc).
// Private to src/io.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include "gyrocomp/io/mapped_file.h"

namespace gyrocomp::bag_internal {

inline std::uint64_t LoadLe(const std::uint8_t* p, std::size_t bytes) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < bytes; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  return v;
}

// A bounded cursor over bytes in memory: every read checks what is left; `failed` says one did
// not fit, `what` names the field.
struct Cursor {
  Cursor(const std::uint8_t* data, std::size_t size) : p(data), n(size) {}
  const std::uint8_t* p = nullptr;
  std::size_t n = 0;
  std::size_t pos = 0;
  std::string failed;  // name of the first field that did not fit
  bool Int(std::size_t bytes, std::uint64_t* v, const char* field) {
    if (!failed.empty()) return false;
    if (bytes > n - pos) {
      failed = field;
      return false;
    }
    *v = LoadLe(p + pos, bytes);
    pos += bytes;
    return true;
  }
  // uint32 length-prefixed bytes (MCAP "String" / "Bytes" with a uint32 length).
  bool Str(std::string* s, const char* field) {
    std::uint64_t len = 0;
    if (!Int(4, &len, field)) return false;
    if (len > n - pos) {
      failed = field;
      return false;
    }
    s->assign(reinterpret_cast<const char*>(p + pos), static_cast<std::size_t>(len));
    pos += static_cast<std::size_t>(len);
    return true;
  }
  std::size_t left() const { return n - pos; }
};

// Reads `n` bytes at `offset` of a stream into `out` (resized). False on a short read.
inline bool ReadAt(std::istream& in, std::uint64_t offset, std::size_t n, std::vector<std::uint8_t>* out) {
  out->resize(n);
  in.clear();
  in.seekg(static_cast<std::streamoff>(offset));
  if (!in) return false;
  in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(n));
  return static_cast<std::size_t>(in.gcount()) == n;
}

// Where a sequential bag reader gets its bytes: a memory-mapped file (no copy; the pages behind
// the cursor are given back) or a seekable stream (copied into the caller's scratch buffer).
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  virtual std::uint64_t size() const = 0;
  // The `n` bytes at `offset` (offset + n <= size()): valid until `scratch` is next used; nullptr
  // on a read error.
  virtual const std::uint8_t* View(std::uint64_t offset, std::size_t n, std::vector<std::uint8_t>* scratch) = 0;
  // Nothing before `offset` will be viewed again.
  virtual void Consumed(std::uint64_t /*offset*/) {}
};

// Size of a seekable stream, or -1.
inline std::int64_t StreamSize(std::istream& in) {
  in.clear();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0);
  return in ? static_cast<std::int64_t>(size) : -1;
}

// A seekable stream (a file opened as a stream, the fuzzers' bytes). size() is -1 as unsigned
// when the stream cannot seek: callers check `ok()` first.
class StreamSource final : public ByteSource {
 public:
  explicit StreamSource(std::istream& in) : in_(in), size_(StreamSize(in)) {}
  bool ok() const { return size_ >= 0; }
  std::uint64_t size() const override { return static_cast<std::uint64_t>(size_); }
  const std::uint8_t* View(std::uint64_t offset, std::size_t n, std::vector<std::uint8_t>* scratch) override {
    static constexpr std::uint8_t kNothing = 0;  // a valid pointer for a 0-byte view
    if (!ReadAt(in_, offset, n, scratch)) return nullptr;
    return n == 0 ? &kNothing : scratch->data();
  }

 private:
  std::istream& in_;
  std::int64_t size_;
};

// A memory-mapped file: views point into the map; consumed pages are released
// (MappedFile::ReleaseBefore) so the resident set stays near one record, not the file.
class MappedSource final : public ByteSource {
 public:
  explicit MappedSource(MappedFile& file) : file_(file) {}
  std::uint64_t size() const override { return file_.size(); }
  const std::uint8_t* View(std::uint64_t offset, std::size_t /*n*/, std::vector<std::uint8_t>* /*scratch*/) override {
    return file_.data() + offset;
  }
  void Consumed(std::uint64_t offset) override {
    // One madvise per 8 MiB read, not per record: the pages behind are given back and the next
    // 8 MiB mapped in one call (MappedFile::Prefetch) instead of a page fault per 64 KiB.
    if (offset >= prefetched_) {
      file_.Prefetch(static_cast<std::size_t>(offset), kWindow);
      prefetched_ = offset + kWindow;
    }
    if (offset - released_ >= kWindow) {
      file_.ReleaseBefore(static_cast<std::size_t>(offset));
      released_ = offset;
    }
  }

 private:
  static constexpr std::uint64_t kWindow = std::uint64_t{8} << 20;
  MappedFile& file_;
  std::uint64_t released_ = 0, prefetched_ = 0;
};

}  // namespace gyrocomp::bag_internal

namespace gyrocomp::bag_internal {

// Decompresses `src` into `dst`, which is already sized to the declared uncompressed size; the
// output must fill it exactly. Returns "" or what went wrong. Nothing is ever written past
// dst->size() (the declared size is the compression-bomb bound).
//   "zstd": Zstandard frames (RFC 8878), ZSTD_decompress into the fixed buffer;
//   "lz4":  the LZ4 *frame* format (lz4/doc/lz4_Frame_format.md, magic 04 22 4D 18), LZ4F;
//   "bz2":  bzip2 (BZ2_bzBuffToBuffDecompress).
std::string Decompress(const std::string& method, const std::uint8_t* src, std::size_t src_size,
                       std::vector<std::uint8_t>* dst);

// zlib crc32 (the CRC-32 of ISO 3309 / ITU-T V.42, as MCAP's CRC fields: spec "Chunk").
std::uint32_t Crc32(const std::uint8_t* data, std::size_t size);
// The CRC-32 of (the bytes whose CRC-32 is `previous`) followed by `data` (zlib crc32 chaining).
std::uint32_t Crc32Update(std::uint32_t previous, const std::uint8_t* data, std::size_t size);

// rosbag2 per-file compression (compression_mode FILE, compression_format zstd: the storage file
// `x.mcap.zstd` / `x.db3.zstd` is one or more Zstandard frames, RFC 8878): the Zstandard frame
// magic 28 B5 2F FD (RFC 8878, 3.1.1 "Magic_Number" 0xFD2FB528, little-endian).
bool HasZstdMagic(const std::uint8_t* head, std::size_t n);
// Stream-decompresses the Zstandard file `in` into `out` (ZSTD_decompressStream, bounded
// buffers), writing at most `max_bytes` (more: refused as a compression bomb), or only the first
// `max_bytes` when `prefix_only`. Returns "" or what went wrong with the compressed byte offset.
std::string DecompressZstdFile(std::istream& in, std::ostream& out, std::uint64_t max_bytes, bool prefix_only = false);

}  // namespace gyrocomp::bag_internal
