// A read-only memory map of a regular file whose already-parsed pages can be given back
// (memory: a 1 h, 1 kHz, 3-IMU log is 1.3 GB; the sequential parsers release what is behind
// their cursor, so the file never sits in memory whole).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "gyrocomp/core/status.h"

namespace gyrocomp {

// A read-only memory map of a whole regular file.
class MappedFile {
 public:
  // Errors: not a regular file, empty, cannot open or map (kIo): callers then read the bytes.
  static Result<MappedFile> Open(const std::string& path);
  // Takes the mapping; `other` is left empty.
  MappedFile(MappedFile&& other) noexcept;
  // Unmaps this one's mapping and takes `other`'s.
  MappedFile& operator=(MappedFile&& other) noexcept;
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile();

  // First byte of the mapping.
  const std::uint8_t* data() const { return data_; }
  // Bytes mapped (the file's size).
  std::size_t size() const { return size_; }
  // Gives the whole pages below `offset` back to the kernel (madvise MADV_DONTNEED): reading them
  // again would read the file again. Only for parsers that never look back.
  void ReleaseBefore(std::size_t offset);
  // Maps the pages of [offset, offset + bytes) now, in one call (madvise MADV_POPULATE_READ, Linux
  // >= 5.14; a no-op elsewhere or on error): a parser about to read them sequentially saves a
  // page fault per few pages.
  void Prefetch(std::size_t offset, std::size_t bytes);

 private:
  MappedFile() = default;
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
  std::size_t released_ = 0;
};

}  // namespace gyrocomp
