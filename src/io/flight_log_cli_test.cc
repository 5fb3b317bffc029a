// Flight-controller logs through the built CLI: convert equals the reference extracts
// (pyulog, pymavlink) value for value, inspect lists instances and compensation parameters, a
// corrupt log is one error line with the byte offset and exit 2, and simulate -o run.ulg -> fit
// gives the model the CSV of the same run gives (ULog -> fit end to end).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "gyrocomp/core/units.h"
#include "gyrocomp/io/io.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

class FlightLogCliTest : public testing::CliTest {
 protected:
  FlightLogCliTest() : CliTest("gyrocomp_flight_log_cli_test") {}
};

TEST_F(FlightLogCliTest, ConvertEqualsPyulogExtractForEachInstance) {
  for (int m = 0; m < 3; ++m) {
    const std::string out = dir_ + "/g" + std::to_string(m) + ".csv";
    std::string log;
    ASSERT_EQ(Run("convert -i '" + testing::FieldlogPath("sample_log_small.ulg") + "' --instance " + std::to_string(m) + " -o '" +
                      out + "'", &log), 0) << log;
    const auto got = testing::ReadGoldenCsv(out);
    const auto want = testing::ReadGoldenCsv(testing::FieldlogPath("sample_log_small.ulg.sensor_gyro_" + std::to_string(m) + ".csv"));
    ASSERT_EQ(got.at("time_s").size(), want.at("timestamp_us").size());
    for (std::size_t i = 0; i < want.at("timestamp_us").size(); ++i) {
      // time_s = timestamp_us / 1e6 printed round-trip: back to the integer microsecond exactly.
      EXPECT_EQ(std::llround(got.at("time_s")[i] * 1e6), std::llround(want.at("timestamp_us")[i]));
      EXPECT_EQ(got.at("x_rad_s")[i], want.at("x_rad_s")[i]);
      EXPECT_EQ(got.at("y_rad_s")[i], want.at("y_rad_s")[i]);
      EXPECT_EQ(got.at("z_rad_s")[i], want.at("z_rad_s")[i]);
      EXPECT_EQ(got.at("temp_c")[i], want.at("temperature_c")[i]);
    }
  }
}

TEST_F(FlightLogCliTest, ConvertEqualsDfReaderExtract) {
  const std::string bin = testing::SharedFieldlogsDir() + "/ardupilot/backend_log_80k.bin";
  if (!fs::exists(bin)) GTEST_SKIP() << "../shared/fieldlogs absent (GPL-3.0 sample, not in the repository)";
  const auto want = testing::ReadGoldenCsv(bin + ".IMU.csv");
  for (int inst = 0; inst < 2; ++inst) {
    const std::string out = dir_ + "/imu" + std::to_string(inst) + ".csv";
    std::string log;
    ASSERT_EQ(Run("convert -i '" + bin + "' --instance " + std::to_string(inst) + " -o '" + out + "'", &log), 0) << log;
    // AHRS_ORIENTATION 0 and INS_TCAL off in this log: the rows are the sensor frame as logged
    // (DFReader's values below), nothing to warn about.
    EXPECT_EQ(log.find("WARNING"), std::string::npos) << log;
    const auto got = testing::ReadGoldenCsv(out);
    std::size_t k = 0;
    for (std::size_t r = 0; r < want.at("I").size(); ++r) {
      if (want.at("I")[r] != inst) continue;
      ASSERT_LT(k, got.at("time_s").size());
      EXPECT_EQ(std::llround(got.at("time_s")[k] * 1e6), std::llround(want.at("TimeUS")[r]));
      EXPECT_EQ(got.at("x_rad_s")[k], want.at("GyrX")[r]);
      EXPECT_EQ(got.at("y_rad_s")[k], want.at("GyrY")[r]);
      EXPECT_EQ(got.at("z_rad_s")[k], want.at("GyrZ")[r]);
      EXPECT_EQ(got.at("temp_c")[k], want.at("T")[r]);
      ++k;
    }
    EXPECT_EQ(k, got.at("time_s").size());
  }
}

TEST_F(FlightLogCliTest, InspectListsInstancesAndCompensation) {
  std::string log;
  const std::string json = dir_ + "/i.json";
  ASSERT_EQ(Run("inspect -i '" + testing::FieldlogPath("sample_log_small.ulg") + "' --json '" + json + "'", &log), 0) << log;
  const auto j = testing::ReadJsonFile(json);
  EXPECT_EQ(j["format"], "ulog");
  ASSERT_EQ(j["gyro_instances"].size(), 4u);  // sensor_gyro 0, 1, 2 and sensor_combined 0
  EXPECT_EQ(j["gyro_instances"][1]["device_id"], 3670050);
  EXPECT_EQ(j["gyro_instances"][1]["rows"], 6);
  EXPECT_TRUE(j["gyro_instances"][3]["temp_range_c"].is_null());
  EXPECT_EQ(j["compensation_parameters"]["TC_G_ENABLE"], 0.0);
  EXPECT_EQ(j["dropouts"]["count"], 1);
  EXPECT_NE(log.find("sensor_gyro"), std::string::npos);
}

TEST_F(FlightLogCliTest, CorruptLogIsOneErrorLineWithTheOffset) {
  std::ifstream in(testing::FieldlogPath("sample_log_small.ulg"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  bytes[16 + 3 + 8] = 2;  // 'B' message (first, at byte 16): incompat_flags[0] bit 1, unknown
  const std::string bad = dir_ + "/bad.ulg";
  std::ofstream(bad, std::ios::binary) << bytes;
  std::string log;
  EXPECT_EQ(Run("allan -i '" + bad + "' -o '" + dir_ + "/out.csv'", &log), 2);
  EXPECT_EQ(log, "gyrocomp allan: error: " + bad + ": byte 16: unknown incompatible flag bits set: cannot parse the log\n");
  EXPECT_FALSE(fs::exists(dir_ + "/out.csv"));
  // Several instances without --instance: refused, listed.
  EXPECT_EQ(Run("allan -i '" + testing::FieldlogPath("sample_log_small.ulg") + "' -o '" + dir_ + "/out.csv'", &log), 2);
  EXPECT_NE(log.find("3 sensor_gyro instances: 0 (6 rows, device_id 2424842)"), std::string::npos) << log;
}

// simulate -o run.ulg and -o run.csv with the same seed: the ULog holds the CSV's rate (x) and
// temperature as float32, and a polynomial fit (deterministic least squares) on either gives the
// same model within float32 rounding of the data.
TEST_F(FlightLogCliTest, SimulatedULogFitsLikeTheCsv) {
  const std::string sim = "simulate --profile ramp --fs 10 --seed 3 --ramp-end 50 ";
  std::string log;
  ASSERT_EQ(Run(sim + "-o '" + dir_ + "/run.ulg'", &log), 0) << log;
  ASSERT_EQ(Run(sim + "-o '" + dir_ + "/run.csv'", &log), 0) << log;
  ASSERT_EQ(Run("convert -i '" + dir_ + "/run.ulg' -o '" + dir_ + "/conv.csv'", &log), 0) << log;
  const auto csv = testing::ReadGoldenCsv(dir_ + "/run.csv");
  const auto conv = testing::ReadGoldenCsv(dir_ + "/conv.csv");
  const double rad_per_deg = 1.0 / units::ToDegPerSec(RateUnit::kRadPerSec);
  ASSERT_EQ(conv.at("time_s").size(), csv.at("time_s").size());
  for (std::size_t i = 0; i < csv.at("time_s").size(); i += 97) {
    ASSERT_EQ(conv.at("x_rad_s")[i], static_cast<double>(static_cast<float>(csv.at("rate_dps")[i] * rad_per_deg)));
    ASSERT_EQ(conv.at("temp_c")[i], static_cast<double>(static_cast<float>(csv.at("temp_c")[i])));
    ASSERT_EQ(std::llround(conv.at("time_s")[i] * 1e6), std::llround(csv.at("time_s")[i] * 1e6));
  }
  ASSERT_EQ(Run("fit -i '" + dir_ + "/run.ulg' --rate-col x_rad_s --model poly -o '" + dir_ + "/mu.json'", &log), 0)
      << log;
  ASSERT_EQ(Run("fit -i '" + dir_ + "/run.csv' --model poly -o '" + dir_ + "/mc.json'", &log), 0) << log;
  const auto mu = testing::ReadJsonFile(dir_ + "/mu.json");
  const auto mc = testing::ReadJsonFile(dir_ + "/mc.json");
  // Model file schema 2: one entry per axis, the polynomial in "structured".
  const auto& tu = mu["axes"][0]["structured"]["terms"];
  const auto& tc = mc["axes"][0]["structured"]["terms"];
  ASSERT_GT(tc.size(), 1u) << mc.dump();
  ASSERT_EQ(tu.size(), tc.size());
  for (std::size_t k = 0; k < tu.size(); ++k) {
    // float32 keeps ~7 digits of each sample; the least-squares coefficients of 46 000 such
    // samples move by far less than 1e-5 of the constant term (measured: ~2e-8 of it).
    EXPECT_NEAR(tu[k]["coefficient"].get<double>(), tc[k]["coefficient"].get<double>(),
                1e-5 * std::abs(tc[0]["coefficient"].get<double>()))
        << "term " << k;
  }
}

// The hook is shared: commands that take -i read a ULog like a CSV (three axes by default).
TEST_F(FlightLogCliTest, LogCommandsReadAULog) {
  std::string log;
  const std::string ulg = dir_ + "/soak.ulg";
  ASSERT_EQ(Run("simulate --profile ramp --ramp-end 40 --fs 10 --seed 5 -o '" + ulg + "'", &log), 0) << log;
  ASSERT_EQ(Run("allan -i '" + ulg + "' --json '" + dir_ + "/a.json'", &log), 0) << log;
  const auto a = testing::ReadJsonFile(dir_ + "/a.json");
  EXPECT_TRUE(a["axes"].contains("x_rad_s") && a["axes"].contains("y_rad_s") && a["axes"].contains("z_rad_s")) << a.dump();
  ASSERT_EQ(Run("denoise -i '" + ulg + "' --method wavelet -o '" + dir_ + "/d.csv'", &log), 0) << log;
  EXPECT_EQ(testing::ReadGoldenCsv(dir_ + "/d.csv").count("z_rad_s_denoised"), 1u);
  ASSERT_EQ(Run("fit -i '" + ulg + "' --rate-col z_rad_s --model poly -o '" + dir_ + "/m.json'", &log), 0) << log;
  ASSERT_EQ(Run("apply -m '" + dir_ + "/m.json' -i '" + ulg + "' --rate-col z_rad_s -o '" + dir_ + "/c.csv'", &log), 0)
      << log;
  EXPECT_EQ(testing::ReadGoldenCsv(dir_ + "/c.csv").count("compensated_dps"), 1u);
  // A --rate-unit that contradicts the log's rad/s is refused.
  EXPECT_EQ(Run("fit -i '" + ulg + "' --rate-col z_rad_s --rate-unit dps --model poly -o '" + dir_ + "/m2.json'", &log),
            2);
  EXPECT_NE(log.find("is a flight-controller log, whose rates are rad/s"), std::string::npos) << log;
}

}  // namespace
}  // namespace gyrocomp
