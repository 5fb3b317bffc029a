// The MCAP reader on files built here record by record (mcap.dev/spec): none / zstd / lz4
// chunks, big-endian CDR, a temperature topic, unchunked messages, receive time, the data
// section CRC; hostile MCAPs (truncated chunk, wrong CRC, compression bombs, a message shorter
// than its CDR, a topic of another type, several IMU topics, no footer, unstamped messages); and
// rosbag2's per-file compression (a whole .mcap.zstd, alone and in a bag folder; hostile zstd).
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "bag_test_util.h"
#include "fixtures.h"
#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/cdr.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;
using testing::BagsDir;
using testing::ExpectSamples;
using testing::Le;
using testing::Str;
using testing::McapMessage;
using testing::Rec;
using testing::Sample;

// ---- MCAP built record by record (mcap.dev/spec) ----

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
      r += McapMessage(2, receive, EncodeCdrTemperature(t, "imu", big_endian));
      r += McapMessage(3, receive, std::string(4000, 'x'));
    }
    r += McapMessage(1, receive, EncodeCdrImu(m, "imu", big_endian));
  }
  return r;
}

class McapTest : public testing::FileTest {
 protected:
  McapTest() : FileTest("gyrocomp_bag_test") {}
  Result<BagImuTable> Read(const std::string& bytes, BagReadOptions o = {}) { return ReadBagImu(Put("x.mcap", bytes), o); }
  void ExpectRefused(const std::string& bytes, const std::string& what, BagReadOptions o = {}) {
    Result<BagImuTable> r = Read(bytes, o);
    ASSERT_FALSE(r.ok()) << what;
    EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
  }
};

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
  // Damage is refused in strict mode (recovery: bag_recovery_test.cc).
  BagReadOptions strict;
  strict.strict = true;
  // A truncated chunk: the file cut inside it. The chunk record starts after magic (8) and the
  // Header record (9 + 4 + 4 + 4 + 8 = 29): byte 37.
  ExpectRefused(good.substr(0, 37 + 200), "byte 37: record 0x06", strict);
  ExpectRefused(good.substr(0, 37 + 200), "truncated", strict);
  // Wrong CRC.
  ExpectRefused(McapFile(ChunkRec(ImuRecords(100), {"lz4", {}, 12345u})), "byte 37: Chunk CRC mismatch", strict);
  // A compression bomb declared as such: refused before any allocation.
  BagReadOptions small = strict;
  small.max_chunk_bytes = 1 << 20;
  ExpectRefused(McapFile(ChunkRec(ImuRecords(100), {"zstd", std::uint64_t{1} << 40, 0u})), "compression bomb", small);
  // A chunk that decompresses to more than it declares: decompression stops at the declared size.
  ExpectRefused(McapFile(ChunkRec(ImuRecords(100), {"zstd", 1000u, 0u})), "byte 37: Chunk: zstd", strict);
  ExpectRefused(McapFile(ChunkRec(ImuRecords(100), {"lz4", 1000u, 0u})), "more than the 1000 bytes", strict);
  // A message shorter than its CDR.
  std::string shortmsg = SchemaRec(1, "sensor_msgs/msg/Imu") + ChannelRec(1, 1, "/imu0") +
                         McapMessage(1, 5, EncodeCdrImu(Sample(0), "imu", false).substr(0, 100));
  ExpectRefused(McapFile(ChunkRec(shortmsg, {"", {}, {}})), "topic /imu0: message byte 100 of 100: message ends inside orientation_covariance");
  // The topic asked for is of another type.
  BagReadOptions cam;
  cam.topic = "/cam0/image_raw";
  ExpectRefused(good, "topic /cam0/image_raw has type sensor_msgs/msg/Image, not sensor_msgs/Imu", cam);
  // Two IMU topics and no choice.
  const std::string two = McapFile(ChunkRec(ImuRecords(20) + ChannelRec(9, 1, "/imu1") + McapMessage(9, 1, EncodeCdrImu(Sample(0), "", false)), {"", {}, {}}));
  ExpectRefused(two, "2 sensor_msgs/Imu topics: /imu0 (20 messages), /imu1 (1 messages); choose one with --topic");
  BagReadOptions imu1;
  imu1.topic = "/imu1";
  EXPECT_TRUE(Read(two, imu1).ok());
  // No footer (an interrupted recording), bad magic, a message on an unknown channel.
  ExpectRefused(McapFile(ChunkRec(ImuRecords(10), {"", {}, {}}), false), "without the Footer record", strict);
  ExpectRefused("\x89MCAP1\r\nxxxxxxxx", "byte 0: not an MCAP");
  ExpectRefused(McapFile(McapMessage(4, 1, "abc")), "Message on channel 4, which no Channel record defined", strict);
}

TEST_F(McapTest, ReceiveTimesFarApartJoinTheNearestTemperature) {
  // A log_time at or above 2^63 ns is a negative stamp: its distance to 1.7e18 ns exceeds the
  // int64 range (fuzz_mcap found the overflow); the nearest temperature is still the one taken.
  std::string r = SchemaRec(1, "sensor_msgs/msg/Imu") + ChannelRec(1, 1, "/imu0") +
                  SchemaRec(2, "sensor_msgs/msg/Temperature") + ChannelRec(2, 2, "/imu0/temperature");
  const ImuMessage m = Sample(0);
  r += McapMessage(2, 0x8069000000000000u, EncodeCdrTemperature(TemperatureMessage{m.stamp_sec, m.stamp_nanosec, 30.0}, "imu", false));
  r += McapMessage(2, 1700000000009000000u, EncodeCdrTemperature(TemperatureMessage{m.stamp_sec, m.stamp_nanosec, 20.0}, "imu", false));
  for (int i = 0; i < 3; ++i) r += McapMessage(1, 1700000000002000000u + i, EncodeCdrImu(Sample(i), "imu", false));
  BagReadOptions o;
  o.time = BagTimeSource::kReceive;
  Result<BagImuTable> t = Read(McapFile(r), o);
  ASSERT_TRUE(t.ok()) << t.error().message;
  ASSERT_EQ(t->table.names.back(), "temp_c");
  for (double c : t->table.columns.back()) EXPECT_EQ(c, 20.0);
}

TEST_F(McapTest, UnstampedMessagesAskForReceiveTime) {
  std::string r = SchemaRec(1, "sensor_msgs/msg/Imu") + ChannelRec(1, 1, "/imu0");
  for (int i = 0; i < 5; ++i) r += McapMessage(1, 1000 + i, EncodeCdrImu(ImuMessage{}, "", false));
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
    BagReadOptions strict;
    strict.strict = true;
    ExpectRefused(McapFile(data, true, 12345u), want, strict);
    // One flipped byte inside the data section (the Header's library string) is caught too.
    std::string flipped = good;
    flipped[30] ^= 1;
    ExpectRefused(flipped, want, strict);
    // In recovery a mismatch is refused only when a row may hold the corrupt byte (a message
    // outside chunks, or in a chunk without CRC: the uncompressed chunk here declares one).
    Result<BagImuTable> r2 = Read(flipped);
    if (data == ImuRecords(100)) {
      ExpectRefused(flipped, want);
    } else {
      ASSERT_TRUE(r2.ok()) << r2.error().message;
      ExpectSamples(*r2, 100);
      ASSERT_EQ(r2->damage.size(), 1u);
      EXPECT_EQ(r2->damage[0].begin, data_end_at);
    }
  }
  // An unwanted message outside chunks larger than 1 MiB is skipped unread: the CRC is then not
  // checked, unless verify_mcap_data_crc asks for every byte.
  const std::string big = ImuRecords(20) + McapMessage(3, 1, std::string((1 << 20) + 10, 'x'));
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

TEST_F(McapTest, Rosbag2FileCompressedZstdIsReadDirectly) {
  // rosbag2 compression_mode FILE: x.mcap.zstd read as the MCAP it holds (two zstd frames, as
  // a stream may be written), alone and in a bag folder.
  const std::string mcap = McapFile(ChunkRec(ImuRecords(100), {"lz4", {}, {}}));
  const std::string half = mcap.substr(0, 1000);
  const std::string file = Put("imu.mcap.zstd", Zstd(half) + Zstd(mcap.substr(1000)));
  EXPECT_EQ(DetectBagFormat(file), BagFormat::kMcap);
  Result<BagImuTable> r = ReadBagImu(file, {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  ExpectSamples(*r, 100);
  fs::create_directories(dir_ + "/folder");
  std::ofstream(dir_ + "/folder/metadata.yaml") << "rosbag2_bagfile_information:\n  relative_file_paths:\n    - "
                                                   "imu.mcap.zstd\n  compression_format: zstd\n  compression_mode: FILE\n";
  std::ofstream(dir_ + "/folder/imu.mcap.zstd", std::ios::binary) << testing::ReadFile(file);
  r = ReadBagImu(dir_ + "/folder", {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  ExpectSamples(*r, 100);
  // rosbag2's talker .db3, compressed: the same listing as the plain file.
  const std::string db3 = Put("talker.db3.zstd", Zstd(testing::ReadFile(BagsDir() + "/rosbag2/talker_db3/talker.db3")));
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
    Result<BagImuTable> r = ReadBagImu(Put("bad.mcap.zstd", bytes), o);
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
  BagReadOptions strict;
  strict.strict = true;
  refused(Zstd(inner), "bad.mcap.zstd (decompressed): byte 37: Chunk CRC mismatch", strict);
  // compression_mode MESSAGE is refused up front.
  fs::create_directories(dir_ + "/msg");
  std::ofstream(dir_ + "/msg/metadata.yaml") << "rosbag2_bagfile_information:\n  relative_file_paths:\n    - x.mcap\n"
                                                "  compression_format: zstd\n  compression_mode: MESSAGE\n";
  std::ofstream(dir_ + "/msg/x.mcap", std::ios::binary) << McapFile(ImuRecords(10));
  Result<BagImuTable> r = ReadBagImu(dir_ + "/msg", {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("compression_mode MESSAGE"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace gyrocomp
