// The report through the CLI: `validate --report` and the demo's
// side-by-side table (console, JSON, report), with the not-applicable rule applied alike.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fixtures.h"
#include "report_page.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

const nlohmann::json* FindTable(const nlohmann::json& data, const std::string& title_prefix) {
  for (const auto& t : data["tables"]) {
    if (t["title"].get<std::string>().rfind(title_prefix, 0) == 0) return &t;
  }
  return nullptr;
}

// Headless Chromium renders the page with data-render-status="ok" and no console error; false
// without Chromium (the caller then skips with testing::kNoChromium).
bool ExpectRendersInChromium(const std::string& path, const std::string& dir) {
  std::string output;
  int status = 0;
  if (!testing::DumpDomInChromium(path, dir, &output, &status)) return false;
  EXPECT_EQ(status, 0) << output;
  EXPECT_NE(output.find("data-render-status=\"ok\""), std::string::npos) << output.substr(0, 4000);
  EXPECT_EQ(output.find("Uncaught"), std::string::npos) << output.substr(0, 4000);
  return true;
}

class ReportCli : public testing::CliTest {
 protected:
  ReportCli() : CliTest("gyrocomp_report_cli") {}
};

// A poly model fitted on a short cooling staircase, validated on a heating ramp of another seed.
TEST_F(ReportCli, ValidateReportHasTheValidationSection) {
  std::string out;
  ASSERT_EQ(Run("simulate --fs 1 --seed 3 --room-hold 1200 --hold 1200 --step 25 --ramp-rate 2 -o " + dir_ + "/cal.csv",
                &out), 0) << out;
  ASSERT_EQ(Run("simulate --fs 1 --seed 4 --profile ramp --room-temp -30 --ramp-end 50 --room-hold 1200 --hold 1200 "
                "--ramp-rate 2 -o " + dir_ + "/heat.csv", &out), 0) << out;
  ASSERT_EQ(Run("fit -i " + dir_ + "/cal.csv --model poly --inputs temp,dtemp -o " + dir_ + "/m.json", &out), 0) << out;
  const std::string report = dir_ + "/v.html";
  ASSERT_EQ(Run("validate -m " + dir_ + "/m.json -i " + dir_ + "/heat.csv --json " + dir_ + "/v.json --report " + report,
                &out), 0) << out;
  const std::string html = testing::ReadFile(report);
  ASSERT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  const nlohmann::json data = testing::ReportDataOf(html);
  ASSERT_TRUE(data.is_object());
  const nlohmann::json* table = FindTable(data, "Validation on a run the model was not fitted on");
  ASSERT_NE(table, nullptr) << data["tables"].dump();
  // The report's numbers are the JSON's (one value column: the one axis).
  const nlohmann::json v = testing::ReadJsonFile(dir_ + "/v.json");
  std::map<std::string, nlohmann::json> rows;
  for (const auto& r : (*table)["rows"]) rows[r[0].get<std::string>()] = r[1];
  EXPECT_DOUBLE_EQ(rows.at("residual drift RMS, compensated (deg/s)").get<double>(), v["residual_drift_rms_dps"].get<double>());
  EXPECT_DOUBLE_EQ(rows.at("drift RMS, raw (deg/s)").get<double>(), v["raw_drift_rms_dps"].get<double>());
  EXPECT_DOUBLE_EQ(rows.at("RMSE vs true drift (deg/s)").get<double>(), v["rmse_vs_true_drift_dps"].get<double>());
  EXPECT_TRUE(rows.at("residual slope vs T (deg/s per deg C)").is_number());
  EXPECT_TRUE(rows.at("residual slope vs dT/dt (deg/s per deg C/s)").is_number());
  EXPECT_TRUE(rows.count("samples with T outside the fitted range"));
  // The prediction band's width and coverage, as in the JSON.
  EXPECT_DOUBLE_EQ(rows.at("90% band half-width RMS (deg/s)").get<double>(), v["band_half_width_rms_dps"].get<double>());
  EXPECT_NE(rows.at("band coverage of the true drift").get<std::string>().find('%'), std::string::npos);
  // ADEV at tau >= 100 s, compensated beside raw, also drawn in the Allan chart.
  int adev_rows = 0;
  for (const auto& [name, value] : rows) adev_rows += name.rfind("ADEV at tau = ", 0) == 0;
  EXPECT_EQ(adev_rows, static_cast<int>(v["adev_tau_s"].size()));
  EXPECT_GT(adev_rows, 0);
  ASSERT_EQ(data["allan"].size(), 2u);
  EXPECT_GE(data["allan"][0]["tau_s"][0].get<double>(), 100.0);
  // The model removes most of the drift on the held-out run.
  EXPECT_LT(v["residual_drift_rms_dps"].get<double>(), 0.5 * v["raw_drift_rms_dps"].get<double>());
  if (!ExpectRendersInChromium(report, dir_)) GTEST_SKIP() << testing::kNoChromium;
}

TEST_F(ReportCli, ValidateReportWritesNothingOnBadInput) {
  std::string out;
  ASSERT_EQ(Run("simulate --fs 1 --seed 3 --room-hold 1200 --hold 1200 --step 25 --ramp-rate 2 -o " + dir_ + "/cal.csv",
                &out), 0) << out;
  ASSERT_EQ(Run("fit -i " + dir_ + "/cal.csv --model poly -o " + dir_ + "/m.json", &out), 0) << out;
  {
    std::ofstream f(dir_ + "/bad.csv");
    f << "time_s,rate_dps,temp_c\n0,0.1,20\n1,0.1,oops\n2,0.1,21\n";
  }
  const std::string report = dir_ + "/r.html";
  EXPECT_EQ(Run("validate -m " + dir_ + "/m.json -i " + dir_ + "/bad.csv --report " + report, &out), 2) << out;
  EXPECT_NE(out.find("bad.csv"), std::string::npos) << out;
  EXPECT_NE(out.find("line 3"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(report));
  // A model file that is not one: exit 2, no report.
  EXPECT_EQ(Run("validate -m " + dir_ + "/cal.csv -i " + dir_ + "/cal.csv --report " + report, &out), 2) << out;
  EXPECT_FALSE(std::filesystem::exists(report));
  // The report may not overwrite an input.
  EXPECT_EQ(Run("validate -m " + dir_ + "/m.json -i " + dir_ + "/cal.csv --report " + dir_ + "/cal.csv", &out), 2) << out;
}

// `process`: the same rule in its JSON (null + reason key) and its report's before/after table.
TEST_F(ReportCli, ProcessMarksNotApplicableTermsAlike) {
  std::string out;
  ASSERT_EQ(Run("simulate --fs 2 --seed 5 --room-hold 1200 --hold 1200 --step 25 --ramp-rate 2 --thermal-lag 300 -o " +
                dir_ + "/run.csv", &out), 0) << out;
  ASSERT_EQ(Run("process -i " + dir_ + "/run.csv --json " + dir_ + "/p.json --report " + dir_ + "/p.html --model poly "
                "--bandwidth-segment 4096 -q", &out), 0) << out;
  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/p.json");
  const double bw = j["bandwidth_hz"].get<double>();
  ASSERT_LT(bw, 1.0) << "the test needs a processed bandwidth below 1 Hz (ARW read from 0.5 s = 1/(2 x 1 Hz))";
  // Raw: Nyquist 1 Hz, 1/(2B) = 0.5 s = the sample period, white: a number. Processed: read
  // below 1/(2 bandwidth): null + reason.
  EXPECT_TRUE(j["before"]["arw_deg_per_sqrt_h"].is_number());
  EXPECT_FALSE(j["before"].contains("arw_not_applicable"));
  EXPECT_TRUE(j["after"]["arw_deg_per_sqrt_h"].is_null());
  EXPECT_NE(j["after"]["arw_not_applicable"].get<std::string>().find("1/(2 bandwidth)"), std::string::npos);
  const nlohmann::json data = testing::ReportDataOf(testing::ReadFile(dir_ + "/p.html"));
  bool arw_na = false;
  for (const auto& r : data["summary"]["rows"]) {
    if (r[0].get<std::string>().rfind("ARW", 0) == 0) arw_na = r[1].is_number() && r[2] == "not applicable";
  }
  EXPECT_TRUE(arw_na) << data["summary"].dump();
  EXPECT_NE(data["summary"]["note"].get<std::string>().find("After: ARW"), std::string::npos);
}

// `process --report`: the drift plot carries the model's 90% prediction band around
// its prediction, and the drift-model table the expected next-run error.
TEST_F(ReportCli, ProcessReportShowsTheDriftBand) {
  std::string out;
  ASSERT_EQ(Run("simulate --fs 2 --seed 5 --room-hold 1200 --hold 1200 --step 25 --ramp-rate 2 --thermal-lag 300 -o " +
                dir_ + "/run.csv", &out), 0) << out;
  ASSERT_EQ(Run("process -i " + dir_ + "/run.csv --report " + dir_ + "/p.html --model poly -q", &out), 0) << out;
  const nlohmann::json data = testing::ReportDataOf(testing::ReadFile(dir_ + "/p.html"));
  const nlohmann::json& d = data["drift"];
  ASSERT_TRUE(d.contains("model_lo_dps") && d.contains("model_hi_dps")) << d.dump().substr(0, 400);
  EXPECT_DOUBLE_EQ(d["band_level"].get<double>(), 0.9);
  ASSERT_EQ(d["model_lo_dps"].size(), d["model_dps"].size());
  double width = 0.0;
  for (std::size_t i = 0; i < d["model_dps"].size(); ++i) {
    const double lo = d["model_lo_dps"][i], mid = d["model_dps"][i], hi = d["model_hi_dps"][i];
    EXPECT_LT(lo, mid) << i;
    EXPECT_LT(mid, hi) << i;
    width = std::max(width, hi - lo);
  }
  EXPECT_GT(width, 0.0);
  const nlohmann::json* table = FindTable(data, "Drift model");
  ASSERT_NE(table, nullptr);
  const auto& cols = (*table)["columns"];
  std::size_t k = 0;
  while (k < cols.size() && cols[k] != "expected next-run error RMS (deg/s)") ++k;
  ASSERT_LT(k, cols.size()) << cols.dump();
  EXPECT_GT((*table)["rows"][0][k].get<double>(), 0.0) << (*table)["rows"].dump();
  if (!ExpectRendersInChromium(dir_ + "/p.html", dir_)) GTEST_SKIP() << testing::kNoChromium;
}

// The demo's side-by-side table: every row present, the drift rows finite for raw, the paper's
// pipeline and the default, non-numbers only with a reason; the same in console, JSON, report.
TEST_F(ReportCli, DemoTableRowsPresentAndFinite) {
  std::string out;
  ASSERT_EQ(Run("demo --out " + dir_ + "/demo -q", &out), 0) << out;
  for (const char* f : {"report.html", "summary.json", "processed.csv.gz"}) {
    EXPECT_TRUE(std::filesystem::exists(dir_ + "/demo/" + f)) << f;
  }
  EXPECT_NE(out.find("reduced budgets for the demo"), std::string::npos) << out;
  EXPECT_NE(out.find("not applicable"), std::string::npos) << out;
  // One line per drift model: the chosen model, its CV error and each tested term's gain +- SE;
  // the candidates' whole explanation only with --verbose.
  EXPECT_NE(out.find("default drift model: poly(temp,dtemp), CV error "), std::string::npos) << out;
  EXPECT_NE(out.find("+dT/dt admitted (gain "), std::string::npos) << out;
  EXPECT_NE(out.find("paper's drift model: cs-svr(temp), CV error "), std::string::npos) << out;
  EXPECT_EQ(out.find("auto chose"), std::string::npos) << out;
  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/demo/summary.json");
  EXPECT_EQ(j["budget"]["auto_generations"], 1);
  EXPECT_EQ(j["budget"]["paper_cs_svr_generations"], 2);
  const nlohmann::json& t = j["side_by_side"];
  std::map<std::string, nlohmann::json> rows;
  for (const auto& r : t["rows"]) rows[r["key"].get<std::string>()] = r;
  for (const char* key : {"arw_deg_per_sqrt_h", "bandwidth_hz", "adev_min_deg_per_h", "adev_min_tau_ge_10s_deg_per_h",
                          "rrw_deg_per_h_per_sqrt_h", "drift_rmse_dps", "held_out_drift_rmse_dps", "rate_rmse_dps"}) {
    ASSERT_TRUE(rows.count(key)) << key;
    for (const std::string col : {"raw", "paper_pipeline", "default", "paper_raw", "paper_processed"}) {
      const nlohmann::json& value = rows[key]["values"][col];
      if (value.is_number()) {
        EXPECT_TRUE(std::isfinite(value.get<double>())) << key << " " << col;
      } else {  // a blank needs a reason or a text ("not reported")
        EXPECT_TRUE(rows[key]["not_applicable"].contains(col) || rows[key]["text"].contains(col)) << key << " " << col;
      }
    }
  }
  for (const char* key : {"drift_rmse_dps", "held_out_drift_rmse_dps", "rate_rmse_dps", "adev_min_deg_per_h"}) {
    for (const char* col : {"raw", "paper_pipeline", "default"}) {
      ASSERT_TRUE(rows[key]["values"][col].is_number()) << key << " " << col;
      EXPECT_GT(rows[key]["values"][col].get<double>(), 0.0) << key << " " << col;
    }
    // Both compensations remove drift: below the raw record's drift.
    if (std::string(key) != "adev_min_deg_per_h") {
      EXPECT_LT(rows[key]["values"]["default"].get<double>(), rows[key]["values"]["raw"].get<double>()) << key;
    }
  }
  // The case: "RRW after" fitted on a slope the low-pass made is not applicable, and so
  // is the paper's processed ARW (no bandwidth published); the raw ARW is a number.
  EXPECT_TRUE(rows["rrw_deg_per_h_per_sqrt_h"]["not_applicable"].contains("default"));
  EXPECT_TRUE(rows["arw_deg_per_sqrt_h"]["not_applicable"].contains("paper_processed"));
  EXPECT_TRUE(rows["arw_deg_per_sqrt_h"]["values"]["raw"].is_number());
  EXPECT_EQ(rows["arw_deg_per_sqrt_h"]["values"]["paper_raw"].get<double>(), 1.667);
  // JSON of the after terms: null plus the reason key.
  EXPECT_TRUE(j["after"]["rrw_deg_per_h_per_sqrt_h"].is_null());
  EXPECT_TRUE(j["after"]["rrw_not_applicable"].is_string());
  EXPECT_TRUE(j["before"]["arw_deg_per_sqrt_h"].is_number());
  // The report has the side-by-side and held-out tables, "not applicable" in the same cells.
  const std::string report = dir_ + "/demo/report.html";
  const nlohmann::json data = testing::ReportDataOf(testing::ReadFile(report));
  const nlohmann::json* side = &data["summary"];  // the headline table
  ASSERT_EQ((*side)["title"].get<std::string>().rfind("Side by side", 0), 0u);
  EXPECT_NE(FindTable(data, "Before and after"), nullptr);
  bool rrw_na = false;
  for (const auto& r : (*side)["rows"]) {
    if (r[0].get<std::string>().rfind("RRW", 0) == 0) rrw_na = r[3] == "not applicable";
  }
  EXPECT_TRUE(rrw_na);
  EXPECT_NE(FindTable(data, "Held-out run"), nullptr);
  // The Allan chart draws no ARW / RRW line the rule rejects (compensated), keeps the raw's.
  ASSERT_EQ(data["allan"].size(), 2u);
  auto lines = [&](int k) {
    std::string names;
    for (const auto& l : data["allan"][k]["lines"]) names += l["name"].get<std::string>() + ";";
    return names;
  };
  EXPECT_EQ(lines(0), "ARW;ADEV min;RRW;");
  EXPECT_EQ(lines(1), "ADEV min;");
  if (!ExpectRendersInChromium(report, dir_)) GTEST_SKIP() << testing::kNoChromium;
}

}  // namespace
}  // namespace gyrocomp
