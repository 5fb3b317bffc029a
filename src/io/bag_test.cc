// ROS bag readers: CDR / ROS 1 decoding against bytes laid out by hand from the specifications,
// MCAP files built here record by record (none / zstd / lz4 chunks, big-endian CDR, a
// temperature topic), hostile MCAPs (truncated chunk, wrong CRC, compression bombs, a message
// shorter than its CDR, a topic of another type, several IMU topics, no footer), and rosbag2's
// own test bags (tests/bags/rosbag2, Apache-2.0) against the message counts and times their
// metadata.yaml (written by rosbag2) gives.
#include "gyrocomp/io/bag.h"

#include <bzlib.h>
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/io/cdr.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

std::string BagsDir() { return std::string(GYROCOMP_FIELDLOGS_DIR) + "/../bags"; }

void Le(std::string* s, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) s->push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void Be(std::string* s, std::uint64_t v, int n) {
  for (int i = n - 1; i >= 0; --i) s->push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
std::uint64_t Bits(double d) {
  std::uint64_t v;
  std::memcpy(&v, &d, 8);
  return v;
}

// ---- CDR laid out by hand (XTypes 7.4.3.5 header; CORBA 9.3.1.1 alignment from byte 4) ----

// sensor_msgs/msg/Imu with frame_id "ab": body offsets (after the 4-byte header): sec 0..3,
// nanosec 4..7, string length 8..11 (= 3: 'a' 'b' NUL), chars 12..14, pad 15, then 37 float64
// from body offset 16.
std::string HandImu(bool big_endian, const double gyro[3], const double accel[3]) {
  std::string s = {0, static_cast<char>(big_endian ? 0 : 1), 0, 0};
  auto put = [&](std::uint64_t v, int n) { big_endian ? Be(&s, v, n) : Le(&s, v, n); };
  put(1700000000, 4);
  put(123456789, 4);
  put(3, 4);
  s += std::string("ab\0", 3);
  s.push_back(0);  // padding to the next multiple of 8 from the body start
  EXPECT_EQ(s.size(), 4u + 16u);
  const double quat[4] = {0, 0, 0, 1};
  for (double v : quat) put(Bits(v), 8);
  for (int i = 0; i < 9; ++i) put(Bits(-1.0), 8);
  for (int i = 0; i < 3; ++i) put(Bits(gyro[i]), 8);
  for (int i = 0; i < 9; ++i) put(Bits(-1.0), 8);
  for (int i = 0; i < 3; ++i) put(Bits(accel[i]), 8);
  for (int i = 0; i < 9; ++i) put(Bits(-1.0), 8);
  return s;
}

TEST(CdrTest, ImuBothByteOrdersFromHandLaidBytes) {
  const double g[3] = {0.25, -1e-3, 3.5}, a[3] = {0.125, -9.81, 1e-7};
  for (bool big : {false, true}) {
    const std::string bytes = HandImu(big, g, a);
    ImuMessage m;
    auto e = DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), &m);
    ASSERT_FALSE(e) << e->what;
    EXPECT_EQ(m.stamp_sec, 1700000000);
    EXPECT_EQ(m.stamp_nanosec, 123456789u);
    EXPECT_EQ(m.StampNs(), 1700000000123456789);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(m.angular_velocity_rad_s[k], g[k]);
      EXPECT_EQ(m.linear_acceleration_m_s2[k], a[k]);
    }
  }
}

TEST(CdrTest, EncoderMatchesHandLayoutAndAlignsEveryFrameIdLength) {
  const double g[3] = {0.25, -1e-3, 3.5}, a[3] = {0.125, -9.81, 1e-7};
  ImuMessage m;
  m.stamp_sec = 1700000000;
  m.stamp_nanosec = 123456789;
  std::memcpy(m.angular_velocity_rad_s, g, sizeof g);
  std::memcpy(m.linear_acceleration_m_s2, a, sizeof a);
  // The hand layout has covariances of -1; compare the parts the encoder writes the same way.
  const std::string enc = EncodeCdrImu(m, "ab", false);
  const std::string hand = HandImu(false, g, a);
  ASSERT_EQ(enc.size(), hand.size());
  EXPECT_EQ(enc.substr(0, 20), hand.substr(0, 20));
  for (int len = 0; len < 12; ++len) {
    for (bool big : {false, true}) {
      const std::string bytes = EncodeCdrImu(m, std::string(len, 'f'), big);
      // Body: 12 bytes of stamp and length, len + 1 string bytes, padding to 8, 37 doubles.
      const std::size_t body = 12 + len + 1;
      EXPECT_EQ(bytes.size(), 4 + (body + 7) / 8 * 8 + 37 * 8) << len;
      ImuMessage back;
      ASSERT_FALSE(DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), &back));
      EXPECT_EQ(back.angular_velocity_rad_s[2], 3.5);
      EXPECT_EQ(back.linear_acceleration_m_s2[1], -9.81);
    }
  }
}

TEST(CdrTest, ShortMessagesAndBadHeadersNameTheByte) {
  const double g[3] = {1, 2, 3}, a[3] = {4, 5, 6};
  const std::string full = HandImu(false, g, a);
  ImuMessage m;
  // Cut inside linear_acceleration: body offset 16 + 8 * (4 + 9 + 3 + 9) = 216, +4 header.
  auto e = DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(full.data()), 4 + 216 + 5, &m);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->offset, 4u + 216u);
  EXPECT_NE(e->what.find("linear_acceleration"), std::string::npos) << e->what;
  std::string bad = full;
  bad[1] = 0x07;  // XCDR2 little-endian: not read
  e = DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(bad.data()), bad.size(), &m);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->offset, 0u);
  bad = full;
  bad[12] = 100;  // frame_id length 100 runs past the message? no: 100 < size; make it huge
  bad[15] = 0x7f;
  e = DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(bad.data()), bad.size(), &m);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->offset, 12u);
  EXPECT_NE(e->what.find("frame_id"), std::string::npos) << e->what;
  e = DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(full.data()), 3, &m);
  ASSERT_TRUE(e);
}

// ROS 1 (wiki msg "Serialization"): seq, secs, nsecs, frame_id (length, no NUL), packed float64s.
TEST(Ros1SerializationTest, ImuAndTemperatureFromHandLaidBytes) {
  std::string s;
  Le(&s, 7, 4);
  Le(&s, 1600000000, 4);
  Le(&s, 5, 4);
  Le(&s, 3, 4);
  s += "imu";  // no padding in ROS 1
  const double values[37] = {0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.5, -0.5, 2.0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                             9.5, -1.5, 0.25, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (double v : values) Le(&s, Bits(v), 8);
  ImuMessage m;
  auto e = DecodeRos1Imu(reinterpret_cast<const std::uint8_t*>(s.data()), s.size(), &m);
  ASSERT_FALSE(e) << e->what;
  EXPECT_EQ(m.StampNs(), 1600000000000000005);
  EXPECT_EQ(m.angular_velocity_rad_s[0], 0.5);
  EXPECT_EQ(m.angular_velocity_rad_s[2], 2.0);
  EXPECT_EQ(m.linear_acceleration_m_s2[0], 9.5);
  EXPECT_EQ(m.linear_acceleration_m_s2[2], 0.25);
  EXPECT_EQ(EncodeRos1Imu(m, "imu").size(), s.size());
  e = DecodeRos1Imu(reinterpret_cast<const std::uint8_t*>(s.data()), s.size() - 1, &m);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->offset, s.size() - 8);
}

// ---- MCAP built record by record (mcap.dev/spec) ----

std::string Str(const std::string& v) {
  std::string s;
  Le(&s, v.size(), 4);
  return s + v;
}
std::string Rec(std::uint8_t op, const std::string& content) {
  std::string s(1, static_cast<char>(op));
  Le(&s, content.size(), 8);
  return s + content;
}
std::string SchemaRec(int id, const std::string& name) {
  std::string c;
  Le(&c, id, 2);
  return Rec(0x03, c + Str(name) + Str("ros2msg") + Str(""));
}
std::string ChannelRec(int id, int schema, const std::string& topic, const std::string& encoding = "cdr") {
  std::string c;
  Le(&c, id, 2);
  Le(&c, schema, 2);
  c += Str(topic) + Str(encoding);
  Le(&c, 0, 4);  // empty metadata map
  return Rec(0x04, c);
}
std::string MessageRec(int channel, std::uint64_t log_time, const std::string& data) {
  std::string c;
  Le(&c, channel, 2);
  Le(&c, 0, 4);
  Le(&c, log_time, 8);
  Le(&c, log_time, 8);
  return Rec(0x05, c + data);
}

struct ChunkSpec {
  std::string compression;             // "", "zstd", "lz4"
  std::optional<std::uint64_t> declared_size;  // overrides the true uncompressed size
  std::optional<std::uint32_t> crc;            // overrides the true CRC (0: none)
};

std::string ChunkRec(const std::string& records, const ChunkSpec& spec) {
  std::string data = records;
  if (spec.compression == "zstd") {
    data.resize(ZSTD_compressBound(records.size()));
    data.resize(ZSTD_compress(data.data(), data.size(), records.data(), records.size(), 3));
  } else if (spec.compression == "lz4") {
    data.resize(LZ4F_compressFrameBound(records.size(), nullptr));
    data.resize(LZ4F_compressFrame(data.data(), data.size(), records.data(), records.size(), nullptr));
  }
  std::string c;
  Le(&c, 0, 8);
  Le(&c, 0, 8);
  Le(&c, spec.declared_size.value_or(records.size()), 8);
  const auto crc = static_cast<std::uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(records.data()), records.size()));
  Le(&c, spec.crc.value_or(crc), 4);
  c += Str(spec.compression);
  Le(&c, data.size(), 8);
  return Rec(0x06, c + data);
}

// data_crc: the Data End's data_section_crc (0: missing; nullopt: the true CRC-32 of every byte
// before the Data End record, leading magic included).
std::string McapFile(const std::string& data_section, bool footer = true, std::optional<std::uint32_t> data_crc = 0u) {
  std::string s = "\x89MCAP0\r\n";
  s += Rec(0x01, Str("ros2") + Str("bag_test"));
  s += data_section;
  std::string crc;
  Le(&crc, data_crc.value_or(static_cast<std::uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(s.data()), s.size()))), 4);
  s += Rec(0x0F, crc);
  if (footer) {
    std::string f;
    Le(&f, 0, 8);
    Le(&f, 0, 8);
    Le(&f, 0, 4);
    s += Rec(0x02, f) + "\x89MCAP0\r\n";
  }
  return s;
}

ImuMessage Sample(int i) {
  ImuMessage m;
  const std::int64_t ns = 1700000000000000000 + static_cast<std::int64_t>(i) * 5000000;
  m.stamp_sec = ns / 1000000000;
  m.stamp_nanosec = static_cast<std::uint32_t>(ns % 1000000000);
  for (int k = 0; k < 3; ++k) {
    m.angular_velocity_rad_s[k] = 1e-3 * (i % 7 - 3) + k;
    m.linear_acceleration_m_s2[k] = 9.81 * (k == 2) + 1e-2 * (i % 5 - 2);
  }
  return m;
}

// The records of an IMU topic /imu0 (n messages), a temperature topic at every 10th message,
// and an image-like topic, as they would sit in a chunk.
std::string ImuRecords(int n, bool big_endian = false, int first = 0) {
  std::string r;
  if (first == 0) {
    r += SchemaRec(1, "sensor_msgs/msg/Imu") + ChannelRec(1, 1, "/imu0");
    r += SchemaRec(2, "sensor_msgs/msg/Temperature") + ChannelRec(2, 2, "/imu0/temperature");
    r += SchemaRec(3, "sensor_msgs/msg/Image") + ChannelRec(3, 3, "/cam0/image_raw");
  }
  for (int i = first; i < first + n; ++i) {
    const ImuMessage m = Sample(i);
    const auto receive = static_cast<std::uint64_t>(m.StampNs() + 2000000);
    if (i % 10 == 0) {
      TemperatureMessage t{m.stamp_sec, m.stamp_nanosec, 20.0 + i};
      r += MessageRec(2, receive, EncodeCdrTemperature(t, "imu", big_endian));
      r += MessageRec(3, receive, std::string(4000, 'x'));
    }
    r += MessageRec(1, receive, EncodeCdrImu(m, "imu", big_endian));
  }
  return r;
}

class McapTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::MakeTempDir("gyrocomp_bag_test"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& bytes) {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  Result<BagImuTable> Read(const std::string& bytes, BagReadOptions o = {}) { return ReadBagImu(Write("x.mcap", bytes), o); }
  void ExpectRefused(const std::string& bytes, const std::string& what, BagReadOptions o = {}) {
    Result<BagImuTable> r = Read(bytes, o);
    ASSERT_FALSE(r.ok()) << what;
    EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
  }
  std::string dir_;
};

void ExpectSamples(const BagImuTable& t, int n) {
  ASSERT_EQ(t.table.num_rows(), static_cast<std::size_t>(n));
  ASSERT_EQ(t.table.names, (std::vector<std::string>{"time_s", "x_rad_s", "y_rad_s", "z_rad_s", "x_m_s2", "y_m_s2",
                                                      "z_m_s2", "temp_c"}));
  for (int i = 0; i < n; ++i) {
    const ImuMessage m = Sample(i);
    // Whole seconds plus the fraction (what the reader computes from the integer stamp).
    const std::int64_t ns = m.StampNs();
    EXPECT_EQ(t.table.columns[0][i], static_cast<double>(ns / 1000000000) + static_cast<double>(ns % 1000000000) / 1e9) << i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(t.table.columns[1 + k][i], m.angular_velocity_rad_s[k]) << i;
      EXPECT_EQ(t.table.columns[4 + k][i], m.linear_acceleration_m_s2[k]) << i;
    }
    // Nearest temperature (every 10th stamp; ties go to the earlier one).
    const int nearest = (i % 10 <= 5) ? i / 10 * 10 : i / 10 * 10 + 10;
    EXPECT_EQ(t.table.columns[7][i], 20.0 + std::min(nearest, (n - 1) / 10 * 10)) << i;
  }
}

TEST_F(McapTest, ChunksUncompressedZstdLz4AndBigEndianCdrReadTheSameRows) {
  for (const std::string compression : {"", "zstd", "lz4"}) {
    for (bool big : {false, true}) {
      SCOPED_TRACE(compression + (big ? " big-endian" : " little-endian"));
      // Two chunks, the second without the schema / channel records.
      const std::string data = ChunkRec(ImuRecords(150, big), {compression, {}, {}}) +
                               ChunkRec(ImuRecords(50, big, 150), {compression, {}, {}});
      Result<BagImuTable> r = Read(McapFile(data));
      ASSERT_TRUE(r.ok()) << r.error().message;
      EXPECT_EQ(r->topic, "/imu0");
      EXPECT_EQ(r->temperature_topic, "/imu0/temperature");
      ExpectSamples(*r, 200);
    }
  }
}

TEST_F(McapTest, UnchunkedMessagesAndReceiveTime) {
  Result<BagImuTable> r = Read(McapFile(ImuRecords(30)));
  ASSERT_TRUE(r.ok()) << r.error().message;
  ExpectSamples(*r, 30);
  BagReadOptions o;
  o.time = BagTimeSource::kReceive;
  r = Read(McapFile(ImuRecords(30)), o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->table.columns[0][3], 1700000000.0 + 0.017);
}

TEST_F(McapTest, HostileFilesAreRefusedWithTheByteOffset) {
  const std::string good = McapFile(ChunkRec(ImuRecords(100), {"zstd", {}, {}}));
  // A truncated chunk: the file cut inside it. The chunk record starts after magic (8) and the
  // Header record (9 + 4 + 4 + 4 + 8 = 29): byte 37.
  ExpectRefused(good.substr(0, 37 + 200), "byte 37: record 0x06");
  ExpectRefused(good.substr(0, 37 + 200), "truncated");
  // Wrong CRC.
  ExpectRefused(McapFile(ChunkRec(ImuRecords(100), {"lz4", {}, 12345u})), "byte 37: Chunk CRC mismatch");
  // A compression bomb declared as such: refused before any allocation.
  BagReadOptions small;
  small.max_chunk_bytes = 1 << 20;
  ExpectRefused(McapFile(ChunkRec(ImuRecords(100), {"zstd", std::uint64_t{1} << 40, 0u})), "compression bomb", small);
  // A chunk that decompresses to more than it declares: decompression stops at the declared size.
  ExpectRefused(McapFile(ChunkRec(ImuRecords(100), {"zstd", 1000u, 0u})), "byte 37: Chunk: zstd");
  ExpectRefused(McapFile(ChunkRec(ImuRecords(100), {"lz4", 1000u, 0u})), "more than the 1000 bytes");
  // A message shorter than its CDR.
  std::string shortmsg = SchemaRec(1, "sensor_msgs/msg/Imu") + ChannelRec(1, 1, "/imu0") +
                         MessageRec(1, 5, EncodeCdrImu(Sample(0), "imu", false).substr(0, 100));
  ExpectRefused(McapFile(ChunkRec(shortmsg, {"", {}, {}})), "topic /imu0: message byte 100 of 100: message ends inside orientation_covariance");
  // The topic asked for is of another type.
  BagReadOptions cam;
  cam.topic = "/cam0/image_raw";
  ExpectRefused(good, "topic /cam0/image_raw has type sensor_msgs/msg/Image, not sensor_msgs/Imu", cam);
  // Two IMU topics and no choice.
  const std::string two = McapFile(ChunkRec(ImuRecords(20) + ChannelRec(9, 1, "/imu1") + MessageRec(9, 1, EncodeCdrImu(Sample(0), "", false)), {"", {}, {}}));
  ExpectRefused(two, "2 sensor_msgs/Imu topics: /imu0 (20 messages), /imu1 (1 messages); choose one with --topic");
  BagReadOptions imu1;
  imu1.topic = "/imu1";
  EXPECT_TRUE(Read(two, imu1).ok());
  // No footer (an interrupted recording), bad magic, a message on an unknown channel.
  ExpectRefused(McapFile(ChunkRec(ImuRecords(10), {"", {}, {}}), false), "without the Footer record");
  ExpectRefused("\x89MCAP1\r\nxxxxxxxx", "byte 0: not an MCAP");
  ExpectRefused(McapFile(MessageRec(4, 1, "abc")), "Message on channel 4, which no Channel record defined");
}

// rosbag2's own test bags (written by rosbag2 with its MCAP and sqlite3 plugins): every topic's
// message count, first and last receive time as metadata.yaml (written by rosbag2) gives them.
// The two files lay the topics_with_message_count items out differently (message_count before
// or after topic_metadata), so each "- " item is read whole.
std::map<std::string, std::size_t> MetadataCounts(const std::string& path, std::uint64_t* start_ns, std::uint64_t* duration_ns) {
  std::ifstream in(path);
  std::map<std::string, std::size_t> out;
  std::string line, name, count, last_key;
  bool in_topics = false;
  auto flush = [&] {
    if (!name.empty() && !count.empty()) out[name] = std::stoul(count);
    name.clear();
    count.clear();
  };
  while (std::getline(in, line)) {
    const std::size_t b = line.find_first_not_of(' ');
    if (b == std::string::npos) continue;
    std::string t = line.substr(b);
    if (b <= 2 && t.rfind("- ", 0) != 0) {  // a top-level key
      flush();
      in_topics = t.rfind("topics_with_message_count:", 0) == 0;
      last_key = t.substr(0, t.find(':'));
      continue;
    }
    if (t.rfind("nanoseconds_since_epoch: ", 0) == 0 && last_key == "starting_time") *start_ns = std::stoull(t.substr(25));
    if (t.rfind("nanoseconds: ", 0) == 0 && last_key == "duration") *duration_ns = std::stoull(t.substr(13));
    if (!in_topics) continue;
    if (t.rfind("- ", 0) == 0) {
      flush();
      t = t.substr(2);
    }
    if (t.rfind("message_count: ", 0) == 0) count = t.substr(15);
    if (t.rfind("name: ", 0) == 0) name = t.substr(6);
  }
  flush();
  return out;
}

TEST(Rosbag2SampleTest, TalkerBagsListAsTheirMetadataSays) {
  for (const std::string folder : {"talker_mcap", "talker_db3"}) {
    SCOPED_TRACE(folder);
    const std::string path = BagsDir() + "/rosbag2/" + folder;
    std::uint64_t start = 0, duration = 0;
    const auto expected = MetadataCounts(path + "/metadata.yaml", &start, &duration);
    ASSERT_EQ(expected.size(), 3u);
    Result<BagListing> list = ListBag(path);
    ASSERT_TRUE(list.ok()) << list.error().message;
    EXPECT_EQ(list->format, folder == "talker_mcap" ? BagFormat::kMcap : BagFormat::kRos2Sqlite);
    ASSERT_EQ(list->topics.size(), expected.size());
    std::uint64_t first = UINT64_MAX, last = 0;
    for (const BagTopicInfo& t : list->topics) {
      EXPECT_EQ(t.messages, expected.at(t.topic)) << t.topic;
      EXPECT_EQ(t.encoding, "cdr");
      if (t.messages) {
        first = std::min(first, t.first_receive_ns);
        last = std::max(last, t.last_receive_ns);
      }
    }
    EXPECT_EQ(first, start);
    EXPECT_EQ(last - first, duration);
    // No IMU topic in it: refused, naming the topic's type when asked for.
    BagReadOptions o;
    o.topic = "/topic";
    Result<BagImuTable> r = ReadBagImu(path, o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("has type std_msgs/msg/String, not sensor_msgs/Imu"), std::string::npos) << r.error().message;
  }
}

// ---- ROS 1 bag v2.0 built record by record (wiki.ros.org/Bags/Format/2.0) ----

std::string Field(const std::string& name, const std::string& value) {
  std::string s;
  Le(&s, name.size() + 1 + value.size(), 4);
  return s + name + "=" + value;
}
std::string IntField(const std::string& name, std::uint64_t v, int n) {
  std::string b;
  Le(&b, v, n);
  return Field(name, b);
}
std::string Ros1Record(const std::string& header, const std::string& data) {
  std::string s;
  Le(&s, header.size(), 4);
  s += header;
  Le(&s, data.size(), 4);
  return s + data;
}
std::string Op(int op) { return Field("op", std::string(1, static_cast<char>(op))); }

// A bag of n IMU messages in one chunk ("none" or "bz2"), plus a temperature topic; with
// `index_counts`, an index section whose chunk info record declares those counts for connections
// 0 (IMU) and 1 (temperature).
std::string Ros1Bag(int n, const std::string& compression, std::optional<std::uint32_t> declared = {},
                    std::optional<std::pair<std::uint32_t, std::uint32_t>> index_counts = {}) {
  std::string records;
  records += Ros1Record(Op(7) + IntField("conn", 0, 4) + Field("topic", "/imu0"),
                        Field("topic", "/imu0") + Field("type", "sensor_msgs/Imu") + Field("md5sum", "6a62c6daae103f4ff57a132d6f95cec2"));
  records += Ros1Record(Op(7) + IntField("conn", 1, 4) + Field("topic", "/imu0/temperature"),
                        Field("topic", "/imu0/temperature") + Field("type", "sensor_msgs/Temperature"));
  for (int i = 0; i < n; ++i) {
    const ImuMessage m = Sample(i);
    const std::int64_t receive = m.StampNs() + 2000000;
    const std::uint64_t time = static_cast<std::uint64_t>(receive / 1000000000) | (static_cast<std::uint64_t>(receive % 1000000000) << 32);
    if (i % 10 == 0) {
      TemperatureMessage t{m.stamp_sec, m.stamp_nanosec, 20.0 + i};
      records += Ros1Record(Op(2) + IntField("conn", 1, 4) + IntField("time", time, 8), EncodeRos1Temperature(t, "imu"));
    }
    records += Ros1Record(Op(2) + IntField("conn", 0, 4) + IntField("time", time, 8), EncodeRos1Imu(m, "imu"));
  }
  std::string data = records;
  if (compression == "bz2") {
    unsigned int len = static_cast<unsigned int>(records.size() + records.size() / 100 + 600);
    data.resize(len);
    EXPECT_EQ(BZ2_bzBuffToBuffCompress(data.data(), &len, records.data(), static_cast<unsigned int>(records.size()), 9, 0, 0), BZ_OK);
    data.resize(len);
  }
  std::string bag = "#ROSBAG V2.0\n";
  const std::string chunk =
      Ros1Record(Op(5) + Field("compression", compression) + IntField("size", declared.value_or(records.size()), 4), data);
  // "Bag header": index_pos, conn_count, chunk_count; its data pads the record to 4096 bytes.
  const std::uint64_t index_pos = index_counts ? 13 + 4096 + chunk.size() : 0;
  const std::string header = Op(3) + IntField("index_pos", index_pos, 8) + IntField("conn_count", 2, 4) + IntField("chunk_count", 1, 4);
  bag += Ros1Record(header, std::string(4096 - 8 - header.size(), ' '));
  bag += chunk;
  if (index_counts) {
    // "Chunk info": ver, chunk_pos, start_time, end_time, count; data: (conn, count) pairs.
    std::string pairs;
    for (auto [conn, count] : {std::pair<std::uint32_t, std::uint32_t>{0, index_counts->first}, {1, index_counts->second}}) {
      Le(&pairs, conn, 4);
      Le(&pairs, count, 4);
    }
    bag += Ros1Record(Op(6) + IntField("ver", 1, 4) + IntField("chunk_pos", 13 + 4096, 8) + IntField("start_time", 0, 8) +
                          IntField("end_time", 0, 8) + IntField("count", 2, 4),
                      pairs);
  }
  return bag;
}

TEST_F(McapTest, Ros1BagsNoneAndBz2ReadTheSameRowsAndRefuseDamage) {
  for (const std::string compression : {"none", "bz2"}) {
    SCOPED_TRACE(compression);
    Result<BagImuTable> r = ReadBagImu(Write("x.bag", Ros1Bag(120, compression)), {});
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->format, BagFormat::kRos1);
    ExpectSamples(*r, 120);
  }
  const std::string good = Ros1Bag(120, "bz2");
  // The chunk record starts after the version line (13) and the 4096-byte bag header record.
  Result<BagImuTable> r = ReadBagImu(Write("cut.bag", good.substr(0, good.size() - 10)), {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("byte 4109: truncated record"), std::string::npos) << r.error().message;
  r = ReadBagImu(Write("bomb.bag", Ros1Bag(120, "bz2", 1000u)), {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("byte 4109: chunk: bz2: the data decompresses to more than the 1000 bytes"), std::string::npos)
      << r.error().message;
}

// Records what the reader announces of each channel (issue 25: the index's message counts let the
// IMU columns be reserved once).
class ChannelRecorder : public BagVisitor {
 public:
  std::optional<Error> OnChannel(const BagChannel& c) override {
    expected[c.topic] = c.expected_messages;
    return std::nullopt;
  }
  bool Wants(std::uint64_t) const override { return false; }
  std::optional<Error> OnMessage(const BagMessage&) override { return std::nullopt; }
  std::map<std::string, std::optional<std::uint64_t>> expected;
};

TEST_F(McapTest, Ros1IndexCountsAreAHintCappedByTheFileSize) {
  ChannelRecorder plain, indexed, hostile;
  std::istringstream a(Ros1Bag(120, "none"));
  ASSERT_FALSE(StreamRos1Bag(a, "a.bag", {}, &plain));
  EXPECT_EQ(plain.expected.at("/imu0"), std::nullopt);  // no index: no hint
  const std::string with_index = Ros1Bag(120, "none", {}, std::pair<std::uint32_t, std::uint32_t>{120, 12});
  std::istringstream b(with_index);
  ASSERT_FALSE(StreamRos1Bag(b, "b.bag", {}, &indexed));
  EXPECT_EQ(indexed.expected.at("/imu0"), 120u);
  EXPECT_EQ(indexed.expected.at("/imu0/temperature"), 12u);
  // An index claiming 4 G messages: capped at what the file could hold (45 bytes a message).
  const std::string lying = Ros1Bag(120, "none", {}, std::pair<std::uint32_t, std::uint32_t>{0xffffffffu, 7});
  std::istringstream c(lying);
  ASSERT_FALSE(StreamRos1Bag(c, "c.bag", {}, &hostile));
  EXPECT_EQ(hostile.expected.at("/imu0"), lying.size() / 45);
  // Either way the rows are the messages, not the hint.
  for (const std::string& bag : {with_index, lying}) {
    Result<BagImuTable> r = ReadBagImu(Write("indexed.bag", bag), {});
    ASSERT_TRUE(r.ok()) << r.error().message;
    ExpectSamples(*r, 120);
  }
}

TEST_F(McapTest, UnstampedMessagesAskForReceiveTime) {
  std::string r = SchemaRec(1, "sensor_msgs/msg/Imu") + ChannelRec(1, 1, "/imu0");
  for (int i = 0; i < 5; ++i) r += MessageRec(1, 1000 + i, EncodeCdrImu(ImuMessage{}, "", false));
  ExpectRefused(McapFile(r), "header.stamp is 0 ns in all 5 messages (the driver does not stamp them): use the bag's "
                             "receive time, --time receive");
  BagReadOptions o;
  o.time = BagTimeSource::kReceive;
  Result<BagImuTable> t = Read(McapFile(r), o);
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_EQ(t->table.columns[0][4], 1004e-9);
}

TEST_F(McapTest, DataSectionCrcIsCheckedWhenEveryByteIsRead) {
  // Chunked (zstd) and unchunked files, with an image topic and a message index-like unknown
  // record between the chunks: the true CRC reads, a wrong one is refused at the Data End.
  const std::string unknown = Rec(0x07, std::string(100, '\x01'));  // "Message Index": skipped, read for the CRC
  for (const std::string& data : {ChunkRec(ImuRecords(50), {"zstd", {}, {}}) + unknown +
                                      ChunkRec(ImuRecords(50, false, 50), {"", {}, {}}) + unknown,
                                  ImuRecords(100)}) {
    Result<BagImuTable> r = Read(McapFile(data, true, std::nullopt));
    ASSERT_TRUE(r.ok()) << r.error().message;
    ExpectSamples(*r, 100);
    const std::string good = McapFile(data, true, std::nullopt);
    const std::size_t data_end_at = good.size() - 9 - 4 - 9 - 20 - 8;  // Data End, Footer, magic
    ASSERT_EQ(good[data_end_at], '\x0f');
    const std::string want = "byte " + std::to_string(data_end_at) + ": Data End: data section CRC mismatch";
    ExpectRefused(McapFile(data, true, 12345u), want);
    // One flipped byte inside the data section (the Header's library string) is caught too.
    std::string flipped = good;
    flipped[30] ^= 1;
    ExpectRefused(flipped, want);
  }
  // An unwanted message outside chunks larger than 1 MiB is skipped unread: the CRC is then not
  // checked, unless verify_mcap_data_crc asks for every byte.
  const std::string big = ImuRecords(20) + MessageRec(3, 1, std::string((1 << 20) + 10, 'x'));
  EXPECT_TRUE(Read(McapFile(big, true, 12345u)).ok());
  BagReadOptions verify;
  verify.verify_mcap_data_crc = true;
  EXPECT_TRUE(Read(McapFile(big, true, std::nullopt), verify).ok());
  ExpectRefused(McapFile(big, true, 12345u), "data section CRC mismatch", verify);
}

std::string Zstd(const std::string& bytes) {
  std::string z(ZSTD_compressBound(bytes.size()), '\0');
  z.resize(ZSTD_compress(z.data(), z.size(), bytes.data(), bytes.size(), 3));
  return z;
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST_F(McapTest, Rosbag2FileCompressedZstdIsReadDirectly) {
  // rosbag2 compression_mode FILE: x.mcap.zstd read as the MCAP it holds (two zstd frames, as
  // a stream may be written), alone and in a bag folder.
  const std::string mcap = McapFile(ChunkRec(ImuRecords(100), {"lz4", {}, {}}));
  const std::string half = mcap.substr(0, 1000);
  const std::string file = Write("imu.mcap.zstd", Zstd(half) + Zstd(mcap.substr(1000)));
  EXPECT_EQ(DetectBagFormat(file), BagFormat::kMcap);
  Result<BagImuTable> r = ReadBagImu(file, {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  ExpectSamples(*r, 100);
  fs::create_directories(dir_ + "/folder");
  std::ofstream(dir_ + "/folder/metadata.yaml") << "rosbag2_bagfile_information:\n  relative_file_paths:\n    - "
                                                   "imu.mcap.zstd\n  compression_format: zstd\n  compression_mode: FILE\n";
  std::ofstream(dir_ + "/folder/imu.mcap.zstd", std::ios::binary) << ReadAll(file);
  r = ReadBagImu(dir_ + "/folder", {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  ExpectSamples(*r, 100);
  // rosbag2's talker .db3, compressed: the same listing as the plain file.
  const std::string db3 = Write("talker.db3.zstd", Zstd(ReadAll(BagsDir() + "/rosbag2/talker_db3/talker.db3")));
  EXPECT_EQ(DetectBagFormat(db3), BagFormat::kRos2Sqlite);
  Result<BagListing> plain = ListBag(BagsDir() + "/rosbag2/talker_db3/talker.db3");
  Result<BagListing> packed = ListBag(db3);
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  ASSERT_TRUE(packed.ok()) << packed.error().message;
  ASSERT_EQ(packed->topics.size(), plain->topics.size());
  ASSERT_EQ(packed->topics.size(), 3u);
  for (std::size_t k = 0; k < plain->topics.size(); ++k) {
    EXPECT_EQ(packed->topics[k].topic, plain->topics[k].topic);
    EXPECT_EQ(packed->topics[k].messages, plain->topics[k].messages);
    EXPECT_EQ(packed->topics[k].last_receive_ns, plain->topics[k].last_receive_ns);
  }
}

TEST_F(McapTest, HostileZstdFilesAreRefusedOnOneLine) {
  const std::string z = Zstd(McapFile(ChunkRec(ImuRecords(100), {"", {}, {}})));
  auto refused = [&](const std::string& bytes, const std::string& what, BagReadOptions o = {}) {
    Result<BagImuTable> r = ReadBagImu(Write("bad.mcap.zstd", bytes), o);
    ASSERT_FALSE(r.ok()) << what;
    EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
    std::string m = r.error().message;  // never the temporary file's name (gyrocomp_bag_XXXXXX)
    m.erase(0, m.find("bad.mcap.zstd"));
    EXPECT_EQ(m.find("gyrocomp_bag_"), std::string::npos) << r.error().message;
  };
  refused(z.substr(0, z.size() - 7), "the file ends inside a frame (truncated)");
  std::string damaged = z;
  damaged[8] = '\xff';  // inside the frame header / first block header
  damaged[9] = '\xff';
  damaged[10] = '\xff';
  refused(damaged, "compressed byte ");
  refused(z + "garbage!", "compressed byte " + std::to_string(z.size()) + ": zstd: ");
  BagReadOptions small;
  small.max_decompressed_file_bytes = 1000;
  refused(z, "decompresses to more than 1000 bytes (BagReadOptions::max_decompressed_file_bytes); refused as a possible "
             "compression bomb", small);
  refused(Zstd("not a bag at all, just text"), "decompressed byte 0: not an MCAP");
  // A damaged MCAP inside names the compressed file.
  std::string inner = McapFile(ChunkRec(ImuRecords(10), {"", {}, 12345u}));
  refused(Zstd(inner), "bad.mcap.zstd (decompressed): byte 37: Chunk CRC mismatch");
  // compression_mode MESSAGE is refused up front.
  fs::create_directories(dir_ + "/msg");
  std::ofstream(dir_ + "/msg/metadata.yaml") << "rosbag2_bagfile_information:\n  relative_file_paths:\n    - x.mcap\n"
                                                "  compression_format: zstd\n  compression_mode: MESSAGE\n";
  std::ofstream(dir_ + "/msg/x.mcap", std::ios::binary) << McapFile(ImuRecords(10));
  Result<BagImuTable> r = ReadBagImu(dir_ + "/msg", {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("compression_mode MESSAGE"), std::string::npos) << r.error().message;
}

TEST_F(McapTest, DamagedSqliteIsRefusedOnOneLine) {
  // The sqlite3 magic, then garbage: sqlite itself refuses it.
  const std::string path = Write("bad.db3", std::string("SQLite format 3\0", 16) + std::string(5000, '\x5a'));
  Result<BagImuTable> r = ReadBagImu(path, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find(path + ": "), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("not a rosbag2 sqlite3 file?"), std::string::npos) << r.error().message;
  EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
}

TEST(BagDetectTest, FormatsByFirstBytes) {
  EXPECT_EQ(DetectBagFormat(BagsDir() + "/rosbag2/talker_mcap/talker.mcap"), BagFormat::kMcap);
  EXPECT_EQ(DetectBagFormat(BagsDir() + "/rosbag2/talker_db3/talker.db3"), BagFormat::kRos2Sqlite);
  EXPECT_EQ(DetectBagFormat(BagsDir() + "/rosbag2/talker_db3"), BagFormat::kRos2Sqlite);
  EXPECT_EQ(DetectBagFormat(BagsDir() + "/rosbag2/talker_db3/metadata.yaml"), BagFormat::kNone);
  EXPECT_EQ(DetectBagFormat("-"), BagFormat::kNone);
}

}  // namespace
}  // namespace gyrocomp
