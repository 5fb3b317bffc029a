// The MCAP reader's class, shared by mcap.cc (reading) and mcap_recovery.cc (recovery); not
// installed. The format, and how this reader streams it:
//
// MCAP reader (include/gyrocomp/io/bag.h: StreamMcap), written from the MCAP specification, version 0
// ("MCAP Format Specification", mcap.dev/spec, foxglove/mcap docs/specification/README.md).
// Quotes below are its section names.
//
// "File Structure": <Magic><Header><Data section>[<Summary section>][<Summary Offset section>]
//   <Footer><Magic>. "Magic": 0x89 M C A P 0x30 \r \n (8 bytes, the '0' is the major version).
// "Records": opcode uint8, length uint64 (little-endian, like every integer), content. Readers
//   skip records with unknown opcodes ("Opcodes 0x80-0xFF are reserved ... readers should ignore
//   unknown records"). "Serialization": String = uint32 length + UTF-8 bytes; Bytes in a Schema
//   = uint32 length + bytes; Timestamp = uint64 nanoseconds.
// This reader streams the data section once: Schema and Channel records are kept (a Channel
// names its topic and message encoding, its Schema the type), Message records of channels the
// consumer does not want are skipped without being read, Chunks are decompressed one at a time
// and only their wanted messages are passed on. The summary section is optional and not needed:
// after "Data End" the records are skipped up to the Footer. Chunk CRCs are checked.
// "Data End": "data_section_crc: CRC-32 of all bytes in the data section. A value of zero
// indicates the CRC is missing." The data section runs from the leading magic (byte 0) to the
// Data End record (excluded), as foxglove/mcap's python StreamReader computes it. Every byte
// this reader reads in that range, in file order, goes into a running CRC-32; the CRC is checked
// when no byte was left unread: chunks (rosbag2 chunks every message) and Schema / Channel
// records are read whole anyway, and records otherwise skipped (message indexes, metadata,
// unknown records, messages of unwanted channels outside chunks) are read for the CRC when they
// are at most kCrcReadBytes; a larger one is skipped unread and the CRC left unchecked, unless
// BagReadOptions::verify_mcap_data_crc asks for every byte to be read.
//
#pragma once

#include <array>
#include <cstdint>
#include <istream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bag_bytes.h"
#include "gyrocomp/io/bag.h"

namespace gyrocomp::mcap_internal {

using bag_internal::Cursor;

constexpr std::array<std::uint8_t, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr std::size_t kRecordHeaderBytes = 9;  // "Records": uint8 opcode + uint64 length

// "Opcodes" table.
enum Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kDataEnd = 0x0F,
};
// "Footer": uint64 summary_start, uint64 summary_offset_start, uint32 summary_crc.
constexpr std::uint64_t kFooterBytes = 20;
// "Message": uint16 channel_id, uint32 sequence, Timestamp log_time, Timestamp publish_time,
// then the message data up to the record's end.
constexpr std::size_t kMessagePrefixBytes = 2 + 4 + 8 + 8;
// "Chunk": Timestamp message_start_time, Timestamp message_end_time, uint64 uncompressed_size,
// uint32 uncompressed_crc, String compression, uint64-prefixed Bytes records.
constexpr std::size_t kChunkFixedBytes = 8 + 8 + 8 + 4;
// Records the reader would skip are still read, for the data section CRC, up to this size.
constexpr std::uint64_t kCrcReadBytes = std::uint64_t{1} << 20;

inline std::string Hex(unsigned v) {
  static const char* d = "0123456789abcdef";
  return std::string("0x") + d[(v >> 4) & 15] + d[v & 15];
}

// "Opcodes" table: the record kinds of version 0 (others are reserved or user-defined).
inline bool KnownOpcode(std::uint8_t op) { return op >= kHeader && op <= kDataEnd; }

// A damaged record found by a handler: the strict error and, in recovery, where reading goes on.
struct Damage {
  std::uint64_t at = 0;  // the record the strict error names
  std::string what;      // the strict error's text after "byte N: " (or with its own position)
  std::uint64_t begin = 0;  // first byte skipped
  // Reading goes on at `resume` when a valid record starts there (or the footer magic ends the
  // file), else at the next valid record after `scan_from`.
  std::optional<std::uint64_t> resume;
  std::uint64_t scan_from = 0;
  bool positioned = false;  // `what` already names its position ("byte N: chunk byte M: ...")
};

class McapReader {
 public:
  McapReader(std::istream& in, const std::string& source, const BagReadOptions& options, BagVisitor* visitor)
      : in_(in), source_(source), options_(options), visitor_(visitor) {}
  std::optional<Error> Run();

 private:
  Error Bad(std::uint64_t offset, const std::string& what) const {
    return InvalidInput(source_ + ": byte " + std::to_string(offset) + ": " + what);
  }
  std::optional<Error> EndWithoutFooter(std::uint64_t pos);
  std::optional<Error> TopRecord(std::uint64_t pos, bool first, std::uint64_t* next, std::optional<Damage>* damage);
  // The record at `at` (opcode and length read, length within the file).
  std::optional<Error> Record(std::uint8_t op, std::uint64_t at, std::uint64_t len, std::optional<Damage>* damage);
  std::optional<Error> Body(std::uint64_t at, std::uint64_t len, const char* what, std::optional<Damage>* damage);
  // Schema, Channel, Message contents in memory; a record that cannot be read sets *why.
  void Schema(const std::uint8_t* p, std::size_t n, std::string* why);
  std::optional<Error> Channel(const std::uint8_t* p, std::size_t n, std::string* why);
  std::optional<Error> Message(const std::uint8_t* p, std::size_t n, const BagPosition& where, std::string* why);
  std::optional<Error> DataMessage(std::uint64_t at, std::uint64_t len, std::optional<Damage>* damage);
  std::optional<Error> Chunk(std::uint64_t at, std::uint64_t len, std::optional<Damage>* damage);
  std::optional<Error> ChunkRecords(std::uint64_t at, std::optional<Damage>* damage);
  std::optional<Error> Footer(std::uint64_t at, std::uint64_t len, std::optional<Damage>* damage);
  std::optional<Error> DataEnd(std::uint64_t at, std::uint64_t len, std::optional<Damage>* damage);
  std::optional<Error> MessageIndex(std::uint64_t at, std::uint64_t len);
  // Feeds bytes [at, at + n) of the file, just read, into the data section CRC.
  void Crc(std::uint64_t at, const std::uint8_t* p, std::size_t n);
  // Reads bytes [at, at + n) that the reader itself does not need, for the CRC only.
  std::optional<Error> CrcSkipped(std::uint64_t at, std::uint64_t n);
  // Recovery.
  bool RecordStartsAt(std::uint64_t pos);
  std::uint64_t NextRecord(std::uint64_t from);
  void AddDamage(const Damage& d, std::uint64_t end);
  void CloseLoss();
  std::string TopicOf(std::uint16_t channel) const;
  const BagChannel* SummaryChannel(std::uint16_t channel);
  void ReadSummary();

  std::istream& in_;
  const std::string& source_;
  const BagReadOptions& options_;
  BagVisitor* visitor_;
  std::uint64_t size_ = 0;
  bool data_end_ = false;
  bool done_ = false;
  std::uint32_t crc_ = 0;       // CRC-32 of bytes [0, crc_end_)
  std::uint64_t crc_end_ = 0;
  bool crc_gap_ = false;        // a byte of the data section was not read
  std::map<std::uint16_t, std::string> schema_names_;   // "Schema": id -> name
  std::map<std::uint16_t, std::string> channels_;       // channel ids announced -> topic
  std::vector<std::uint8_t> record_, compressed_, chunk_;
  // Recovery. "Message Index": a sequence of them follows each chunk in the data section, one
  // per channel with messages in it: after a damaged chunk they tell its messages per channel. `loss_` is the damage they count for (none after an intact chunk), `delivered_`
  // the messages read since it began (a resynchronising scan may land inside an uncompressed
  // chunk), `last_chunk_` the message count per channel of the last intact chunk (its own
  // Message Index records, when the damage hit one of them, are not a loss).
  std::vector<LogDamage> damage_;
  std::optional<std::size_t> loss_;
  bool loss_told_ = false;
  // Messages lost by (index in damage_, channel): named by topic at the file's end, when a
  // channel first seen after its lost chunk is known.
  std::map<std::pair<std::size_t, std::uint16_t>, std::uint64_t> lost_;
  std::map<std::uint16_t, std::uint64_t> delivered_, chunk_delivered_, last_chunk_;
  std::map<std::uint16_t, std::size_t> unknown_channel_damage_;  // channel -> index in damage_
  // The summary section's Channel records (with their Schema names), read once in recovery when a
  // message's Channel record was lost with a damaged chunk.
  std::optional<std::map<std::uint16_t, BagChannel>> summary_channels_;
  std::uint64_t record_at_ = 0, record_end_ = 0;  // the record being read
  bool unverified_rows_ = false;  // a message was read outside a chunk, or from a chunk without CRC
};

}  // namespace gyrocomp::mcap_internal
