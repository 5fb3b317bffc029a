// End-to-end checks of docs/reference/cli-contract.md through the built CLI: numbers at the edges of the
// double range are refused at load with file:line:column and the value (exit 2) or computed right,
// never written as NaN with exit 0; options at the edges (sample rate, seeds, --resample memory,
// /dev/zero) are refused with exit 2 before allocating; running a subcommand on its own output
// keeps the column names unique; a model file is byte-reproducible.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gyrocomp/io/io.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

class HostileInputCliTest : public testing::CliTest {
 protected:
  HostileInputCliTest() : CliTest("gyrocomp_hostile_input_test") {}
  // A 2000-row log at 100 Hz: rate = scale * (deterministic +-1 pattern), temperature ramp, and
  // `bad` written in place of the cell (row `bad_row`, column `bad_col`) when non-empty.
  std::string Log(const std::string& name, double scale, const std::string& bad = "", int bad_row = -1,
                  int bad_col = -1) {
    const std::string path = dir_ + "/" + name;
    std::ofstream out(path);
    out << "time_s,rate_dps,temp_c\n";
    for (int i = 0; i < 2000; ++i) {
      std::string cells[3] = {std::to_string(i * 0.01), "", std::to_string(20.0 + 0.01 * i)};
      char rate[64];
      std::snprintf(rate, sizeof rate, "%.17g", scale * (((i * 7919) % 101) - 50) / 50.0);
      cells[1] = rate;
      if (i == bad_row) cells[bad_col] = bad;
      out << cells[0] << "," << cells[1] << "," << cells[2] << "\n";
    }
    return path;
  }
};

TEST_F(HostileInputCliTest, ExtremeValuesAreRefusedWithFileLineColumnAndValue) {
  const std::string big = Log("big.csv", 1e300);
  ExpectRefused("allan -i '" + big + "' --json -", {big + ":2:2: rate rate_dps = -1e+300 is beyond any gyroscope"});
  const std::string alt = Log("alt.csv", 1.0, "1e308", 10, 1);
  ExpectRefused("denoise -i '" + alt + "' --method wflp -o '" + dir_ + "/d.csv'",
                {alt + ":12:2: rate rate_dps = 1e+308"});
  const std::string hot = Log("hot.csv", 0.1, "1e300", 100, 2);
  ExpectRefused("allan -i '" + hot + "' --json -", {hot + ":102:3: temperature temp_c = 1e+300 C is outside"});
  EXPECT_FALSE(fs::exists(dir_ + "/d.csv"));
}

TEST_F(HostileInputCliTest, TinyValuesAreComputedNotZeroedOrNaN) {
  // Allan normalises internally: a 1e-300 deg/s record gives ADEV 1e-300 times that of the same
  // record at 1 deg/s (within rounding), with every number finite in the JSON.
  std::string out;
  ASSERT_EQ(Run("allan -i '" + Log("one.csv", 1.0) + "' --json '" + dir_ + "/one.json'", &out), 0) << out;
  ASSERT_EQ(Run("allan -i '" + Log("tiny.csv", 1e-300) + "' --json '" + dir_ + "/tiny.json'", &out), 0) << out;
  const auto one = testing::ReadJsonFile(dir_ + "/one.json");
  const auto tiny = testing::ReadJsonFile(dir_ + "/tiny.json");
  ASSERT_EQ(one["adev_dps"].size(), tiny["adev_dps"].size());
  for (std::size_t j = 0; j < one["adev_dps"].size(); ++j) {
    const double a = one["adev_dps"][j].get<double>();
    EXPECT_NEAR(tiny["adev_dps"][j].get<double>() / 1e-300, a, 1e-9 * a);
  }
  ASSERT_TRUE(tiny["arw_deg_per_sqrt_h"].is_number());
}

// A valid record scaled to ~1e-302 crashed decompose and process (SIGSEGV in the VMD's
// reconstruction) and left their temporaries. Now: exit 2, one line naming the cause and the
// option that fixes it, nothing left in the folder; the relative rule decomposes it.
TEST_F(HostileInputCliTest, RecordNear1eMinus302IsRefusedWithTheReasonNotASegfault) {
  const std::string in = Log("tiny302.csv", 3.249723276931597e-302);
  const std::string tol = "--vmd-stop relative";
  ExpectRefused("decompose -i '" + in + "' -o '" + dir_ + "/m.csv' --json '" + dir_ + "/m.json'", {tol});
  ExpectRefused("process -i '" + in + "' -o '" + dir_ + "/p.csv' --json '" + dir_ + "/p.json'", {tol});
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string(), "tiny302.csv") << "left behind: " << entry.path();
  }
  std::string out;
  EXPECT_EQ(Run("decompose -i '" + in + "' " + tol + " -o '" + dir_ + "/m.csv' --json '" + dir_ + "/m.json'", &out), 0)
      << out;
}

TEST_F(HostileInputCliTest, OptionsAtTheEdgesAreRefusedBeforeAllocating) {
  const std::string log = Log("log.csv", 1.0);
  ExpectRefused("allan -i '" + log + "' --fs 1e-300 --json -", {"--fs: 1e-300: must be in [1e-06, 1e+09]"});
  ExpectRefused("allan -i '" + log + "' --fs 1e308 --json -", {"--fs: 1e308: must be in [1e-06, 1e+09]"});
  ExpectRefused("allan -i '" + log + "' --resample 1e9 --json -", {"needs"});
  ExpectRefused("allan -i '" + log + "' --resample 1e9 --json -", {"(--max-memory)"});
  ExpectRefused("allan -i '" + log + "' --max-memory 0.00001 --json -", {"at most 1e-05 GB allowed (--max-memory)"});
  ExpectRefused("allan -i /dev/zero --json -", {"/dev/zero:1:1: line longer than"});
  std::string out;
  for (const char* seed : {"-1", "18446744073709551616", "1e3", "''"}) {
    EXPECT_EQ(Run("simulate --duration 10 -o '" + dir_ + "/s.csv' --seed " + seed, &out), 2) << seed << ": " << out;
  }
  EXPECT_EQ(Run("simulate --duration 10 -o '" + dir_ + "/s.csv' --seed 18446744073709551615", &out), 0) << out;
}

TEST_F(HostileInputCliTest, ModelValuesAreBoundedAtLoad) {
  const std::string sim = dir_ + "/sim.csv", model = dir_ + "/m.json";
  std::string out;
  ASSERT_EQ(Run("simulate --fs 1 --duration 7200 -o '" + sim + "'", &out), 0) << out;
  ASSERT_EQ(Run("fit -i '" + sim + "' --model poly --degree 2 -o '" + model + "'", &out), 0) << out;
  nlohmann::json j = testing::ReadJsonFile(model);
  // Model file schema 2: the polynomial of axis 0 is "structured".
  ASSERT_TRUE(j["axes"][0]["structured"]["terms"].size() > 1) << j.dump();
  j["axes"][0]["structured"]["terms"][1]["coefficient"] = 1e308;
  std::ofstream(dir_ + "/huge.json") << j.dump(1);
  ExpectRefused(
      "apply -i '" + sim + "' -m '" + dir_ + "/huge.json' -o '" + dir_ + "/a.csv'",
      {"axes[0]: field 'structured.terms[].coefficient' = 1e+308: must be a finite number of magnitude <= 1e100"});
  EXPECT_FALSE(fs::exists(dir_ + "/a.csv"));
}

TEST_F(HostileInputCliTest, FitTwiceGivesByteIdenticalModelFiles) {
  const std::string sim = dir_ + "/sim.csv";
  std::string out;
  ASSERT_EQ(Run("simulate --fs 0.5 --duration 20000 -o '" + sim + "'", &out), 0) << out;
  for (const char* model : {"poly --degree 3", "cs-svr --nests 4 --generations 2 --seed 5"}) {
    SCOPED_TRACE(model);
    ASSERT_EQ(Run("fit -i '" + sim + "' --model " + model + " -o '" + dir_ + "/a.json'", &out), 0) << out;
    ASSERT_EQ(Run("fit -i '" + sim + "' --model " + model + " -o '" + dir_ + "/b.json'", &out), 0) << out;
    EXPECT_EQ(testing::ReadFile(dir_ + "/a.json"), testing::ReadFile(dir_ + "/b.json"));
    EXPECT_EQ(testing::ReadFile(dir_ + "/a.json").find("fit_time_s"), std::string::npos);
  }
}

TEST_F(HostileInputCliTest, FlatTemperatureIsWarnedAbout) {
  const std::string sim = dir_ + "/flat.csv";
  std::string out;
  ASSERT_EQ(Run("simulate --profile soak --fs 1 --duration 3000 --hot 25 --room-temp 25 -o '" + sim + "'", &out), 0)
      << out;
  ASSERT_EQ(Run("fit -i '" + sim + "' --model poly -o '" + dir_ + "/m.json'", &out), 0) << out;
  EXPECT_NE(out.find("warning: the temperature spans only"), std::string::npos) << out;
}

// Each subcommand whose output is "the input columns plus ...", run on its own output: the
// second output reads back (unique names), the column is replaced, and a warning says so.
TEST_F(HostileInputCliTest, RunningOnItsOwnOutputKeepsColumnNamesUnique) {
  const std::string sim = dir_ + "/sim.csv", model = dir_ + "/m.json";
  std::string out;
  ASSERT_EQ(Run("simulate --fs 1 --duration 7200 -o '" + sim + "'", &out), 0) << out;
  ASSERT_EQ(Run("fit -i '" + sim + "' --model poly -o '" + model + "'", &out), 0) << out;
  struct Chain {
    std::string first, again, column;
  };
  const std::string d = dir_ + "/";
  const Chain chains[] = {
      {"denoise -i '" + sim + "' --method wavelet -o '" + d + "d1.csv'",
       "denoise -i '" + d + "d1.csv' --method wavelet -o '" + d + "d2.csv'", "denoised_dps"},
      {"apply -i '" + sim + "' -m '" + model + "' -o '" + d + "a1.csv'",
       "apply -i '" + d + "a1.csv' -m '" + model + "' -o '" + d + "a2.csv'", "compensated_dps"},
      {"process -q --model poly -i '" + sim + "' -o '" + d + "p1.csv'",
       "process -q --model poly -i '" + d + "p1.csv' -o '" + d + "p2.csv'", "compensated_dps"},
      {"apply -i '" + d + "p1.csv' -m '" + model + "' -o '" + d + "pa.csv'",
       "denoise -i '" + d + "pa.csv' --method flp -o '" + d + "pad.csv'", "compensated_dps"},
  };
  for (const Chain& c : chains) {
    SCOPED_TRACE(c.again);
    ASSERT_EQ(Run(c.first, &out), 0) << out;
    ASSERT_EQ(Run(c.again, &out), 0) << out;
    if (c.again.rfind("denoise -i '" + d + "pa", 0) != 0) {
      EXPECT_NE(out.find("already has a column"), std::string::npos) << out;
    }
    const std::string second = c.again.substr(c.again.rfind("-o '") + 4, c.again.rfind('\'') - c.again.rfind("-o '") - 4);
    const auto table = ReadCsv(second);
    ASSERT_TRUE(table.ok()) << table.error().message;
    EXPECT_GE(table->Find(c.column), 0);
  }
}

}  // namespace
}  // namespace gyrocomp
