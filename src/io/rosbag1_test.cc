// The ROS 1 bag v2.0 reader on bags built here record by record (wiki.ros.org/Bags/Format/2.0):
// none and bz2 chunks, a truncated bag and a bz2 bomb refused with the byte offset (strict), and the
// index's message counts taken as a hint capped by the file size.
#include <bzlib.h>

#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "bag_test_util.h"
#include "fixtures.h"
#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/cdr.h"

namespace gyrocomp {
namespace {

using testing::ExpectSamples;
using testing::Le;
using testing::Field;
using testing::IntField;
using testing::Ros1Record;
using testing::Op;
using testing::Sample;

class Ros1BagTest : public testing::FileTest {
 protected:
  Ros1BagTest() : FileTest("gyrocomp_bag_test") {}
};

// ---- ROS 1 bag v2.0 built record by record (wiki.ros.org/Bags/Format/2.0) ----


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

TEST_F(Ros1BagTest, Ros1BagsNoneAndBz2ReadTheSameRowsAndRefuseDamage) {
  for (const std::string compression : {"none", "bz2"}) {
    SCOPED_TRACE(compression);
    Result<BagImuTable> r = ReadBagImu(Put("x.bag", Ros1Bag(120, compression)), {});
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->format, BagFormat::kRos1);
    ExpectSamples(*r, 120);
  }
  const std::string good = Ros1Bag(120, "bz2");
  // Strict mode (recovery: bag_recovery_test.cc). The chunk record starts after the version line
  // (13) and the 4096-byte bag header record.
  BagReadOptions strict;
  strict.strict = true;
  Result<BagImuTable> r = ReadBagImu(Put("cut.bag", good.substr(0, good.size() - 10)), strict);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("byte 4109: truncated record"), std::string::npos) << r.error().message;
  r = ReadBagImu(Put("bomb.bag", Ros1Bag(120, "bz2", 1000u)), strict);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("byte 4109: chunk: bz2: the data decompresses to more than the 1000 bytes"), std::string::npos)
      << r.error().message;
}

// Records what the reader announces of each channel (the index's message counts let the
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

TEST_F(Ros1BagTest, Ros1IndexCountsAreAHintCappedByTheFileSize) {
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
    Result<BagImuTable> r = ReadBagImu(Put("indexed.bag", bag), {});
    ASSERT_TRUE(r.ok()) << r.error().message;
    ExpectSamples(*r, 120);
  }
}

}  // namespace
}  // namespace gyrocomp
