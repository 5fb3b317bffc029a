#include "gyrocomp/report/report.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_support.h"

namespace gyrocomp {
namespace {

TEST(MinMaxEnvelope, ShortSeriesIsKeptWhole) {
  const std::vector<double> x = {0, 1, 2, 3};
  const std::vector<double> y = {5, -1, 7, 2};
  const DisplaySeries d = MinMaxEnvelope(x, y, 10);
  EXPECT_EQ(d.x, x);
  EXPECT_EQ(d.y, y);
}

TEST(MinMaxEnvelope, KeepsEveryBucketsExtremesInTimeOrder) {
  // 10,000 samples of a ramp with one spike up and one down: the envelope must keep both spikes
  // (a plain decimation would drop them), and each bucket's pair is in time order.
  const std::size_t n = 10000;
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = static_cast<double>(i);
    y[i] = 1e-3 * static_cast<double>(i);
  }
  y[1234] = 100.0;
  y[8765] = -100.0;
  const DisplaySeries d = MinMaxEnvelope(x, y, 100);
  ASSERT_EQ(d.x.size(), 200u);
  EXPECT_DOUBLE_EQ(*std::max_element(d.y.begin(), d.y.end()), 100.0);
  EXPECT_DOUBLE_EQ(*std::min_element(d.y.begin(), d.y.end()), -100.0);
  for (std::size_t i = 1; i < d.x.size(); ++i) EXPECT_LE(d.x[i - 1], d.x[i]);
  // Bucket 12 holds samples 1200..1299: ramp minimum first, spike maximum second.
  EXPECT_DOUBLE_EQ(d.y[24], 1e-3 * 1200);
  EXPECT_DOUBLE_EQ(d.y[25], 100.0);
}

ReportData SampleReport() {
  ReportData data;
  auto& c = data.content;
  c["title"] = "test report </script><b>";
  c["subtitle"] = "synthetic";
  c["summary"] = {{"columns", {"metric", "before", "after"}},
                  {"rows", {{"ARW (deg/sqrt(h))", 1.667, 0.0667}}}};
  std::vector<double> t, rate, temp;
  for (int i = 0; i < 5000; ++i) {
    t.push_back(i / 100.0);
    rate.push_back(std::sin(i * 0.01));
    temp.push_back(20 + i * 0.001);
  }
  const auto env = MinMaxEnvelopes(t, {rate, temp}, 500);
  c["timeseries"] = {{"x_label", "time (s)"},
                     {"x", env[0].x},
                     {"series", {{{"name", "rate"}, {"y", env[0].y}, {"axis", "rate"}},
                                 {{"name", "temperature"}, {"y", env[1].y}, {"axis", "temp"}}}}};
  c["modes"] = {{{"index", 1}, {"sample_entropy", 0.1}, {"center_frequency_hz", 0.0},
                 {"class", "drift"}, {"x", env[0].x}, {"y", env[0].y}}};
  std::vector<double> tau = {0.01, 0.1, 1, 10, 100}, adev = {1, 0.3, 0.1, 0.05, 0.07};
  std::vector<double> lo, hi;
  for (double a : adev) { lo.push_back(a * 0.9); hi.push_back(a * 1.1); }
  c["allan"] = {{{"name", "raw"}, {"tau_s", tau}, {"adev_dps", adev}, {"lo_dps", lo}, {"hi_dps", hi},
                 {"lines", {{{"name", "ARW"}, {"tau_s", {0.01, 1.0}}, {"adev_dps", {1.0, 0.1}}}}}}};
  c["drift"] = {{"temp_c", {30, -10, 20, std::nan("")}}, {"drift_dps", {0.1, -0.2, 0.05, 0.0}},
                {"model_temp_c", {-10, 30}}, {"model_dps", {-0.2, 0.1}}};
  // An xy section: unsorted x, a temperature two points share, a line and a band; and one with
  // no chart (a skipped sensor's).
  c["sections"] = {{{"title", "sensor 0"}, {"note", "points, curve and band"},
                    {"table", {{"columns", {"axis", "rms"}}, {"rows", nlohmann::json::array({nlohmann::json::array({"x", 0.1})})}}},
                    {"charts", {{{"title", "drift"}, {"x_label", "temperature (deg C)"}, {"y_label", "drift"},
                                 {"points", {{{"name", "log 1"}, {"x", {30.0, 10.0, 20.0, 20.0}}, {"y", {0.3, 0.1, 0.2, 0.25}}},
                                             {{"name", "log 2"}, {"x", {15.0, 25.0}}, {"y", {0.15, 0.2}}}}},
                                 {"lines", {{{"name", "cubic"}, {"x", {10.0, 20.0, 30.0}}, {"y", {0.1, 0.2, 0.3}}}}},
                                 {"bands", {{{"name", "90% band"}, {"x", {10.0, 20.0, 30.0}}, {"lo", {0.0, 0.1, 0.2}},
                                             {"hi", {0.2, 0.3, 0.4}}}}}},
                                {{"title", "residual"}, {"points", {{{"name", "log 1"}, {"x", {10.0}}, {"y", {0.0}}}}}}}}},
                   {{"title", "sensor 1: skipped"}, {"note", "why"}, {"charts", nlohmann::json::array()}}};
  c["tables"] = {{{"title", "comparison"}, {"columns", {"method", "rmse"}}, {"rows", {{"a", 1.0}}}}};
  c["parameters"] = {{"vmd", {{"K", 6}}}};
  c["versions"] = {{"gyrocomp", "test"}};
  return data;
}

TEST(RenderReportHtml, IsSelfContainedAndEscapesScriptText) {
  const std::string html = RenderReportHtml(SampleReport());
  EXPECT_NE(html.find("<!DOCTYPE html>"), std::string::npos);
  EXPECT_NE(html.find("uPlot"), std::string::npos);       // the library is inlined
  EXPECT_EQ(html.find("<script src"), std::string::npos);  // nothing fetched
  // The title is escaped where it appears as HTML.
  EXPECT_NE(html.find("<title>test report &lt;/script&gt;&lt;b&gt;</title>"), std::string::npos);
  // The JSON block ends exactly once with </script>: the title's "</script>" was escaped.
  const auto start = html.find("id=\"report-data\">");
  ASSERT_NE(start, std::string::npos);
  const auto end = html.find("</script>", start);
  EXPECT_NE(html.substr(start, end - start).find("<\\/script>"), std::string::npos);
}

// Loads the report in Debian's headless Chromium: the page must report data-render-status="ok"
// (set by the page script after every chart was built) and log no console error.
TEST(RenderReportHtml, RendersInHeadlessChromium) {
  const char* chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium)) {
    GTEST_SKIP() << "Debian chromium is not installed (scripts/install-deps.sh --browser installs it)";
  }
  const std::string dir = testing::MakeTempDir("gyrocomp_report");
  const std::string path = dir + "/report.html";
  std::ofstream(path) << RenderReportHtml(SampleReport());
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
      " --disable-background-networking --disable-component-update --disable-sync"
      " --user-data-dir=" + dir + "/profile --enable-logging=stderr --v=0"
      " --virtual-time-budget=5000 --dump-dom file://" + path;
  std::string output;
  const int status = testing::RunCommand(std::string(chromium) + flags, &output);
  ASSERT_EQ(status, 0) << output;
  EXPECT_NE(output.find("data-render-status=\"ok\""), std::string::npos) << output.substr(0, 4000);
  EXPECT_EQ(output.find("Uncaught"), std::string::npos) << output.substr(0, 4000);
  EXPECT_EQ(output.find(":CONSOLE("), std::string::npos) << output.substr(0, 4000);
  // Every chart of each section was drawn (report.h, sections), none for the chartless one.
  EXPECT_NE(output.find("data-title=\"sensor 0\" data-charts=\"2\""), std::string::npos) << output.substr(0, 4000);
  EXPECT_NE(output.find("data-title=\"sensor 1: skipped\" data-charts=\"0\""), std::string::npos) << output.substr(0, 4000);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocomp
