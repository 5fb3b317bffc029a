// Recovery of damaged rosbag2 sqlite3 files (BagReadOptions::strict false; ros2_sqlite_recovery.cc):
// the simulated IMU of tests/bags/make_imu_bags.py as a .db3 (--formats db3), then damaged as
// power loss or a bad disk leaves it (a zeroed table page, a page header overwritten, a file cut
// short, a message whose data no longer decode). Every row kept is a row of the undamaged file,
// bit for bit; the damage is listed as message id ranges, in one warning; strict mode refuses
// the same file naming where. A file whose schema page is gone is refused on one line either way.
#include <algorithm>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bag_test_util.h"
#include "fixtures.h"
#include "gyrocomp/io/bag.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

using testing::BagRow;
using testing::BagRows;
using testing::DamageLines;
using testing::IsSubset;


// sqlite3 fileformat2.html "1.3 The Database Header": page size at offset 16 (big-endian; 1 means
// 65536); "1.6 B-tree Pages": the page type byte first (at 100 on page 1), 0x0D a table leaf.
std::size_t PageSize(const std::string& db) {
  const std::size_t v = (static_cast<unsigned char>(db[16]) << 8) | static_cast<unsigned char>(db[17]);
  return v == 1 ? 65536 : v;
}
std::vector<std::size_t> TableLeafPages(const std::string& db) {  // 0-based page numbers, page 1 left out
  std::vector<std::size_t> pages;
  const std::size_t ps = PageSize(db);
  for (std::size_t p = 1; (p + 1) * ps <= db.size(); ++p) {
    if (db[p * ps] == 0x0D) pages.push_back(p);
  }
  return pages;
}
std::string ZeroPage(std::string db, std::size_t page) {
  std::fill_n(db.begin() + static_cast<std::ptrdiff_t>(page * PageSize(db)), PageSize(db), '\0');
  return db;
}

class Ros2SqliteRecoveryTest : public testing::FileTest {
 protected:
  Ros2SqliteRecoveryTest() : FileTest("gyrocomp_ros2_sqlite_recovery_test") {}
  // 20 s of /imu0 at 200 Hz, /imu0/temperature at 1 Hz and a 500-byte image every 10th IMU message:
  // 4420 rows in about 400 pages of 4096 bytes.
  static void SetUpTestSuite() {
    std::string out;
    if (testing::RunCommand(std::string(testing::kPython3) + " -c 'import numpy, sqlite3'", &out) != 0) {
      skip_ = "python3-numpy is not installed (scripts/install-deps.sh): " + out;
      return;
    }
    dir_ = testing::MakeTempDir("gyrocomp_ros2_sqlite_recovery_bags");
    const std::string script = testing::BagsDir() + "/make_imu_bags.py";
    if (testing::RunCommand(std::string(testing::kPython3) + " '" + script + "' '" + dir_ +
                                "' --seconds 20 --rate 200 --camera-bytes 500 --formats db3",
                            &out) != 0) {
      skip_ = "make_imu_bags.py failed: " + out;
    }
  }
  static void TearDownTestSuite() {
    if (!dir_.empty()) std::filesystem::remove_all(dir_);
  }
  void SetUp() override {
    if (!skip_.empty()) GTEST_SKIP() << skip_;
    FileTest::SetUp();
    bytes_ = testing::ReadFile(Db3());
    Result<BagImuTable> r = ReadBagImu(Db3(), {});
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_TRUE(r->damage.empty());
    original_ = BagRows(*r);
    ASSERT_EQ(original_.size(), 4000u);
  }
  static std::string Db3() { return dir_ + "/imu_db3/imu_db3_0.db3"; }

  // Reads the damaged bytes in recovery: every kept row one of the original's, one warning, the
  // damage as message id ranges; strict mode refuses them naming `strict_says`.
  BagImuTable Recover(const std::string& name, const std::string& damaged, const std::string& strict_says) {
    const std::string path = Put(name, damaged);
    Result<BagImuTable> r = ReadBagImu(path, {});
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    if (!r.ok()) return {};
    EXPECT_TRUE(IsSubset(BagRows(*r), original_)) << "a row that is not in the undamaged file";
    EXPECT_LT(r->table.num_rows(), original_.size());
    EXPECT_FALSE(r->damage.empty());
    for (const LogDamage& d : r->damage) EXPECT_TRUE(d.message_ids);
    EXPECT_EQ(DamageLines(*r), 1u);
    BagReadOptions strict;
    strict.strict = true;
    Result<BagImuTable> s = ReadBagImu(path, strict);
    EXPECT_FALSE(s.ok());
    if (!s.ok()) {
      EXPECT_NE(s.error().message.find(path + ": " + strict_says), std::string::npos) << s.error().message;
    }
    return std::move(*r);
  }

  // Messages counted by ListBag plus the ids recorded lost: every message of the original (rosbag2
  // numbers its messages 1, 2, 3, ...), when every damage is closed by a row read after it.
  static std::size_t CountedAndLost(const BagListing& l) {
    std::size_t n = 0;
    for (const BagTopicInfo& t : l.topics) n += t.messages;
    for (const LogDamage& d : l.damage) n += d.records_unidentified;
    return n;
  }

  static std::string dir_, skip_;
  std::string bytes_;
  std::vector<BagRow> original_;
};
std::string Ros2SqliteRecoveryTest::dir_, Ros2SqliteRecoveryTest::skip_;

TEST_F(Ros2SqliteRecoveryTest, ZeroedTablePageLosesOnlyItsRows) {
  const std::vector<std::size_t> leaves = TableLeafPages(bytes_);
  ASSERT_GT(leaves.size(), 100u);
  const BagImuTable t = Recover("zeroed.db3", ZeroPage(bytes_, leaves[leaves.size() / 2]), "table 'messages' after message id ");
  ASSERT_EQ(t.damage.size(), 1u);
  const LogDamage& d = t.damage[0];
  EXPECT_GT(d.end, d.begin);
  EXPECT_EQ(d.records_unidentified, d.end - d.begin);
  // A 4096-byte page holds at most 13 IMU rows (over 300 bytes each).
  EXPECT_LE(original_.size() - t.table.num_rows(), 13u);
  EXPECT_NE(t.warnings[0].find("message ids " + std::to_string(d.begin) + "-" + std::to_string(d.end)), std::string::npos)
      << t.warnings[0];
  Result<BagListing> l = ListBag(Put("zeroed_list.db3", ZeroPage(bytes_, leaves[leaves.size() / 2])), {});
  ASSERT_TRUE(l.ok()) << l.error().message;
  EXPECT_EQ(CountedAndLost(*l), 4420u);
}

TEST_F(Ros2SqliteRecoveryTest, TwoBrokenPageHeadersAreTwoRanges) {
  const std::vector<std::size_t> leaves = TableLeafPages(bytes_);
  std::string damaged = bytes_;
  for (const std::size_t page : {leaves[leaves.size() / 4], leaves[3 * leaves.size() / 4]}) {
    std::fill_n(damaged.begin() + static_cast<std::ptrdiff_t>(page * PageSize(bytes_)), 8, '\xff');
  }
  const BagImuTable t = Recover("headers.db3", damaged, "table 'messages' after message id ");
  ASSERT_EQ(t.damage.size(), 2u);
  EXPECT_LT(t.damage[0].end, t.damage[1].begin);
  Result<BagListing> l = ListBag(Put("headers_list.db3", damaged), {});
  ASSERT_TRUE(l.ok()) << l.error().message;
  EXPECT_EQ(CountedAndLost(*l), 4420u);
}

TEST_F(Ros2SqliteRecoveryTest, FileCutShortKeepsTheRowsBeforeTheCut) {
  // Power lost while the file was copied: the pages after the cut read as zeros.
  // Strict mode leaves SQLite's own check on: a file shorter than its header says is refused whole.
  const BagImuTable t = Recover("cut.db3", bytes_.substr(0, bytes_.size() / 2),
                                "reading table 'topics': database disk image is malformed");
  EXPECT_GT(t.table.num_rows(), original_.size() / 3);
}

TEST_F(Ros2SqliteRecoveryTest, MessageThatDoesNotDecodeIsTheOnlyRowLost) {
  // The 100th /imu0 message's data replaced by its 4-byte CDR encapsulation alone: SQLite reads
  // the row, the CDR decoder refuses it (SQLite keeps no checksum of a row's data).
  const std::string path = Put("short.db3", bytes_);
  std::string out;
  ASSERT_EQ(testing::RunCommand(std::string(testing::kPython3) + " -c \"import sqlite3; d = sqlite3.connect('" + path +
                                    "'); d.execute(\\\"UPDATE messages SET data = X'00010000' WHERE id = (SELECT id FROM "
                                    "messages WHERE topic_id = (SELECT id FROM topics WHERE name = '/imu0') ORDER BY id "
                                    "LIMIT 1 OFFSET 99)\\\"); d.commit()\"",
                                &out),
            0)
      << out;
  const BagImuTable t = Recover("short2.db3", testing::ReadFile(path), "message id ");
  EXPECT_EQ(t.table.num_rows(), original_.size() - 1);
  ASSERT_EQ(t.damage.size(), 1u);
  EXPECT_EQ(t.damage[0].end, t.damage[0].begin + 1);
  EXPECT_EQ(testing::Lost(t.damage[0], "/imu0"), 1u);
  EXPECT_EQ(t.damage[0].records_unidentified, 0u);
}

TEST_F(Ros2SqliteRecoveryTest, DestroyedSchemaPageIsRefusedOnOneLine) {
  // Page 1 (the database header and the schema) gone: nothing can be read, strict or not.
  std::string no_schema = bytes_;
  std::fill(no_schema.begin() + 100, no_schema.begin() + static_cast<std::ptrdiff_t>(PageSize(bytes_)), '\0');
  for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"no_schema.db3", no_schema},
                                    {"no_header.db3", ZeroPage(bytes_, 0)}}) {
    SCOPED_TRACE(name);
    const std::string path = Put(name, bytes);
    Result<BagImuTable> r = ReadBagImu(path, {});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message.find(path + ": "), 0u) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
  }
}

TEST_F(Ros2SqliteRecoveryTest, RandomPageDamageNeverInventsARow) {
  // Whole-page damage SQLite can see (a zeroed page, an overwritten page header, the file cut at
  // any byte): whatever is read is rows of the original. (Bytes changed inside a row's data are
  // not in this list: SQLite keeps no checksum, so such a row can only be refused if it no longer
  // decodes.)
  std::mt19937 rng(7);
  const std::size_t ps = PageSize(bytes_), pages = bytes_.size() / ps;
  std::size_t read = 0;
  for (int k = 0; k < 40; ++k) {
    const std::size_t page = 1 + rng() % (pages - 1);
    std::string damaged = bytes_;
    switch (k % 3) {
      case 0: damaged = ZeroPage(bytes_, page); break;
      case 1: std::fill_n(damaged.begin() + static_cast<std::ptrdiff_t>(page * ps), 1 + rng() % 12, static_cast<char>(rng())); break;
      default: damaged.resize(page * ps + rng() % ps); break;
    }
    SCOPED_TRACE("case " + std::to_string(k) + ", page " + std::to_string(page));
    Result<BagImuTable> r = ReadBagImu(Put("random.db3", damaged), {});
    if (!r.ok()) continue;  // the topics page, say: refused
    ++read;
    ASSERT_TRUE(IsSubset(BagRows(*r), original_));
  }
  EXPECT_GT(read, 30u);
}

class Ros2SqliteRecoveryCliTest : public Ros2SqliteRecoveryTest {
 protected:
  void SetUp() override {
    if (const std::string why = testing::CliSkipReason(); !why.empty()) GTEST_SKIP() << why;
    Ros2SqliteRecoveryTest::SetUp();
  }
};

TEST_F(Ros2SqliteRecoveryCliTest, DamagedDb3WarnsOnceAndStrictRefuses) {
  const std::vector<std::size_t> leaves = TableLeafPages(bytes_);
  const std::string path = Put("zeroed.db3", ZeroPage(bytes_, leaves[leaves.size() / 2]));
  std::string out;
  ASSERT_EQ(testing::RunCli("convert -i '" + path + "' -o '" + dir_ + "/z.csv' --json '" + dir_ + "/z.json'", &out), 0) << out;
  std::size_t lines = 0;
  for (std::size_t at = out.find(": damaged: "); at != std::string::npos; at = out.find(": damaged: ", at + 1)) ++lines;
  EXPECT_EQ(lines, 1u) << out;
  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/z.json");
  ASSERT_EQ(j["damage"].size(), 1u) << j.dump();
  EXPECT_GT(j["damage"][0]["end_message_id"].get<std::size_t>(), j["damage"][0]["begin_message_id"].get<std::size_t>());
  EXPECT_FALSE(j["damage"][0].contains("begin_byte"));
  ASSERT_EQ(testing::RunCli("inspect -i '" + path + "'", &out), 0) << out;
  EXPECT_NE(out.find("damage: 1 message id range(s), "), std::string::npos) << out;
  testing::ExpectCliRefused("convert -i '" + path + "' --strict -o '" + dir_ + "/s.csv'",
                            {path + ": table 'messages' after message id ", "(a damaged sqlite3 file)"});
}

}  // namespace
}  // namespace gyrocomp
