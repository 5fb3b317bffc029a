// `gyrocomp export` end to end (cli.md contract: files, JSON, one-line errors with exit 2).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "export_test_models.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

class ExportCli : public testing::CliTest {
 protected:
  ExportCli() : CliTest("export_cli_test") {}
  void SetUp() override {
    CliTest::SetUp();
    if (IsSkipped()) return;
    run_ = export_test::ChamberRun(51);
    std::ofstream f(dir_ + "/cal.csv");
    f.precision(17);
    f << "time_s,rate_dps,temp_c\n";
    for (std::size_t i = 0; i < run_.temp_c.size(); ++i) f << i << "," << run_.rate_dps[i] << "," << run_.temp_c[i] << "\n";
    f.close();
    models_ = {export_test::Fit(run_, DriftModelKind::kPolynomial, DriftInputSet::kTemp, 5),
               export_test::Fit(run_, DriftModelKind::kPolynomial, DriftInputSet::kTempAndRate),
               export_test::Fit(run_, DriftModelKind::kSvr, DriftInputSet::kTemp)};
    for (int a = 0; a < 3; ++a) ASSERT_TRUE(SaveDriftModel(models_[a], Model(a)).ok());
  }
  std::string Model(int a) const { return dir_ + "/m" + std::to_string(a) + ".json"; }
  std::string Models() const { return " -m " + Model(0) + " -m " + Model(1) + " -m " + Model(2); }
  SimulatedRun run_;
  std::vector<DriftModel> models_;
};

TEST_F(ExportCli, Px4FileAndCostOnTheCalibrationRun) {
  std::string out;
  ASSERT_EQ(Run("export" + Models() + " --format px4 --device-id 2293768 --index 1 -i " + dir_ +
                    "/cal.csv -o " + dir_ + "/tc.params --json " + dir_ + "/e.json", &out), 0) << out;
  std::ifstream f(dir_ + "/tc.params");
  const std::string text((std::istreambuf_iterator<char>(f)), {});
  EXPECT_NE(text.find("1\t1\tTC_G1_ID\t2293768\t6\n"), std::string::npos) << text;
  EXPECT_NE(text.find("1\t1\tTC_G_ENABLE\t1\t6\n"), std::string::npos);
  EXPECT_NE(text.find("# Vehicle-Id Component-Id Name Value Type\n"), std::string::npos);
  EXPECT_NE(text.find("rad/s = deg/s x pi/180"), std::string::npos);  // the unit conversion is stated
  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/e.json");
  ASSERT_EQ(j["axes"].size(), 3u);
  for (int a = 0; a < 3; ++a) {
    // The reported cost is the library's, on the same run and the same cubic.
    TemperatureCubic c;
    c.ref_temp_c = j["ref_temp_c"].get<double>();
    c.temp_min_c = j["temp_min_c"].get<double>();
    c.temp_max_c = j["temp_max_c"].get<double>();
    c.coeff = j["axes"][a]["cubic_dps"]["coeff"].get<std::array<double, 4>>();
    auto cost = MeasureCubicProjectionCost(models_[a], c, DriftInputs{run_.temp_c, 1.0});
    ASSERT_TRUE(cost.ok());
    EXPECT_NEAR(j["axes"][a]["cost_calibration"]["rms_dps"].get<double>(), cost->rms, 1e-12);
    EXPECT_TRUE(j["axes"][a]["cost_validation"].is_null());
  }
}

// --static-weight (default auto): with -i each axis's cubic is the time or the temperature one,
// as the JSON says, and equal to that option's cubic; without -i auto is the model's own curve,
// and temperature is an error (exit 2, no file).
TEST_F(ExportCli, StaticWeightAutoExportsTheChosenCubicPerAxis) {
  std::string out;
  std::map<std::string, nlohmann::json> j;
  for (const std::string w : {"auto", "time", "temperature"}) {
    ASSERT_EQ(Run("export" + Models() + " --format px4 --device-id 7 -i " + dir_ + "/cal.csv --static-weight " + w +
                      " -o " + dir_ + "/" + w + ".params --json " + dir_ + "/" + w + ".json", &out), 0) << out;
    j[w] = testing::ReadJsonFile(dir_ + "/" + w + ".json");
  }
  for (int a = 0; a < 3; ++a) {
    const nlohmann::json& x = j["auto"]["axes"][a];
    const std::string chosen = x["static_weight"]["static_weight"];
    ASSERT_TRUE(chosen == "time" || chosen == "temperature") << x.dump();
    EXPECT_EQ(x["cubic_dps"]["coeff"], j[chosen]["axes"][a]["cubic_dps"]["coeff"]) << a;
    EXPECT_EQ(j["temperature"]["axes"][a]["static_weight"]["static_weight"], "temperature");
    EXPECT_NE(j["time"]["axes"][a]["cubic_dps"]["coeff"], j["temperature"]["axes"][a]["cubic_dps"]["coeff"]) << a;
    if (x["static_weight"].contains("time")) {  // models with a band: both expected errors
      const double t = x["static_weight"]["time"]["total_rms_dps"].get<double>();
      const double p = x["static_weight"]["temperature"]["total_rms_dps"].get<double>();
      EXPECT_EQ(chosen, p < t ? "temperature" : "time");
    }
  }
  ASSERT_EQ(Run("export" + Models() + " --format px4 --device-id 7 -o " + dir_ + "/n.params --json " + dir_ + "/n.json",
                &out), 0) << out;
  const nlohmann::json n = testing::ReadJsonFile(dir_ + "/n.json");
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(n["axes"][a]["static_weight"]["static_weight"], "time");
    EXPECT_NE(n["axes"][a]["static_weight"]["reason"].get<std::string>().find("without a calibration run"), std::string::npos);
  }
  EXPECT_EQ(Run("export" + Models() + " --format px4 --device-id 7 --static-weight temperature -o " + dir_ + "/x.params",
                &out), 2) << out;
  EXPECT_NE(out.find("needs the calibration run"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/x.params"));
}

// Model file schema 2: one file holding the three axes (fit --rate-col gx,gy,gz) is enough, and
// gives the same parameters as three one-axis files.
TEST_F(ExportCli, OneThreeAxisFileEqualsThreeFiles) {
  DriftModelSet set;
  const char* cols[3] = {"gx", "gy", "gz"};
  for (int a = 0; a < 3; ++a) {
    set.axes.push_back(models_[a]);
    set.axes.back().rate_col = cols[a];
  }
  ASSERT_TRUE(SaveDriftModelSet(set, dir_ + "/xyz.json").ok());
  std::string one, three;
  ASSERT_EQ(Run("export -m " + dir_ + "/xyz.json --format ardupilot", &one), 0) << one;
  ASSERT_EQ(Run("export" + Models() + " --format ardupilot", &three), 0) << three;
  auto params = [](const std::string& text) {  // the parameter lines, comments dropped
    std::istringstream in(text);
    std::string line, out;
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#') out += line + "\n";
    return out;
  };
  EXPECT_EQ(params(one), params(three));
  EXPECT_NE(one.find("x: gx of"), std::string::npos) << one;
}

TEST_F(ExportCli, ArduPilotToStdout) {
  std::string out;
  ASSERT_EQ(Run("export" + Models() + " --format ardupilot --index 2", &out), 0) << out;
  EXPECT_NE(out.find("INS_TCAL2_ENABLE,1\n"), std::string::npos) << out;
  EXPECT_NE(out.find("INS_TCAL2_GYR3_Z,"), std::string::npos) << out;
  EXPECT_NE(out.find("cost not measured"), std::string::npos) << out;
}

TEST_F(ExportCli, BadRequestsAreOneLineErrors) {
  struct Case {
    std::string args, says;
  };
  const std::vector<Case> cases = {
      {"export" + Models() + " --format px4 -o " + dir_ + "/x.params", "device_id"},
      {"export -m " + Model(0) + " -m " + Model(1) + " --format ardupilot", "three axis models"},
      {"export -m " + Model(0) + " --format c", "-o DIR/NAME"},
      {"export -m " + Model(0) + " --format c -o " + dir_ + "/9bad", "C identifier"},
      {"export -m " + dir_ + "/missing.json --format c -o " + dir_ + "/g", "missing.json"},
      {"export" + Models() + " --format px4 --device-id 0", "--device-id"},
  };
  for (const Case& c : cases) {
    std::string out;
    EXPECT_EQ(Run(c.args, &out), 2) << c.args << "\n" << out;
    EXPECT_NE(out.find(c.says), std::string::npos) << c.args << "\n" << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  }
  EXPECT_FALSE(std::ifstream(dir_ + "/x.params").good());  // no partial output
}

// The headline: a PX4 ULog in, a parameter file out, with no --device-id: fit keeps the
// log's sensor_gyro.device_id in the model file and export writes it as TC_G<i>_ID.
TEST_F(ExportCli, UlogFitThenPx4ExportCarriesTheDeviceId) {
  std::string out;
  const std::string ulg = dir_ + "/chamber.ulg";
  ASSERT_EQ(Run("simulate --profile ramp --ramp-end 40 --fs 10 --seed 7 -o " + ulg, &out), 0) << out;
  ASSERT_EQ(Run("fit -i " + ulg + " --instance 0 --model poly -o " + dir_ + "/m.json", &out), 0) << out;
  const nlohmann::json m = testing::ReadJsonFile(dir_ + "/m.json");
  ASSERT_EQ(m["axes"].size(), 3u);
  const std::uint32_t id = m.at("device_id").get<std::uint32_t>();  // what simulate writes into the ULog
  EXPECT_EQ(id, BoardGyroDeviceId(0));  // realistic: ICM20689 on SPI1 (PX4 DeviceStructure)
  EXPECT_EQ(id, 3932170u);
  ASSERT_EQ(Run("export -m " + dir_ + "/m.json --format px4 -o " + dir_ + "/tc.params", &out), 0) << out;
  std::ifstream f(dir_ + "/tc.params");
  const std::string text((std::istreambuf_iterator<char>(f)), {});
  EXPECT_NE(text.find("1\t1\tTC_G0_ID\t" + std::to_string(id) + "\t6\n"), std::string::npos) << text;
  // --device-id still overrides the file's.
  ASSERT_EQ(Run("export -m " + dir_ + "/m.json --format px4 --device-id 2293768 -o " + dir_ + "/tc2.params", &out), 0)
      << out;
  std::ifstream f2(dir_ + "/tc2.params");
  const std::string text2((std::istreambuf_iterator<char>(f2)), {});
  EXPECT_NE(text2.find("1\t1\tTC_G0_ID\t2293768\t6\n"), std::string::npos) << text2;
}

}  // namespace
}  // namespace gyrocomp

namespace gyrocomp {
namespace {

TEST_F(ExportCli, IndexFollowsTheGyroInstance) {
  // One file with three axes, fitted on instance 2 of a log (model file "sensor").
  DriftModelSet set;
  set.axes = models_;
  set.axes[0].rate_col = "x_rad_s";
  set.axes[1].rate_col = "y_rad_s";
  set.axes[2].rate_col = "z_rad_s";
  set.sensor = SensorIdentity{"gyro", 2, 2293768u, "sensor"};
  set.device_id = 2293768u;
  const std::string m = dir_ + "/inst2.json";
  ASSERT_TRUE(SaveDriftModelSet(set, m).ok());
  std::string out;
  ASSERT_EQ(Run("export -m " + m + " --format px4 -o " + dir_ + "/a.params", &out), 0) << out;
  std::ifstream a(dir_ + "/a.params");
  const std::string px4((std::istreambuf_iterator<char>(a)), {});
  EXPECT_NE(px4.find("1\t1\tTC_G2_ID\t2293768\t6\n"), std::string::npos) << px4;
  ASSERT_EQ(Run("export -m " + m + " --format ardupilot -o " + dir_ + "/b.param", &out), 0) << out;
  std::ifstream b(dir_ + "/b.param");
  const std::string ap((std::istreambuf_iterator<char>(b)), {});
  EXPECT_NE(ap.find("INS_TCAL3_ENABLE,1\n"), std::string::npos) << ap;
  // --index wins.
  ASSERT_EQ(Run("export -m " + m + " --format ardupilot --index 1 -o " + dir_ + "/c.param", &out), 0) << out;
  std::ifstream c(dir_ + "/c.param");
  const std::string ap1((std::istreambuf_iterator<char>(c)), {});
  EXPECT_NE(ap1.find("INS_TCAL1_ENABLE,1\n"), std::string::npos) << ap1;
  // Instance 3 has no ArduPilot INS_TCAL4: refused, asking for --index.
  set.sensor->instance = 3;
  ASSERT_TRUE(SaveDriftModelSet(set, m).ok());
  EXPECT_EQ(Run("export -m " + m + " --format ardupilot -o " + dir_ + "/d.param", &out), 2) << out;
  EXPECT_NE(out.find("choose one with --index"), std::string::npos) << out;
}

}  // namespace
}  // namespace gyrocomp
