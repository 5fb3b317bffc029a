// DataFlash reader: value-for-value against pymavlink DFReader's extracts of real ArduPilot logs
// (../shared/fieldlogs, GPL/LGPL: not in the repository, skipped when absent), and on logs built
// here byte by byte (FMT, PARM, IMU with and without an instance field, truncation, corruption).
#include "gyrocomp/io/dataflash.h"

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/io/flight_log.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

std::string SharedFixture(const std::string& name) {
  return testing::SharedFieldlogsDir() + "/ardupilot/" + name;
}

void ExpectEqualsDfReaderCsv(const DataFlashContents& log, const std::string& csv_path) {
  const auto csv = testing::ReadGoldenCsv(csv_path);
  // The CSV interleaves instances in file order; the reader splits them by instance I.
  std::map<int, std::size_t> next;
  for (std::size_t r = 0; r < csv.at("TimeUS").size(); ++r) {
    const int inst = static_cast<int>(csv.at("I")[r]);
    const DataFlashImuSeries* s = nullptr;
    for (const auto& imu : log.imus) {
      if (imu.instance == inst) s = &imu;
    }
    ASSERT_NE(s, nullptr) << "instance " << inst;
    const std::size_t i = next[inst]++;
    ASSERT_LT(i, s->time_us.size());
    // Exact: the CSV holds repr() of each float32 widened to double.
    EXPECT_EQ(static_cast<double>(s->time_us[i]), csv.at("TimeUS")[r]) << "row " << r;
    EXPECT_EQ(s->gyr_x_rad_s[i], csv.at("GyrX")[r]) << "row " << r;
    EXPECT_EQ(s->gyr_y_rad_s[i], csv.at("GyrY")[r]) << "row " << r;
    EXPECT_EQ(s->gyr_z_rad_s[i], csv.at("GyrZ")[r]) << "row " << r;
    EXPECT_EQ(s->temp_c[i], csv.at("T")[r]) << "row " << r;
  }
  std::size_t rows = 0;
  for (const auto& imu : log.imus) rows += imu.time_us.size();
  EXPECT_EQ(rows, csv.at("TimeUS").size());
}

TEST(DataFlashTest, ModernLogEqualsDfReaderExtract) {
  const std::string path = SharedFixture("backend_log_80k.bin");
  if (!std::ifstream(path)) GTEST_SKIP() << "../shared/fieldlogs absent (GPL-3.0 sample, not in the repository)";
  Result<DataFlashContents> log = ReadDataFlash(path);
  ASSERT_TRUE(log.ok()) << log.error().message;
  // The fixtures README says the file ends on a record boundary; it ends with the first 2 bytes
  // (A3 95) of a next record's header, which DFReader skips silently and this reader reports.
  ASSERT_EQ(log->warnings.size(), 1u);
  EXPECT_NE(log->warnings[0].find("byte 81918: truncated last record (2 of 3 header bytes) dropped"), std::string::npos)
      << log->warnings[0];
  ASSERT_EQ(log->imus.size(), 2u);
  EXPECT_EQ(log->imus[0].time_us.size(), 10u);
  EXPECT_EQ(log->imus[1].time_us.size(), 10u);
  EXPECT_EQ(log->message_counts.at("FMT"), 184u);
  EXPECT_EQ(log->message_counts.at("PARM"), 1077u);
  ExpectEqualsDfReaderCsv(*log, path + ".IMU.csv");
}

TEST(DataFlashTest, LegacyLogEqualsDfReaderExtractAndDropsTheCutRecord) {
  const std::string path = SharedFixture("test.BIN");
  if (!std::ifstream(path)) GTEST_SKIP() << "../shared/fieldlogs absent (LGPL-3.0 sample, not in the repository)";
  Result<DataFlashContents> log = ReadDataFlash(path);
  ASSERT_TRUE(log.ok()) << log.error().message;
  ASSERT_EQ(log->imus.size(), 2u);
  EXPECT_EQ(log->imus[0].message, "IMU");
  EXPECT_EQ(log->imus[1].message, "IMU2");
  EXPECT_EQ(log->imus[0].time_us.size(), 45u);
  EXPECT_EQ(log->imus[1].time_us.size(), 45u);
  // The file (65536 bytes) ends with 24 of the 45 bytes of an AHR2 record (fixtures README).
  ASSERT_EQ(log->warnings.size(), 1u);
  EXPECT_NE(log->warnings[0].find("byte 65512: truncated last record (AHR2, 24 of 45 bytes) dropped"),
            std::string::npos)
      << log->warnings[0];
  ExpectEqualsDfReaderCsv(*log, path + ".IMU.csv");
}

// ---- logs built here ----------------------------------------------------------------------

void Put(std::string* s, const void* p, std::size_t n) { s->append(static_cast<const char*>(p), n); }
template <typename T>
void PutValue(std::string* s, T v) { Put(s, &v, sizeof v); }
void PutText(std::string* s, const std::string& text, std::size_t n) {
  std::string t = text;
  t.resize(n, '\0');
  s->append(t);
}

std::string Fmt(int type, int length, const std::string& name, const std::string& format, const std::string& labels) {
  std::string s("\xA3\x95\x80", 3);
  PutValue<std::uint8_t>(&s, static_cast<std::uint8_t>(type));
  PutValue<std::uint8_t>(&s, static_cast<std::uint8_t>(length));
  PutText(&s, name, 4);
  PutText(&s, format, 16);
  PutText(&s, labels, 64);
  return s;
}

// FMT, PARM INS_TCAL1_ENABLE = 1, and IMU rows "QBffff f" for instances 0 and 1.
std::string BuildLog(int rows) {
  std::string s = Fmt(0x80, 89, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns");
  s += Fmt(64, 3 + 8 + 16 + 4, "PARM", "QNf", "TimeUS,Name,Value");
  s += Fmt(65, 3 + 8 + 1 + 4 * 4, "IMU", "QBffff", "TimeUS,I,GyrX,GyrY,GyrZ,T");
  s += std::string("\xA3\x95\x40", 3);
  PutValue<std::uint64_t>(&s, 1);
  PutText(&s, "INS_TCAL1_ENABLE", 16);
  PutValue<float>(&s, 1.0f);
  for (int i = 0; i < rows; ++i) {
    for (std::uint8_t inst = 0; inst < 2; ++inst) {
      s += std::string("\xA3\x95\x41", 3);
      PutValue<std::uint64_t>(&s, 1000000 + 2500 * static_cast<std::uint64_t>(i));
      PutValue<std::uint8_t>(&s, inst);
      PutValue<float>(&s, 0.001f * static_cast<float>(i));
      PutValue<float>(&s, -0.5f);
      PutValue<float>(&s, static_cast<float>(inst));
      PutValue<float>(&s, 30.0f + static_cast<float>(inst));
    }
  }
  return s;
}

Result<DataFlashContents> Parse(const std::string& b) {
  return ParseDataFlash(reinterpret_cast<const std::uint8_t*>(b.data()), b.size(), "mem.bin");
}

// DataFlashReadOptions::strict: the first damaged record is an error (recovery: log_recovery_test.cc).
Result<DataFlashContents> ParseStrict(const std::string& b) {
  DataFlashReadOptions options;
  options.strict = true;
  return ParseDataFlash(reinterpret_cast<const std::uint8_t*>(b.data()), b.size(), "mem.bin", options);
}

TEST(DataFlashTest, BuiltLogIsReadWithInstancesAndParameters) {
  const std::string bytes = BuildLog(100);
  ASSERT_TRUE(HasDataFlashMagic(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
  Result<DataFlashContents> log = Parse(bytes);
  ASSERT_TRUE(log.ok()) << log.error().message;
  ASSERT_EQ(log->imus.size(), 2u);
  EXPECT_EQ(log->imus[1].time_us.size(), 100u);
  EXPECT_EQ(log->imus[1].gyr_x_rad_s[7], static_cast<double>(0.001f * 7.0f));
  EXPECT_EQ(log->imus[1].temp_c[7], 31.0);
  EXPECT_EQ(log->parameters.at("INS_TCAL1_ENABLE"), 1.0);

  Result<FlightLogTable> none = FlightLogFromDataFlash(*log, std::nullopt);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("2 IMU instances: 0 (IMU, 100 rows), 1 (IMU, 100 rows); choose one with --instance N"),
            std::string::npos)
      << none.error().message;
  Result<FlightLogTable> t0 = FlightLogFromDataFlash(*log, 0);
  ASSERT_TRUE(t0.ok());
  EXPECT_EQ(t0->origin, "DataFlash IMU I=0");
  // INS_TCAL1_ENABLE = 1 with no coefficients in the log (firmware defaults 0): the correction
  // added back is zero, and the reader says what it did.
  bool tcal = false;
  for (const auto& w : t0->warnings) tcal |= w.rfind("mem.bin: INS_TCAL1_ENABLE = 1 in the log's parameters: ArduPilot's thermal correction", 0) == 0;
  EXPECT_TRUE(tcal);
  EXPECT_EQ(t0->table.columns[1][7], static_cast<double>(0.001f * 7.0f));
  // Instance 1 is calibrated by INS_TCAL2_*, which this log does not enable.
  Result<FlightLogTable> t1 = FlightLogFromDataFlash(*log, 1);
  ASSERT_TRUE(t1.ok());
  for (const auto& w : t1->warnings) EXPECT_EQ(w.find("INS_TCAL"), std::string::npos) << w;
}

TEST(DataFlashTest, EveryTruncationDropsOnlyTheCutRecord) {
  const std::string bytes = BuildLog(3);
  const std::size_t imu_len = 3 + 8 + 1 + 16;
  for (std::size_t cut = 1; cut < imu_len; ++cut) {
    Result<DataFlashContents> log = Parse(bytes.substr(0, bytes.size() - cut));
    ASSERT_TRUE(log.ok()) << log.error().message;
    ASSERT_EQ(log->warnings.size(), 1u);
    const std::size_t at = bytes.size() - imu_len;
    EXPECT_NE(log->warnings[0].find("byte " + std::to_string(at) + ": truncated last record"), std::string::npos)
        << log->warnings[0];
    EXPECT_EQ(log->imus[0].time_us.size(), 3u);
    EXPECT_EQ(log->imus[1].time_us.size(), 2u);
  }
}

TEST(DataFlashTest, StrictRefusesCorruptLogsWithTheByteOffset) {
  const std::string good = BuildLog(3);
  const std::size_t first_imu = 3 * 89 + (3 + 8 + 16 + 4);
  std::string bad = good;
  bad[first_imu + 1] = 0x00;  // broken A3 95 header
  Result<DataFlashContents> r = ParseStrict(bad);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("mem.bin: byte " + std::to_string(first_imu) + ": no record header"),
            std::string::npos)
      << r.error().message;
  bad = good;
  bad[first_imu + 2] = 0x50;  // a type no FMT defined
  r = ParseStrict(bad);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("byte " + std::to_string(first_imu) + ": record of message type 80"),
            std::string::npos)
      << r.error().message;
  bad = good;
  bad[2 * 89 + 4] = 30;  // IMU's FMT length disagrees with its format
  r = ParseStrict(bad);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("byte 178: FMT for 'IMU': format 'QBffff' needs 28 bytes, its length says 30"),
            std::string::npos)
      << r.error().message;
}

}  // namespace
}  // namespace gyrocomp
