// What every bag format shares: rosbag2's own test bags (tests/bags/rosbag2, Apache-2.0, an MCAP
// and a sqlite3 one) list as the metadata.yaml rosbag2 wrote says, a damaged .db3 is refused on
// one line, and the format is told by the first bytes. The formats themselves: cdr_test (message
// encodings), mcap_test (MCAP and rosbag2's per-file zstd), rosbag1_test (ROS 1 bags).
#include "gyrocomp/io/bag.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "bag_test_util.h"
#include "fixtures.h"

namespace gyrocomp {
namespace {

using testing::BagsDir;

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

class Rosbag2Test : public testing::FileTest {
 protected:
  Rosbag2Test() : FileTest("gyrocomp_bag_test") {}
};

TEST_F(Rosbag2Test, DamagedSqliteIsRefusedOnOneLine) {
  // The sqlite3 magic, then garbage: sqlite itself refuses it.
  const std::string path = Put("bad.db3", std::string("SQLite format 3\0", 16) + std::string(5000, '\x5a'));
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
