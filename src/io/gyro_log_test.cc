// Tests of LoadGyroLog / ReadGyroLog / MeasureSampling / ResampleTable: column selection, units,
// timestamp errors, irregular-sampling detection (synthetic and the real MPU-6050 logs) and
// linear resampling.
#include "gyrocomp/io/gyro_log.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_support.h"

namespace gyrocomp {
namespace {

Table MakeTable(const std::vector<double>& t, const std::vector<double>& rate, const std::string& time_name = "time_s",
                const std::string& rate_name = "rate_dps") {
  Table table;
  table.source = "mem.csv";
  table.Add(time_name, t);
  table.Add(rate_name, rate);
  return table;
}

std::vector<double> Uniform(std::size_t n, double fs_hz) {
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) t[i] = static_cast<double>(i) / fs_hz;
  return t;
}

// Expects kInvalidInput with message prefix "<file>:<line>:<col>: " and all `words`.
void ExpectBad(const Result<GyroLog>& r, const std::string& prefix, const std::vector<std::string>& words) {
  ASSERT_FALSE(r.ok()) << "accepted bad input";
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidInput) << r.error().message;
  EXPECT_EQ(r.error().message.rfind(prefix, 0), 0u) << "expected prefix '" << prefix << "' in: " << r.error().message;
  for (const std::string& w : words) {
    EXPECT_NE(r.error().message.find(w), std::string::npos) << "'" << w << "' missing from: " << r.error().message;
  }
}

TEST(GyroLogTest, SelectsSeveralAxesAndTemperature) {
  Table t;
  t.source = "imu.csv";
  t.Add("t_s", Uniform(5, 10.0));
  t.Add("gz", {5, 5, 5, 5, 5});
  t.Add("gx", {1, 2, 3, 4, 5});
  t.Add("temp_C", {20, 21, 22, 23, 24});
  LogSpec spec;
  spec.time_col = "t_s";
  spec.rate_cols = {"gx", "gz"};
  spec.temp_col = "temp_C";
  const auto log = LoadGyroLog(t, spec);
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_EQ(log->axis_names, (std::vector<std::string>{"gx", "gz"}));  // spec order, not file order
  ASSERT_EQ(log->rate_dps.size(), 2u);
  EXPECT_EQ(log->rate_dps[0], (std::vector<double>{1, 2, 3, 4, 5}));
  EXPECT_EQ(log->rate_dps[1][0], 5.0);
  EXPECT_TRUE(log->has_temperature());
  EXPECT_EQ(log->temp_c[4], 24.0);
  EXPECT_NEAR(log->fs_hz, 10.0, 1e-12);  // mean rate of i/10: exact up to rounding of i/10
  EXPECT_FALSE(log->sampling.irregular);
  EXPECT_FALSE(log->sampling.resampled);
  EXPECT_EQ(log->source, "imu.csv");
}

TEST(GyroLogTest, ConvertsRateUnitsToDps) {
  const std::vector<double> raw = {1.0, -0.5, 3600.0};
  const Table t = MakeTable(Uniform(3, 1.0), raw, "time_s", "w");
  LogSpec spec;
  spec.rate_cols = {"w"};
  const struct {
    RateUnit unit;
    double factor;
  } cases[] = {{RateUnit::kDegPerSec, 1.0},
               {RateUnit::kRadPerSec, 180.0 / M_PI},  // 1 rad/s = 57.29578 deg/s
               {RateUnit::kDegPerHour, 1.0 / 3600.0}};
  for (const auto& c : cases) {
    spec.rate_unit = c.unit;
    const auto log = LoadGyroLog(t, spec);
    ASSERT_TRUE(log.ok()) << log.error().message;
    for (std::size_t i = 0; i < raw.size(); ++i) {
      // One multiplication by the factor: equal to within 1 ulp of the exact product.
      EXPECT_DOUBLE_EQ(log->rate_dps[0][i], raw[i] * c.factor) << RateUnitName(c.unit);
    }
  }
  EXPECT_DOUBLE_EQ(units::ToDegPerSec(RateUnit::kRadPerSec), 57.295779513082323);
  EXPECT_EQ(*ParseRateUnit("dph"), RateUnit::kDegPerHour);
  EXPECT_FALSE(ParseRateUnit("deg/s").has_value());
}

TEST(GyroLogTest, MissingColumnNamesItAndListsTheOthers) {
  Table t = MakeTable(Uniform(4, 1.0), {1, 2, 3, 4}, "t_s", "gx");
  t.Add("temp_C", {1, 1, 1, 1});
  LogSpec spec;
  spec.time_col = "t_s";
  spec.rate_cols = {"gx", "gy"};
  ExpectBad(LoadGyroLog(t, spec), "mem.csv:1:1: ", {"missing column 'gy'", "t_s, gx, temp_C"});
  spec.rate_cols = {"gx"};
  spec.temp_required = true;  // default temp_col "temp_c": suggest the differently-cased one
  ExpectBad(LoadGyroLog(t, spec), "mem.csv:1:1: ", {"missing column 'temp_c'", "did you mean 'temp_C'"});
  spec.temp_required = false;
  const auto ok = LoadGyroLog(t, spec);  // temperature optional: absent is fine
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_FALSE(ok->has_temperature());
  spec.time_col = "time_s";
  ExpectBad(LoadGyroLog(t, spec), "mem.csv:1:1: ", {"missing column 'time_s'", "--fs"});
}

TEST(GyroLogTest, TimeGoingBackwardsOrRepeatingNamesBothLines) {
  // Rows 0..4 are lines 2..6.
  ExpectBad(LoadGyroLog(MakeTable({0, 0.1, 0.2, 0.15, 0.4}, {0, 0, 0, 0, 0}), LogSpec{}), "mem.csv:5:1: ",
            {"backwards", "time_s = 0.15", "line 5", "0.2", "line 4"});
  ExpectBad(LoadGyroLog(MakeTable({0, 0.1, 0.2, 0.2, 0.4}, {0, 0, 0, 0, 0}), LogSpec{}), "mem.csv:5:1: ",
            {"repeats", "line 5", "line 4"});
}

TEST(GyroLogTest, FsWithoutTimeColumn) {
  Table t;
  t.source = "notime.csv";
  t.Add("rate_dps", {1, 2, 3, 4});
  LogSpec spec;
  ExpectBad(LoadGyroLog(t, spec), "notime.csv:1:1: ", {"missing column 'time_s'", "--fs"});
  spec.fs_hz = 4.0;
  const auto log = LoadGyroLog(t, spec);
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_EQ(log->time_s, (std::vector<double>{0, 0.25, 0.5, 0.75}));
  EXPECT_EQ(log->fs_hz, 4.0);
  EXPECT_TRUE(log->sampling.time_from_fs);
  spec.resample_hz = 2.0;  // nothing to resample without timestamps
  ExpectBad(LoadGyroLog(t, spec), "notime.csv:1:1: ", {"--resample"});
}

TEST(GyroLogTest, FsAndTimeColumnMustAgree) {
  const Table t = MakeTable(Uniform(100, 100.0), std::vector<double>(100, 0.0));
  LogSpec spec;
  spec.fs_hz = 100.5;  // 0.5 %: within the documented 1 %
  EXPECT_TRUE(LoadGyroLog(t, spec).ok());
  spec.fs_hz = 50.0;
  ExpectBad(LoadGyroLog(t, spec), "mem.csv:2:1: ", {"--fs 50", "100 Hz", "time column"});
}

TEST(GyroLogTest, TooFewSamples) {
  LogSpec spec;
  spec.min_samples = 10;
  ExpectBad(LoadGyroLog(MakeTable(Uniform(5, 1.0), std::vector<double>(5, 0.0)), spec), "mem.csv:6:1: ",
            {"too few samples", "5 data row", "at least 10"});
  ExpectBad(LoadGyroLog(MakeTable({0.0}, {1.0}), LogSpec{}), "mem.csv:2:1: ", {"too few samples"});
}

TEST(GyroLogTest, SpecValidation) {
  std::string why;
  LogSpec spec;
  EXPECT_TRUE(spec.IsValid(&why)) << why;
  spec.fs_hz = -1;
  EXPECT_FALSE(spec.IsValid(&why));
  EXPECT_EQ(why, "LogSpec::fs_hz = -1 Hz: must be in [1e-06, 1e+09] Hz");
  spec.fs_hz.reset();
  spec.gap_factor = 0.5;
  EXPECT_FALSE(spec.IsValid(&why));
  EXPECT_NE(why.find("gap_factor"), std::string::npos);
  spec.gap_factor = 1.5;
  spec.rate_cols = {"a", "a"};
  EXPECT_FALSE(spec.IsValid(&why));
  const auto r = LoadGyroLog(MakeTable(Uniform(3, 1.0), {0, 0, 0}), spec);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidArgument);
}

// ---- irregular sampling --------------------------------------------------------------------

TEST(GyroLogTest, SmallJitterIsRegular) {
  // 100 Hz with +-2 % uniform jitter on every interval: inside the 10 % tolerance.
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  std::vector<double> t(5000);
  for (std::size_t i = 1; i < t.size(); ++i) t[i] = t[i - 1] + 0.01 * (1.0 + jitter(rng));
  const auto log = LoadGyroLog(MakeTable(t, std::vector<double>(t.size(), 0.0)), LogSpec{});
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_FALSE(log->sampling.irregular);
  EXPECT_EQ(log->sampling.num_irregular, 0u);
  EXPECT_NEAR(log->fs_hz, 100.0, 0.5);  // mean of 4999 jittered intervals: sd of mean ~ 0.016 %
}

TEST(GyroLogTest, LargeJitterAndGapsAreIrregularWithStatistics) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);  // +-30 %: ~2/3 of intervals outside 10 %
  std::vector<double> t(2000);
  for (std::size_t i = 1; i < t.size(); ++i) t[i] = t[i - 1] + 0.01 * (1.0 + jitter(rng));
  const Table jittered = MakeTable(t, std::vector<double>(t.size(), 0.0));
  ExpectBad(LoadGyroLog(jittered, LogSpec{}), "mem.csv:",
            {"irregular timestamps", "median dt", "min", "max", "gaps", "--resample"});
  const SamplingReport rep = MeasureSampling(t, LogSpec{});
  EXPECT_TRUE(rep.irregular);
  EXPECT_GT(rep.num_irregular, rep.num_intervals / 2);
  EXPECT_EQ(rep.num_gaps, 0u);  // max interval 1.3 x 10 ms < 1.5 x median

  // Perfectly regular except one 0.5 s gap after row 1000 (line 1002 starts after it).
  std::vector<double> g = Uniform(2000, 100.0);
  for (std::size_t i = 1001; i < g.size(); ++i) g[i] += 0.49;
  const Table gapped = MakeTable(g, std::vector<double>(g.size(), 0.0));
  ExpectBad(LoadGyroLog(gapped, LogSpec{}), "mem.csv:1003:1: ", {"1 gaps", "longest 0.5 s", "line 1003"});
  const SamplingReport r2 = MeasureSampling(g, LogSpec{});
  EXPECT_EQ(r2.num_gaps, 1u);
  EXPECT_NEAR(r2.longest_gap_s, 0.5, 1e-12);
  EXPECT_NEAR(r2.median_dt_s, 0.01, 1e-15);
  EXPECT_EQ(r2.num_irregular, 1u);
}

TEST(GyroLogTest, BurstyReadTimesGetAHint) {
  // FIFO-style: 10 reads 2 ms apart, then an 82 ms wait: mean 100 Hz, median dt 2 ms.
  std::vector<double> t = {0.0};
  for (int b = 0; b < 50; ++b) {
    for (int k = 0; k < 9; ++k) t.push_back(t.back() + 0.002);
    t.push_back(t.back() + 0.082);
  }
  ExpectBad(LoadGyroLog(MakeTable(t, std::vector<double>(t.size(), 0.0)), LogSpec{}), "mem.csv:",
            {"irregular timestamps", "bursts of reads", "--fs 100"});
  // Plain jitter is not called bursty.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<double> j(500);
  for (std::size_t i = 1; i < j.size(); ++i) j[i] = j[i - 1] + 0.01 * (1.0 + jitter(rng));
  const auto r = LoadGyroLog(MakeTable(j, std::vector<double>(j.size(), 0.0)), LogSpec{});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message.find("bursts"), std::string::npos) << r.error().message;
}

TEST(GyroLogTest, ResamplesALinearSignalExactly) {
  // Irregular times (bursts and gaps); rate and temperature linear in t. Linear interpolation
  // reproduces a linear function, so every resampled value must equal a + b t_k up to rounding.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> dt(0.001, 0.05);
  std::vector<double> t = {0.0};
  while (t.back() < 10.0) t.push_back(t.back() + dt(rng));
  std::vector<double> rate(t.size()), temp(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    rate[i] = 0.25 - 0.125 * t[i];
    temp[i] = 20.0 + 3.0 * t[i];
  }
  Table table = MakeTable(t, rate);
  table.Add("temp_c", temp);
  LogSpec spec;
  ASSERT_FALSE(LoadGyroLog(table, spec).ok());  // never resampled silently
  spec.resample_hz = 50.0;
  const auto log = LoadGyroLog(table, spec);
  ASSERT_TRUE(log.ok()) << log.error().message;
  const std::size_t expect_rows = static_cast<std::size_t>(std::floor((t.back() - t.front()) * 50.0)) + 1;
  ASSERT_EQ(log->num_samples(), expect_rows);
  EXPECT_TRUE(log->sampling.resampled);
  EXPECT_TRUE(log->sampling.irregular);
  EXPECT_EQ(log->sampling.rows_in, t.size());
  EXPECT_EQ(log->sampling.rows_out, expect_rows);
  EXPECT_EQ(log->fs_hz, 50.0);
  for (std::size_t k = 0; k < log->num_samples(); ++k) {
    const double tk = log->time_s[k];
    EXPECT_NEAR(tk, k / 50.0, 1e-12);  // uniform grid from t0 = 0
    // Values are O(1..50); interpolation of a linear function loses a few ulps: 1e-12 absolute.
    EXPECT_NEAR(log->rate_dps[0][k], 0.25 - 0.125 * tk, 1e-12) << k;
    EXPECT_NEAR(log->temp_c[k], 20.0 + 3.0 * tk, 1e-12) << k;
  }
  EXPECT_NE(log->sampling.BriefReport().find("resampled"), std::string::npos);

  // ResampleTable produces the same grid and values, bit for bit, and keeps every column.
  const auto rt = ResampleTable(table, "time_s", 50.0);
  ASSERT_TRUE(rt.ok()) << rt.error().message;
  EXPECT_EQ(rt->names, table.names);
  ASSERT_EQ(rt->num_rows(), log->num_samples());
  EXPECT_EQ(std::memcmp(rt->columns[0].data(), log->time_s.data(), expect_rows * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(rt->columns[1].data(), log->rate_dps[0].data(), expect_rows * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(rt->columns[2].data(), log->temp_c.data(), expect_rows * sizeof(double)), 0);
}

TEST(GyroLogTest, ResamplingCountsRowsInterpolatedAcrossGaps) {
  // 10 Hz samples on [0, 1] and [3, 4]: the 2 s hole holds the 20 Hz grid points 1.05 .. 2.95.
  std::vector<double> t;
  for (int i = 0; i <= 10; ++i) t.push_back(i * 0.1);
  for (int i = 0; i <= 10; ++i) t.push_back(3.0 + i * 0.1);
  LogSpec spec;
  spec.resample_hz = 20.0;
  const auto log = LoadGyroLog(MakeTable(t, std::vector<double>(t.size(), 1.0)), spec);
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_EQ(log->num_samples(), 81u);
  EXPECT_EQ(log->sampling.num_gaps, 1u);
  EXPECT_EQ(log->sampling.rows_in_gaps, 39u);
}

TEST(GyroLogTest, ReadGyroLogFromFileWithRadPerSec) {
  const std::string dir = testing::MakeTempDir("gyrocomp_gyro_log_test");
  Table t = MakeTable(Uniform(100, 200.0), std::vector<double>(100, 0.01), "t", "wz");
  ASSERT_TRUE(WriteCsvAtomic(dir + "/log.csv.gz", t).ok());
  LogSpec spec;
  spec.time_col = "t";
  spec.rate_cols = {"wz"};
  spec.rate_unit = RateUnit::kRadPerSec;
  const auto log = ReadGyroLog(dir + "/log.csv.gz", spec);
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_DOUBLE_EQ(log->rate_dps[0][7], 0.01 * units::kDegPerRad);
  EXPECT_NEAR(log->fs_hz, 200.0, 1e-9);
  std::filesystem::remove_all(dir);
}

// ---- the real MPU-6050 logs: bursty FIFO reads --------------------------------------------

TEST(GyroLogTest, RealMpu6050LogsAreDetectedAsIrregular) {
  for (const char* name : {"mpu6050_x-pointing-forward.csv", "mpu6050_z-pointing-front-and-x-up.csv"}) {
    const std::string path = testing::RealdataPath(name);
    if (path.empty()) GTEST_SKIP() << "real recordings not available (../shared/realdata is licensed, not in the repo)";
    SCOPED_TRACE(name);
    LogSpec spec;
    spec.time_col = "t_s";
    spec.rate_cols = {"gx", "gy", "gz"};
    spec.temp_col = "temp_C";
    const auto bad = ReadGyroLog(path, spec);
    ExpectBad(bad, path + ":", {"irregular timestamps", "median dt", "--resample", "bursts of reads"});
    const auto table = ReadCsv(path);
    ASSERT_TRUE(table.ok()) << table.error().message;
    const SamplingReport rep = MeasureSampling(table->columns[0], spec);
    // README: ~99 Hz mean, bursty. Observed: median dt ~2.09 ms (reads inside a FIFO burst),
    // gaps up to ~0.25 s. Bounds are loose on purpose: they check the character, not digits.
    EXPECT_NEAR(rep.fs_hz, 99.4, 1.0);
    EXPECT_LT(rep.median_dt_s, 0.005);
    EXPECT_GT(rep.max_dt_s, 0.2);
    EXPECT_GT(rep.num_gaps, 1000u);
    spec.resample_hz = 100.0;
    const auto log = ReadGyroLog(path, spec);
    ASSERT_TRUE(log.ok()) << log.error().message;
    EXPECT_TRUE(log->sampling.resampled);
    EXPECT_EQ(log->fs_hz, 100.0);
    EXPECT_EQ(log->rate_dps.size(), 3u);
    EXPECT_EQ(log->temp_c.size(), log->num_samples());
    const double span = table->columns[0].back() - table->columns[0].front();
    EXPECT_EQ(log->num_samples(), static_cast<std::size_t>(std::floor(span * 100.0)) + 1);
  }
}

}  // namespace
}  // namespace gyrocomp
