// Tests of the Kalibr noise figures (conversions computed by hand) and of `gyrocomp allan
// --kalibr-yaml / --deviation` end to end.
#include "gyrocomp/allan/kalibr.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "gyrocomp/allan/deviations.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

// The value after "key: " in the YAML text (NaN when absent).
double YamlValue(const std::string& yaml, const std::string& key) {
  std::istringstream in(yaml);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key + ": ", 0) == 0) return std::stod(line.substr(key.size() + 2));
  }
  return NAN;
}

AllanResult Terms(const std::string& axis, double arw_deg_per_sqrt_h, std::optional<double> rrw) {
  AllanResult r;
  r.axis = axis;
  r.terms.arw_deg_per_sqrt_h = arw_deg_per_sqrt_h;
  r.terms.rrw_deg_per_h_per_sqrt_h = rrw;
  return r;
}

TEST(Kalibr, ConversionsComputedByHand) {
  // By hand: 1 deg/sqrt(h) = (1/60) deg/sqrt(s) = (1/60)(pi/180) rad/s/sqrt(Hz)
  //        = 0.0166667 x 0.0174533 = 2.908882e-4 rad/s/sqrt(Hz);
  // 5 deg/h/sqrt(h) = 5 / (3600 x 60) deg/s/sqrt(s) = 2.314815e-5 x 0.0174533 = 4.040114e-7
  // rad/s^2/sqrt(Hz). Relative 1e-6: the hand values have 7 digits.
  Result<KalibrAxisNoise> g = KalibrNoiseFromAllan(Terms("gz_dps", 1.0, 5.0), KalibrSensor::kGyroscope);
  ASSERT_TRUE(g.ok());
  EXPECT_NEAR(g->noise_density, 2.908882e-4, 1e-6 * 2.908882e-4);
  EXPECT_NEAR(g->random_walk, 4.040114e-7, 1e-6 * 4.040114e-7);
  EXPECT_FALSE(g->random_walk_is_upper_bound);
  // Accelerometer: sigma(1 s) = 0.006 m/s^2 reads as "ARW" 0.36 (x 60): density 0.006 m/s^2/sqrt(Hz);
  // K = 1e-4 m/s^2/sqrt(s) reads as "RRW" 21.6 (x 216000): 1e-4 m/s^3/sqrt(Hz). No pi/180.
  Result<KalibrAxisNoise> acc = KalibrNoiseFromAllan(Terms("ax", 0.36, 21.6), KalibrSensor::kAccelerometer);
  ASSERT_TRUE(acc.ok());
  EXPECT_NEAR(acc->noise_density, 0.006, 1e-15);
  EXPECT_NEAR(acc->random_walk, 1e-4, 1e-15);

  // The file: the largest axis as the scalar, every axis in comments, update rate, topic.
  Result<KalibrAxisNoise> g2 = KalibrNoiseFromAllan(Terms("gx_dps", 2.0, 1.0), KalibrSensor::kGyroscope);
  ASSERT_TRUE(g2.ok());
  KalibrYamlOptions yo;
  yo.rostopic = "/imu/data";
  const std::string yaml = KalibrImuYaml({*g, *g2}, {*acc}, 200.0, yo);
  EXPECT_NEAR(YamlValue(yaml, "gyroscope_noise_density"), 2.0 * 2.908882e-4, 1e-6 * 5.8e-4);  // gx
  EXPECT_NEAR(YamlValue(yaml, "gyroscope_random_walk"), 4.040114e-7, 1e-6 * 4.040114e-7);          // gz
  EXPECT_NEAR(YamlValue(yaml, "accelerometer_noise_density"), 0.006, 1e-15);
  EXPECT_NEAR(YamlValue(yaml, "accelerometer_random_walk"), 1e-4, 1e-15);
  EXPECT_EQ(YamlValue(yaml, "update_rate"), 200.0);
  EXPECT_NE(yaml.find("rostopic: /imu/data\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("#   gz_dps: noise_density"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("#   gx_dps: noise_density"), std::string::npos) << yaml;
  // Without accelerometer axes: no accelerometer keys, a comment saying they must be filled.
  const std::string gyro_only = KalibrImuYaml({*g}, {}, 200.0, yo);
  EXPECT_TRUE(std::isnan(YamlValue(gyro_only, "accelerometer_noise_density")));
  EXPECT_NE(gyro_only.find("must be filled"), std::string::npos) << gyro_only;
}

TEST(Kalibr, RandomWalkUpperBoundWithoutAPlusHalfRegion) {
  // A white-only curve sigma = 0.01 / sqrt(tau): no +1/2 region; the bound
  // min sigma(tau) sqrt(3 / tau) = 0.01 sqrt(3) / tau_max at the longest usable tau.
  AllanResult r = Terms("g", 0.6, std::nullopt);
  r.curve.tau_s = {1, 10, 100, 1000};
  for (double t : r.curve.tau_s) r.curve.adev_dps.push_back(0.01 / std::sqrt(t));
  r.curve.edf = {1000, 100, 10, 1};  // the last tau is not usable (EDF < 10)
  Result<KalibrAxisNoise> k = KalibrNoiseFromAllan(r, KalibrSensor::kAccelerometer);
  ASSERT_TRUE(k.ok());
  EXPECT_TRUE(k->random_walk_is_upper_bound);
  EXPECT_NEAR(k->random_walk, 0.01 * std::sqrt(3.0) / 100.0, 1e-15);
  // No ARW (curve short of 1 s): an error naming the axis.
  r.terms.arw_deg_per_sqrt_h.reset();
  k = KalibrNoiseFromAllan(r, KalibrSensor::kGyroscope);
  ASSERT_FALSE(k.ok());
  EXPECT_NE(k.error().message.find("'g'"), std::string::npos);
}

class AllanCliKinds : public testing::CliTest {
 protected:
  AllanCliKinds() : CliTest("allan_kinds_cli") {}
};

TEST_F(AllanCliKinds, DeviationJsonAndKalibrFileFromTheGoldenInput) {
  const std::string input = testing::GoldenPath("allan_kinds/rate.csv");
  std::string out;
  const int rc = Run("allan -i " + input + " --deviation mdev --json " + dir_ + "/m.json -o " + dir_ +
                         "/m.csv --kalibr-yaml " + dir_ + "/imu.yaml --rostopic /imu0",
                     &out);
  ASSERT_EQ(rc, 0) << out;
  const auto j = testing::ReadJsonFile(dir_ + "/m.json");
  // The contract's keys stay; the chosen curve is added with its interval arrays.
  for (const char* key : {"tau_s", "adev_dps", "arw_deg_per_sqrt_h", "adev_min_deg_per_h", "adev_min_at_longest_tau",
                          "adev_min_usable_deg_per_h", "min_edf", "mdev_tau_s", "mdev_dps", "mdev_lo_dps",
                          "mdev_hi_dps", "mdev_edf", "mdev_n"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  const auto golden = testing::ReadJsonFile(testing::GoldenPath("allan_kinds/deviations.json"));
  const auto mdev = j["mdev_dps"].get<std::vector<double>>();
  const auto gold = golden["mdev"]["dev_dps"].get<std::vector<double>>();
  ASSERT_EQ(mdev.size(), gold.size());
  for (std::size_t k = 0; k < gold.size(); ++k) EXPECT_NEAR(mdev[k], gold[k], 1e-9 * gold[k]);
  const auto csv = testing::ReadGoldenCsv(dir_ + "/m.csv");
  ASSERT_TRUE(csv.count("mdev_dps"));
  EXPECT_EQ(csv.at("mdev_dps"), mdev);
  // The Kalibr file agrees with the JSON's ARW through the documented conversion.
  const std::string yaml = testing::ReadFile(dir_ + "/imu.yaml");
  const double arw = j["arw_deg_per_sqrt_h"].get<double>();
  EXPECT_NEAR(YamlValue(yaml, "gyroscope_noise_density"), arw / 60.0 * M_PI / 180.0, 1e-12 * arw);
  EXPECT_EQ(YamlValue(yaml, "update_rate"), 10.0);

  // Bad kind: exit 2, one line naming the option, no output.
  const int bad = Run("allan -i " + input + " --deviation oadev --json " + dir_ + "/bad.json", &out);
  EXPECT_EQ(bad, 2) << out;
  EXPECT_NE(out.find("--deviation oadev"), std::string::npos) << out;
  EXPECT_FALSE(std::ifstream(dir_ + "/bad.json").good());
}

}  // namespace
}  // namespace gyrocomp
