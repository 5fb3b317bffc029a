// Recovery of damaged ROS 1 bags and MCAP files (BagReadOptions::strict false): bags built here
// with several chunks and their index records, then damaged (a flipped byte in a record header,
// a deleted record, a truncated file, a wrong chunk CRC, a corrupted compressed chunk). Each
// loses only the damaged unit's messages; every row kept is a message of the undamaged bag, bit
// for bit; the damage is listed with its byte range and messages lost per topic, in one warning;
// strict mode refuses the same file naming the byte offset.
#include <bzlib.h>
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "bag_test_util.h"
#include "fixtures.h"
#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/cdr.h"

namespace gyrocomp {
namespace {

using testing::Le;
using testing::Field;
using testing::IntField;
using testing::Ros1Record;
using testing::Op;
using testing::Str;
using testing::McapMessage;
using testing::Rec;
using testing::Sample;

constexpr int kChunks = 4;
constexpr int kPerChunk = 30;  // IMU messages per chunk; a temperature message every 10th

// ---- Rows as bits (bag_test_util.h) ----

using Row = testing::BagRow;
using testing::DamageLines;
using testing::IsSubset;
using testing::Lost;

std::uint64_t ReceiveNs(int i) { return static_cast<std::uint64_t>(Sample(i).StampNs() + 2000000); }

// ---- ROS 1 bag v2.0 with several chunks and an index (wiki.ros.org/Bags/Format/2.0) ----


std::string Compress(const std::string& method, const std::string& raw) {
  std::string out;
  if (method == "bz2") {
    unsigned int len = static_cast<unsigned int>(raw.size() + raw.size() / 100 + 600);
    out.resize(len);
    EXPECT_EQ(BZ2_bzBuffToBuffCompress(out.data(), &len, const_cast<char*>(raw.data()), static_cast<unsigned int>(raw.size()), 9, 0, 0), BZ_OK);
    out.resize(len);
  } else if (method == "lz4") {
    out.resize(LZ4F_compressFrameBound(raw.size(), nullptr));
    out.resize(LZ4F_compressFrame(out.data(), out.size(), raw.data(), raw.size(), nullptr));
  } else if (method == "zstd") {
    out.resize(ZSTD_compressBound(raw.size()));
    out.resize(ZSTD_compress(out.data(), out.size(), raw.data(), raw.size(), 3));
  } else {
    out = raw;
  }
  return out;
}

// Where the pieces of a built bag are.
struct Layout {
  std::vector<std::size_t> chunk_at;  // offset of each chunk record
  std::vector<std::size_t> data_at;   // offset of each chunk's (stored) data
  std::vector<std::size_t> chunk_end;  // offset just past each chunk record
  std::vector<std::vector<std::size_t>> message_at;  // offsets of the IMU message records in each chunk's data
};

// kChunks chunks of kPerChunk IMU messages (connection 0, /imu0) and a temperature message every
// 10th (connection 1); each chunk followed by its "Index data" records; the index section holds
// both connection records and a "Chunk info" per chunk, as rosbag writes them.
std::string Ros1Bag(const std::string& compression, Layout* layout) {
  const std::string conn0 = Ros1Record(Op(7) + IntField("conn", 0, 4) + Field("topic", "/imu0"),
                                       Field("topic", "/imu0") + Field("type", "sensor_msgs/Imu"));
  const std::string conn1 = Ros1Record(Op(7) + IntField("conn", 1, 4) + Field("topic", "/imu0/temperature"),
                                       Field("topic", "/imu0/temperature") + Field("type", "sensor_msgs/Temperature"));
  std::string body;
  std::string infos;
  const std::size_t first_chunk = 13 + 4096;
  for (int c = 0; c < kChunks; ++c) {
    std::string records = c == 0 ? conn0 + conn1 : "";
    std::vector<std::size_t> at;
    int temps = 0;
    for (int i = c * kPerChunk; i < (c + 1) * kPerChunk; ++i) {
      const std::uint64_t r = ReceiveNs(i);
      const std::uint64_t time = (r / 1000000000) | ((r % 1000000000) << 32);
      if (i % 10 == 0) {
        const ImuMessage m = Sample(i);
        records += Ros1Record(Op(2) + IntField("conn", 1, 4) + IntField("time", time, 8),
                              EncodeRos1Temperature(TemperatureMessage{m.stamp_sec, m.stamp_nanosec, 20.0 + i}, "imu"));
        ++temps;
      }
      at.push_back(records.size());
      records += Ros1Record(Op(2) + IntField("conn", 0, 4) + IntField("time", time, 8), EncodeRos1Imu(Sample(i), "imu"));
    }
    const std::string header = Op(5) + Field("compression", compression) + IntField("size", records.size(), 4);
    const std::size_t chunk_at = first_chunk + body.size();
    layout->chunk_at.push_back(chunk_at);
    layout->data_at.push_back(chunk_at + 8 + header.size());
    layout->message_at.push_back(at);
    body += Ros1Record(header, Compress(compression, records));
    layout->chunk_end.push_back(first_chunk + body.size());
    // "Index data" per connection: (time, offset) pairs (offsets left 0: not read).
    for (auto [conn, count] : {std::pair<int, int>{0, kPerChunk}, {1, temps}}) {
      body += Ros1Record(Op(4) + IntField("ver", 1, 4) + IntField("conn", conn, 4) + IntField("count", count, 4),
                         std::string(12 * count, '\0'));
    }
    std::string pairs;
    Le(&pairs, 0, 4);
    Le(&pairs, kPerChunk, 4);
    Le(&pairs, 1, 4);
    Le(&pairs, temps, 4);
    infos += Ros1Record(Op(6) + IntField("ver", 1, 4) + IntField("chunk_pos", chunk_at, 8) + IntField("start_time", 0, 8) +
                            IntField("end_time", 0, 8) + IntField("count", 2, 4),
                        pairs);
  }
  const std::string header = Op(3) + IntField("index_pos", first_chunk + body.size(), 8) + IntField("conn_count", 2, 4) +
                             IntField("chunk_count", kChunks, 4);
  std::string bag = "#ROSBAG V2.0\n" + Ros1Record(header, std::string(4096 - 8 - header.size(), ' '));
  EXPECT_EQ(bag.size(), first_chunk);
  return bag + body + conn0 + conn1 + infos;
}

class BagRecoveryTest : public testing::FileTest {
 protected:
  BagRecoveryTest() : FileTest("gyrocomp_bag_recovery_test") {}

  // Reads the damaged bytes in recovery, checks what every damaged file must show and returns the
  // table; then checks strict mode refuses them at `strict_at` ("byte N" or "byte N: chunk byte M").
  BagImuTable Recover(const std::string& name, const std::string& damaged, const std::vector<Row>& original,
                      const std::string& strict_at) {
    const std::string path = Put(name, damaged);
    Result<BagImuTable> r = ReadBagImu(path, {});
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    if (!r.ok()) return {};
    EXPECT_TRUE(IsSubset(testing::BagRows(*r), original)) << "a row that is not in the undamaged bag";
    EXPECT_FALSE(r->damage.empty());
    EXPECT_EQ(DamageLines(*r), 1u);
    BagReadOptions strict;
    strict.strict = true;
    Result<BagImuTable> s = ReadBagImu(path, strict);
    EXPECT_FALSE(s.ok());
    if (!s.ok()) {
      // A position ending in a number is followed by ": " (byte 41 is not byte 4109).
      const std::string want = path + ": " + strict_at + (std::isdigit(static_cast<unsigned char>(strict_at.back())) ? ":" : "");
      EXPECT_NE(s.error().message.find(want), std::string::npos) << s.error().message;
    }
    return std::move(*r);
  }
};

std::vector<Row> ReadRows(const std::string& path) {
  Result<BagImuTable> r = ReadBagImu(path, {});
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  EXPECT_TRUE(r.ok() && r->damage.empty() && r->warnings.empty());
  return r.ok() ? testing::BagRows(*r) : std::vector<Row>{};
}

TEST_F(BagRecoveryTest, Ros1FlippedChunkHeaderLosesOnlyThatChunk) {
  for (const std::string compression : {"none", "bz2", "lz4"}) {
    SCOPED_TRACE(compression);
    Layout at;
    const std::string good = Ros1Bag(compression, &at);
    const std::vector<Row> all = ReadRows(Put("good.bag", good));
    ASSERT_EQ(all.size(), static_cast<std::size_t>(kChunks * kPerChunk));
    // The top byte of chunk 2's header_len: the record no longer frames.
    std::string bad = good;
    bad[at.chunk_at[2] + 3] ^= 0x40;
    const BagImuTable t = Recover("flip.bag", bad, all, "byte " + std::to_string(at.chunk_at[2]));
    ASSERT_EQ(t.damage.size(), 1u);
    EXPECT_EQ(t.damage[0].begin, at.chunk_at[2]);
    if (compression == "none") {
      // The chunk's records are the file's bytes: reading goes on at its first message.
      EXPECT_EQ(t.table.num_rows(), all.size());
      EXPECT_EQ(t.damage[0].end, at.data_at[2]);
      EXPECT_EQ(Lost(t.damage[0], "/imu0"), 0u);
    } else {
      // Resynchronised at the chunk's first index record: exactly its 30 + 3 messages lost.
      EXPECT_EQ(t.table.num_rows(), all.size() - kPerChunk);
      EXPECT_EQ(Lost(t.damage[0], "/imu0"), static_cast<std::size_t>(kPerChunk));
      EXPECT_EQ(Lost(t.damage[0], "/imu0/temperature"), 3u);
    }
  }
}

TEST_F(BagRecoveryTest, Ros1FlippedMessageHeaderLosesOnlyThatMessage) {
  Layout at;
  const std::string good = Ros1Bag("none", &at);
  const std::vector<Row> all = ReadRows(Put("good.bag", good));
  // header_len of the 5th IMU message record of chunk 1 made far too large.
  const std::size_t msg = at.data_at[1] + at.message_at[1][4];
  std::string bad = good;
  bad[msg + 2] ^= 0x10;
  const BagImuTable t = Recover("flip.bag", bad, all,
                                "byte " + std::to_string(at.chunk_at[1]) + ": chunk byte " + std::to_string(at.message_at[1][4]));
  EXPECT_EQ(t.table.num_rows(), all.size() - 1);
  ASSERT_EQ(t.damage.size(), 1u);
  EXPECT_EQ(t.damage[0].begin, msg);
  EXPECT_EQ(Lost(t.damage[0], "/imu0"), 1u);
  EXPECT_EQ(Lost(t.damage[0], "/imu0/temperature"), 0u);
}

TEST_F(BagRecoveryTest, Ros1DeletedMessageRecordLosesOnlyThatMessage) {
  Layout at;
  const std::string good = Ros1Bag("none", &at);
  const std::vector<Row> all = ReadRows(Put("good.bag", good));
  // The 8th IMU message record of chunk 1 cut out: the chunk's size now overruns its records,
  // and index_pos points past the index section.
  const std::size_t msg = at.data_at[1] + at.message_at[1][7];
  const std::size_t len = at.message_at[1][8] - at.message_at[1][7];
  std::string bad = good;
  bad.erase(msg, len);
  const BagImuTable t = Recover("deleted.bag", bad, all, "byte " + std::to_string(at.chunk_at[1]) + ": chunk byte");
  EXPECT_EQ(t.table.num_rows(), all.size() - 1);
  std::size_t lost = 0;
  for (const LogDamage& d : t.damage) lost += Lost(d, "/imu0");
  EXPECT_EQ(lost, 1u);  // the chunk info records, read where they are, still tell
}

TEST_F(BagRecoveryTest, Ros1GarbageInsideAnUncompressedChunkLosesNothing) {
  Layout at;
  const std::string good = Ros1Bag("none", &at);
  const std::vector<Row> all = ReadRows(Put("good.bag", good));
  // 3000 bytes of noise before the 10th IMU message record of chunk 1: every record is still
  // there, after the noise (and every offset the index gives after it is 3000 bytes off).
  std::string noise;
  std::uint32_t x = 12345;
  for (int i = 0; i < 3000; ++i) noise.push_back(static_cast<char>((x = x * 1103515245u + 12345u) >> 24));
  std::string bad = good;
  const std::size_t msg = at.data_at[1] + at.message_at[1][9];
  bad.insert(msg, noise);
  const BagImuTable t = Recover("noise.bag", bad, all, "byte " + std::to_string(at.chunk_at[1]) + ": chunk byte");
  EXPECT_EQ(t.table.num_rows(), all.size());
  ASSERT_EQ(t.damage.size(), 1u);
  EXPECT_EQ(t.damage[0].begin, msg);
  EXPECT_EQ(t.damage[0].end, msg + noise.size());
  EXPECT_EQ(Lost(t.damage[0], "/imu0"), 0u);  // read all the same, though the chunk overran
  EXPECT_EQ(Lost(t.damage[0], "/imu0/temperature"), 0u);
  // Noise longer than a chunk: the index puts chunk 2 inside the skipped range, yet it was read
  // (3000 + 20000 bytes later); nothing is counted lost.
  bad.insert(msg, std::string(20000, '\xee'));
  const BagImuTable u = Recover("noise2.bag", bad, all, "byte " + std::to_string(at.chunk_at[1]) + ": chunk byte");
  EXPECT_EQ(u.table.num_rows(), all.size());
  ASSERT_EQ(u.damage.size(), 1u);
  EXPECT_LT(at.chunk_at[2], u.damage[0].end);
  EXPECT_TRUE(u.damage[0].rows_lost.empty() || Lost(u.damage[0], "/imu0") == 0u);
}

TEST_F(BagRecoveryTest, Ros1CorruptedCompressedChunkLosesItsMessages) {
  for (const std::string compression : {"bz2", "lz4"}) {
    SCOPED_TRACE(compression);
    Layout at;
    const std::string good = Ros1Bag(compression, &at);
    const std::vector<Row> all = ReadRows(Put("good.bag", good));
    std::string bad = good;
    // bz2: a byte of the stream (its block CRC fails); lz4: the frame descriptor's BD byte (its
    // header checksum fails; LZ4 frames without a content checksum cannot catch every flip).
    bad[at.data_at[1] + (compression == "bz2" ? 200 : 5)] ^= 0x21;
    const BagImuTable t = Recover("corrupt.bag", bad, all, "byte " + std::to_string(at.chunk_at[1]) + ": chunk: " + compression);
    EXPECT_EQ(t.table.num_rows(), all.size() - kPerChunk);
    ASSERT_EQ(t.damage.size(), 1u);
    EXPECT_EQ(t.damage[0].begin, at.chunk_at[1]);
    EXPECT_EQ(t.damage[0].end, at.chunk_end[1]);
    EXPECT_EQ(Lost(t.damage[0], "/imu0"), static_cast<std::size_t>(kPerChunk));
    EXPECT_EQ(Lost(t.damage[0], "/imu0/temperature"), 3u);
  }
}

TEST_F(BagRecoveryTest, Ros1TruncatedFileKeepsTheChunksBeforeTheCut) {
  Layout at;
  const std::string good = Ros1Bag("bz2", &at);
  const std::vector<Row> all = ReadRows(Put("good.bag", good));
  // Cut inside chunk 2's data: no index section, so the loss is not known by topic.
  const BagImuTable t = Recover("cut.bag", good.substr(0, at.data_at[2] + 100), all, "byte " + std::to_string(at.chunk_at[2]));
  EXPECT_EQ(t.table.num_rows(), static_cast<std::size_t>(2 * kPerChunk));
  ASSERT_EQ(t.damage.size(), 1u);
  EXPECT_EQ(t.damage[0].begin, at.chunk_at[2]);
  EXPECT_EQ(t.damage[0].end, at.data_at[2] + 100);
  EXPECT_EQ(t.damage[0].records_unidentified, 1u);
}

// ---- MCAP with several chunks, each followed by its Message Index records (mcap.dev/spec) ----

std::string McapChunk(const std::string& records, const std::string& compression) {
  const std::string data = Compress(compression, records);
  std::string c;
  Le(&c, 0, 8);
  Le(&c, 0, 8);
  Le(&c, records.size(), 8);
  Le(&c, crc32(0, reinterpret_cast<const Bytef*>(records.data()), static_cast<uInt>(records.size())), 4);
  c += Str(compression);
  Le(&c, data.size(), 8);
  return Rec(0x06, c + data);
}
std::string MessageIndex(int channel, int count) {
  std::string c;
  Le(&c, channel, 2);
  Le(&c, 16 * count, 4);
  return Rec(0x07, c + std::string(16 * count, '\0'));
}

// kChunks chunks of kPerChunk IMU messages (channel 1, /imu0) and a temperature message every
// 10th (channel 2); schemas and channels in the first chunk; a Message Index per channel after
// each chunk; Data End (no CRC) and Footer.
// The Schema and Channel records of /imu0 (1) and /imu0/temperature (2).
std::string McapChannels() {
  std::string r;
  for (auto [id, name, topic] : {std::tuple<int, const char*, const char*>{1, "sensor_msgs/msg/Imu", "/imu0"},
                                 {2, "sensor_msgs/msg/Temperature", "/imu0/temperature"}}) {
    std::string schema, channel;
    Le(&schema, id, 2);
    Le(&channel, id, 2);
    Le(&channel, id, 2);
    channel += Str(topic) + Str("cdr");
    Le(&channel, 0, 4);
    r += Rec(0x03, schema + Str(name) + Str("ros2msg") + Str("")) + Rec(0x04, channel);
  }
  return r;
}

std::string McapBag(const std::string& compression, Layout* layout, bool summary = false) {
  std::string s = "\x89MCAP0\r\n" + Rec(0x01, Str("ros2") + Str("bag_recovery_test"));
  for (int c = 0; c < kChunks; ++c) {
    std::string r = c == 0 ? McapChannels() : "";
    std::vector<std::size_t> at;
    int temps = 0;
    for (int i = c * kPerChunk; i < (c + 1) * kPerChunk; ++i) {
      const ImuMessage m = Sample(i);
      if (i % 10 == 0) {
        r += McapMessage(2, ReceiveNs(i), EncodeCdrTemperature(TemperatureMessage{m.stamp_sec, m.stamp_nanosec, 20.0 + i}, "imu", false));
        ++temps;
      }
      at.push_back(r.size());
      r += McapMessage(1, ReceiveNs(i), EncodeCdrImu(m, "imu", false));
    }
    layout->chunk_at.push_back(s.size());
    const std::string chunk = McapChunk(r, compression);
    layout->data_at.push_back(s.size() + chunk.size() - Compress(compression, r).size());
    layout->message_at.push_back(at);
    layout->chunk_end.push_back(s.size() + chunk.size());
    s += chunk + MessageIndex(1, kPerChunk) + MessageIndex(2, temps);
  }
  std::string crc, footer;
  Le(&crc, 0, 4);
  s += Rec(0x0F, crc);
  // "Footer": summary_start, summary_offset_start, summary_crc; the summary repeats the channels.
  Le(&footer, summary ? s.size() : 0, 8);
  Le(&footer, 0, 12);
  if (summary) s += McapChannels();
  return s + Rec(0x02, footer) + "\x89MCAP0\r\n";
}

TEST_F(BagRecoveryTest, McapBadCrcOrCorruptChunkLosesOnlyThatChunk) {
  for (const std::string compression : {"", "zstd", "lz4"}) {
    SCOPED_TRACE(compression);
    Layout at;
    const std::string good = McapBag(compression, &at);
    const std::vector<Row> all = ReadRows(Put("good.mcap", good));
    ASSERT_EQ(all.size(), static_cast<std::size_t>(kChunks * kPerChunk));
    // The chunk's uncompressed_crc (9 + 24 bytes into the record), then a byte of its data.
    for (std::size_t byte : {at.chunk_at[1] + 9 + 24, at.data_at[1] + 40}) {
      std::string bad = good;
      bad[byte] ^= 0x04;
      const BagImuTable t = Recover("bad.mcap", bad, all, "byte " + std::to_string(at.chunk_at[1]));
      EXPECT_EQ(t.table.num_rows(), all.size() - kPerChunk);
      ASSERT_EQ(t.damage.size(), 1u);
      EXPECT_EQ(t.damage[0].begin, at.chunk_at[1]);
      EXPECT_EQ(t.damage[0].end, at.chunk_end[1]);
      EXPECT_EQ(Lost(t.damage[0], "/imu0"), static_cast<std::size_t>(kPerChunk));
      EXPECT_EQ(Lost(t.damage[0], "/imu0/temperature"), 3u);
    }
  }
}

TEST_F(BagRecoveryTest, McapChannelsLostWithTheFirstChunkComeFromTheSummary) {
  Layout at;
  const std::string good = McapBag("zstd", &at, true);
  const std::vector<Row> all = ReadRows(Put("good.mcap", good));
  std::string bad = good;
  bad[at.data_at[0] + 40] ^= 0x04;  // the chunk holding the Schema and Channel records
  const BagImuTable t = Recover("first.mcap", bad, all, "byte " + std::to_string(at.chunk_at[0]));
  EXPECT_EQ(t.table.num_rows(), all.size() - kPerChunk);
  ASSERT_EQ(t.damage.size(), 1u);
  EXPECT_EQ(Lost(t.damage[0], "/imu0"), static_cast<std::size_t>(kPerChunk));
}

TEST_F(BagRecoveryTest, McapFlippedRecordLengthResynchronisesAtTheNextRecord) {
  for (const std::string compression : {"", "zstd"}) {
    SCOPED_TRACE(compression);
    Layout at;
    const std::string good = McapBag(compression, &at);
    const std::vector<Row> all = ReadRows(Put("good.mcap", good));
    std::string bad = good;
    bad[at.chunk_at[2] + 1 + 6] ^= 0x01;  // the length's 7th byte: the record runs past the file
    const BagImuTable t = Recover("flip.mcap", bad, all, "byte " + std::to_string(at.chunk_at[2]));
    ASSERT_GE(t.damage.size(), 1u);
    EXPECT_EQ(t.damage[0].begin, at.chunk_at[2]);
    if (compression.empty()) {
      // The chunk's records are the file's bytes: reading goes on at the first of them.
      EXPECT_EQ(t.table.num_rows(), all.size());
      EXPECT_EQ(Lost(t.damage[0], "/imu0"), 0u);
    } else {
      EXPECT_EQ(t.table.num_rows(), all.size() - kPerChunk);
      EXPECT_EQ(Lost(t.damage[0], "/imu0"), static_cast<std::size_t>(kPerChunk));
    }
  }
}

TEST_F(BagRecoveryTest, McapDeletedMessageInAChunkLosesOnlyThatMessage) {
  Layout at;
  const std::string good = McapBag("", &at);
  const std::vector<Row> all = ReadRows(Put("good.mcap", good));
  const std::size_t msg = at.data_at[1] + at.message_at[1][7];
  std::string bad = good;
  bad.erase(msg, at.message_at[1][8] - at.message_at[1][7]);
  const BagImuTable t = Recover("deleted.mcap", bad, all, "byte " + std::to_string(at.chunk_at[1]));
  EXPECT_EQ(t.table.num_rows(), all.size() - 1);
  std::size_t lost = 0;
  for (const LogDamage& d : t.damage) lost += Lost(d, "/imu0");
  EXPECT_EQ(lost, 1u);
}

TEST_F(BagRecoveryTest, McapTruncatedFileKeepsTheChunksBeforeTheCut) {
  Layout at;
  const std::string good = McapBag("zstd", &at);
  const std::vector<Row> all = ReadRows(Put("good.mcap", good));
  const std::string cut = good.substr(0, at.data_at[2] + 50);
  const BagImuTable t = Recover("cut.mcap", cut, all, "byte " + std::to_string(at.chunk_at[2]));
  EXPECT_EQ(t.table.num_rows(), static_cast<std::size_t>(2 * kPerChunk));
  ASSERT_EQ(t.damage.size(), 1u);
  EXPECT_EQ(t.damage[0].begin, at.chunk_at[2]);
  EXPECT_EQ(t.damage[0].end, cut.size());
  EXPECT_EQ(t.damage[0].records_unidentified, 1u);
  // A recording cut between records (no Footer) keeps every row.
  Result<BagImuTable> r = ReadBagImu(Put("nofooter.mcap", good.substr(0, at.chunk_at[3])), {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r->table.num_rows(), static_cast<std::size_t>(3 * kPerChunk));
  EXPECT_EQ(DamageLines(*r), 1u);
}

TEST_F(BagRecoveryTest, ListingCarriesTheDamage) {
  Layout at;
  std::string bad = McapBag("zstd", &at);
  bad[at.data_at[1] + 40] ^= 0x04;
  const std::string path = Put("list.mcap", bad);
  Result<BagListing> l = ListBag(path);
  ASSERT_TRUE(l.ok()) << l.error().message;
  ASSERT_EQ(l->damage.size(), 1u);
  ASSERT_EQ(l->warnings.size(), 1u);
  EXPECT_NE(l->warnings[0].find("/imu0 30"), std::string::npos) << l->warnings[0];
  BagReadOptions strict;
  strict.strict = true;
  EXPECT_FALSE(ListBag(path, strict).ok());
}

// Every 7th byte of a bag whose message records a checksum covers (bz2 chunks; MCAP chunks with
// their CRC) flipped in turn: the read never fails on the damage, and no row is one the
// undamaged bag does not hold. (A flipped topic name or lost channel may still leave no IMU
// topic to read: such a read fails with that reason, never with a row invented.)
TEST_F(BagRecoveryTest, EveryFlippedByteKeepsOnlyRowsOfTheUndamagedBag) {
  for (const std::string format : {"bz2.bag", "zstd.mcap", "lz4.mcap"}) {
    SCOPED_TRACE(format);
    Layout at;
    const bool ros1 = format == "bz2.bag";
    const std::string good = ros1 ? Ros1Bag("bz2", &at) : McapBag(format.substr(0, format.find('.')), &at);
    const std::vector<Row> all = ReadRows(Put("good." + format, good));
    std::size_t read = 0, tried = 0;
    for (std::size_t byte = 0; byte < good.size(); byte += 7) {
      std::string bad = good;
      bad[byte] ^= 0x5a;
      ++tried;
      Result<BagImuTable> r = ReadBagImu(Put("flip." + format, bad), {});
      if (!r.ok()) {
        // The schemas and channels are in the first chunk: with it lost no topic is known. A
        // flipped magic is not a bag.
        EXPECT_TRUE(r.error().message.find("no sensor_msgs/Imu topic in the bag") != std::string::npos ||
                    r.error().message.find("byte 0: not an MCAP") != std::string::npos ||
                    r.error().message.find("data section CRC") != std::string::npos)
            << r.error().message;
        continue;
      }
      ++read;
      ASSERT_TRUE(IsSubset(testing::BagRows(*r), all)) << "byte " << byte;
      ASSERT_LE(DamageLines(*r), 1u) << "byte " << byte;
    }
    EXPECT_GT(read, tried * 7 / 10);
  }
}

// Random damage of whole byte ranges (a range deleted, duplicated, overwritten with noise, or the
// file cut), 150 files per format: the reader never fails on the damage itself, and where the
// message records are covered by a checksum (bz2 chunks, MCAP chunk CRCs) every row read is a
// row of the undamaged bag.
TEST_F(BagRecoveryTest, RandomRangeDamageNeverInventsARow) {
  std::uint32_t seed = 2024;
  const auto next = [&seed](std::size_t n) { return static_cast<std::size_t>((seed = seed * 1664525u + 1013904223u) >> 8) % n; };
  for (const std::string format : {"none.bag", "bz2.bag", "zstd.mcap", "lz4.mcap"}) {
    SCOPED_TRACE(format);
    Layout at;
    const std::string method = format.substr(0, format.find('.'));
    const bool ros1 = format.find(".bag") != std::string::npos;
    const std::string good = ros1 ? Ros1Bag(method, &at) : McapBag(method, &at, true);
    const std::vector<Row> all = ReadRows(Put("good." + format, good));
    const bool checksummed = method != "none";
    std::size_t read = 0;
    for (int k = 0; k < 150; ++k) {
      std::string bad = good;
      const std::size_t from = 64 + next(good.size() - 64), len = 1 + next(2000);
      switch (k % 4) {
        case 0: bad.erase(from, len); break;
        case 1: bad.insert(from, good.substr(from, len)); break;
        case 2:
          for (std::size_t i = from; i < std::min(bad.size(), from + len); ++i) bad[i] = static_cast<char>(next(256));
          break;
        default: bad.resize(from); break;
      }
      Result<BagImuTable> r = ReadBagImu(Put("range." + format, bad), {});
      if (!r.ok()) {
        EXPECT_TRUE(r.error().message.find("no sensor_msgs/Imu topic in the bag") != std::string::npos ||
                    r.error().message.find(" has no messages") != std::string::npos ||
                    (!checksummed && (r.error().message.find(": message byte ") != std::string::npos ||
                                      r.error().message.find("NaN in") != std::string::npos ||
                                      r.error().message.find("infinity in") != std::string::npos)))  // a cut message in a "none" chunk
            << r.error().message;
        continue;
      }
      ++read;
      std::vector<Row> rows = testing::BagRows(*r);
      if (k % 4 == 1) rows.erase(std::unique(rows.begin(), rows.end()), rows.end());  // a duplicated record reads twice
      if (checksummed) {
        ASSERT_TRUE(IsSubset(rows, all)) << "damage " << k % 4 << " at " << from << " of " << len;
      }
      ASSERT_LE(DamageLines(*r), 1u);
    }
    EXPECT_GT(read, 100u);
  }
}

}  // namespace
}  // namespace gyrocomp
