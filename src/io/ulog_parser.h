// The ULog parser's internals, shared by ulog.cc (parsing) and ulog_recovery.cc (how a damaged
// record is told from an intact one). Not installed: the public API is include/gyrocomp/io/ulog.h.
#pragma once

#include "gyrocomp/io/ulog.h"

#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gyrocomp::ulog_detail {

// spec "File Header": 'U' 'L' 'o' 'g' 0x01 0x12 0x35, then version and timestamp.
inline constexpr std::uint8_t kMagic[7] = {0x55, 0x4C, 0x6F, 0x67, 0x01, 0x12, 0x35};
inline constexpr std::size_t kHeaderBytes = 16;
inline constexpr std::size_t kMessageHeaderBytes = 3;  // uint16 msg_size, uint8 msg_type
// spec "Synchronization message" ('S'): uint8 sync_magic[8].
inline constexpr std::uint8_t kSyncMagic[8] = {0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12};
// The message types of the spec. In recovery, a record of another type is taken as the spec asks
// (skipped) only when the record after it is one of these.
inline bool KnownType(char t) {
  switch (t) {
    case 'A': case 'B': case 'C': case 'D': case 'F': case 'I': case 'L': case 'M': case 'O': case 'P':
    case 'Q': case 'R': case 'S': return true;
    default: return false;
  }
}
// Nested formats are flattened; a deeper nesting than this is taken for a format loop.
inline constexpr int kMaxNestingDepth = 16;
// Flattening steps per subscription (fields and nested elements visited); a format whose arrays
// of empty nested types would take longer than this is refused instead of hanging.
inline constexpr std::size_t kMaxFlattenSteps = 1u << 20;

inline std::uint16_t U16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
inline std::uint32_t U32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
inline std::uint64_t U64(const std::uint8_t* p) {
  return static_cast<std::uint64_t>(U32(p)) | (static_cast<std::uint64_t>(U32(p + 4)) << 32);
}
inline float F32(const std::uint8_t* p) {
  const std::uint32_t bits = U32(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

// Size of a basic ULog type (spec "Definitions Section", format message), 0 if not basic.
inline std::size_t BasicSize(std::string_view t) {
  if (t == "int8_t" || t == "uint8_t" || t == "bool" || t == "char") return 1;
  if (t == "int16_t" || t == "uint16_t") return 2;
  if (t == "int32_t" || t == "uint32_t" || t == "float") return 4;
  if (t == "int64_t" || t == "uint64_t" || t == "double") return 8;
  return 0;
}

struct FieldDef {
  std::string type;
  std::size_t array_size = 0;  // 0: not an array
  std::string name;
};

// A basic field of a flattened message: "gyro_rad[1]", "float", offset in the data payload.
struct FlatField {
  std::string name;
  std::string type;
  std::size_t offset = 0;
};

// Which gyro fields a subscription decodes (offsets into the 'D' payload after msg_id).
struct GyroFields {
  std::size_t timestamp = 0, x = 0, y = 0, z = 0, temperature = 0, device_id = 0;
  bool has_temperature = false, has_device_id = false;
};

struct Subscription {
  std::size_t topic = 0;           // index into ULogContents::topics
  std::size_t min_size = 0;        // data bytes without trailing _padding fields
  std::size_t max_size = 0;        // with them
  int series = -1;                 // index into gyros (kind 1) or combined (kind 2)
  int kind = 0;                    // 0 other, 1 sensor_gyro, 2 sensor_combined, 3 accel, 4 baro, 5 state
  GyroFields g;
  bool device_id_change_reported = false;
  // ULogReadOptions::average_window_us: the open window's sums.
  std::uint64_t window = 0;
  std::size_t count = 0;
  double sum_t = 0, sum_x = 0, sum_y = 0, sum_z = 0, sum_temp = 0;
};

// One decoded sensor row.
struct RowValues {
  std::uint64_t t = 0;
  double x = 0, y = 0, z = 0, temp = 0;
};


// What a record introduces for the records after it (recovery: a 'D' may follow its 'A').
struct Introduced {
  std::optional<std::uint16_t> msg_id;  // an 'A': the msg_id it subscribes
  std::string format;                   // an 'F': the format name it defines
};

class Parser {
 public:
  Parser(const std::uint8_t* data, std::size_t size, std::string source, ULogReadOptions options,
         std::function<void(std::size_t)> release)
      : d_(data), n_(size), options_(options), release_(std::move(release)) {
    out_.source = std::move(source);
  }
  Result<ULogContents> Run();

 private:
  Error Bad(std::size_t offset, const std::string& what) const {
    return InvalidInput(out_.source + ": byte " + std::to_string(offset) + ": " + what);
  }
  void Warn(std::size_t offset, const std::string& what) {
    out_.warnings.push_back(out_.source + ": byte " + std::to_string(offset) + ": " + what);
  }
  std::optional<Error> ParseAll();
  // Recovery (ULogReadOptions::strict false), in ulog_recovery.cc. What the record at `at`
  // introduces for the one after it: an 'F' its format name, an 'A' its msg_id.
  Introduced IntroducedBy(std::size_t at) const;
  // A record at `at` that passes every check this reader can make before parsing it (known type,
  // the type's own sizes and markers, printable keys, an 'A' of a known format, a 'D' for a
  // subscribed msg_id with a size its format allows); `prev` is what the record before it
  // introduced (a 'D' may follow its 'A', an 'A' its 'F'). With `allow_cut`, a record cut by
  // the end of the segment passes on the bytes it has (the last record of a truncated log).
  bool PlausibleAt(std::size_t at, std::size_t end, const Introduced& prev, bool allow_cut) const;
  // The first offset in [from, end) where a plausible record starts and is followed by another
  // one (or ends the segment exactly); nullopt when there is none.
  std::optional<std::size_t> Resync(std::size_t from, std::size_t end) const;
  // Whether the record [at, after) may be decoded: `after` is the segment's end, a plausible
  // record (possibly cut by the end), or one damaged header whose intact part still leads to a
  // plausible record (one damaged header right after an intact record does not take that record
  // with it).
  bool FollowedByValid(std::size_t at, std::size_t after, std::size_t end) const;
  // Whether `len` is the payload size of a 'D' for some subscription (msg_id + data).
  bool DataRecordSize(std::size_t len) const;
  // Records [begin, resume) as skipped, with the rows lost in it where the topic can be told.
  void NoteDamage(std::size_t begin, std::size_t resume, const std::string& what);
  std::optional<Error> ParseMessage(char type, std::size_t at, const std::uint8_t* p, std::size_t len);
  std::optional<Error> ParseFlagBits(std::size_t at, const std::uint8_t* p, std::size_t len);
  bool unknown_incompat_ = false;  // the 'B' message set incompatible flags this reader does not know
  std::optional<Error> ParseFormat(std::size_t at, const std::uint8_t* p, std::size_t len);
  std::optional<Error> ParseKeyValue(char type, std::size_t at, const std::uint8_t* p, std::size_t len);
  std::optional<Error> ParseSubscription(std::size_t at, const std::uint8_t* p, std::size_t len);
  std::optional<Error> ParseData(std::size_t at, const std::uint8_t* p, std::size_t len);
  std::optional<Error> Flatten(std::size_t at, const std::string& type, const std::string& prefix, int depth,
                               std::vector<FlatField>* fields, std::size_t* size, std::size_t* padding_tail);
  void DecodeRow(Subscription& s, const std::uint8_t* row);
  // A vehicle-state row (kind 5): kept when it is the first or its value changes.
  void DecodeState(const Subscription& s, const std::uint8_t* row);
  // The vehicle-state field a subscription of `topic` is read for (kind 5), or nullptr.
  static const char* StateField(const std::string& topic);
  void PushRow(const Subscription& s, const RowValues& v);
  void FlushWindow(Subscription& s);
  void NoteDeviceId(Subscription& s, const std::uint8_t* row, const std::string& what, std::size_t rows,
                    std::optional<std::uint32_t>* device_id);

  const std::uint8_t* d_;
  std::size_t n_;
  ULogReadOptions options_;
  std::function<void(std::size_t)> release_;  // gives the bytes before an offset back (mapped files)
  std::size_t released_ = 0;
  ULogContents out_;
  std::map<std::string, std::vector<FieldDef>> formats_;
  std::map<int, Subscription> subs_;  // active subscriptions by msg_id
  bool first_message_ = true;
  std::size_t flatten_steps_ = 0;
};

}  // namespace gyrocomp::ulog_detail
