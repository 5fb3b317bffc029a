// ROS bags end to end through the built CLI (docs/reference/input-formats.md "ROS bags"): the same
// simulated six-axis IMU written as a ROS 1 bag by Debian's python3-rosbag (none / bz2 / lz4
// chunks), as MCAP (none / zstd / lz4, written from the spec by tests/bags/make_imu_bags.py) and as
// a rosbag2 sqlite3 folder reads back value for value (the values the script wrote; for ROS 1 also
// what Python rosbag reads from the bag, the independent reference), and gives identical Allan
// results and noise files in every format, equal to those of the CSV extract. Skipped, with the
// reason, when python3-rosbag / python3-sensor-msgs / python3-roslz4 are not installed.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kBags = {"imu.bag",  "imu_bz2.bag",   "imu_lz4.bag", "imu.mcap",
                                        "imu_zstd.mcap", "imu_lz4.mcap", "imu_db3",     "imu_db3/imu_db3_0.db3"};
constexpr std::size_t kRows = 60 * 200;

class BagCliTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    skip_ = testing::CliSkipReason();
    if (!skip_.empty()) return;
    std::string out;
    if (testing::RunCommand(std::string(testing::kPython3) + " -c 'import rosbag, roslz4, sensor_msgs.msg, numpy'", &out) != 0) {
      skip_ = "python3-rosbag, python3-roslz4 or python3-sensor-msgs is not installed (scripts/install-deps.sh): " + out;
      return;
    }
    dir_ = testing::MakeTempDir("gyrocomp_bag_cli_test");
    // 60 s at 200 Hz, a 1 Hz temperature topic and a 500-byte image every 10th IMU message.
    const std::string cmd = std::string(testing::kPython3) + " '" + Script() + "' '" + dir_ + "' --seconds 60 --rate 200 --camera-bytes 500";
    if (testing::RunCommand(cmd, &out) != 0) skip_ = "make_imu_bags.py failed: " + out;
  }
  static void TearDownTestSuite() {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  void SetUp() override {
    if (!skip_.empty()) GTEST_SKIP() << skip_;
  }
  static std::string Script() { return testing::BagsDir() + "/make_imu_bags.py"; }
  static std::string P(const std::string& name) { return dir_ + "/" + name; }
  static std::string Flat(const std::string& name) {
    std::string s = name;
    std::replace(s.begin(), s.end(), '/', '_');
    return s;
  }
  int Run(const std::string& args, std::string* out) { return testing::RunCli(args, out); }
  void ExpectRefused(const std::string& args, const std::vector<std::string>& what) {
    testing::ExpectCliRefused(args, what);
  }
  static std::string dir_, skip_;
};
std::string BagCliTest::dir_, BagCliTest::skip_;

// Exact equality: both sides hold 17-significant-digit text of the same doubles.
void ExpectColumnsEqual(const std::map<std::string, std::vector<double>>& got,
                        const std::map<std::string, std::vector<double>>& want, const std::vector<std::string>& names,
                        const std::string& what) {
  for (const std::string& n : names) {
    ASSERT_TRUE(got.count(n)) << what << ": no column " << n;
    ASSERT_TRUE(want.count(n)) << what << ": reference has no column " << n;
    ASSERT_EQ(got.at(n).size(), want.at(n).size()) << what << " " << n;
    for (std::size_t i = 0; i < want.at(n).size(); ++i) {
      ASSERT_EQ(got.at(n)[i], want.at(n)[i]) << what << ": column " << n << " row " << i;
    }
  }
}

TEST_F(BagCliTest, EveryFormatConvertsToTheValuesWritten) {
  const auto want = testing::ReadGoldenCsv(P("imu.csv"));
  ASSERT_EQ(want.at("time_s").size(), kRows);
  for (const std::string& bag : kBags) {
    std::string out;
    const std::string csv = P("convert_" + Flat(bag) + ".csv");
    ASSERT_EQ(Run("convert -i '" + P(bag) + "' --topic /imu0 -o '" + csv + "'", &out), 0) << bag << ": " << out;
    ExpectColumnsEqual(testing::ReadGoldenCsv(csv), want,
                       {"time_s", "x_rad_s", "y_rad_s", "z_rad_s", "x_m_s2", "y_m_s2", "z_m_s2", "temp_c"}, bag);
    // --time receive: the bag's record time (2 ms after the stamp in the script).
    ASSERT_EQ(Run("convert -i '" + P(bag) + "' --time receive -o '" + csv + "'", &out), 0) << bag << ": " << out;
    const auto receive = testing::ReadGoldenCsv(csv);
    ASSERT_EQ(receive.at("time_s"), want.at("receive_time_s")) << bag;
  }
}

TEST_F(BagCliTest, Ros1BagsEqualPythonRosbagsReading) {
  for (const std::string bag : {"imu.bag", "imu_bz2.bag", "imu_lz4.bag"}) {
    std::string out;
    const std::string ref = P("rosbag_" + Flat(bag) + ".csv");
    ASSERT_EQ(testing::RunCommand(std::string(testing::kPython3) + " '" + Script() + "' --dump-ros1 '" + P(bag) + "' /imu0 '" + ref + "'", &out), 0) << out;
    const std::string csv = P("convert_ref_" + Flat(bag) + ".csv");
    ASSERT_EQ(Run("convert -i '" + P(bag) + "' -o '" + csv + "'", &out), 0) << out;
    ExpectColumnsEqual(testing::ReadGoldenCsv(csv), testing::ReadGoldenCsv(ref),
                       {"time_s", "x_rad_s", "y_rad_s", "z_rad_s", "x_m_s2", "y_m_s2", "z_m_s2"}, bag);
  }
}

// Drops what names the input or times the run.
void Strip(nlohmann::json* j) {
  if (j->is_object()) {
    for (const std::string key : {"input", "seconds", "source", "sampling"}) j->erase(key);
    std::vector<std::string> timing;
    for (auto& [k, v] : j->items()) {
      if (k.size() > 8 && k.substr(k.size() - 8) == "_seconds") timing.push_back(k);
      else Strip(&v);
    }
    for (const std::string& k : timing) j->erase(k);
  } else if (j->is_array()) {
    for (auto& v : *j) Strip(&v);
  }
}

// A noise file without its "written by ... from <input>" line.
std::string WithoutSource(const std::string& text) {
  std::string out, line;
  std::istringstream in(text);
  while (std::getline(in, line)) {
    if (line.find("written by gyrocomp") == std::string::npos) out += line + "\n";
  }
  return out;
}

TEST_F(BagCliTest, AllanIsIdenticalInEveryFormatAndEqualsTheCsvExtract) {
  std::string out;
  const std::string files = " --kalibr-yaml '" + P("k_csv.yaml") + "' --openvins-yaml '" + P("o_csv.yaml") + "' --vins-yaml '" +
                            P("v_csv.yaml") + "' --rostopic /imu0";
  ASSERT_EQ(Run("allan -i '" + P("imu.csv") + "' --rate-col x_rad_s,y_rad_s,z_rad_s --rate-unit rads "
                "--accel-col x_m_s2,y_m_s2,z_m_s2 --json '" + P("a_csv.json") + "'" + files, &out), 0) << out;
  nlohmann::json ref = testing::ReadJsonFile(P("a_csv.json"));
  // The CSV run has no accel_axes / gyro_noise (those are the bag's six-axis outputs): compare
  // the gyro axes with it, and the whole JSON between bags.
  Strip(&ref);
  ASSERT_TRUE(ref.contains("axes"));
  nlohmann::json first;
  for (const std::string& bag : kBags) {
    SCOPED_TRACE(bag);
    const std::string f = Flat(bag);
    ASSERT_EQ(Run("allan -i '" + P(bag) + "' --topic /imu0 --json '" + P("a_" + f + ".json") + "' --kalibr-yaml '" +
                      P("k_" + f + ".yaml") + "' --openvins-yaml '" + P("o_" + f + ".yaml") + "' --vins-yaml '" +
                      P("v_" + f + ".yaml") + "'", &out), 0) << out;
    nlohmann::json j = testing::ReadJsonFile(P("a_" + f + ".json"));
    Strip(&j);
    ASSERT_EQ(j["axes"].size(), 3u);
    ASSERT_EQ(j["accel_axes"].size(), 3u);
    EXPECT_EQ(j["axes"], ref["axes"]);
    EXPECT_EQ(j["fs_hz"], ref["fs_hz"]);
    if (first.is_null()) first = j;
    EXPECT_EQ(j, first);
    for (const char* k : {"k_", "o_", "v_"}) {
      EXPECT_EQ(WithoutSource(testing::ReadFile(P(k + f + ".yaml"))),
                WithoutSource(testing::ReadFile(P(std::string(k) + "csv.yaml"))))
          << k;
    }
  }
  // The accelerometer figures are the Kalibr file's (the largest axis).
  double largest = 0;
  for (const auto& [name, axis] : first["accel_axes"].items()) {
    largest = std::max(largest, axis["noise_density_m_s2_per_sqrt_hz"].get<double>());
  }
  EXPECT_NE(
      testing::ReadFile(P("k_imu.mcap.yaml")).find("accelerometer_noise_density: " + nlohmann::json(largest).dump()),
      std::string::npos);
}

TEST_F(BagCliTest, InspectListsTopicsAndHostileInputIsOneLineExit2) {
  std::string out;
  ASSERT_EQ(Run("inspect -i '" + P("imu_zstd.mcap") + "' --json '" + P("i.json") + "'", &out), 0) << out;
  const nlohmann::json j = testing::ReadJsonFile(P("i.json"));
  ASSERT_EQ(j["topics"].size(), 3u);
  for (const auto& t : j["topics"]) {
    if (t["topic"] == "/imu0") {
      EXPECT_EQ(t["messages"].get<std::size_t>(), kRows);
      EXPECT_NEAR(t["rate_hz"].get<double>(), 200.0, 1e-9);
      EXPECT_TRUE(t["imu"].get<bool>());
    }
  }
  ExpectRefused("allan -i '" + P("imu.mcap") + "' --topic /imu0/temperature",
                {"topic /imu0/temperature has type sensor_msgs/msg/Temperature, not sensor_msgs/Imu"});
  ExpectRefused("allan -i '" + P("imu.bag") + "' --topic /nope",
                {"no sensor_msgs/Imu topic /nope in the bag; IMU topics: /imu0"});
  // A truncated copy, cut in the middle of a chunk: refused with --strict.
  const std::string bytes = testing::ReadFile(P("imu_zstd.mcap"));
  std::ofstream(P("cut.mcap"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  ExpectRefused("allan -i '" + P("cut.mcap") + "' --strict --json '" + P("cut.json") + "'", {"runs past the end of the file"});
  EXPECT_FALSE(fs::exists(P("cut.json")));
  const std::string bag = testing::ReadFile(P("imu_bz2.bag"));
  std::ofstream(P("cut.bag"), std::ios::binary) << bag.substr(0, bag.size() / 2);
  ExpectRefused("convert -i '" + P("cut.bag") + "' --strict -o '" + P("cut.csv") + "'", {"truncated record"});
  EXPECT_FALSE(fs::exists(P("cut.csv")));
}

TEST_F(BagCliTest, DamagedBagsKeepTheIntactRowsWithOneWarning) {
  // The same truncated copies without --strict: the rows before the cut, one warning line, and
  // the damage in --json.
  for (const std::string name : {"imu_bz2.bag", "imu_zstd.mcap"}) {
    SCOPED_TRACE(name);
    const std::string bytes = testing::ReadFile(P(name));
    const std::string cut = P("half_" + name);
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    std::string out;
    ASSERT_EQ(Run("convert -i '" + cut + "' -o '" + P("half.csv") + "' --json '" + P("half.json") + "'", &out), 0) << out;
    std::size_t lines = 0;
    for (std::size_t at = out.find(": damaged: "); at != std::string::npos; at = out.find(": damaged: ", at + 1)) ++lines;
    EXPECT_EQ(lines, 1u) << out;
    const nlohmann::json j = testing::ReadJsonFile(P("half.json"));
    ASSERT_EQ(j["damage"].size(), 1u) << j.dump();
    EXPECT_EQ(j["damage"][0]["end_byte"].get<std::size_t>(), bytes.size() / 2);
    EXPECT_GT(j["rows"].get<std::size_t>(), kRows / 3);
    EXPECT_LT(j["rows"].get<std::size_t>(), kRows);
    ASSERT_EQ(Run("inspect -i '" + cut + "' --json '" + P("half_i.json") + "'", &out), 0) << out;
    EXPECT_EQ(testing::ReadJsonFile(P("half_i.json"))["damage"].size(), 1u);
  }
}

}  // namespace
}  // namespace gyrocomp
