#include "gyrocomp/report/pipeline_report.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/sim/simulator.h"

namespace gyrocomp {
namespace {

TEST(AdevMinAbove, IsTheLowestAdevFromThatTauInDegPerHour) {
  AllanCurve c;
  c.tau_s = {1.0, 10.0, 100.0, 1000.0};
  c.adev_dps = {3e-3, 1e-3, 2e-3, 4e-3};
  EXPECT_DOUBLE_EQ(*AdevMinAbove(c, 1.0), 1e-3 * 3600.0);  // deg/s -> deg/h
  EXPECT_DOUBLE_EQ(*AdevMinAbove(c, 50.0), 2e-3 * 3600.0);
  EXPECT_FALSE(AdevMinAbove(c, 2000.0).has_value());
}

// A short chamber run (1 Hz, about 3.3 h) through the parallel model with a polynomial drift model:
// the report holds every section of the schema, sized for the page, and the figures the console
// and the JSON print (BeforeAfterRows, PipelineOptionsJson).
TEST(BuildPipelineReport, HoldsEverySectionOfTheRun) {
  SimulatorOptions s;
  s.fs_hz = 1.0;
  s.seed = 3;
  s.profile.room_hold_s = 1200;
  s.profile.hold_s = 1200;
  s.profile.step_c = 25;
  s.profile.ramp_rate_c_per_min = 2.0;
  Result<SimulatedRun> run = Simulate(s);
  ASSERT_TRUE(run.ok()) << run.error().message;
  PipelineOptions o;
  o.drift.model = DriftModelKind::kPolynomial;
  o.measure_bandwidth = true;
  o.bandwidth_segment_samples = 4096;
  o.bandwidth_frequencies = 6;
  Result<PipelineResult> r = RunParallelModel({run->rate_dps, run->temp_c, run->fs_hz, {}}, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  PipelineReportContext ctx;
  ctx.title = "gyrocomp: simulated";
  ctx.source = "simulated";
  ctx.axis = "rate_dps";
  ctx.time_s = run->time_s;
  ctx.rate_dps = run->rate_dps;
  ctx.temp_c = run->temp_c;
  ctx.parameters = PipelineOptionsJson(o);
  const nlohmann::json c = BuildPipelineReport(*r, ctx).content;

  EXPECT_EQ(c["title"], "gyrocomp: simulated");
  EXPECT_EQ(c["subtitle"].get<std::string>().rfind("simulated, axis rate_dps: " + std::to_string(r->num_samples), 0), 0u);
  const std::vector<BeforeAfterRow> rows = BeforeAfterRows(*r);
  ASSERT_EQ(c["summary"]["rows"].size(), rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k)
    EXPECT_EQ(c["summary"]["rows"][k][0], rows[k].metric + " (" + rows[k].unit + ")");
  // 1500 buckets of two points, three series on one x.
  const nlohmann::json& ts = c["timeseries"];
  EXPECT_LE(ts["x"].size(), 3000u);
  ASSERT_EQ(ts["series"].size(), 3u);
  for (const auto& series : ts["series"]) EXPECT_EQ(series["y"].size(), ts["x"].size());
  EXPECT_EQ(c["modes"].size(), r->modes.size());
  ASSERT_EQ(c["allan"].size(), 2u);
  EXPECT_EQ(c["allan"][0]["tau_s"].size(), r->allan_before.curve.tau_s.size());
  // Drift against temperature: block means, with the model's band around its prediction.
  const nlohmann::json& d = c["drift"];
  ASSERT_EQ(d["temp_c"].size(), 1500u);
  ASSERT_TRUE(d.contains("model_lo_dps"));
  for (std::size_t i = 0; i < 1500; ++i) {
    EXPECT_LE(d["model_lo_dps"][i].get<double>(), d["model_dps"][i].get<double>());
    EXPECT_GE(d["model_hi_dps"][i].get<double>(), d["model_dps"][i].get<double>());
  }
  std::vector<std::string> titles;
  for (const auto& t : c["tables"]) titles.push_back(t["title"]);
  EXPECT_EQ(titles.front(), "Classification rule");
  EXPECT_NE(std::find(titles.begin(), titles.end(), "Drift model"), titles.end());
  EXPECT_NE(std::find(titles.begin(), titles.end(), "Timings"), titles.end());
  EXPECT_EQ(c["parameters"]["drift_model"]["model"], "poly");
  EXPECT_EQ(c["versions"]["gyrocomp"], SoftwareVersions()["gyrocomp"]);
  // The page renders from this content.
  const std::string html = RenderReportHtml({c});
  EXPECT_NE(html.find("id=\"report-data\""), std::string::npos);
}

}  // namespace
}  // namespace gyrocomp
