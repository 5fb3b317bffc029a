// gyrocomp/plan/plan.h: the unit read from recordings, the comparison of profiles, and that
// PlanChamberRun is what `gyrocomp plan --json` writes.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/plan/plan.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

// PlanOptions::IsValid names what is wrong (the messages name the flags of `gyrocomp plan`).
TEST(PlanOptions, IsValidRefusesSeedsProfilesAndRates) {
  std::string why;
  EXPECT_TRUE(PlanOptions{}.IsValid(&why)) << why;
  PlanOptions o;
  o.seeds = 0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(why, "--seeds must be in 1..50");
  o = PlanOptions{};
  o.profiles = {"ramp", "user"};  // the user's schedule has no data here
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("'user'"), std::string::npos) << why;
  o.profiles.clear();
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(why, "--profiles: none given");
  o = PlanOptions{};
  o.fs_hz = std::nan("");
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("PlanOptions::fs_hz"), std::string::npos) << why;
  auto r = PlanChamberRun(o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidArgument);
}

// A pilot run without a temperature span gives no drift family: the error names its span.
TEST(PlanUnit, PilotWithoutATemperatureSpanIsRefused) {
  const std::vector<double> rate(1000, 0.01), temp(1000, 25.0);
  const PlanRecording pilot{"flat", rate, temp, 1.0};
  auto u = PlanUnitFromRecordings(PlanOptions{}, &pilot, nullptr);
  ASSERT_FALSE(u.ok());
  EXPECT_EQ(u.error().kind, ErrorKind::kInvalidInput);
  EXPECT_NE(u.error().message.find("flat: the pilot run spans 0 C"), std::string::npos) << u.error().message;
}

// Stated figures keep their values over the recordings; without recordings the unit is the
// options' own, and the sources say so.
TEST(PlanUnit, WithoutRecordingsTheUnitIsTheOptions) {
  PlanOptions o;
  o.unit.noise.arw_deg_per_sqrt_h = 0.3;
  auto u = PlanUnitFromRecordings(o, nullptr, nullptr);
  ASSERT_TRUE(u.ok()) << u.error().message;
  EXPECT_EQ(u->sim.noise.arw_deg_per_sqrt_h, 0.3);
  EXPECT_EQ(u->sim.fs_hz, o.fs_hz);
  EXPECT_EQ(u->family_source, "flags (or the simulator's defaults)");
  EXPECT_TRUE(u->notes.empty());
  EXPECT_NE(u->BriefReport().find("ARW 0.3 deg/sqrt(h)"), std::string::npos) << u->BriefReport();
}

// Every number of `want` (the CLI's --json) equals the library's, bit for bit: the CLI prints what
// PlanChamberRun returned (JSON keeps 17 significant digits, enough to round-trip a double).
void ExpectSameJsonAsPlan(const nlohmann::json& want, const PlanResult& got) {
  const SimulatorOptions& u = got.unit.sim;
  const nlohmann::json& wu = want["unit"];
  EXPECT_EQ(wu["noise"]["arw_deg_per_sqrt_h"].get<double>(), u.noise.arw_deg_per_sqrt_h);
  EXPECT_EQ(wu["noise"]["bias_instability_deg_per_h"].get<double>(), u.noise.bias_instability_deg_per_h);
  EXPECT_EQ(wu["noise"]["rrw_deg_per_h_per_sqrt_h"].get<double>(), u.noise.rrw_deg_per_h_per_sqrt_h);
  EXPECT_EQ(wu["noise"]["source"].get<std::string>(), got.unit.noise_source);
  EXPECT_EQ(wu["drift"]["poly_dps"].get<std::vector<double>>(), u.bias.poly_dps);
  EXPECT_EQ(wu["drift"]["dtemp_coeff_dps_per_c_per_s"].get<double>(), u.bias.dtemp_coeff_dps_per_c_per_s);
  EXPECT_EQ(wu["drift"]["hysteresis_width_c"].get<double>(), u.bias.hysteresis_width_c);
  EXPECT_EQ(wu["drift"]["hysteresis_coeff_dps_per_c"].get<double>(), u.bias.hysteresis_coeff_dps_per_c);
  EXPECT_EQ(wu["drift"]["source"].get<std::string>(), got.unit.family_source);
  EXPECT_EQ(wu["cold_c"].get<double>(), u.profile.cold_temp_c);
  EXPECT_EQ(wu["hot_c"].get<double>(), u.profile.hot_temp_c);
  EXPECT_EQ(wu["notes"].get<std::vector<std::string>>(), got.unit.notes);
  ASSERT_EQ(want["profiles"].size(), got.profiles.size());
  for (std::size_t k = 0; k < got.profiles.size(); ++k) {
    const nlohmann::json& w = want["profiles"][k];
    const PlanProfileOutcome& o = got.profiles[k];
    EXPECT_EQ(w["profile"].get<std::string>(), o.profile);
    EXPECT_EQ(w["hours"].get<double>(), o.hours);
    EXPECT_EQ(w["models"].get<std::vector<std::string>>(), o.models);
    EXPECT_EQ(w["left_out"].get<std::vector<std::string>>(), o.excluded);
    EXPECT_EQ(w["predicted_rms_heating"].get<double>(), o.predicted_heat_dps);
    EXPECT_EQ(w["predicted_rms_cooling"].get<double>(), o.predicted_cool_dps);
    EXPECT_EQ(w["simulated_rms_heating"].get<double>(), o.simulated_heat_dps);
    EXPECT_EQ(w["simulated_rms_cooling"].get<double>(), o.simulated_cool_dps);
    EXPECT_EQ(w["predicted_rms"].get<double>(), o.predicted_dps());
    EXPECT_EQ(w["simulated_rms"].get<double>(), o.simulated_dps());
    if (std::isfinite(o.simulated_rel_se())) EXPECT_EQ(w["simulated_rms_rel_se"].get<double>(), o.simulated_rel_se());
    else EXPECT_TRUE(w["simulated_rms_rel_se"].is_null());
  }
  EXPECT_EQ(want["recommended"].get<std::string>(), got.Recommended().profile);
  EXPECT_EQ(want["seeds"].get<int>(), got.seeds);
}

// PlanChamberRun equals `gyrocomp plan --json`: stated figures, two seeds, two profiles.
TEST(PlanCli, LibraryEqualsThePlanJson) {
  const std::string cli = testing::CliPath();
  if (cli.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  const testing::TempDir dir("plan_parity_test");
  std::string out;
  ASSERT_EQ(testing::RunCommand(cli + " plan --profiles ramp,paper --seeds 2 --fs 0.2 --arw 0.5 --bias-instability 10 "
                                      "--cold -20 --hot 70 --drift-poly 0.01,0.001 --json " + dir / "p.json", &out), 0)
      << out;
  PlanOptions o;
  o.profiles = {"ramp", "paper"};
  o.seeds = 2;
  o.fs_hz = 0.2;
  o.unit.noise.arw_deg_per_sqrt_h = 0.5;
  o.unit.noise.bias_instability_deg_per_h = 10.0;
  o.unit.profile.cold_temp_c = -20.0;
  o.unit.profile.hot_temp_c = 70.0;
  o.unit.bias.poly_dps = {0.01, 0.001};
  o.stated = {.arw = true, .bias_instability = true, .drift_poly = true, .cold = true, .hot = true};
  auto got = PlanChamberRun(o);
  ASSERT_TRUE(got.ok()) << got.error().message;
  ExpectSameJsonAsPlan(testing::ReadJsonFile(dir / "p.json"), *got);
  EXPECT_NE(got->BriefReport().find("recommended: " + got->Recommended().profile), std::string::npos);
}

// The same with the unit read from a pilot run (its family, the noise of its residual, its range).
TEST(PlanCli, LibraryEqualsThePlanJsonWithAPilotRun) {
  const std::string cli = testing::CliPath();
  if (cli.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  const testing::TempDir dir("plan_pilot_parity_test");
  std::string out;
  ASSERT_EQ(testing::RunCommand(cli + " simulate --profile cycle --fs 0.5 --seed 37 -o " + dir / "pilot.csv", &out), 0)
      << out;
  ASSERT_EQ(testing::RunCommand(cli + " plan --pilot " + dir / "pilot.csv" + " --profiles ramp --seeds 1 --fs 0.2 "
                                      "--hot 80 --json " + dir / "p.json", &out), 0)
      << out;
  LogSpec spec;
  spec.min_samples = 3;
  spec.temp_required = true;
  auto log = ReadGyroLog(dir / "pilot.csv", spec);
  ASSERT_TRUE(log.ok()) << log.error().message;
  const PlanRecording pilot{dir / "pilot.csv", log->rate_dps.front(), log->temp_c, log->fs_hz};
  PlanOptions o;
  o.profiles = {"ramp"};
  o.seeds = 1;
  o.fs_hz = 0.2;
  o.unit.profile.hot_temp_c = 80.0;
  o.stated.hot = true;
  auto got = PlanChamberRun(o, &pilot);
  ASSERT_TRUE(got.ok()) << got.error().message;
  ExpectSameJsonAsPlan(testing::ReadJsonFile(dir / "p.json"), *got);
  EXPECT_NE(got->unit.family_source.find("pilot "), std::string::npos);
  EXPECT_FALSE(got->unit.notes.empty());  // extrapolated beyond the pilot's 60 C
}

// --pilot: a noise-free heat-cool pilot of the simulator's default family (cubic, dT/dt gain 1.5,
// hysteresis 4 C x 2e-3) gives that family back through the fitted two-state polynomial
// (FamilyFromModel re-expands it about 25 C); --noise-from reads the noise exactly as `allan`
// does; a flag overrides what a file gave; a pilot without a temperature span is exit 2.
TEST(PlanCli, ReadsTheUnitFromAPilotRunAndAnAllanRun) {
  const std::string cli = testing::CliPath();
  if (cli.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  const testing::TempDir dir("plan_unit_test");
  const std::string d = dir.path() + "/";
  std::string out;
  ASSERT_EQ(testing::RunCommand(cli + " simulate --profile heat-cool --fs 0.2 --arw 0 --bias-instability 0 --rrw 0 "
                                      "--temp-noise 0 -o " + d + "pilot.csv", &out), 0) << out;
  ASSERT_EQ(testing::RunCommand(cli + " simulate --profile soak --fs 10 --duration 14400 --seed 3 -o " + d + "soak.csv",
                                &out), 0) << out;
  ASSERT_EQ(testing::RunCommand(cli + " plan --pilot " + d + "pilot.csv --noise-from " + d + "soak.csv --arw 0.5 "
                                      "--profiles ramp --seeds 1 --fs 0.2 --json " + d + "p.json", &out), 0) << out;
  const nlohmann::json u = testing::ReadJsonFile(d + "p.json")["unit"];
  const nlohmann::json& f = u["drift"];
  const std::vector<double> truth = {0.02, 1.5e-3, 1.2e-5, -2.0e-7};  // BiasModelOptions' defaults
  ASSERT_EQ(f["poly_dps"].size(), truth.size()) << u.dump();
  EXPECT_NEAR(f["poly_dps"][0].get<double>(), truth[0], 5e-4) << u.dump();
  for (std::size_t k = 1; k < truth.size(); ++k) EXPECT_NEAR(f["poly_dps"][k].get<double>(), truth[k], 0.02 * std::abs(truth[k])) << k;
  EXPECT_NEAR(f["dtemp_coeff_dps_per_c_per_s"].get<double>(), 1.5, 0.05);
  EXPECT_EQ(f["hysteresis_width_c"].get<double>(), 4.0);
  EXPECT_NEAR(f["hysteresis_coeff_dps_per_c"].get<double>(), 2e-3, 1e-4);
  EXPECT_NEAR(u["cold_c"].get<double>(), -40.0, 0.1);
  EXPECT_NEAR(u["hot_c"].get<double>(), 60.0, 0.1);
  ASSERT_EQ(testing::RunCommand(cli + " allan -i " + d + "soak.csv --json " + d + "a.json", &out), 0) << out;
  const nlohmann::json al = testing::ReadJsonFile(d + "a.json");
  EXPECT_EQ(u["noise"]["arw_deg_per_sqrt_h"].get<double>(), 0.5);  // the flag overrides the file
  EXPECT_DOUBLE_EQ(u["noise"]["bias_instability_deg_per_h"].get<double>(), al["bias_instability_deg_per_h"].get<double>());
  EXPECT_EQ(testing::RunCommand(cli + " plan --pilot " + d + "soak.csv --profiles ramp --seeds 1", &out), 2) << out;
  EXPECT_NE(out.find("spans"), std::string::npos) << out;
  // The reader's advice names plan's own flags.
  EXPECT_EQ(testing::RunCommand(cli + " plan --pilot " + d + "pilot.csv --pilot-temp-col nosuch --profiles ramp", &out), 2);
  EXPECT_NE(out.find("choose it with --pilot-temp-col"), std::string::npos) << out;
}

// gyrocomp plan: one table row per profile with the predicted and the simulated error, a
// recommendation among them, and JSON with both numbers.
TEST(PlanCli, ComparesProfilesAndRecommendsOne) {
  const std::string cli = testing::CliPath();
  if (cli.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  const std::string dir = testing::MakeTempDir("plan_test");
  std::string out;
  ASSERT_EQ(testing::RunCommand(cli + " plan --profiles ramp,paper --seeds 1 --fs 0.2 --json " + dir + "/p.json", &out), 0)
      << out;
  EXPECT_NE(out.find("\n  ramp "), std::string::npos) << out;  // a row of the summary table
  EXPECT_NE(out.find("recommended: "), std::string::npos) << out;
  const nlohmann::json j = testing::ReadJsonFile(dir + "/p.json");
  ASSERT_EQ(j["profiles"].size(), 2u);
  for (const auto& p : j["profiles"]) {
    EXPECT_GT(p["predicted_rms"].get<double>(), 0.0);
    EXPECT_GT(p["simulated_rms"].get<double>(), 0.0);
  }
  // The heating-only ramp identifies no dT/dt gain (Eq. I-1).
  EXPECT_NE(j["profiles"][0]["left_out"].dump().find("dT/dt gain"), std::string::npos);
  EXPECT_TRUE(j["recommended"] == "ramp" || j["recommended"] == "paper");
  EXPECT_EQ(testing::RunCommand(cli + " plan --profiles nosuch --seeds 1", &out), 2) << out;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocomp
