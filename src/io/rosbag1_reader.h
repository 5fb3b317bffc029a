// The ROS 1 bag reader's class, shared by rosbag1.cc (reading) and rosbag1_recovery.cc
// (recovery); not installed. The format, and how this reader streams it:
//
// ROS 1 bag reader, format version 2.0 (include/gyrocomp/io/bag.h), written from the ROS wiki
// page "Bags/Format/2.0" (wiki.ros.org/Bags/Format/2.0). Quotes below are its section names.
//
// "Version": the file starts with the line "#ROSBAG V2.0\n".
// "Records": <header_len uint32><header><data_len uint32><data>; the header is a sequence of
//   fields <field_len uint32><name>=<value>; "op" (1 byte) gives the record's kind. Integers are
//   little-endian.
//   op 0x03 "Bag header": index_pos uint64, conn_count uint32, chunk_count uint32 (data: padding)
//   op 0x05 "Chunk": compression ("none", "bz2", "lz4"), size uint32 (uncompressed bytes); data:
//           the (compressed) connection and message data records
//   op 0x07 "Connection": conn uint32, topic; data: a connection header (fields topic, type,
//           md5sum, message_definition, ...)
//   op 0x02 "Message data": conn uint32, time uint64 (uint32 secs, uint32 nsecs: the receive
//           time); data: the ROS 1 serialized message
//   op 0x04 "Index data" (ver, conn, count), op 0x06 "Chunk info" (ver, chunk_pos, start_time,
//           end_time, count; data: conn uint32, count uint32 pairs): the index, not needed by a
//           sequential read.
// The whole file is read in order, chunk by chunk (unindexed bags, whose index_pos is 0, read the
// same); connection records repeated in the index section are announced once. "lz4" chunks are
// roslz4's, which writes the LZ4 frame format (ros_comm utilities/roslz4/src/lz4s.c).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bag_bytes.h"
#include "gyrocomp/io/bag.h"

namespace gyrocomp::ros1_internal {

using bag_internal::LoadLe;

constexpr char kVersionLine[] = "#ROSBAG V2.0\n";
constexpr std::size_t kVersionBytes = sizeof kVersionLine - 1;

enum Op : std::uint8_t {
  kMessageData = 0x02,
  kBagHeader = 0x03,
  kIndexData = 0x04,
  kChunk = 0x05,
  kChunkInfo = 0x06,
  kConnection = 0x07
};

// The fields of a record header (or a connection header) by name: views into the header's
// bytes, which outlive them (no allocation per record: a 3 h 200 Hz bag has 2 M of them).
class Fields {
 public:
  void clear() { items_.clear(); }
  void Add(std::string_view name, std::string_view value) { items_.emplace_back(name, value); }
  // The value of the last field of that name (a repeated name: the last one wins, as a map
  // assignment would), or nullopt.
  std::optional<std::string_view> Find(std::string_view name) const {
    for (auto it = items_.rbegin(); it != items_.rend(); ++it) {
      if (it->first == name) return it->second;
    }
    return std::nullopt;
  }

 private:
  std::vector<std::pair<std::string_view, std::string_view>> items_;
};

// Splits a header into fields; "" or the problem.
std::string ParseFields(const std::uint8_t* p, std::size_t n, Fields* out);
// The integer field `name` of exactly `bytes` bytes; false when absent or of another size.
bool FieldInt(const Fields& f, const char* name, std::size_t bytes, std::uint64_t* v);
// Whether the `avail` bytes at p start a record a resynchronising scan accepts, whose header and
// data fit in the `left` bytes of the file from p (rosbag1_recovery.cc).
bool RecordStartsAt(const std::uint8_t* p, std::uint64_t avail, std::uint64_t left, Fields* scratch);
// Largest record header a resynchronising scan accepts: real headers are tens of bytes (a
// connection record's holds its topic name), so a damaged length is not followed far.
inline constexpr std::uint64_t kMaxResyncHeader = 64 * 1024;

// A damaged record found by a handler: the strict error and, in recovery, where reading goes on.
struct Damage {
  BagPosition where;  // the record (and byte in its chunk) the strict error names
  std::string what;   // the strict error's text after the position
  std::uint64_t begin = 0;  // first byte skipped
  // Reading goes on at `resume` when a valid record starts there (or the file ends there), else
  // at the next valid record after `scan_from`.
  std::optional<std::uint64_t> resume;
  std::uint64_t scan_from = 0;
  std::optional<std::uint64_t> chunk;  // offset of the chunk record whose messages it loses
};

class Ros1Reader {
 public:
  Ros1Reader(bag_internal::ByteSource& bytes, const std::string& source, const BagReadOptions& options,
             BagVisitor* visitor)
      : bytes_(bytes), source_(source), options_(options), visitor_(visitor) {}
  std::optional<Error> Run();

 private:
  Error Bad(const BagPosition& where, const std::string& what) const {
    return InvalidInput(source_ + ": " + where.ToString() + ": " + what);
  }
  Error ReadError(std::uint64_t offset) const { return IoError(source_ + ": read error at " + At(offset).ToString()); }
  static BagPosition At(std::uint64_t offset) { return BagPosition{offset, {}, {}}; }
  // One record of the file at `pos`: sets *next to the record after it, or *damage.
  std::optional<Error> TopRecord(std::uint64_t pos, bool first, std::uint64_t* next, std::optional<Damage>* damage);
  // One record in memory (a chunk's content, or the data of a record of the file): its op,
  // header fields, data. A record that cannot be read sets *why.
  std::optional<Error> InnerRecord(const BagPosition& where, const Fields& f, const std::uint8_t* data, std::size_t n,
                                   std::string* why);
  std::optional<Error> Chunk(std::uint64_t at, const Fields& f, std::uint64_t data_at, std::uint64_t data_len,
                             std::optional<Damage>* damage);
  std::optional<Error> ChunkRecords(std::uint64_t at, const std::uint8_t* chunk, std::size_t n, std::size_t* bad_at,
                                    std::string* why);
  std::optional<Error> Connection(const BagPosition& where, const Fields& f, const std::uint8_t* data, std::size_t n,
                                  std::string* why);
  std::optional<Error> Message(const BagPosition& where, const Fields& f, const std::uint8_t* data, std::size_t n,
                               std::string* why);
  void ReadIndex(const Fields& bag_header);
  void AddChunkInfo(std::uint64_t chunk_pos, const std::uint8_t* data, std::uint64_t n);
  std::optional<Error> ChunkInfo(const Fields& f, std::uint64_t data_at, std::uint64_t data_len);
  // Recovery: the next offset >= from where a record starts (RecordStartsAt), or the file's size.
  std::uint64_t NextRecord(std::uint64_t from);
  bool ResumesAt(std::uint64_t pos);
  void AddDamage(const Damage& d, std::uint64_t end);
  void CountDelivered(const BagPosition& where, std::uint64_t conn);
  std::string TopicOf(std::uint64_t conn) const;
  void ReportDamage();
  void FitToIndexTotals(std::vector<std::map<std::uint64_t, std::uint64_t>>* lost) const;

  bag_internal::ByteSource& bytes_;
  const std::string& source_;
  const BagReadOptions& options_;
  BagVisitor* visitor_;
  std::set<std::uint64_t> connections_;
  std::map<std::uint64_t, std::uint64_t> expected_;  // messages per connection, from the index
  // From the index section ("Chunk info", "Connection"): each chunk's message count per
  // connection by the chunk record's offset, and every connection (topic, type).
  std::map<std::uint64_t, std::map<std::uint64_t, std::uint64_t>> chunk_counts_;
  std::uint64_t index_pos_ = 0;
  std::map<std::uint64_t, BagChannel> index_channels_;
  std::map<std::uint64_t, std::string> topics_;  // connection -> topic, of the connections read
  // Recovery: the skipped ranges, each with the chunk record it was found in (if any); the
  // messages read all the same of what each damage lost (index in damage_ -> connection ->
  // count): those of its chunk read before it, and those read outside chunks after it up to the
  // next chunk record (a resynchronising scan landed inside an uncompressed chunk); the
  // messages of the chunk being read. The losses are worked out at the file's end
  // (ReportDamage), when the index section has been read whatever happened to index_pos.
  std::vector<LogDamage> damage_;
  std::vector<std::optional<std::uint64_t>> damage_chunk_;
  std::map<std::size_t, std::map<std::uint64_t, std::uint64_t>> delivered_;
  std::map<std::uint64_t, std::uint64_t> chunk_delivered_;
  std::optional<std::size_t> open_damage_;  // the damage top-level messages are read after
  bool index_read_ = false;  // chunk_counts_ came from index_pos
  std::optional<std::uint64_t> header_chunk_count_;  // the bag header's chunk_count
  std::map<std::uint64_t, std::uint64_t> read_;  // messages read per connection (recovery)
  std::map<std::uint64_t, std::size_t> unknown_conn_damage_;  // connection -> index in damage_
  std::uint64_t record_end_ = 0;  // end of the file record being read (for damage ranges)
  // Scratch buffers of a stream source (a mapped file views its pages instead): the record
  // header, its data, a compressed chunk and its decompressed bytes, a resynchronising scan's
  // window. Separate, because the header fields are views into the header's bytes while the
  // data is read.
  std::vector<std::uint8_t> header_buf_, data_buf_, compressed_, chunk_, scan_buf_;
  Fields fields_, inner_fields_, scan_fields_;
};

}  // namespace gyrocomp::ros1_internal
