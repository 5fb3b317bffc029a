// End-to-end tests of `gyrocomp process`, `compare` and `demo` through the built CLI.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gyrocomp/io/io.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

class PipelineCli : public testing::CliTest {
 protected:
  PipelineCli() : CliTest("gyrocomp_pipeline_cli") {}
  void SetUp() override {
    CliTest::SetUp();
    if (IsSkipped()) return;
    // A short chamber run: 2 Hz, 20-minute holds, 25 C steps (about 3.3 h, 24k samples).
    std::string out;
    const std::string sim =
        "simulate --fs 2 --seed 5 --room-hold 1200 --hold 1200 --step 25"
        " --ramp-rate 2 --thermal-lag 300 -o " +
        dir_ + "/run.csv";
    ASSERT_EQ(Run(sim, &out), 0) << out;
  }
  // Small cuckoo-search budget: the default budget is benchmarked, not tested.
  std::string Fast() const { return " --nests 6 --generations 3 --bandwidth-segment 4096 -q"; }
};

TEST_F(PipelineCli, ProcessWritesTheContractsColumnsJsonAndReport) {
  std::string out;
  const std::string cmd = "process -i " + dir_ + "/run.csv -o " + dir_ + "/out.csv --json " + dir_ +
                          "/out.json --report " + dir_ + "/report.html" + Fast();
  ASSERT_EQ(Run(cmd, &out), 0) << out;
  Result<Table> table = ReadCsv(dir_ + "/out.csv");
  ASSERT_TRUE(table.ok()) << table.error().message;
  for (const char* col : {"time_s", "rate_dps", "temp_c", "compensated_dps", "drift_feature_dps",
                          "mixed_feature_dps", "noise_feature_dps"}) {
    EXPECT_GE(table->Find(col), 0) << col;
  }
  // Closer to the truth than the raw record (the truth columns pass through from the input).
  const auto& rate = table->columns[table->Find("rate_dps")];
  const auto& comp = table->columns[table->Find("compensated_dps")];
  const auto& truth = table->columns[table->Find("true_rate_dps")];
  double e_raw = 0, e_out = 0;
  for (std::size_t i = 0; i < rate.size(); ++i) {
    e_raw += (rate[i] - truth[i]) * (rate[i] - truth[i]);
    e_out += (comp[i] - truth[i]) * (comp[i] - truth[i]);
  }
  EXPECT_LT(e_out, 0.25 * e_raw);  // RMS error at least halved

  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/out.json");
  for (const char* side : {"before", "after"}) {
    ASSERT_TRUE(j.contains(side)) << side;
    for (const char* key : {"arw_deg_per_sqrt_h", "adev_min_deg_per_h", "tau_at_min_s",
                            "bias_instability_deg_per_h", "rrw_deg_per_h_per_sqrt_h"}) {
      EXPECT_TRUE(j[side].contains(key)) << side << "." << key;
    }
  }
  ASSERT_TRUE(j.contains("modes"));
  EXPECT_EQ(j["modes"].size(), 6u);
  for (const auto& m : j["modes"]) {
    for (const char* key : {"index", "center_frequency_hz", "center_frequency_cycles_per_sample",
                            "sample_entropy", "class"}) {
      EXPECT_TRUE(m.contains(key)) << key;
    }
  }
  EXPECT_TRUE(j.contains("bandwidth_hz"));
  EXPECT_TRUE(j.contains("drift_model"));
  EXPECT_TRUE(j["timings_s"].contains("vmd"));
  EXPECT_EQ(j["parameters"]["drift_model"]["nests"], 6);  // parameters recorded

  const std::string text = testing::ReadFile(dir_ + "/report.html");
  EXPECT_NE(text.find("report-data"), std::string::npos);
}

TEST_F(PipelineCli, OutputIsTheSameFromAFileAndFromStdinWithAnyThreadCount) {
  // From a file, the input table is dropped during the pipeline and read again for the output
  // CSV; from stdin it is kept. Both, and one thread against the default, give the same bytes.
  std::string out;
  const std::string base = "process -o " + dir_ + "/";
  ASSERT_EQ(Run(base + "file.csv -i " + dir_ + "/run.csv" + Fast(), &out), 0) << out;
  ASSERT_EQ(Run(base + "stdin.csv -i - --threads 1" + Fast() + " < " + dir_ + "/run.csv", &out), 0) << out;
  const std::string from_file = testing::ReadFile(dir_ + "/file.csv");
  EXPECT_GT(from_file.size(), 1000u);
  EXPECT_EQ(from_file, testing::ReadFile(dir_ + "/stdin.csv"));
  EXPECT_EQ(from_file.substr(0, from_file.find('\n')),
            "time_s,rate_dps,temp_c,chamber_temp_c,sensor_temp_c,true_rate_dps,true_drift_dps,true_noise_dps,"
            "compensated_dps,drift_feature_dps,mixed_feature_dps,noise_feature_dps,mixed_denoised_dps,"
            "predicted_drift_dps");
  EXPECT_EQ(Run(base + "x.csv -i " + dir_ + "/run.csv --threads 0" + Fast(), &out), 2) << out;
}

TEST_F(PipelineCli, ProcessWithoutTemperatureIsBadInputAndLeavesNoOutput) {
  const std::string path = dir_ + "/notemp.csv";
  std::ofstream(path) << "time_s,rate_dps\n0,0.1\n0.5,0.2\n1,0.1\n";
  std::string out;
  EXPECT_EQ(Run("process -i " + path + " -o " + dir_ + "/o.csv -q", &out), 2) << out;
  EXPECT_NE(out.find("temp_c"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/o.csv"));
}

TEST_F(PipelineCli, CompareUsesTheTruthColumns) {
  std::string out;
  const std::string cmd = "compare -i " + dir_ + "/run.csv --no-grid --json " + dir_ + "/cmp.json" + Fast();
  ASSERT_EQ(Run(cmd, &out), 0) << out;
  EXPECT_NE(out.find("WFLP"), std::string::npos) << out;
  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/cmp.json");
  ASSERT_TRUE(j.contains("rows"));
  int drift_rows = 0, scheme_rows = 0;
  for (const auto& r : j["rows"]) {
    if (r["group"] == "drift") {
      ++drift_rows;
      EXPECT_TRUE(r["drift_rmse_vs_truth_dps"].is_number()) << r.dump();
    }
    if (r["group"] == "scheme") ++scheme_rows;
  }
  EXPECT_EQ(drift_rows, 4);   // poly(T), poly(T, dT/dt), SVR defaults, the parallel run's
  EXPECT_EQ(scheme_rows, 3);  // raw, serial, parallel
}

// The demo: src/report/report_cli_test.cc (ReportCli.DemoTableRowsPresentAndFinite).

}  // namespace
}  // namespace gyrocomp
