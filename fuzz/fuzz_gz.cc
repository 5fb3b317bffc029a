// libFuzzer harness: the gzip path of the CSV reader. The first byte chooses the mode:
//   even: the rest is given to the reader as is (seeds are .csv.gz files, so mutations make
//         corrupt, truncated and concatenated gzip streams);
//   odd:  the rest is gzip-compressed first, so mutations of the CSV text reach the parser
//         through inflate (multi-member streams: the rest split in two members).
#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"

namespace {

std::string Gzip(const std::uint8_t* data, std::size_t size) {
  z_stream zs{};
  if (deflateInit2(&zs, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) return {};
  std::string out(deflateBound(&zs, size) + 64, '\0');
  zs.next_in = const_cast<Bytef*>(data);
  zs.avail_in = static_cast<uInt>(size);
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  deflate(&zs, Z_FINISH);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  if (data[0] % 2 == 0) {
    gyrocomp::fuzz::MemoryFile file(data + 1, size - 1);
    gyrocomp::fuzz::ReadAndLoad(file.path());
    return 0;
  }
  const std::size_t half = (size - 1) / 2;
  const std::string gz = Gzip(data + 1, half) + Gzip(data + 1 + half, size - 1 - half);
  gyrocomp::fuzz::MemoryFile file(reinterpret_cast<const std::uint8_t*>(gz.data()), gz.size());
  gyrocomp::fuzz::ReadAndLoad(file.path());
  return 0;
}
