#include "gyrocomp/export/axis_cubics.h"

#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

#include "export_test_models.h"

namespace gyrocomp {
namespace {

using export_test::ChamberRun;
using export_test::Fit;

// The run as a one-axis GyroLog (what `export -i` reads), its rate column named `axis`.
GyroLog AsLog(const SimulatedRun& run, const std::string& axis) {
  GyroLog log;
  log.fs_hz = run.fs_hz;
  log.time_s = run.time_s;
  log.axis_names = {axis};
  log.rate_dps = {run.rate_dps};
  log.temp_c = run.temp_c;
  return log;
}

// Three axes fitted on one run: every cubic spans the range the models share; without a run the
// static curve is the model's own (auto says why) and "temperature" is refused; with the run each
// weighting is what was asked, the costs are measured on the runs given, auto compares both.
TEST(ExportAxisCubics, SharedRangeWeightsAndCosts) {
  const SimulatedRun run = ChamberRun(11, 0.0);
  std::vector<AxisDriftModel> axes;
  for (int k = 0; k < 3; ++k) axes.push_back({"rate_dps", Fit(run, DriftModelKind::kPolynomial, DriftInputSet::kTemp, 3 - k % 2)});
  axes[1].model.summary.temp_min_c += 5.0;  // a narrower range on one axis: the shared range follows it
  Result<std::vector<AxisCubic>> own = ExportAxisCubics(axes, nullptr, nullptr);
  ASSERT_TRUE(own.ok()) << own.error().message;
  ASSERT_EQ(own->size(), 3u);
  for (const AxisCubic& c : *own) {
    EXPECT_DOUBLE_EQ(c.cubic_dps.temp_min_c, axes[1].model.summary.temp_min_c);
    EXPECT_DOUBLE_EQ(c.cubic_dps.temp_max_c, axes[0].model.summary.temp_max_c);
    EXPECT_EQ(c.weight, "time");
    EXPECT_NE(c.weight_reason.find("without a calibration run"), std::string::npos) << c.weight_reason;
    EXPECT_FALSE(c.calibration.has_value());
  }
  AxisCubicsOptions temperature;
  temperature.static_weight = StaticWeight::kTemperature;
  Result<std::vector<AxisCubic>> refused = ExportAxisCubics(axes, nullptr, nullptr, temperature);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().kind, ErrorKind::kInvalidArgument);

  const GyroLog cal = AsLog(run, "rate_dps");
  const GyroLog val = AsLog(ChamberRun(12, 0.0), "rate_dps");
  Result<std::vector<AxisCubic>> by_temp = ExportAxisCubics(axes, &cal, &val, temperature);
  ASSERT_TRUE(by_temp.ok()) << by_temp.error().message;
  Result<std::vector<AxisCubic>> chosen = ExportAxisCubics(axes, &cal, &val);
  ASSERT_TRUE(chosen.ok()) << chosen.error().message;
  for (std::size_t k = 0; k < 3; ++k) {
    const AxisCubic& t = (*by_temp)[k];
    EXPECT_EQ(t.weight, "temperature");
    ASSERT_TRUE(t.calibration && t.validation);
    EXPECT_EQ(t.calibration->num_samples, run.num_samples());
    const AxisCubic& a = (*chosen)[k];
    ASSERT_TRUE(a.weight_choice.has_value()) << a.weight_reason;
    EXPECT_EQ(a.weight, StaticWeightName(a.weight_choice->chosen));
    if (a.weight == "temperature") {
      EXPECT_EQ(a.cubic_dps.coeff, t.cubic_dps.coeff);
    }
  }
  // A run without the models' column (and not one rate column per model): refused for temperature.
  const GyroLog other = AsLog(run, "gx");
  Result<std::vector<AxisCubic>> no_column = ExportAxisCubics(axes, &other, nullptr, temperature);
  ASSERT_FALSE(no_column.ok());
  EXPECT_EQ(no_column.error().kind, ErrorKind::kInvalidInput);
}

}  // namespace
}  // namespace gyrocomp
