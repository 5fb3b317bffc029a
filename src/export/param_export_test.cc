// PX4 and ArduPilot parameter files evaluated with the firmware's own formulas (written here from
// the sources cited in param_export.h and docs/explanation/flight-controller-export.md), compared with the model's prediction;
// and the cubic projection they rest on.
#include "gyrocomp/export/param_export.h"

#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include <gtest/gtest.h>

#include "export_test_models.h"
#include "param_files_test_util.h"
#include "gyrocomp/export/causal_drift.h"

namespace gyrocomp {
namespace {

constexpr double kRadPerDegree = std::numbers::pi / 180.0;
constexpr double kFloatEps = 1.0 / (1 << 24);  // float32 unit roundoff

// ---- PX4: TemperatureCompensation::calc_thermal_offsets_3D, in float as on the vehicle ----
struct Px4GyroCal {
  float tref = 0, tmin = 0, tmax = 0;
  float x0[3]{}, x1[3]{}, x2[3]{}, x3[3]{};
};

void Px4Offsets(const Px4GyroCal& c, float measured_temp, float offset[3]) {
  float delta_temp;
  if (measured_temp > c.tmax) delta_temp = c.tmax - c.tref;
  else if (measured_temp < c.tmin) delta_temp = c.tmin - c.tref;
  else delta_temp = measured_temp - c.tref;
  const float delta_temp_2 = delta_temp * delta_temp;
  const float delta_temp_3 = delta_temp_2 * delta_temp;
  for (int i = 0; i < 3; ++i)
    offset[i] = c.x0[i] + c.x1[i] * delta_temp + c.x2[i] * delta_temp_2 + c.x3[i] * delta_temp_3;
}

// QGroundControl file (param_files_test_util.h): sys 1, comp 1; name -> (value, type).
std::map<std::string, std::pair<std::string, int>> ParseQgc(const std::string& text) {
  std::map<std::string, std::pair<std::string, int>> out;
  for (const auto& [name, param] : testing::ReadQgcFile(text).params) {
    EXPECT_EQ(param.sys, "1");
    EXPECT_EQ(param.comp, "1");
    out[name] = {param.value, std::stoi(param.type)};
  }
  return out;
}

// One slot (prefix "TC_G1_") of a parsed file.
Px4GyroCal ReadPx4Slot(const std::map<std::string, std::pair<std::string, int>>& p, const std::string& s) {
  auto f = [&](const std::string& name) { return std::stof(p.at(s + name).first); };
  Px4GyroCal c;
  c.tref = f("TREF");
  c.tmin = f("TMIN");
  c.tmax = f("TMAX");
  for (int a = 0; a < 3; ++a) {
    c.x0[a] = f("X0_" + std::to_string(a));
    c.x1[a] = f("X1_" + std::to_string(a));
    c.x2[a] = f("X2_" + std::to_string(a));
    c.x3[a] = f("X3_" + std::to_string(a));
  }
  return c;
}

// A file of one enabled gyro slot: the enable, the slot's ID and its 15 REAL32 coefficients.
Px4GyroCal ReadPx4(const std::string& text, int slot, std::uint32_t id) {
  auto p = ParseQgc(text);
  const std::string s = "TC_G" + std::to_string(slot) + "_";
  EXPECT_EQ(p.at("TC_G_ENABLE"), (std::pair<std::string, int>{"1", 6}));
  EXPECT_EQ(p.at(s + "ID"), (std::pair<std::string, int>{std::to_string(id), 6}));
  EXPECT_EQ(p.size(), 2u + 3u + 12u);
  for (const auto& [name, value] : p) {
    if (name.starts_with(s) && name != s + "ID") {
      EXPECT_EQ(value.second, 9) << name;
    }
  }
  return ReadPx4Slot(p, s);
}

// ---- ArduPilot: AP_InertialSensor_TCal::polynomial_eval / correct_sensor, in float ----
struct ApTcal {
  float tmin = 0, tmax = 0;
  float gyr[3][3]{};  // [order-1][axis]
};

float ApPoly(const ApTcal& c, int axis, float tdiff) {
  return (c.gyr[0][axis] + (c.gyr[1][axis] + c.gyr[2][axis] * tdiff) * tdiff) * tdiff * 1.0e-6f;
}

// correct_sensor: v -= p(T - 35); v += p(Tcal - 35), both clamped; returns the amount removed.
float ApCorrection(const ApTcal& c, int axis, float temperature, float cal_temp) {
  temperature = std::min(std::max(temperature, c.tmin), c.tmax);
  cal_temp = std::min(std::max(cal_temp, c.tmin), c.tmax);
  return ApPoly(c, axis, temperature - 35.0f) - ApPoly(c, axis, cal_temp - 35.0f);
}

ApTcal ReadArduPilot(const std::string& text, int imu) {
  std::map<std::string, float> p;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto comma = line.find(',');  // mavparm.py: ',' -> ' ', then exactly two fields
    EXPECT_NE(comma, std::string::npos) << line;
    EXPECT_EQ(line.find(',', comma + 1), std::string::npos) << line;
    p[line.substr(0, comma)] = std::stof(line.substr(comma + 1));
  }
  const std::string s = "INS_TCAL" + std::to_string(imu) + "_";
  // Gyro, and the IMU's ACC coefficients written as 0 (no older accel calibration stays active).
  EXPECT_EQ(p.size(), 3u + 18u);
  EXPECT_EQ(p.at(s + "ENABLE"), 1.0f);
  for (int k = 1; k <= 3; ++k)
    for (const char* a : {"X", "Y", "Z"}) EXPECT_EQ(p.at(s + "ACC" + std::to_string(k) + "_" + a), 0.0f);
  ApTcal c;
  c.tmin = p.at(s + "TMIN");
  c.tmax = p.at(s + "TMAX");
  const char* axis = "XYZ";
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) c.gyr[k][a] = p.at(s + "GYR" + std::to_string(k + 1) + "_" + axis[a]);
  return c;
}

// Three temperature-only models whose drift is an exact cubic (noise-free targets): the export
// must then reproduce the model itself.
std::vector<DriftModel> ExactCubicModels() {
  const std::vector<std::vector<double>> coeffs = {
      {0.02, 1.5e-3, 1.2e-5, -2.0e-7}, {-0.01, -8e-4, 3e-5, 4e-7}, {0.05, 2e-4, -2e-5, 1e-7}};
  std::vector<double> temp;
  for (int i = 0; i < 2000; ++i) temp.push_back(-30.0 + 90.0 * i / 1999.0);
  std::vector<DriftModel> out;
  for (const auto& c : coeffs) {
    std::vector<double> y;
    for (double t : temp) {
      const double d = t - 25.0;
      y.push_back(c[0] + d * (c[1] + d * (c[2] + d * c[3])));
    }
    DriftFitOptions o;
    o.model = DriftModelKind::kPolynomial;
    o.inputs = DriftInputSet::kTemp;
    auto m = FitDriftModel(DriftInputs{temp, 1.0}, y, o);
    EXPECT_TRUE(m.ok());
    out.push_back(std::move(*m));
  }
  return out;
}

ThreeAxisCubics ProjectRadps(const std::vector<DriftModel>& models) {
  CubicProjectionOptions po;
  po.temp_min_c = models[0].summary.temp_min_c;
  po.temp_max_c = models[0].summary.temp_max_c;
  ThreeAxisCubics c;
  for (int a = 0; a < 3; ++a) {
    auto p = ProjectOntoCubic(models[a], po);
    EXPECT_TRUE(p.ok());
    c[a] = p->Scaled(kRadPerDegree);
  }
  return c;
}

double ModelRadps(const DriftModel& m, double temp_c) {
  const double t = std::clamp(temp_c, m.summary.temp_min_c, m.summary.temp_max_c);
  return EvaluateDriftModel(m, t, 0.0) * kRadPerDegree;
}

// Float rounding bound of the firmware's sum_k c_k x^k at x = T - Tref: each term carries a few
// float roundings (parameter storage, products, sums): 8 unit roundoffs per term; and the
// temperature itself is a float (T, Tref and x rounded: |T| + |Tref| + |x| units of roundoff),
// which moves the value by the slope sum_k k |c_k| |x|^(k-1) times that.
double FloatBound(double c0, double c1, double c2, double c3, double x, double temp_c = 0.0, double ref_c = 0.0) {
  const double ax = std::abs(x);
  const double terms = std::abs(c0) + std::abs(c1) * ax + std::abs(c2) * ax * ax + std::abs(c3) * ax * ax * ax;
  const double slope = std::abs(c1) + 2.0 * std::abs(c2) * ax + 3.0 * std::abs(c3) * ax * ax;
  return 8.0 * kFloatEps * terms + 2.0 * kFloatEps * (std::abs(temp_c) + std::abs(ref_c) + ax) * slope;
}

TEST(Px4Export, FirmwareFormulaReproducesAnExactCubicModel) {
  const auto models = ExactCubicModels();
  const ThreeAxisCubics radps = ProjectRadps(models);
  Px4ThermalParamOptions o;
  o.index = 2;
  o.device_id = 2293768;
  auto text = WritePx4ThermalParams(radps, o, {"test"});
  ASSERT_TRUE(text.ok()) << text.error().message;
  const Px4GyroCal cal = ReadPx4(*text, 2, 2293768);
  EXPECT_NEAR(cal.tref, 15.0, 1e-5);  // middle of -30..60 C
  for (double t = -40.0; t <= 70.0; t += 0.37) {
    float off[3];
    Px4Offsets(cal, static_cast<float>(t), off);
    const double dt = std::clamp(t, -30.0, 60.0) - cal.tref;
    for (int a = 0; a < 3; ++a) {
      const auto& c = radps[a].coeff;
      // raw - offset must equal raw - model: offset = model (rad/s, clamped).
      EXPECT_NEAR(off[a], ModelRadps(models[a], t), FloatBound(c[0], c[1], c[2], c[3], dt, t, cal.tref)) << "T " << t << " axis " << a;
    }
  }
}

TEST(ArduPilotExport, FirmwareFormulaReproducesAnExactCubicModel) {
  const auto models = ExactCubicModels();
  const ThreeAxisCubics radps = ProjectRadps(models);
  auto text = WriteArduPilotThermalParams(radps, ArduPilotThermalParamOptions{3}, {"test"});
  ASSERT_TRUE(text.ok()) << text.error().message;
  const ApTcal cal = ReadArduPilot(*text, 3);
  // Gyro offsets are measured at boot at Tcal: INS_GYR_OFFS = drift(Tcal). Then the vehicle
  // removes p(T) - p(Tcal) + drift(Tcal), which must be drift(T).
  for (double tcal : {-25.0, 20.0, 35.0, 58.0}) {
    for (double t = -40.0; t <= 70.0; t += 0.53) {
      for (int a = 0; a < 3; ++a) {
        const double removed = ApCorrection(cal, a, static_cast<float>(t), static_cast<float>(tcal)) +
                               ModelRadps(models[a], tcal);
        const auto g = ArduPilotGyrCoefficients(radps[a]);
        const double x = std::clamp(t, -30.0, 60.0) - 35.0, xc = std::clamp(tcal, -30.0, 60.0) - 35.0;
        const double tol = (FloatBound(0, g[0], g[1], g[2], x, t, 35.0) + FloatBound(0, g[0], g[1], g[2], xc, tcal, 35.0)) * 1e-6;
        EXPECT_NEAR(removed, ModelRadps(models[a], t), tol) << "T " << t << " Tcal " << tcal << " axis " << a;
      }
    }
  }
}

// Models that are not cubics (degree 5; SVR; dT/dt-driven drift): the firmware evaluates the
// projected cubic exactly (within float), and its RMS distance to the full model over the run is
// the reported projection cost.
TEST(Px4Export, NonCubicModelsCostIsWhatTheFirmwareLoses) {
  for (std::uint64_t seed : {11u, 12u}) {
    const SimulatedRun run = export_test::ChamberRun(seed);
    const std::vector<DriftModel> models = {
        export_test::Fit(run, DriftModelKind::kPolynomial, DriftInputSet::kTemp, 5),
        export_test::Fit(run, DriftModelKind::kSvr, DriftInputSet::kTemp),
        export_test::Fit(run, DriftModelKind::kPolynomial, DriftInputSet::kTempAndRate)};
    const ThreeAxisCubics radps = ProjectRadps(models);
    Px4ThermalParamOptions o;
    o.device_id = 1;
    auto text = WritePx4ThermalParams(radps, o, {});
    ASSERT_TRUE(text.ok());
    const Px4GyroCal cal = ReadPx4(*text, 0, 1);
    for (int a = 0; a < 3; ++a) {
      auto cost = MeasureCubicProjectionCost(models[a], radps[a].Scaled(1.0 / kRadPerDegree), DriftInputs{run.temp_c, 1.0});
      ASSERT_TRUE(cost.ok());
      auto full = models[a].Predict(DriftInputs{run.temp_c, 1.0});
      double ss = 0.0, bound = 0.0;
      for (std::size_t i = 0; i < run.temp_c.size(); ++i) {
        float off[3];
        Px4Offsets(cal, static_cast<float>(run.temp_c[i]), off);
        const double e = (*full)[i] * kRadPerDegree - off[a];
        ss += e * e;
        const auto& c = radps[a].coeff;
        bound = std::max(bound, FloatBound(c[0], c[1], c[2], c[3], run.temp_c[i] - cal.tref, run.temp_c[i], cal.tref));
      }
      const double rms_fw = std::sqrt(ss / static_cast<double>(run.temp_c.size()));
      EXPECT_NEAR(rms_fw, cost->rms * kRadPerDegree, bound) << "seed " << seed << " axis " << a;
      EXPECT_GT(cost->rms, 0.0);
      EXPECT_LT(cost->rms, cost->model_span);  // a projection, not garbage
    }
  }
}

TEST(ThermalCubic, RecenteredIsTheSamePolynomial) {
  TemperatureCubic c;
  c.ref_temp_c = 12.5;
  c.temp_min_c = -100;
  c.temp_max_c = 100;
  c.coeff = {0.3, -0.02, 4e-4, -3e-6};
  const TemperatureCubic r = c.Recentered(35.0);
  for (double t = -50; t <= 80; t += 3.1) EXPECT_NEAR(r.Evaluate(t), c.Evaluate(t), 1e-13 * (1 + std::abs(c.Evaluate(t))));
  // Clamping: outside the range the value at the end.
  c.temp_min_c = 0;
  c.temp_max_c = 40;
  EXPECT_EQ(c.Evaluate(-10), c.Evaluate(0));
  EXPECT_EQ(c.Evaluate(55), c.Evaluate(40));
}

TEST(ThermalCubic, ProjectionOfACubicIsExact) {
  const auto models = ExactCubicModels();
  for (const auto& m : models) {
    auto c = ProjectOntoCubic(m);
    ASSERT_TRUE(c.ok());
    auto p = m.Predict(DriftInputs{std::vector<double>{-30, -7.3, 0, 25, 44.4, 60}, 1.0});
    const std::vector<double> t = {-30, -7.3, 0, 25, 44.4, 60};
    for (std::size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(c->Evaluate(t[i]), (*p)[i], 1e-12);
  }
}

// Found by fuzz_numeric_drift: a model fitted on a temperature span of ~1e-303 C projected onto
// infinite coefficients with a success status (c_k = fit coefficient / h^k, h^k underflowing).
// Now a Status error naming the span; a narrow but representable span still projects.
TEST(ThermalCubic, SpanTooNarrowForACubicIsAnErrorNamingIt) {
  std::vector<double> temp_c, rate_dps;
  for (int i = 0; i < 300; ++i) {
    temp_c.push_back(1e-303 * i);
    rate_dps.push_back(0.01 * i + 0.001 * std::sin(0.1 * i));
  }
  DriftFitOptions o;  // what the fuzzer's input fits: an RBF SVR (a polynomial refuses the span)
  o.model = DriftModelKind::kSvr;
  o.inputs = DriftInputSet::kTemp;
  o.svr.C = 1.0;
  o.svr.gamma = 1.0;
  auto m = FitDriftModel(DriftInputs{temp_c, 1.0}, rate_dps, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  auto c = ProjectOntoCubic(*m);
  ASSERT_FALSE(c.ok()) << "c3 = " << c->coeff[3];
  EXPECT_EQ(c.error().kind, ErrorKind::kInvalidInput);
  EXPECT_NE(c.error().message.find("temperature span 2.99e-301 C"), std::string::npos) << c.error().message;
  EXPECT_NE(c.error().message.find("too narrow for a cubic"), std::string::npos) << c.error().message;
  // The same through an explicit range on a well-fitted model.
  const DriftModel exact = ExactCubicModels().front();
  CubicProjectionOptions po;
  po.temp_min_c = 0.0;
  po.temp_max_c = 1e-303;
  EXPECT_FALSE(ProjectOntoCubic(exact, po).ok());
  // A range whose span overflows.
  po.temp_min_c = -1e308;
  po.temp_max_c = 1e308;
  auto inf = ProjectOntoCubic(exact, po);
  ASSERT_FALSE(inf.ok());
  EXPECT_NE(inf.error().message.find("span is not a finite number"), std::string::npos) << inf.error().message;
  // 1e-6 C: narrow, representable, finite coefficients.
  po.temp_min_c = 20.0;
  po.temp_max_c = 20.0 + 1e-6;
  auto narrow = ProjectOntoCubic(exact, po);
  ASSERT_TRUE(narrow.ok()) << narrow.error().message;
  for (double v : narrow->coeff) EXPECT_TRUE(std::isfinite(v)) << v;
}

TEST(ParamExport, RefusesWhatTheFirmwareCannotUse) {
  const ThreeAxisCubics radps = ProjectRadps(ExactCubicModels());
  EXPECT_FALSE(WritePx4ThermalParams(radps, {}, {}).ok());  // no device id
  Px4ThermalParamOptions o;
  o.device_id = 5;
  o.index = 4;
  EXPECT_FALSE(WritePx4ThermalParams(radps, o, {}).ok());
  EXPECT_FALSE(WriteArduPilotThermalParams(radps, ArduPilotThermalParamOptions{0}, {}).ok());
  ThreeAxisCubics mixed = radps;
  mixed[1].temp_max_c += 1.0;
  o.index = 0;
  EXPECT_FALSE(WritePx4ThermalParams(mixed, o, {}).ok());
  ThreeAxisCubics nan = radps;
  nan[2].coeff[3] = NAN;
  EXPECT_FALSE(WriteArduPilotThermalParams(nan, {}, {}).ok());
}

}  // namespace
}  // namespace gyrocomp

namespace gyrocomp {
namespace {

TEST(ArduPilotExport, WholeImuFileOwnsEveryCoefficientOfItsImus) {
  const auto models = ExactCubicModels();
  const ThreeAxisCubics radps = ProjectRadps(models);
  // An accelerometer cubic (m/s^2): the gyro's scaled, same range (one TMIN/TMAX per IMU).
  ThreeAxisCubics accel;
  for (int a = 0; a < 3; ++a) accel[a] = radps[a].Scaled(50.0);
  ArduPilotTcalImu imu1{1, radps, accel, ""}, imu2{2, std::nullopt, std::nullopt, "temperature span 0.4 C < 10 C"};
  auto text = WriteArduPilotTcalFile({imu1, imu2}, {"test"});
  ASSERT_TRUE(text.ok()) << text.error().message;
  const auto p = testing::ReadMissionPlannerFile(*text);
  EXPECT_EQ(p.size(), 21u + 19u);  // IMU 1: ENABLE, TMIN, TMAX, 18; IMU 2: ENABLE, 18 zeros
  EXPECT_EQ(p.at("INS_TCAL1_ENABLE"), 1.0f);
  EXPECT_EQ(p.at("INS_TCAL2_ENABLE"), 0.0f);
  EXPECT_EQ(p.count("INS_TCAL2_TMIN"), 0u);
  EXPECT_NE(text->find("# INS_TCAL2 disabled: temperature span 0.4 C < 10 C"), std::string::npos);
  const char* axis = "XYZ";
  for (int a = 0; a < 3; ++a) {
    const auto g = ArduPilotGyrCoefficients(accel[a]);
    for (int k = 0; k < 3; ++k) {
      const std::string sfx = std::to_string(k + 1) + "_" + axis[a];
      EXPECT_EQ(p.at("INS_TCAL1_ACC" + sfx), static_cast<float>(g[k])) << sfx;
      EXPECT_EQ(p.at("INS_TCAL2_ACC" + sfx), 0.0f);
      EXPECT_EQ(p.at("INS_TCAL2_GYR" + sfx), 0.0f);
    }
  }
  // correct_accel is correct_sensor: the accel model is reproduced relative to Tcal.
  ApTcal acc;
  acc.tmin = p.at("INS_TCAL1_TMIN");
  acc.tmax = p.at("INS_TCAL1_TMAX");
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) acc.gyr[k][a] = p.at("INS_TCAL1_ACC" + std::to_string(k + 1) + "_" + axis[a]);
  for (double t = -30.0; t <= 60.0; t += 1.7)
    for (int a = 0; a < 3; ++a) {
      const double want = accel[a].Evaluate(t) - accel[a].Evaluate(20.0);
      EXPECT_NEAR(ApCorrection(acc, a, static_cast<float>(t), 20.0f), want, 2e-6 * 50.0) << t;
    }
  ThreeAxisCubics shifted = accel;
  for (auto& c : shifted) c.temp_max_c += 1.0;
  EXPECT_FALSE(WriteArduPilotTcalFile({{1, radps, shifted, ""}}, {}).ok());
  EXPECT_FALSE(WriteArduPilotTcalFile({imu1, imu1}, {}).ok());
  EXPECT_FALSE(WriteArduPilotTcalFile({{4, radps, std::nullopt, ""}}, {}).ok());
}

TEST(Px4Export, WholeFileWritesEverySlotOfEachKindItEnables) {
  const auto models = ExactCubicModels();
  const ThreeAxisCubics radps = ProjectRadps(models);
  Px4TcalFile f;
  f.gyro.push_back({1, 2293768, radps});
  f.gyro.push_back({0, 2359304, radps});
  TemperatureCubic baro = radps[0].Scaled(1e4);
  f.baro.push_back({0, 6620689, baro});
  auto text = WritePx4TcalFile(f, {"test"});
  ASSERT_TRUE(text.ok()) << text.error().message;
  auto p = ParseQgc(*text);
  EXPECT_EQ(p.at("TC_G_ENABLE"), (std::pair<std::string, int>{"1", 6}));
  EXPECT_EQ(p.at("TC_A_ENABLE"), (std::pair<std::string, int>{"0", 6}));
  EXPECT_EQ(p.at("TC_B_ENABLE"), (std::pair<std::string, int>{"1", 6}));
  EXPECT_EQ(p.at("TC_G1_ID").first, "2293768");
  EXPECT_EQ(p.at("TC_G0_ID").first, "2359304");
  EXPECT_EQ(p.at("TC_G2_ID").first, "0");  // unused slots: ID 0 matches no sensor, zeros
  EXPECT_EQ(p.at("TC_G3_X0_1").first, "0");
  EXPECT_EQ(p.at("TC_B0_ID").first, "6620689");
  EXPECT_EQ(std::stof(p.at("TC_B0_X1").first), static_cast<float>(baro.coeff[1]));
  EXPECT_EQ(p.at("TC_B0_X5").first, "0");
  EXPECT_EQ(p.count("TC_A0_ID"), 0u);
  // 3 enables + 4 gyro slots x 16 + 4 baro slots x 10.
  EXPECT_EQ(p.size(), 3u + 64u + 40u);
  const Px4GyroCal cal = ReadPx4Slot(p, "TC_G1_");
  for (double t = -30.0; t <= 60.0; t += 3.1) {
    float off[3];
    Px4Offsets(cal, static_cast<float>(t), off);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(off[a], ModelRadps(models[a], t), 2e-6) << t;
  }
  f.accel.push_back({0, 0, radps});
  EXPECT_FALSE(WritePx4TcalFile(f, {}).ok());  // device id 0
  f.accel = {{4, 1, radps}};
  EXPECT_FALSE(WritePx4TcalFile(f, {}).ok());  // slot 4
}

}  // namespace
}  // namespace gyrocomp

namespace gyrocomp {
namespace {

// A dT/dt model (drift = a (T - 25) + b dT/dt, with the model's own dT/dt estimate) on a run that
// heats at 0.02 C/s in 20 C steps with holds: the steady cubic is a (T - 25); the warm-up cubic
// adds about b x 0.02 (the state the run had while heating); both is their mean.
TEST(ThermalCubic, ConditionChoosesTheStateTheCubicIsFittedAt) {
  const double fs = 1.0, a = 2e-3, b = 1.5, rate = 0.02;
  std::vector<double> temp;
  double t = 20.0;
  for (int step = 0; step < 3; ++step) {
    for (int i = 0; i < 1000; ++i) temp.push_back(t += rate);
    for (int i = 0; i < 600; ++i) temp.push_back(t);
  }
  auto state = ComputeThermalState(temp, fs, DriftInputSet::kTempAndRate, TemperatureRateOptions{}, ThermalStateOptions{}, false);
  ASSERT_TRUE(state.ok());
  std::vector<double> y;
  for (std::size_t i = 0; i < temp.size(); ++i) y.push_back(a * (temp[i] - 25.0) + b * (*state)[i]);
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  o.inputs = DriftInputSet::kTempAndRate;
  o.polynomial.degree = 1;
  auto m = FitDriftModel(DriftInputs{temp, fs}, y, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  auto warm = StateWhileHeating(*m, DriftInputs{temp, fs});
  ASSERT_TRUE(warm.ok()) << warm.error().message;
  EXPECT_NEAR(warm->At(30.0), rate, 1e-3);  // the middle of the first heating step
  CubicProjectionOptions po;
  po.temp_min_c = 25.0;
  po.temp_max_c = 75.0;
  auto steady = ProjectOntoCubic(*m, po);
  ASSERT_TRUE(steady.ok());
  po.condition = CubicCondition::kWarmUp;
  EXPECT_FALSE(ProjectOntoCubic(*m, po).ok());  // needs the warm-up state
  po.warm_up = *warm;
  auto up = ProjectOntoCubic(*m, po);
  po.condition = CubicCondition::kBoth;
  auto both = ProjectOntoCubic(*m, po);
  ASSERT_TRUE(up.ok() && both.ok());
  for (double tc : {30.0, 50.0, 70.0}) {
    EXPECT_NEAR(steady->Evaluate(tc), a * (tc - 25.0), 2e-4) << tc;
    EXPECT_NEAR(up->Evaluate(tc) - steady->Evaluate(tc), b * rate, 0.2 * b * rate) << tc;
    EXPECT_NEAR(both->Evaluate(tc), 0.5 * (steady->Evaluate(tc) + up->Evaluate(tc)), 1e-12) << tc;
  }
  EXPECT_EQ(ParseCubicCondition("warm-up"), CubicCondition::kWarmUp);
  EXPECT_FALSE(ParseCubicCondition("hot"));
}

}  // namespace
}  // namespace gyrocomp
