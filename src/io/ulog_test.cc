// ULog reader and writer: value-for-value against pyulog's extracts of real PX4 logs
// (tests/fieldlogs, BSD-3-Clause), truncation and corruption, and a write/read round trip.
#include "gyrocomp/io/ulog.h"

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/core/units.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/gyro_log.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

Result<ULogContents> ParseUlg(const std::string& bytes) {
  return ParseULog(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "mem.ulg");
}

// ULogReadOptions::strict: the first damaged record is an error (recovery: log_recovery_test.cc).
Result<ULogContents> ParseUlgStrict(const std::string& bytes) {
  ULogReadOptions options;
  options.strict = true;
  return ParseULog(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "mem.ulg", options);
}

// Exact equality (no tolerance): pyulog's CSV holds repr() of each float32 widened to double,
// so strtod gives back the very value the reader must produce.
void ExpectSeriesEqualsCsv(const ULogGyroSeries& g, const std::string& csv_path, bool with_temperature) {
  const auto csv = testing::ReadGoldenCsv(csv_path);
  const auto& ts = csv.at("timestamp_us");
  ASSERT_EQ(g.timestamp_us.size(), ts.size()) << csv_path;
  for (std::size_t i = 0; i < ts.size(); ++i) {
    EXPECT_EQ(static_cast<double>(g.timestamp_us[i]), ts[i]) << csv_path << " row " << i;
    EXPECT_EQ(g.x_rad_s[i], csv.at("x_rad_s")[i]) << csv_path << " row " << i;
    EXPECT_EQ(g.y_rad_s[i], csv.at("y_rad_s")[i]) << csv_path << " row " << i;
    EXPECT_EQ(g.z_rad_s[i], csv.at("z_rad_s")[i]) << csv_path << " row " << i;
    if (with_temperature) {
      EXPECT_EQ(g.temperature_c[i], csv.at("temperature_c")[i]) << csv_path << " row " << i;
    }
  }
  if (!with_temperature) {
    EXPECT_TRUE(g.temperature_c.empty());
  }
}

TEST(ULogTest, SampleLogSmallEqualsPyulogExtracts) {
  const std::string path = testing::FieldlogPath("sample_log_small.ulg");
  Result<ULogContents> log = ReadULog(path);
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_EQ(log->version, 1);
  EXPECT_TRUE(log->warnings.empty()) << log->warnings.front();
  ASSERT_EQ(log->gyros.size(), 3u);
  const std::uint32_t device_ids[3] = {2424842, 3670050, 2621474};  // fixtures README (pyulog)
  for (int m = 0; m < 3; ++m) {
    const ULogGyroSeries& g = log->gyros[static_cast<std::size_t>(m)];
    EXPECT_EQ(g.multi_id, m);
    ASSERT_TRUE(g.device_id.has_value());
    EXPECT_EQ(*g.device_id, device_ids[m]);
    ExpectSeriesEqualsCsv(g, path + ".sensor_gyro_" + std::to_string(m) + ".csv", true);
  }
  ASSERT_EQ(log->combined.size(), 1u);
  ExpectSeriesEqualsCsv(log->combined[0], path + ".sensor_combined_0.csv", false);
  ASSERT_EQ(log->dropouts.size(), 1u);
  EXPECT_EQ(log->dropouts[0].duration_ms, 30);
  EXPECT_EQ(log->topics.size(), 72u);  // 'A' messages in the fixtures README's census
}

TEST(ULogTest, AppendedDataFallsBackToSensorCombined) {
  const std::string path = testing::FieldlogPath("sample_appended_multiple.ulg");
  Result<ULogContents> log = ReadULog(path);
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_EQ(log->appended_offsets, (std::vector<std::uint64_t>{434369, 451825, 469281}));
  EXPECT_TRUE(log->gyros.empty());
  ASSERT_EQ(log->combined.size(), 1u);
  ExpectSeriesEqualsCsv(log->combined[0], path + ".sensor_combined_0.csv", false);

  Result<FlightLogTable> t = FlightLogFromULog(*log, std::nullopt);
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_EQ(t->origin, "ULog sensor_combined multi_id 0");
  EXPECT_LT(t->table.Find("temp_c"), 0);
  bool said_no_temperature = false;
  for (const auto& w : t->warnings) said_no_temperature |= w.find("no temperature") != std::string::npos;
  EXPECT_TRUE(said_no_temperature);
}

TEST(ULogTest, TaggedAndDefaultParamsEqualsPyulogExtracts) {
  const std::string path = testing::SharedFieldlogsDir() + "/px4/sample_logging_tagged_and_default_params.ulg";
  if (!std::ifstream(path)) GTEST_SKIP() << "../shared/fieldlogs absent (this fixture is not in the repository)";
  Result<ULogContents> log = ReadULog(path);
  ASSERT_TRUE(log.ok()) << log.error().message;
  ASSERT_EQ(log->gyros.size(), 3u);
  for (int m = 0; m < 3; ++m) {
    ExpectSeriesEqualsCsv(log->gyros[static_cast<std::size_t>(m)], path + ".sensor_gyro_" + std::to_string(m) + ".csv",
                          true);
  }
  ASSERT_EQ(log->combined.size(), 1u);
  ExpectSeriesEqualsCsv(log->combined[0], path + ".sensor_combined_0.csv", false);
}

TEST(ULogTest, SeveralInstancesAreListedNotGuessed) {
  Result<ULogContents> log = ReadULog(testing::FieldlogPath("sample_log_small.ulg"));
  ASSERT_TRUE(log.ok());
  Result<FlightLogTable> none = FlightLogFromULog(*log, std::nullopt);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("3 sensor_gyro instances: 0 (6 rows, device_id 2424842), 1"), std::string::npos)
      << none.error().message;
  EXPECT_NE(none.error().message.find("--instance"), std::string::npos);
  Result<FlightLogTable> bad = FlightLogFromULog(*log, 5);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("no sensor_gyro instance 5"), std::string::npos) << bad.error().message;
  Result<FlightLogTable> one = FlightLogFromULog(*log, 1);
  ASSERT_TRUE(one.ok());
  EXPECT_EQ(one->device_id, std::optional<std::uint32_t>(3670050));
  EXPECT_EQ(one->table.names, (std::vector<std::string>{"time_s", "x_rad_s", "y_rad_s", "z_rad_s", "temp_c"}));
  EXPECT_EQ(one->table.columns[0][0], 21311176 / 1e6);  // first timestamp of multi_id 1, in s
}

// Every cut of the file's last data message: the prefix is read, the cut record dropped with a
// warning naming its offset, and the rows before it are all there.
TEST(ULogTest, TruncatedLastRecordIsDroppedWithItsOffset) {
  const std::string bytes = testing::ReadExistingFile(testing::FieldlogPath("sample_log_small.ulg"));
  Result<ULogContents> full = ParseUlg(bytes);
  ASSERT_TRUE(full.ok());
  for (std::size_t cut : {std::size_t{1}, std::size_t{2}, std::size_t{3}, std::size_t{17}, std::size_t{5000},
                          std::size_t{400000}}) {
    const std::string part = bytes.substr(0, bytes.size() - cut);
    Result<ULogContents> log = ParseUlg(part);
    ASSERT_TRUE(log.ok()) << "cut " << cut << ": " << log.error().message;
    ASSERT_EQ(log->warnings.size(), 1u) << "cut " << cut;
    EXPECT_NE(log->warnings[0].find("truncated last record"), std::string::npos) << log->warnings[0];
    EXPECT_NE(log->warnings[0].find("mem.ulg: byte "), std::string::npos) << log->warnings[0];
    // The rows read are a prefix of the full file's rows.
    const auto& a = log->combined[0].timestamp_us;
    const auto& b = full->combined[0].timestamp_us;
    ASSERT_LE(a.size(), b.size());
    EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin()));
  }
}

TEST(ULogTest, StrictRefusesCorruptFilesWithTheByteOffset) {
  const std::string bytes = testing::ReadExistingFile(testing::FieldlogPath("sample_log_small.ulg"));
  {
    Result<ULogContents> r = ParseUlgStrict(bytes.substr(0, 10));
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("byte 10: file too short"), std::string::npos) << r.error().message;
  }
  {
    std::string bad = bytes;
    bad[3] = 'X';
    Result<ULogContents> r = ParseUlgStrict(bad);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("byte 0: not a ULog file"), std::string::npos) << r.error().message;
  }
  // First 'D' message: give it an msg_id nobody subscribed to.
  {
    std::string bad = bytes;
    std::size_t pos = 16;
    while (bad[pos + 2] != 'D') pos += 3 + (static_cast<unsigned char>(bad[pos]) | (static_cast<unsigned char>(bad[pos + 1]) << 8));
    bad[pos + 3] = static_cast<char>(0xFF);
    bad[pos + 4] = static_cast<char>(0xFF);
    Result<ULogContents> r = ParseUlgStrict(bad);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("byte " + std::to_string(pos) + ": data ('D') for msg_id 65535 without a subscription"),
              std::string::npos)
        << r.error().message;
    // ... and a size that does not match its format.
    bad = bytes;
    bad[pos] = static_cast<char>(static_cast<unsigned char>(bad[pos]) - 1);
    r = ParseUlgStrict(bad);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("byte " + std::to_string(pos) + ": data ('D') for"), std::string::npos)
        << r.error().message;
  }
}

std::string Message(char type, const std::string& payload) {
  std::string m;
  m.push_back(static_cast<char>(payload.size() & 0xFF));
  m.push_back(static_cast<char>(payload.size() >> 8));
  m.push_back(type);
  return m + payload;
}

// Arrays of empty nested types: flattening would take 99999^3 steps; refused instead.
TEST(ULogTest, FormatBombIsRefused) {
  std::string b("\x55\x4C\x6F\x67\x01\x12\x35\x01", 8);
  b.append(8, '\0');
  b += Message('F', "e:");
  b += Message('F', "n1:e[99999] a;");
  b += Message('F', "n2:n1[99999] b;");
  b += Message('F', "top:n2[99999] c;");
  b += Message('A', std::string("\0\0\0", 3) + "top");
  Result<ULogContents> r = ParseUlgStrict(b);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("too many (nested) fields"), std::string::npos) << r.error().message;
  // A format that names itself.
  std::string c = b.substr(0, 16) + Message('F', "loop:loop x;") + Message('A', std::string("\0\0\0", 3) + "loop");
  r = ParseUlgStrict(c);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("nested deeper than"), std::string::npos) << r.error().message;
}

ULogGyroWriteInput SmallSeries(std::size_t n) {
  ULogGyroWriteInput in;
  for (std::size_t i = 0; i < n; ++i) {
    in.timestamp_us.push_back(1000000 + 10000 * i);
    in.x_rad_s.push_back(0.01f * static_cast<float>(std::sin(0.1 * static_cast<double>(i))));
    in.y_rad_s.push_back(-0.002f * static_cast<float>(i));
    in.z_rad_s.push_back(1e-4f);
    in.temperature_c.push_back(25.0f + 0.01f * static_cast<float>(i));
  }
  in.device_id = 2424842;
  return in;
}

TEST(ULogTest, WriterRoundTrip) {
  const ULogGyroWriteInput in = SmallSeries(500);
  Result<std::string> bytes = EncodeULogGyro(in);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message;
  Result<ULogContents> log = ParseUlg(*bytes);
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_TRUE(log->warnings.empty());
  ASSERT_EQ(log->gyros.size(), 1u);
  const ULogGyroSeries& g = log->gyros[0];
  EXPECT_EQ(g.device_id, std::optional<std::uint32_t>(2424842));
  EXPECT_EQ(g.timestamp_us, in.timestamp_us);
  for (std::size_t i = 0; i < in.timestamp_us.size(); ++i) {
    ASSERT_EQ(g.x_rad_s[i], static_cast<double>(in.x_rad_s[i]));
    ASSERT_EQ(g.y_rad_s[i], static_cast<double>(in.y_rad_s[i]));
    ASSERT_EQ(g.z_rad_s[i], static_cast<double>(in.z_rad_s[i]));
    ASSERT_EQ(g.temperature_c[i], static_cast<double>(in.temperature_c[i]));
  }
  EXPECT_EQ(log->parameters.at("TC_G_ENABLE"), 0.0);

  // Through ReadGyroLog, as every subcommand reads it: deg/s, 100 Hz, device id kept.
  const std::string dir = testing::MakeTempDir("ulog_rt");
  const std::string path = dir + "/run.ulg";
  std::ofstream(path, std::ios::binary) << *bytes;
  EXPECT_EQ(DetectLogFormat(path), LogFormat::kULog);
  LogSpec spec;
  spec.temp_required = true;
  Result<GyroLog> gl = ReadGyroLog(path, spec);
  ASSERT_TRUE(gl.ok()) << gl.error().message;
  EXPECT_NEAR(gl->fs_hz, 100.0, 1e-9);
  ASSERT_EQ(gl->rate_dps.size(), 3u);
  EXPECT_EQ(gl->rate_dps[1][7], static_cast<double>(in.y_rad_s[7]) * units::ToDegPerSec(RateUnit::kRadPerSec));
  EXPECT_EQ(gl->temp_c[7], static_cast<double>(in.temperature_c[7]));
  EXPECT_EQ(gl->device_id, std::optional<std::uint32_t>(2424842));
  EXPECT_EQ(gl->origin, "ULog sensor_gyro multi_id 0");
}

TEST(ULogTest, CompensationEnabledDoesNotTouchSensorGyro) {
  // PX4 applies TC_G* after sensor_gyro (sensors module, calibration::Gyroscope::Correct): its
  // rates are raw whatever TC_G_ENABLE says, so there is nothing to warn about or undo.
  ULogGyroWriteInput in = SmallSeries(10);
  in.int_parameters["TC_G_ENABLE"] = 1;
  Result<std::string> bytes = EncodeULogGyro(in);
  ASSERT_TRUE(bytes.ok());
  Result<ULogContents> log = ParseUlg(*bytes);
  ASSERT_TRUE(log.ok());
  Result<FlightLogTable> t = FlightLogFromULog(*log, std::nullopt);
  ASSERT_TRUE(t.ok());
  for (const std::string& w : t->warnings) EXPECT_EQ(w.find("TC_G_ENABLE"), std::string::npos) << w;
  EXPECT_EQ(t->table.columns[1][7], static_cast<double>(in.x_rad_s[7]));
}

TEST(ULogTest, ConstantTemperatureIsAWarning) {
  ULogGyroWriteInput in = SmallSeries(10);
  for (float& t : in.temperature_c) t = 0.0f;  // as PX4 SITL logs it
  Result<std::string> bytes = EncodeULogGyro(in);
  ASSERT_TRUE(bytes.ok());
  Result<ULogContents> log = ParseUlg(*bytes);
  ASSERT_TRUE(log.ok());
  Result<FlightLogTable> t = FlightLogFromULog(*log, std::nullopt);
  ASSERT_TRUE(t.ok());
  ASSERT_EQ(t->warnings.size(), 1u);
  EXPECT_NE(t->warnings[0].find("the temperature is 0 C in every row"), std::string::npos) << t->warnings[0];
  // ... and a varying one is not.
  Result<ULogContents> varying = ParseUlg(*EncodeULogGyro(SmallSeries(10)));
  EXPECT_TRUE(FlightLogFromULog(*varying, std::nullopt)->warnings.empty());
}

TEST(ULogTest, NonFiniteValuesAreRefused) {
  ULogGyroWriteInput in = SmallSeries(10);
  in.y_rad_s[4] = std::numeric_limits<float>::quiet_NaN();
  Result<ULogContents> log = ParseUlg(*EncodeULogGyro(in));
  ASSERT_TRUE(log.ok());  // the reader reads what is logged ...
  Result<FlightLogTable> t = FlightLogFromULog(*log, std::nullopt);
  ASSERT_FALSE(t.ok());  // ... the gyro table refuses it, as ReadCsv refuses NaN
  EXPECT_EQ(t.error().message, "mem.ulg[sensor_gyro.0]:6:3: NaN in column 'y_rad_s' (row 4, time_s 1.04)");
}

TEST(ULogTest, WriterRefusesBadInput) {
  ULogGyroWriteInput in = SmallSeries(10);
  in.timestamp_us[5] = in.timestamp_us[4];
  EXPECT_FALSE(EncodeULogGyro(in).ok());
  in = SmallSeries(10);
  in.z_rad_s.pop_back();
  EXPECT_FALSE(EncodeULogGyro(in).ok());
}

}  // namespace
}  // namespace gyrocomp

namespace gyrocomp {
namespace {

TEST(ULogTest, MultiSensorLogRoundTrips) {
  ULogWriteInput in;
  in.int_parameters["TC_G_ENABLE"] = 0;
  in.float_parameters["SENS_BOARD_X_OFF"] = 0.5f;
  for (int m = 0; m < 2; ++m)
    for (const char* topic : {"sensor_gyro", "sensor_accel"}) {
      ULogSensorWriteSeries s;
      s.topic = topic;
      s.multi_id = m;
      s.device_id = 3932170u + static_cast<std::uint32_t>(m);
      for (int i = 0; i < 20; ++i) {
        s.timestamp_us.push_back(1000 + 1000 * static_cast<std::uint64_t>(i) + static_cast<std::uint64_t>(m));
        s.x.push_back(0.1f * static_cast<float>(i));
        s.y.push_back(-9.8f);
        s.z.push_back(static_cast<float>(m));
        s.temperature_c.push_back(30.0f + 0.1f * static_cast<float>(i));
      }
      in.series.push_back(s);
    }
  ULogSensorWriteSeries baro;
  baro.topic = "sensor_baro";
  baro.device_id = 3997730u;
  for (int i = 0; i < 5; ++i) {
    baro.timestamp_us.push_back(500 + 4000 * static_cast<std::uint64_t>(i));
    baro.x.push_back(101325.0f + static_cast<float>(i));
    baro.temperature_c.push_back(31.0f);
  }
  in.series.push_back(baro);
  Result<std::string> bytes = EncodeULog(in);
  ASSERT_TRUE(bytes.ok()) << bytes.error().message;
  Result<ULogContents> log = ParseULog(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size(), "m.ulg");
  ASSERT_TRUE(log.ok()) << log.error().message;
  ASSERT_EQ(log->gyros.size(), 2u);
  ASSERT_EQ(log->accels.size(), 2u);
  ASSERT_EQ(log->baros.size(), 1u);
  EXPECT_EQ(log->accels[1].multi_id, 1);
  EXPECT_EQ(log->accels[1].device_id, std::optional<std::uint32_t>(3932171u));
  EXPECT_EQ(log->accels[1].y_m_s2[3], static_cast<double>(-9.8f));
  EXPECT_EQ(log->accels[0].temperature_c[5], static_cast<double>(30.0f + 0.1f * 5.0f));
  EXPECT_EQ(log->gyros[1].x_rad_s[7], static_cast<double>(0.1f * 7.0f));
  EXPECT_EQ(log->baros[0].pressure_pa[4], 101329.0);
  EXPECT_EQ(log->baros[0].device_id, std::optional<std::uint32_t>(3997730u));
  EXPECT_EQ(log->parameters.at("SENS_BOARD_X_OFF"), 0.5);
  EXPECT_TRUE(log->warnings.empty());
  // Rows are written in time order.
  in.series[0].timestamp_us[3] = in.series[0].timestamp_us[2];
  EXPECT_FALSE(EncodeULog(in).ok());
}

}  // namespace
}  // namespace gyrocomp

namespace gyrocomp {
namespace {

TEST(ULogTest, AverageWindowKeepsOneMeanRowPerWindow) {
  ULogWriteInput in;
  for (const char* topic : {"sensor_gyro", "sensor_accel", "sensor_baro"}) {
    ULogSensorWriteSeries s;
    s.topic = topic;
    s.device_id = 3932170u;
    for (int i = 0; i < 3000; ++i) {  // 1 kHz for 3 s, from t = 0.5 s
      s.timestamp_us.push_back(500000 + 1000 * static_cast<std::uint64_t>(i));
      s.x.push_back(static_cast<float>(i));
      s.y.push_back(1.0f);
      s.z.push_back(-9.8f);
      s.temperature_c.push_back(30.0f);
    }
    in.series.push_back(s);
  }
  Result<std::string> bytes = EncodeULog(in);
  ASSERT_TRUE(bytes.ok());
  ULogReadOptions o;
  o.average_window_us = 1000000;
  Result<ULogContents> log = ParseULog(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size(), "w.ulg", o);
  ASSERT_TRUE(log.ok()) << log.error().message;
  // Windows [0, 1), [1, 2), [2, 3), [3, 4) s: 500, 1000, 1000, 500 rows.
  ASSERT_EQ(log->gyros[0].timestamp_us.size(), 4u);
  EXPECT_EQ(log->gyros[0].x_rad_s[0], 249.5);      // mean of 0..499
  EXPECT_EQ(log->gyros[0].x_rad_s[1], 999.5);      // mean of 500..1499
  EXPECT_EQ(log->gyros[0].timestamp_us[1], 1499500u);
  EXPECT_EQ(log->accels[0].x_m_s2[3], 2749.5);
  EXPECT_NEAR(log->accels[0].z_m_s2[2], -9.8, 1e-6);
  EXPECT_EQ(log->baros[0].pressure_pa.size(), 4u);
  EXPECT_EQ(log->gyros[0].device_id, std::optional<std::uint32_t>(3932170u));
}

}  // namespace
}  // namespace gyrocomp
