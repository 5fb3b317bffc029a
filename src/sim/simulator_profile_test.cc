// Chamber profiles for calibration design (docs/guides/plan-chamber-run.md): heat-cool, stairs, the
// user's schedule (CSV).
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "gyrocomp/sim/simulator.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

// heat-cool: cold soak, heat to hot, hold, cool to cold, hold; 6.33 h with the defaults.
TEST(SimulatorProfile, HeatCoolHeatsThenCoolsOverTheWholeRange) {
  ThermalProfileOptions o;
  o.kind = ThermalProfileKind::kHeatCool;
  auto s = MakeThermalSchedule(o);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_DOUBLE_EQ(s->duration_s(), 3600.0 + 6000.0 + 3600.0 + 6000.0 + 3600.0);
  EXPECT_DOUBLE_EQ(s->ChamberTempC(0.0), -40.0);
  EXPECT_DOUBLE_EQ(s->ChamberTempC(3600.0 + 3000.0), 10.0);   // heating, half way
  EXPECT_DOUBLE_EQ(s->ChamberTempC(9600.0 + 1800.0), 60.0);   // hot hold
  EXPECT_DOUBLE_EQ(s->ChamberTempC(13200.0 + 3000.0), 10.0);  // cooling, half way
  EXPECT_DOUBLE_EQ(s->ChamberTempC(22800.0), -40.0);
  EXPECT_STREQ(ThermalProfileKindName(*ParseThermalProfileKind("heat-cool")), "heat-cool");
}

// stairs: cold soak; up in 20 C steps at 1 C/min to -20, 0, 20, 40, 60; down at 0.5 C/min to the
// plateaus between them, 50, 30, 10, -10, -30, then -40; every plateau held 30 min: 11.5 h.
TEST(SimulatorProfile, StairsHoldAndRampInBothDirectionsAtTwoRates) {
  ThermalProfileOptions o;
  o.kind = ThermalProfileKind::kStairs;
  auto s = MakeThermalSchedule(o);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const double up_s = 3600.0 + 5 * 1200.0 + 5 * 1800.0;  // soak, 5 ramps of 20 C at 1 C/min, 5 holds
  EXPECT_DOUBLE_EQ(s->duration_s(), up_s + 1200.0 + 4 * 2400.0 + 1200.0 + 6 * 1800.0);  // 41,400 s
  EXPECT_DOUBLE_EQ(s->ChamberTempC(3600.0 + 600.0), -30.0);               // heating at 1 C/min
  EXPECT_DOUBLE_EQ(s->ChamberTempC(3600.0 + 1200.0 + 900.0), -20.0);      // first heating plateau
  EXPECT_DOUBLE_EQ(s->ChamberTempC(up_s - 1.0), 60.0);                     // hot plateau
  EXPECT_DOUBLE_EQ(s->ChamberTempC(up_s + 600.0), 55.0);                  // cooling at 0.5 C/min
  EXPECT_DOUBLE_EQ(s->ChamberTempC(up_s + 1200.0 + 1800.0), 50.0);        // first cooling plateau
  EXPECT_DOUBLE_EQ(s->ChamberTempC(s->duration_s()), -40.0);
  EXPECT_STREQ(ThermalProfileKindName(*ParseThermalProfileKind("stairs")), "stairs");
}

// rate-cycles: 30 min at -40 C; 4 x (to 60 C, 20 min, to -40 C, 20 min), heating at 2 / 1 / 2 / 1
// C/min and cooling at 1 / 2 / 1 / 2 C/min: 47,400 s.
TEST(SimulatorProfile, RateCyclesReverseFourTimesAtTwoRatesEachWay) {
  ThermalProfileOptions o;
  o.kind = ThermalProfileKind::kRateCycles;
  auto s = MakeThermalSchedule(o);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const double slow_fast = 3000.0 + 1200.0 + 6000.0 + 1200.0;  // up at 2 C/min, hold, down at 1, hold
  EXPECT_DOUBLE_EQ(s->duration_s(), 1800.0 + 4 * slow_fast);
  EXPECT_DOUBLE_EQ(s->ChamberTempC(1800.0), -40.0);
  EXPECT_DOUBLE_EQ(s->ChamberTempC(1800.0 + 1500.0), 10.0);                 // cycle 1: heating at 2 C/min
  EXPECT_DOUBLE_EQ(s->ChamberTempC(1800.0 + 4200.0 + 3000.0), 10.0);        // cycle 1: cooling at 1 C/min
  EXPECT_DOUBLE_EQ(s->ChamberTempC(1800.0 + slow_fast + 3000.0), 10.0);     // cycle 2: heating at 1 C/min
  EXPECT_DOUBLE_EQ(s->ChamberTempC(1800.0 + slow_fast + 7200.0 + 1500.0), 10.0);  // cycle 2: cooling at 2
  EXPECT_DOUBLE_EQ(s->ChamberTempC(1800.0 + slow_fast + 6500.0), 60.0);     // cycle 2: hot hold
  EXPECT_DOUBLE_EQ(s->ChamberTempC(s->duration_s()), -40.0);
  EXPECT_STREQ(ThermalProfileKindName(*ParseThermalProfileKind("rate-cycles")), "rate-cycles");
}

// user: the given breakpoints, linear in between, held at the first before it.
TEST(SimulatorProfile, UserScheduleIsFollowedAndCheckedAsGiven) {
  ThermalProfileOptions o;
  o.kind = ThermalProfileKind::kUser;
  o.user_time_s = {600.0, 1200.0, 4800.0};
  o.user_temp_c = {20.0, 20.0, -40.0};
  auto s = MakeThermalSchedule(o);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_DOUBLE_EQ(s->ChamberTempC(0.0), 20.0);
  EXPECT_DOUBLE_EQ(s->ChamberTempC(3000.0), -10.0);
  EXPECT_DOUBLE_EQ(s->duration_s(), 4800.0);
  std::string why;
  o.user_time_s = {0.0, 1200.0, 1200.0};
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("user_time_s"), std::string::npos) << why;
  o.user_time_s = {0.0};
  o.user_temp_c = {20.0};
  EXPECT_FALSE(o.IsValid(&why));
}

// simulate --profile-csv: follows the file; a bad row is refused with the file and row, exit 2,
// no output.
TEST(SimulatorProfile, SimulateProfileCsv) {
  const std::string cli = testing::CliPath();
  if (cli.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  const std::string dir = testing::MakeTempDir("sim_profile_test");
  {
    std::ofstream f(dir + "/p.csv");
    f << "time_s,chamber_temp_c\n0,25\n600,25\n3000,-15\n3600,-15\n";
  }
  std::string out;
  ASSERT_EQ(testing::RunCommand(cli + " simulate --profile-csv " + dir + "/p.csv --fs 1 -o " + dir + "/r.csv", &out), 0)
      << out;
  auto r = testing::ReadGoldenCsv(dir + "/r.csv");
  ASSERT_EQ(r["chamber_temp_c"].size(), 3600u);
  EXPECT_NEAR(r["chamber_temp_c"][1800], 5.0, 1e-9);
  EXPECT_NEAR(r["chamber_temp_c"][3500], -15.0, 1e-9);
  {
    std::ofstream f(dir + "/bad.csv");
    f << "time_s,chamber_temp_c\n0,25\n600,25\n500,-15\n";
  }
  EXPECT_EQ(testing::RunCommand(cli + " simulate --profile-csv " + dir + "/bad.csv -o " + dir + "/b.csv", &out), 2);
  EXPECT_NE(out.find("bad.csv:4"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir + "/b.csv"));
  std::filesystem::remove_all(dir);
}

// plan: the simulated figure carries its standard error over the seeds (null with one seed), and
// rate-cycles is a profile it compares.
TEST(SimulatorProfile, PlanReportsTheSimulatedErrorsStandardError) {
  const std::string cli = testing::CliPath();
  if (cli.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  const std::string dir = testing::MakeTempDir("sim_plan_se_test");
  std::string out;
  ASSERT_EQ(testing::RunCommand(cli + " plan --profiles ramp --seeds 3 --fs 0.2 --verbose --json " + dir + "/p.json", &out), 0)
      << out;
  EXPECT_NE(out.find("simulated: 1 SE (seeds)"), std::string::npos) << out;
  nlohmann::json j = testing::ReadJsonFile(dir + "/p.json");
  ASSERT_EQ(j["profiles"].size(), 1u);
  const double se = j["profiles"][0]["simulated_rms_rel_se"].get<double>();
  EXPECT_GT(se, 0.0);
  EXPECT_LT(se, 1.0);
  ASSERT_EQ(testing::RunCommand(cli + " plan --profiles ramp --seeds 1 --fs 0.2 --json " + dir + "/q.json", &out), 0)
      << out;
  j = testing::ReadJsonFile(dir + "/q.json");
  EXPECT_TRUE(j["profiles"][0]["simulated_rms_rel_se"].is_null());
  EXPECT_EQ(testing::RunCommand(cli + " plan --profiles nosuch --seeds 1", &out), 2) << out;
  EXPECT_NE(out.find("rate-cycles"), std::string::npos) << out;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocomp
