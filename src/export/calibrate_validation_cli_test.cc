// `gyrocomp calibrate --validation RUN --report R` and the expected-error bands of `calibrate`
// and `export`: the validation scores are the firmware formula on the validation log,
// recomputed here from the parameter file alone; the report holds the tables; a bad validation
// run is exit 2 with no file; the bands are the library's ExpectedCubicError.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "export_test_models.h"
#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "gyrocomp/io/ulog.h"
#include "param_files_test_util.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

std::map<std::string, float> ReadQgcValues(const std::string& text) {
  std::map<std::string, float> p;
  for (const auto& [name, param] : testing::ReadQgcFile(text).params) p[name] = std::stof(param.value);
  return p;
}

// RMS of 10-row block means of v - offset, their mean removed; offset from the PX4 file in float
// (calc_thermal_offsets_3D), written here independently of the library.
double Px4Score(const std::map<std::string, float>& p, const std::string& pre, int axis, const std::vector<double>& temp,
                const std::vector<double>& v) {
  const float tmin = p.at(pre + "TMIN"), tmax = p.at(pre + "TMAX"), tref = p.at(pre + "TREF");
  std::vector<double> means;
  for (std::size_t b = 0; b + 10 <= v.size(); b += 10) {
    double s = 0.0;
    for (std::size_t i = b; i < b + 10; ++i) {
      const float t = static_cast<float>(temp[i]);
      const float dt = (t > tmax ? tmax : t < tmin ? tmin : t) - tref;
      const std::string a = "_" + std::to_string(axis);
      const float off = p.at(pre + "X0" + a) + p.at(pre + "X1" + a) * dt + p.at(pre + "X2" + a) * dt * dt +
                        p.at(pre + "X3" + a) * dt * dt * dt;
      s += v[i] - off;
    }
    means.push_back(s / 10.0);
  }
  double mean = 0.0, ss = 0.0;
  for (double m : means) mean += m / static_cast<double>(means.size());
  for (double m : means) ss += (m - mean) * (m - mean);
  return std::sqrt(ss / static_cast<double>(means.size()));
}

// The same with no correction.
double RawScore(const std::vector<double>& v) {
  std::vector<double> means;
  for (std::size_t b = 0; b + 10 <= v.size(); b += 10) {
    double s = 0.0;
    for (std::size_t i = b; i < b + 10; ++i) s += v[i];
    means.push_back(s / 10.0);
  }
  double mean = 0.0, ss = 0.0;
  for (double m : means) mean += m / static_cast<double>(means.size());
  for (double m : means) ss += (m - mean) * (m - mean);
  return std::sqrt(ss / static_cast<double>(means.size()));
}

class CalibrateValidationCli : public testing::CliTest {
 protected:
  CalibrateValidationCli() : CliTest("calibrate_validation_cli_test") {}
  // The bench's board: cold start, heating ramp at 1 C/min behind a 120 s lag; `profile` adds
  // the direction (cooling: --room-temp 60 --ramp-end 10).
  std::string Simulate(const std::string& name, int seed, const std::string& profile) {
    std::string out;
    const std::string path = dir_ + "/" + name;
    EXPECT_EQ(Run("simulate --profile ramp --thermal-lag 120 --room-hold 600 --hold 600 --ramp-rate 1 --fs 10 --imus 2 "
                  "--seed " + std::to_string(seed) + " " + profile + " -o " + path, &out), 0) << out;
    return path;
  }
};

TEST_F(CalibrateValidationCli, ScoresEveryCubicWithTheFirmwareFormulaOnTheValidationRun) {
  // The static structure (bias(T) only): what a cubic can remove.
  const std::string stat = " --dtemp-coeff 0 --hysteresis-coeff 0";
  const std::string cal = Simulate("cal.ulg", 11, "--room-temp 10 --ramp-end 60" + stat);
  const std::string val = Simulate("val.ulg", 12, "--room-temp 60 --ramp-end 10" + stat);
  std::string out;
  ASSERT_EQ(Run("calibrate -i " + cal + " --format px4 -o " + dir_ + "/tc.params --json " + dir_ + "/c.json --validation " +
                    val + " --report " + dir_ + "/r.html --verbose", &out), 0) << out;
  EXPECT_NE(out.find("validation run: RMS of block means"), std::string::npos) << out;
  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/c.json");
  EXPECT_EQ(j["validation_run"], val);
  const auto p = ReadQgcValues(testing::ReadFile(dir_ + "/tc.params"));
  ULogReadOptions ro;
  ro.average_window_us = 1000000;  // the rows calibrate scores: 1 s means (--fit-rate 1)
  auto log = ReadULog(val, ro);
  ASSERT_TRUE(log.ok());
  int scored = 0;
  for (const auto& s : j["sensors"]) {
    ASSERT_EQ(s["status"], "calibrated") << s.dump();
    const auto& v = s["validation"];
    ASSERT_EQ(v["status"], "scored") << s.dump();
    const std::string type = s["type"];
    const int inst = s["instance"];
    if (type == "baro") continue;
    const bool gyro = type == "gyro";
    std::vector<double> temp;
    std::vector<std::vector<double>> axes;
    for (const auto& g : log->gyros)
      if (gyro && g.multi_id == inst) temp = g.temperature_c, axes = {g.x_rad_s, g.y_rad_s, g.z_rad_s};
    for (const auto& a : log->accels)
      if (!gyro && a.multi_id == inst) temp = a.temperature_c, axes = {a.x_m_s2, a.y_m_s2, a.z_m_s2};
    ASSERT_FALSE(axes.empty());
    const std::string pre = std::string("TC_") + (gyro ? "G" : "A") + std::to_string(s["slot"].get<int>()) + "_";
    for (int a = 0; a < 3; ++a) {
      const double want = Px4Score(p, pre, a, temp, axes[a]);
      EXPECT_NEAR(v["cubic_rms"][a].get<double>(), want, 1e-6 * want + 1e-12) << pre << a;
      EXPECT_NEAR(v["raw_rms"][a].get<double>(), RawScore(axes[a]), 1e-9 * RawScore(axes[a])) << pre << a;
      // On the opposite-direction run the cubic and the full model remove most of the accel's
      // drift (0.02 m/s^2 against a 4e-4 m/s^2 flicker floor) and part of the gyro's (a static
      // drift here, of the order of the gyro's own flicker: docs/explanation/flight-controller-export.md).
      const double keep = gyro ? 0.9 : 0.1;
      EXPECT_LT(v["cubic_rms"][a].get<double>(), keep * v["raw_rms"][a].get<double>()) << pre << a;
      EXPECT_LT(v["full_model_rms"][a].get<double>(), keep * v["raw_rms"][a].get<double>()) << pre << a;
      ++scored;
    }
  }
  EXPECT_EQ(scored, 12);  // 2 gyros + 2 accels x 3 axes
  // The report: self-contained HTML with the three tables and each sensor's charts
  // (src/report/calibrate_report_cli_test.cc checks their data).
  const std::string html = testing::ReadFile(dir_ + "/r.html");
  for (const char* s : {"<html", "Sensors", "Exported cubics", "Validation on", "gyro 0 (slot 0): single run",
                        "x_rad_s: drift and exported cubic", "expected error, steady"})
    EXPECT_NE(html.find(s), std::string::npos) << s;
}

TEST_F(CalibrateValidationCli, ExpectedErrorPerConditionInTheHeaderAndTheJson) {
  const std::string cal = Simulate("cal.ulg", 21, "--room-temp 10 --ramp-end 60");
  std::string out;
  ASSERT_EQ(Run("calibrate -i " + cal + " --format px4 -o " + dir_ + "/tc.params --json " + dir_ + "/c.json", &out), 0)
      << out;
  const std::string text = testing::ReadFile(dir_ + "/tc.params");
  EXPECT_NE(text.find("#     expected error steady "), std::string::npos) << text;
  EXPECT_NE(text.find("; warm-up "), std::string::npos) << text;
  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/c.json");
  for (const auto& s : j["sensors"]) {
    const auto& e = s["expected_error"];
    ASSERT_FALSE(e["band_level"].is_null()) << e.dump();
    for (std::size_t a = 0; a < s["axes"].size(); ++a) {
      const auto& ax = e["axes"][a];
      for (const char* cond : {"steady", "warm_up"}) {
        ASSERT_TRUE(ax[cond].is_object()) << s["type"] << " " << cond << " " << e.dump();
        const double total = ax[cond]["total_rms"], proj = ax[cond]["projection_rms"], sd = ax[cond]["band_sd_rms"];
        EXPECT_NEAR(total, std::hypot(proj, sd), 1e-12 * total);
        EXPECT_GT(sd, 0.0);
        EXPECT_EQ(e[cond][a].get<double>(), total);
      }
    }
  }
  EXPECT_FALSE(j["sensors"][0].contains("validation"));  // no --validation
  EXPECT_TRUE(j["validation_run"].is_null());
}

TEST_F(CalibrateValidationCli, AValidationRunOfTheOtherKindIsExit2AndNoFile) {
  const std::string cal = Simulate("cal.ulg", 31, "--room-temp 10 --ramp-end 60");
  std::string out;
  ASSERT_EQ(Run("simulate --profile ramp --fs 10 --seed 3 -o " + dir_ + "/val.bin", &out), 0) << out;
  EXPECT_EQ(Run("calibrate -i " + cal + " --format px4 -o " + dir_ + "/tc.params --report " + dir_ + "/r.html --validation " +
                    dir_ + "/val.bin", &out), 2) << out;
  EXPECT_NE(out.find("--validation must be a log of the same kind"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir_ + "/tc.params"));
  EXPECT_FALSE(fs::exists(dir_ + "/r.html"));
  EXPECT_EQ(Run("calibrate -i " + cal + " --format px4 -o " + dir_ + "/tc.params --block 0", &out), 2) << out;
}

// calibrate -i A -i B: one pooled cubic per sensor over both runs' still rows, on the range
// either covers; the order of the runs does not change the cubics; the same log twice is the
// pooled fit of that log; a log of the other kind is exit 2.
TEST_F(CalibrateValidationCli, SeveralRunsOfOneBoardArePooled) {
  const std::string a = Simulate("a.ulg", 51, "--room-temp 10 --ramp-end 60");
  const std::string b = Simulate("b.ulg", 52, "--room-temp 12 --ramp-end 58");
  std::string out;
  auto cubics = [&](const std::string& inputs, const std::string& name) {
    EXPECT_EQ(Run("calibrate " + inputs + " --format px4 -o " + dir_ + "/" + name + ".params --json " + dir_ + "/" + name +
                  ".json", &out), 0) << out;
    return testing::ReadJsonFile(dir_ + "/" + name + ".json");
  };
  const nlohmann::json once = cubics("-i " + a, "once"), twice = cubics("-i " + a + " -i " + a, "twice");
  const nlohmann::json ab = cubics("-i " + a + " -i " + b, "ab"), ba = cubics("-i " + b + " -i " + a, "ba");
  EXPECT_EQ(twice["inputs"].size(), 2u);
  ASSERT_EQ(ab["logs"].size(), 2u);
  for (const auto& log : ab["logs"]) EXPECT_EQ(log["still_segments"].size(), 1u) << log;  // chamber runs: still throughout
  for (std::size_t i = 0; i < once["sensors"].size(); ++i) {
    EXPECT_EQ(once["sensors"][i]["runs_combined"], 1);
    EXPECT_EQ(once["sensors"][i]["fit"], "single run");
    EXPECT_EQ(ab["sensors"][i]["runs_combined"], 2);
    EXPECT_EQ(ab["sensors"][i]["fit"], "pooled");
    EXPECT_EQ(twice["sensors"][i]["fit"], "pooled");
    EXPECT_EQ(ab["sensors"][i]["identification"]["logs_with_still"], 2);
    for (std::size_t k = 0; k < once["sensors"][i]["axes"].size(); ++k) {
      // Both runs: the range either covers (a's, 10..60 C, holds b's) and the same cubic in either order.
      const auto& x = ab["sensors"][i]["axes"][k]["cubic"];
      const auto& y = ba["sensors"][i]["axes"][k]["cubic"];
      EXPECT_EQ(x["temp_min_c"], y["temp_min_c"]);
      EXPECT_LT(x["temp_min_c"].get<double>(), 11.0);
      EXPECT_GT(x["temp_max_c"].get<double>(), 59.0);
      for (int j = 0; j < 4; ++j)
        EXPECT_NEAR(x["coeff"][j].get<double>(), y["coeff"][j].get<double>(), 1e-9 * std::abs(x["coeff"][j].get<double>()) + 1e-300);
    }
  }
  ASSERT_EQ(Run("simulate --profile ramp --fs 10 --seed 3 -o " + dir_ + "/c.bin", &out), 0) << out;
  EXPECT_EQ(Run("calibrate -i " + a + " -i " + dir_ + "/c.bin --format px4 -o " + dir_ + "/x.params", &out), 2) << out;
  EXPECT_NE(out.find("every -i must be a log of the same kind"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir_ + "/x.params"));
}

// --static-weight auto (the default): each axis's exported cubic is the one the JSON says was
// chosen, i.e. equal to that axis's cubic under --static-weight time or temperature, and the
// choice is the estimator with the lower expected error; the header and the console say it.
TEST_F(CalibrateValidationCli, AutoStaticWeightExportsTheChosenEstimatorPerAxis) {
  const std::string a = Simulate("a.ulg", 61, "--room-temp 10 --ramp-end 60");
  std::string out;
  std::map<std::string, nlohmann::json> j;
  for (const char* w : {"", "time", "temperature"}) {
    const std::string weight = w, name = "w_" + weight;
    ASSERT_EQ(Run("calibrate -i " + a + " --format px4 -o " + dir_ + "/" + name + ".params --json " + dir_ + "/" + name +
                      ".json" + (weight.empty() ? " --verbose" : " --static-weight " + weight), &out), 0) << out;
    j[w] = testing::ReadJsonFile(dir_ + "/" + name + ".json");
    if (!*w) {
      EXPECT_NE(out.find("static weight"), std::string::npos) << out;
      EXPECT_NE(testing::ReadFile(dir_ + "/" + name + ".params").find("static weight"), std::string::npos);
    }
  }
  EXPECT_EQ(j[""]["static_weight"], "auto");
  int axes = 0;
  for (std::size_t i = 0; i < j[""]["sensors"].size(); ++i) {
    if (j[""]["sensors"][i]["status"] != "calibrated") continue;
    for (std::size_t k = 0; k < j[""]["sensors"][i]["axes"].size(); ++k) {
      const nlohmann::json& ax = j[""]["sensors"][i]["axes"][k];
      const std::string chosen = ax["static_weight"];
      ASSERT_TRUE(chosen == "time" || chosen == "temperature") << chosen;
      const nlohmann::json& c = ax["static_weight_choice"];
      ASSERT_TRUE(c.is_object()) << ax.dump();
      EXPECT_EQ(c["chosen"], chosen);
      const double t = c["time"]["total_rms"].get<double>(), p = c["temperature"]["total_rms"].get<double>();
      EXPECT_EQ(chosen, p < t ? "temperature" : "time") << t << " " << p;
      EXPECT_EQ(ax["cubic"]["coeff"], j[chosen]["sensors"][i]["axes"][k]["cubic"]["coeff"]) << ax["col"];
      EXPECT_EQ(j[chosen]["sensors"][i]["axes"][k]["static_weight"], chosen);
      ++axes;
    }
  }
  EXPECT_GE(axes, 12);  // 2 IMUs x gyro + accel x 3 axes (and the baro)
}

// export: the header and the JSON carry each axis's expected error, the library's numbers.
TEST_F(CalibrateValidationCli, ExportCarriesTheLibrarysExpectedError) {
  const SimulatedRun run = export_test::ChamberRun(41);
  {
    std::ofstream f(dir_ + "/cal.csv");
    f.precision(17);
    f << "time_s,rate_dps,temp_c\n";
    for (std::size_t i = 0; i < run.temp_c.size(); ++i) f << i << "," << run.rate_dps[i] << "," << run.temp_c[i] << "\n";
  }
  const DriftModel m = export_test::Fit(run, DriftModelKind::kPolynomial, DriftInputSet::kTempAndRate);
  ASSERT_TRUE(SaveDriftModel(m, dir_ + "/m.json").ok());
  const std::string models = " -m " + dir_ + "/m.json -m " + dir_ + "/m.json -m " + dir_ + "/m.json";
  std::string out;
  ASSERT_EQ(Run("export" + models + " --format ardupilot -i " + dir_ + "/cal.csv -o " + dir_ + "/tc.param --json " + dir_ +
                    "/e.json", &out), 0) << out;
  EXPECT_NE(testing::ReadFile(dir_ + "/tc.param").find("expected next-run error of the cubic"), std::string::npos);
  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/e.json");
  TemperatureCubic c;
  c.ref_temp_c = j["ref_temp_c"].get<double>();
  c.temp_min_c = j["temp_min_c"].get<double>();
  c.temp_max_c = j["temp_max_c"].get<double>();
  c.coeff = j["axes"][0]["cubic_dps"]["coeff"].get<std::array<double, 4>>();
  auto e = ExpectedCubicError(m, c, DriftInputs{run.temp_c, 1.0});
  ASSERT_TRUE(e.ok());
  const auto& x = j["axes"][0]["expected_error"];
  EXPECT_NEAR(x["steady"]["total_rms_dps"].get<double>(), e->steady.total_rms, 1e-9 * e->steady.total_rms);
  ASSERT_TRUE(e->warm_up.has_value());
  EXPECT_NEAR(x["warm_up"]["total_rms_dps"].get<double>(), e->warm_up->total_rms, 1e-9 * e->warm_up->total_rms);
  // Without -i: steady only, warm-up with the reason.
  ASSERT_EQ(Run("export" + models + " --format ardupilot -o " + dir_ + "/tc2.param --json " + dir_ + "/e2.json", &out), 0)
      << out;
  const nlohmann::json j2 = testing::ReadJsonFile(dir_ + "/e2.json");
  EXPECT_TRUE(j2["axes"][0]["expected_error"]["warm_up"].is_null());
  EXPECT_NEAR(j2["axes"][0]["expected_error"]["steady"]["total_rms_dps"].get<double>(), e->steady.total_rms,
              1e-9 * e->steady.total_rms);
}

}  // namespace
}  // namespace gyrocomp
