// ROS bags as IMU tables: ROS 1 bag v2.0, ROS 2 MCAP and ROS 2 sqlite3 (.db3), recognised by
// their first bytes (a ROS 2 bag folder by its metadata.yaml), read as a stream: only the
// selected sensor_msgs/Imu topic's rows (and a sensor_msgs/Temperature topic's) are kept, every
// other message is skipped, so memory follows the IMU rows, not the bag.
//
// The table of a bag has the columns
//     time_s                      header.stamp (default) or the bag's receive time (--time receive), s
//     x_rad_s, y_rad_s, z_rad_s   angular_velocity, rad/s (as gyro_log.h's flight-log tables)
//     x_m_s2, y_m_s2, z_m_s2      linear_acceleration, m/s^2 (design-imu-trust.md: accel axes)
//     temp_c                      a sensor_msgs/Temperature topic's temperature, joined by the
//                                 nearest stamp (only when the bag has one such topic, or one in
//                                 the IMU topic's namespace)
// Rows are sorted by the chosen time (stable: a bag's chunks may overlap in time; MCAP spec,
// "Chunk": message_start_time/end_time may overlap). Repeated times stay, for the sampling check
// to name.
//
// Damage (BagReadOptions::strict false, the default): the ROS 1 and MCAP readers skip a damaged
// record or chunk to the next valid record (log_damage.h), keep every intact message and list
// what they skipped in BagImuTable::damage / BagListing::damage, with one warning line per file.
// The rosbag2 sqlite3 reader does the same as far as SQLite tells: rows SQLite cannot read (a
// damaged page) and wanted rows whose data do not decode are skipped, listed as message id
// ranges. A kept row is always the bytes of one intact message record; none is invented or altered.
//
// Format readers: src/io/mcap.cc (MCAP), src/io/ros2_sqlite.cc, src/io/rosbag1.cc; message
// decoding: gyrocomp/io/cdr.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/io/log_damage.h"

namespace gyrocomp {

// Container format of a bag; kNone: not a bag.
enum class BagFormat { kNone, kMcap, kRos2Sqlite, kRos1 };
std::string_view BagFormatName(BagFormat format);  // "mcap", "ros2-sqlite3", "rosbag1", "none"

// By the first bytes of a regular file (MCAP magic 89 4D 43 41 50 30 0D 0A; "SQLite format 3\0";
// "#ROSBAG V2.0\n"), or a directory holding metadata.yaml (a ROS 2 bag folder: the format of its
// first storage file). kNone otherwise (pipes are never peeked at).
BagFormat DetectBagFormat(const std::string& path);

// Which time stamps the table's time_s column is.
enum class BagTimeSource {
  kHeader,   // the message's header.stamp (the sensor driver's time; the default)
  kReceive,  // MCAP Message.log_time, rosbag2 messages.timestamp, ROS 1 message data 'time'
};

// How ReadBagImu, ListBag and the storage readers read a bag.
struct BagReadOptions {
  // The sensor_msgs/Imu topic. nullopt: the only one; with several, reading fails and lists them.
  std::optional<std::string> topic;
  BagTimeSource time = BagTimeSource::kHeader;  // which stamp becomes time_s
  // Largest decompressed chunk (MCAP Chunk.uncompressed_size, ROS 1 chunk 'size') and largest
  // single record read into memory, bytes. A chunk declaring more is refused before anything is
  // allocated (a compression bomb); decompression never writes past the declared size. rosbag2
  // writes 768 KiB MCAP chunks by default, ROS 1 768 KiB; 1 GiB leaves room for anything sane.
  std::uint64_t max_chunk_bytes = std::uint64_t{1} << 30;
  // MCAP "Data End" data_section_crc (CRC-32 of bytes 0 .. Data End; 0 = not written). false
  // (default): checked whenever the reader has read every byte of the data section anyway, which
  // it does for chunked files (rosbag2's) since chunks are read whole and the small records
  // between them (indexes, metadata; up to 1 MiB each) are read for the CRC; a larger record the
  // reader does not need (an attachment, an unwanted unchunked message over 1 MiB) is skipped
  // unread and the CRC then not checked. true: such records are read too, so the CRC is always
  // checked (a 10 GB bag of camera frames outside chunks is then read whole).
  bool verify_mcap_data_crc = false;
  // rosbag2 per-file compression (`x.mcap.zstd`, `x.db3.zstd`; metadata.yaml compression_mode
  // FILE, compression_format zstd): the file is stream-decompressed into a temporary file in
  // $TMPDIR (sqlite3 needs a file) and read there. Largest decompressed size, bytes: a file
  // decompressing to more is refused (a compression bomb filling the disk). 64 GiB.
  std::uint64_t max_decompressed_file_bytes = std::uint64_t{64} << 30;
  // false (the default): a damaged record of a ROS 1 bag or an MCAP file (a record header that
  // does not parse, a chunk that fails to decompress or whose CRC does not match, a record
  // running past its chunk or the file) is skipped to the next valid record; every intact
  // message is kept and the skipped byte ranges, with the messages lost per topic where the
  // file's own index tells, go to BagVisitor::OnDamage. true: the first damaged record is an
  // error naming its byte offset. rosbag2 .db3 (src/io/ros2_sqlite_recovery.cc): a row SQLite
  // reports damaged (SQLITE_CORRUPT) or a wanted row whose CDR does not decode is skipped, the
  // table sought again at the next readable message id, the ids skipped reported (LogDamage::
  // message_ids); true: the first such row is an error. A .db3 whose schema or topics table
  // cannot be read is refused either way.
  bool strict = false;
  // Checks the byte limits are > 0; false with the reason in `error`.
  bool IsValid(std::string* error) const;
};

// What a storage reader reports to its consumer. Channel ids are the format's own (MCAP channel
// id, ROS 1 connection id, rosbag2 topics.id).
struct BagChannel {
  std::uint64_t id = 0;  // MCAP channel id, ROS 1 connection id or rosbag2 topics.id
  std::string topic;  // topic name, e.g. "/imu0"
  std::string type;      // "sensor_msgs/msg/Imu" (ROS 2) or "sensor_msgs/Imu" (ROS 1)
  std::string encoding;  // "cdr" or "ros1"
  // How many messages the bag's index says this channel has (ROS 1 chunk info records), when it
  // says: a hint for reserving memory, capped by the file's size; never used as a count.
  std::optional<std::uint64_t> expected_messages;
};

// Where a record is, for errors (built into text only when one is reported): "byte N", "byte N:
// chunk byte M" (M from the start of the decompressed chunk at byte N), or "message id N" (sqlite).
struct BagPosition {
  std::uint64_t offset = 0;  // byte offset of the record in the file
  std::optional<std::uint64_t> chunk_byte;  // offset inside the decompressed chunk, when the record is in one
  std::optional<std::int64_t> message_id;  // rosbag2 messages.id (sqlite), instead of a byte offset
  // "byte N", "byte N: chunk byte M" or "message id N".
  std::string ToString() const;
};

// One message as a storage reader hands it to its visitor; the bytes are valid only during OnMessage.
struct BagMessage {
  std::uint64_t channel = 0;  // BagChannel::id of its channel
  std::uint64_t receive_time_ns = 0;  // receive (log) time, ns
  const std::uint8_t* data = nullptr;  // serialised message (CDR or ROS 1), not owned
  std::size_t size = 0;  // bytes at data
  BagPosition where;  // where it is in the file, for errors
};

// The consumer of a stream of channels and messages. Wants() is asked once per message before
// its bytes are read (a reader may then skip them without reading); a returned Error stops the
// stream and is returned by the reader.
class BagVisitor {
 public:
  virtual ~BagVisitor() = default;
  // A new channel (before any message of it); an Error stops the stream.
  virtual std::optional<Error> OnChannel(const BagChannel& channel) = 0;
  // Whether OnMessage should get this channel's messages.
  virtual bool Wants(std::uint64_t channel) const = 0;
  // A wanted message; an Error stops the stream.
  virtual std::optional<Error> OnMessage(const BagMessage& message) = 0;
  // Called for every message, wanted or not (counts for `inspect`).
  virtual void Count(std::uint64_t /*channel*/, std::uint64_t /*receive_time_ns*/) {}
  // A damaged byte range skipped (BagReadOptions::strict false): each range once, in file order,
  // when the reader has reached the file's end (its rows_lost then complete).
  virtual void OnDamage(const LogDamage& /*damage*/) {}
};

// The storage readers (source names the input in messages). Errors: kInvalidInput with
// "<source>: byte <offset>: <what>" (sqlite: "message id N"), kIo when a file cannot be read.
std::optional<Error> StreamMcap(std::istream& in, const std::string& source, const BagReadOptions& options,
                                BagVisitor* visitor);
// ROS 1 bag (format 2.0) from a stream.
std::optional<Error> StreamRos1Bag(std::istream& in, const std::string& source, const BagReadOptions& options,
                                   BagVisitor* visitor);
// The same from a file, memory-mapped (no copy of uncompressed chunks; the pages read are given
// back as the reader moves on); a file that cannot be mapped is read as a stream.
std::optional<Error> StreamRos1BagFile(const std::string& path, const BagReadOptions& options, BagVisitor* visitor);
// rosbag2 sqlite3 storage file (.db3).
std::optional<Error> StreamRos2Sqlite(const std::string& path, const BagReadOptions& options, BagVisitor* visitor);
// Any of them by DetectBagFormat; a ROS 2 folder streams its storage files in metadata.yaml's
// order (relative_file_paths), else in name order.
std::optional<Error> StreamBag(const std::string& path, const BagReadOptions& options, BagVisitor* visitor);

// One topic of a bag as `inspect` lists it.
struct BagTopicInfo {
  std::string topic;  // topic name
  std::string type;  // message type, e.g. "sensor_msgs/msg/Imu"
  std::string encoding;  // "cdr" or "ros1"
  std::size_t messages = 0;  // messages on the topic
  std::uint64_t first_receive_ns = 0;  // receive time of the first message, ns
  std::uint64_t last_receive_ns = 0;  // receive time of the last message, ns
  // (messages - 1) / (last - first) by receive time, Hz; nullopt with fewer than 2 messages.
  std::optional<double> RateHz() const;
};

// What ListBag found.
struct BagListing {
  std::string source;  // the path given
  BagFormat format = BagFormat::kNone;  // container format
  std::vector<BagTopicInfo> topics;  // in order of first appearance; one entry per topic name
  std::vector<LogDamage> damage;  // byte ranges skipped (BagReadOptions::strict false), in file order
  std::vector<std::string> warnings;  // the damage as one line (DamageWarning), when there is any
};

// Every topic with its message count (all messages are visited; none is decoded).
Result<BagListing> ListBag(const std::string& path, const BagReadOptions& options = {});

// The selected IMU topic as a table (columns above), with where it came from.
struct BagImuTable {
  Table table;  // time_s, gyro (rad/s), accel (m/s^2) and, when joined, temperature (deg C) columns
  BagFormat format = BagFormat::kNone;  // container format read
  std::string topic;                   // the IMU topic read
  std::string temperature_topic;       // "" when none was joined
  std::string origin;                  // "MCAP /imu0 (sensor_msgs/msg/Imu), header stamps"
  std::vector<std::string> warnings;  // one line each, e.g. several temperature topics and none joined
  std::vector<LogDamage> damage;  // byte ranges skipped (BagReadOptions::strict false), in file order
};

// Column names of a bag table.
inline constexpr const char* kBagTimeCol = "time_s";
// x, y, z angular velocity, rad/s (sensor frame).
inline constexpr const char* kBagGyroCols[3] = {"x_rad_s", "y_rad_s", "z_rad_s"};
// x, y, z linear acceleration, m/s^2 (sensor frame).
inline constexpr const char* kBagAccelCols[3] = {"x_m_s2", "y_m_s2", "z_m_s2"};
inline constexpr const char* kBagTempCol = "temp_c";  // deg C, present when a temperature topic was joined

// Reads the IMU topic (BagReadOptions::topic) of a bag of any supported format as a table.
Result<BagImuTable> ReadBagImu(const std::string& path, const BagReadOptions& options);

}  // namespace gyrocomp
