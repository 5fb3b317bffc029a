// Read-only file maps (include/gyrocomp/io/mapped_file.h).
#include "gyrocomp/io/mapped_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <utility>

namespace gyrocomp {

Result<MappedFile> MappedFile::Open(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return IoError(path + ": cannot open");
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size <= 0) {
    ::close(fd);
    return IoError(path + ": not a non-empty regular file (not mapped)");
  }
  void* p = ::mmap(nullptr, static_cast<std::size_t>(st.st_size), PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);
  if (p == MAP_FAILED) return IoError(path + ": cannot map");
  ::madvise(p, static_cast<std::size_t>(st.st_size), MADV_SEQUENTIAL);
  MappedFile f;
  f.data_ = static_cast<const std::uint8_t*>(p);
  f.size_ = static_cast<std::size_t>(st.st_size);
  return f;
}

MappedFile::MappedFile(MappedFile&& o) noexcept
    : data_(std::exchange(o.data_, nullptr)), size_(std::exchange(o.size_, 0)), released_(std::exchange(o.released_, 0)) {}

MappedFile& MappedFile::operator=(MappedFile&& o) noexcept {
  if (this != &o) {
    if (data_) ::munmap(const_cast<std::uint8_t*>(data_), size_);
    data_ = std::exchange(o.data_, nullptr);
    size_ = std::exchange(o.size_, 0);
    released_ = std::exchange(o.released_, 0);
  }
  return *this;
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(const_cast<std::uint8_t*>(data_), size_);
}

void MappedFile::ReleaseBefore(std::size_t offset) {
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const std::size_t end = std::min(offset, size_) / page * page;
  if (!data_ || end <= released_) return;
  ::madvise(const_cast<std::uint8_t*>(data_) + released_, end - released_, MADV_DONTNEED);
  released_ = end;
}

void MappedFile::Prefetch(std::size_t offset, std::size_t bytes) {
#ifdef MADV_POPULATE_READ
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const std::size_t begin = std::min(offset, size_) / page * page;
  const std::size_t end = std::min(size_, offset + std::min(bytes, size_));
  if (!data_ || end <= begin) return;
  ::madvise(const_cast<std::uint8_t*>(data_) + begin, end - begin, MADV_POPULATE_READ);  // best effort
#else
  (void)offset;
  (void)bytes;
#endif
}

}  // namespace gyrocomp
