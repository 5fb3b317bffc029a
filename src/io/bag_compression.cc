// Chunk decompression and CRC for the bag readers (src/io/bag_bytes.h).
#include <bzlib.h>
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <climits>
#include <memory>
#include <istream>
#include <ostream>
#include <vector>

#include "bag_bytes.h"

namespace gyrocomp::bag_internal {

namespace {

std::string Zstd(const std::uint8_t* src, std::size_t n, std::vector<std::uint8_t>* dst) {
  // ZSTD_decompress stops with dstSize_tooSmall rather than write past the declared size.
  const std::size_t got = ZSTD_decompress(dst->data(), dst->size(), src, n);
  if (ZSTD_isError(got)) return std::string("zstd: ") + ZSTD_getErrorName(got);
  if (got != dst->size()) {
    return "zstd: " + std::to_string(got) + " bytes decompressed, the chunk declares " + std::to_string(dst->size());
  }
  return "";
}

std::string Lz4Frame(const std::uint8_t* src, std::size_t n, std::vector<std::uint8_t>* dst) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION))) return "lz4: cannot create a context";
  std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(raw, &LZ4F_freeDecompressionContext);
  std::size_t in_pos = 0, out_pos = 0;
  while (true) {
    std::size_t out_size = dst->size() - out_pos;
    std::size_t in_size = n - in_pos;
    const std::size_t hint = LZ4F_decompress(ctx.get(), dst->data() + out_pos, &out_size, src + in_pos, &in_size, nullptr);
    if (LZ4F_isError(hint)) return std::string("lz4: ") + LZ4F_getErrorName(hint);
    in_pos += in_size;
    out_pos += out_size;
    if (hint == 0) {
      // End of a frame; the LZ4 frame format allows several frames one after the other.
      if (in_pos == n) break;
      continue;
    }
    if (in_size == 0 && out_size == 0) {  // no progress: the output is full or the input ended
      if (out_pos == dst->size()) {
        return "lz4: the data decompresses to more than the " + std::to_string(dst->size()) + " bytes the chunk declares";
      }
      return "lz4: the compressed data ends inside a frame";
    }
  }
  if (out_pos != dst->size()) {
    return "lz4: " + std::to_string(out_pos) + " bytes decompressed, the chunk declares " + std::to_string(dst->size());
  }
  return "";
}

std::string Bzip2(const std::uint8_t* src, std::size_t n, std::vector<std::uint8_t>* dst) {
  if (n > UINT_MAX || dst->size() > UINT_MAX) return "bz2: chunk larger than 4 GiB";
  unsigned int out = static_cast<unsigned int>(dst->size());
  const int rc = BZ2_bzBuffToBuffDecompress(reinterpret_cast<char*>(dst->data()), &out,
                                            const_cast<char*>(reinterpret_cast<const char*>(src)),
                                            static_cast<unsigned int>(n), 0, 0);
  if (rc == BZ_OUTBUFF_FULL) return "bz2: the data decompresses to more than the " + std::to_string(dst->size()) + " bytes the chunk declares";
  if (rc != BZ_OK) return "bz2: corrupt data (libbz2 error " + std::to_string(rc) + ")";
  if (out != dst->size()) return "bz2: " + std::to_string(out) + " bytes decompressed, the chunk declares " + std::to_string(dst->size());
  return "";
}

}  // namespace

std::string Decompress(const std::string& method, const std::uint8_t* src, std::size_t src_size,
                       std::vector<std::uint8_t>* dst) {
  if (method == "zstd") return Zstd(src, src_size, dst);
  if (method == "lz4") return Lz4Frame(src, src_size, dst);
  if (method == "bz2") return Bzip2(src, src_size, dst);
  return "unknown compression '" + method + "'";
}

std::uint32_t Crc32(const std::uint8_t* data, std::size_t size) { return Crc32Update(0, data, size); }

std::uint32_t Crc32Update(std::uint32_t previous, const std::uint8_t* data, std::size_t size) {
  uLong crc = previous;
  while (size > 0) {
    const uInt step = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
    crc = crc32(crc, data, step);
    data += step;
    size -= step;
  }
  return static_cast<std::uint32_t>(crc);
}

bool HasZstdMagic(const std::uint8_t* head, std::size_t n) {
  return n >= 4 && head[0] == 0x28 && head[1] == 0xB5 && head[2] == 0x2F && head[3] == 0xFD;
}

std::string DecompressZstdFile(std::istream& in, std::ostream& out, std::uint64_t max_bytes, bool prefix_only) {
  std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> dctx(ZSTD_createDCtx(), &ZSTD_freeDCtx);
  if (!dctx) return "zstd: out of memory";
  std::vector<char> src(ZSTD_DStreamInSize()), dst(ZSTD_DStreamOutSize());
  std::uint64_t consumed = 0, written = 0;
  std::size_t last = 0;  // ZSTD_decompressStream's last return: 0 = a frame ended and was flushed
  bool any = false;
  while (true) {
    in.read(src.data(), static_cast<std::streamsize>(src.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (got == 0) break;
    any = true;
    ZSTD_inBuffer input{src.data(), got, 0};
    while (input.pos < input.size) {
      ZSTD_outBuffer output{dst.data(), dst.size(), 0};
      last = ZSTD_decompressStream(dctx.get(), &output, &input);
      if (ZSTD_isError(last)) {
        return "compressed byte " + std::to_string(consumed + input.pos) + ": zstd: " + ZSTD_getErrorName(last);
      }
      const std::uint64_t room = max_bytes - written;
      if (output.pos > room) {
        if (prefix_only) {
          out.write(dst.data(), static_cast<std::streamsize>(room));
          return out ? "" : "cannot write the decompressed file";
        }
        return "decompresses to more than " + std::to_string(max_bytes) +
               " bytes (BagReadOptions::max_decompressed_file_bytes); refused as a possible compression bomb";
      }
      out.write(dst.data(), static_cast<std::streamsize>(output.pos));
      if (!out) return "cannot write the decompressed file (disk full?)";
      written += output.pos;
    }
    consumed += got;
  }
  if (!any) return "empty file";
  if (last != 0 && !prefix_only) {
    return "compressed byte " + std::to_string(consumed) + ": zstd: the file ends inside a frame (truncated)";
  }
  return "";
}

}  // namespace gyrocomp::bag_internal
