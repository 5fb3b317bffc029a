// `gyrocomp calibrate --report`: one section per sensor (tools/calibrate_report.h). A calibrated
// sensor's charts hold the rows the fit saw (x inside the sensor's span, one series per log), the
// exported cubic as the JSON gives it, its band, and the residual = points - curve; its table's
// compensated RMS is the residual's; a skipped sensor's section has its reason and no chart; the
// page renders in headless Chromium with every chart drawn.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fixtures.h"
#include "report_page.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

constexpr double kZ90 = 1.6448536269514722;  // z of the two-sided 90 % normal interval
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// The JSON's exported cubic (firmware unit) at t: T clamped to the range, powers of T - ref.
double Cubic(const nlohmann::json& c, double t) {
  t = std::clamp(t, c["temp_min_c"].get<double>(), c["temp_max_c"].get<double>());
  const double d = t - c["ref_temp_c"].get<double>();
  const auto& k = c["coeff"];
  return k[0].get<double>() + k[1].get<double>() * d + k[2].get<double>() * d * d + k[3].get<double>() * d * d * d;
}

std::vector<double> Doubles(const nlohmann::json& a) { return a.get<std::vector<double>>(); }

double Rms(const std::vector<double>& v) {
  double ss = 0.0;
  for (double x : v) ss += x * x;
  return std::sqrt(ss / static_cast<double>(v.size()));
}

class CalibrateReportCli : public testing::CliTest {
 protected:
  CalibrateReportCli() : CliTest("calibrate_report_cli") {}
  // A chamber run of the simulated board (calibrate_validation_cli_test's): `profile` and IMUs.
  std::string Simulate(const std::string& name, const std::string& profile) {
    std::string out;
    const std::string path = dir_ + "/" + name;
    EXPECT_EQ(Run("simulate --thermal-lag 120 --room-hold 600 --hold 600 --ramp-rate 1 --fs 10 " + profile + " -o " + path,
                  &out), 0) << out;
    return path;
  }
  // calibrate on `inputs`: its JSON summary into *summary, the report's data block returned.
  // --fit-rate 0.5 (default): at most 2100 rows a log, every row drawn (the table's RMS is the points').
  nlohmann::json Calibrate(const std::string& inputs, nlohmann::json* summary, const std::string& fit_rate = "0.5") {
    std::string out;
    EXPECT_EQ(Run("calibrate " + inputs + " --format px4 --fit-rate " + fit_rate + " -o " + dir_ + "/tc.params --json " + dir_ + "/c.json --report " +
                  Report(), &out), 0) << out;
    *summary = testing::ReadJsonFile(dir_ + "/c.json");
    return testing::ReportDataOf(testing::ReadFile(Report()));
  }
  // The charts each section drew in Chromium (data-charts, in page order); nullopt without Chromium.
  std::optional<std::vector<int>> ChartsDrawn() {
    std::string dom;
    int status = 0;
    if (!testing::DumpDomInChromium(Report(), dir_, &dom, &status)) return std::nullopt;
    EXPECT_EQ(status, 0) << dom.substr(0, 4000);
    EXPECT_NE(dom.find("data-render-status=\"ok\""), std::string::npos) << dom.substr(0, 4000);
    EXPECT_EQ(dom.find("Uncaught"), std::string::npos) << dom.substr(0, 4000);
    std::vector<int> drawn;
    const std::regex attr("data-charts=\"([0-9]+)\"");
    for (std::sregex_iterator it(dom.begin(), dom.end(), attr), end; it != end; ++it) drawn.push_back(std::stoi((*it)[1]));
    return drawn;
  }
  std::string Report() const { return dir_ + "/r.html"; }
};

// One axis's drift chart: every log's points inside the span, the curve = the JSON's cubic (display
// unit), the band about it; returns the points (x, y) over every log, in series order.
std::pair<std::vector<double>, std::vector<double>> CheckDriftChart(const nlohmann::json& chart, const nlohmann::json& s,
                                                                    std::size_t k, std::size_t logs) {
  const double scale = s["type"] == "gyro" ? kDegPerRad : 1.0;
  const double lo = s["temp_min_c"], hi = s["temp_max_c"];
  const nlohmann::json& cubic = s["axes"][k]["cubic"];
  std::vector<double> xs, ys;
  EXPECT_EQ(chart["points"].size(), logs) << s["type"] << " " << k;
  for (const auto& p : chart["points"]) {
    EXPECT_FALSE(p["x"].empty()) << p["name"];
    EXPECT_EQ(p["every"], 1) << p["name"];  // every row drawn
    EXPECT_EQ(p["x"].size(), p["rows"].get<std::size_t>()) << p["name"];
    for (double x : Doubles(p["x"])) EXPECT_TRUE(x >= lo - 1e-9 && x <= hi + 1e-9) << x << " outside " << lo << " .. " << hi;
    for (double y : Doubles(p["y"])) EXPECT_TRUE(std::isfinite(y));
    for (double x : Doubles(p["x"])) xs.push_back(x);
    for (double y : Doubles(p["y"])) ys.push_back(y);
  }
  const std::vector<double> cx = Doubles(chart["lines"][0]["x"]), cy = Doubles(chart["lines"][0]["y"]);
  EXPECT_NEAR(cx.front(), lo, 1e-9);
  EXPECT_NEAR(cx.back(), hi, 1e-9);
  double ymax = 0.0;
  for (double x : cx) ymax = std::max(ymax, std::abs(Cubic(cubic, x) * scale));
  for (std::size_t i = 0; i < cx.size(); ++i) EXPECT_NEAR(cy[i], Cubic(cubic, cx[i]) * scale, 1e-6 * ymax) << cx[i];
  const nlohmann::json& band = chart["bands"][0];
  EXPECT_EQ(Doubles(band["x"]), cx);
  for (std::size_t i = 0; i < cx.size(); ++i) EXPECT_TRUE(band["lo"][i] <= cy[i] && cy[i] <= band["hi"][i]) << cx[i];
  return {xs, ys};
}

// The band's sd ((hi - lo) / 2z) at each temperature, display unit.
std::vector<double> BandSd(const nlohmann::json& band) {
  std::vector<double> sd;
  for (std::size_t i = 0; i < band["lo"].size(); ++i) sd.push_back((band["hi"][i].get<double>() - band["lo"][i].get<double>()) / (2 * kZ90));
  return sd;
}

// A calibrated sensor's section: two charts per axis with real rows, the residual chart the points
// minus the curve, the table's compensated RMS the residual's, the band the JSON's expected error
// (single run: its RMS sd is the steady figure; pooled: curve_sd at every temperature).
void CheckCalibratedSection(const nlohmann::json& sec, const nlohmann::json& s, std::size_t logs) {
  const double scale = s["type"] == "gyro" ? kDegPerRad : 1.0;
  ASSERT_EQ(sec["charts"].size(), 2 * s["axes"].size()) << sec["title"];
  for (std::size_t k = 0; k < s["axes"].size(); ++k) {
    const auto [xs, ys] = CheckDriftChart(sec["charts"][2 * k], s, k, logs);
    const nlohmann::json& res = sec["charts"][2 * k + 1];
    std::vector<double> rx, ry;
    for (const auto& p : res["points"]) {
      for (double x : Doubles(p["x"])) rx.push_back(x);
      for (double y : Doubles(p["y"])) ry.push_back(y);
    }
    ASSERT_EQ(rx, xs) << sec["title"] << " " << k;
    for (std::size_t i = 0; i < xs.size(); ++i)
      EXPECT_NEAR(ry[i], ys[i] - Cubic(s["axes"][k]["cubic"], xs[i]) * scale, 1e-9 * (std::abs(ys[i]) + 1.0));
    const nlohmann::json& row = sec["table"]["rows"][k];
    EXPECT_NEAR(row[2].get<double>(), Rms(ry), 1e-9 * Rms(ry)) << sec["title"] << " " << k;
    const std::vector<double> sd = BandSd(sec["charts"][2 * k]["bands"][0]);
    if (s["fit"] == "pooled") {
      for (double v : sd) EXPECT_NEAR(v, s["curve_sd"][k].get<double>() * scale, 1e-6 * v);
    } else {
      const double steady = s["expected_error"]["steady"][k].get<double>() * scale;
      EXPECT_NEAR(Rms(sd), steady, 1e-6 * steady) << sec["title"] << " " << k;
    }
    // The simulated accelerometer and barometer drift is static: the cubic removes most of it.
    if (s["type"] != "gyro") {
      EXPECT_LT(row[2].get<double>(), 0.5 * row[1].get<double>()) << sec["title"] << " " << k;
    }
  }
}

TEST_F(CalibrateReportCli, SingleRunEverySensorHasItsRowsCurveAndResidual) {
  const std::string cal = Simulate("cal.ulg", "--profile ramp --imus 2 --seed 11 --room-temp 10 --ramp-end 60");
  nlohmann::json summary;
  const nlohmann::json data = Calibrate("-i " + cal, &summary);
  ASSERT_TRUE(data.is_object());
  ASSERT_EQ(data["sections"].size(), summary["sensors"].size());
  std::vector<int> want;
  for (std::size_t i = 0; i < summary["sensors"].size(); ++i) {
    const nlohmann::json& s = summary["sensors"][i];
    ASSERT_EQ(s["status"], "calibrated") << s.dump();
    CheckCalibratedSection(data["sections"][i], s, 1);
    want.push_back(static_cast<int>(2 * s["axes"].size()));
  }
  EXPECT_EQ(want, (std::vector<int>{6, 6, 6, 6, 2}));  // 2 gyros, 2 accels, the barometer
  const std::optional<std::vector<int>> drawn = ChartsDrawn();
  if (!drawn) GTEST_SKIP() << testing::kNoChromium;
  EXPECT_EQ(*drawn, want);
}

// A soak of two IMUs pooled with a ramp of the first: IMU 0 and the barometer are calibrated over
// both logs (one point series per log); IMU 1 has 0.02 C of change and is skipped: no chart.
TEST_F(CalibrateReportCli, PooledLogsColouredPerLogAndSkippedSensorsHaveNoChart) {
  const std::string a = Simulate("a.ulg", "--profile soak --soak-temp 20 --soak-duration 900 --imus 2 --seed 5");
  const std::string b = Simulate("b.ulg", "--profile ramp --imus 1 --seed 6 --room-temp 10 --ramp-end 60");
  nlohmann::json summary;
  const nlohmann::json data = Calibrate("-i " + a + " -i " + b, &summary);
  ASSERT_TRUE(data.is_object());
  ASSERT_EQ(data["sections"].size(), summary["sensors"].size());
  std::vector<int> want;
  for (std::size_t i = 0; i < summary["sensors"].size(); ++i) {
    const nlohmann::json& s = summary["sensors"][i];
    const nlohmann::json& sec = data["sections"][i];
    if (s["status"] == "calibrated") {
      EXPECT_EQ(s["fit"], "pooled");
      CheckCalibratedSection(sec, s, 2);
      EXPECT_EQ(sec["charts"][0]["points"][0]["name"], "a.ulg");
      EXPECT_EQ(sec["charts"][0]["points"][1]["name"], "b.ulg");
    } else {
      EXPECT_TRUE(sec["charts"].empty()) << sec.dump();
      EXPECT_NE(sec["title"].get<std::string>().find("skipped"), std::string::npos) << sec["title"];
      EXPECT_NE(sec["note"].get<std::string>().find(s["reason"].get<std::string>()), std::string::npos) << sec["note"];
    }
    want.push_back(sec["charts"].size());
  }
  EXPECT_EQ(want, (std::vector<int>{6, 0, 6, 0, 2}));  // gyro 0, gyro 1, accel 0, accel 1, baro 0
  const std::optional<std::vector<int>> drawn = ChartsDrawn();
  if (!drawn) GTEST_SKIP() << testing::kNoChromium;
  EXPECT_EQ(*drawn, want);
}

// At 1 row a second the ramp's 4200 rows are drawn every second row (at most 2500 a log and chart).
TEST_F(CalibrateReportCli, LongLogsAreDrawnEveryKthRow) {
  const std::string cal = Simulate("cal.ulg", "--profile ramp --imus 1 --seed 11 --room-temp 10 --ramp-end 60");
  nlohmann::json summary;
  const nlohmann::json data = Calibrate("-i " + cal, &summary, "1");
  ASSERT_TRUE(data.is_object());
  for (const auto& sec : data["sections"]) {
    ASSERT_FALSE(sec["charts"].empty()) << sec["title"];
    for (const auto& chart : sec["charts"]) {
      const nlohmann::json& p = chart["points"][0];
      const std::size_t rows = p["rows"], every = p["every"];
      EXPECT_GT(rows, 2500u);
      EXPECT_EQ(every, (rows + 2499) / 2500) << rows;
      EXPECT_EQ(p["x"].size(), (rows + every - 1) / every);
    }
  }
}

}  // namespace
}  // namespace gyrocomp
