// End-to-end tests of `gyrocomp fit` and `gyrocomp apply` (cli.md contract).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "test_support.h"

namespace gyrocomp {
namespace {

class FitApplyCli : public ::testing::Test {
 protected:
  void SetUp() override {
    cli_ = testing::CliPath();
    if (cli_.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
    dir_ = testing::MakeTempDir("drift_cli_test");
  }
  int Run(const std::string& args, std::string* out) { return testing::RunCommand(cli_ + " " + args, out); }
  std::string cli_, dir_;
};

// The golden SVR through the CLI: fit on train.csv (no time column: --fs 1, no decimation),
// apply on the golden temperature grid, compare with scikit-learn's predictions. Tolerance 1e-6
// of the target's span, as in svr_test (same solver, same KKT tolerance; the CSV round trip is
// exact: shortest round-trip formatting).
TEST_F(FitApplyCli, GoldenSvrEndToEnd) {
  const nlohmann::json golden = testing::ReadJsonFile(testing::GoldenPath("svr/svr.json"));
  const auto& c = golden["cases"][2];  // C = 10, gamma = 0.01, epsilon = 0.001
  const auto grid = c["grid_temp_c"].get<std::vector<double>>();
  const auto expected = c["grid_prediction"].get<std::vector<double>>();
  {
    std::ofstream f(dir_ + "/grid.csv");
    f.precision(17);
    f << "temp_c,rate_dps\n";
    for (double t : grid) f << t << ",0\n";
  }
  std::string out;
  const std::string fit = "fit -i " + testing::GoldenPath("svr/train.csv") +
                          " --fs 1 --target drift_dps --model svr --scale none --C 10 --gamma 0.01"
                          " --epsilon 0.001 --svr-tol 1e-6 --train-period 1 -o " + dir_ + "/m.json --json " +
                          dir_ + "/fit.json";
  ASSERT_EQ(Run(fit, &out), 0) << out;
  const nlohmann::json fj = testing::ReadJsonFile(dir_ + "/fit.json");
  EXPECT_EQ(fj["num_support"].get<int>(), c["n_support"].get<int>());
  // The grid reaches -45 and 65 C, outside the fitted -39.6..59.8 C: apply must say so.
  ASSERT_EQ(Run("apply -m " + dir_ + "/m.json -i " + dir_ + "/grid.csv --fs 1 -o " + dir_ + "/out.csv --json " +
                    dir_ + "/apply.json",
                &out),
            0)
      << out;
  EXPECT_NE(out.find("warning: temperature outside the fitted range"), std::string::npos) << out;
  const nlohmann::json aj = testing::ReadJsonFile(dir_ + "/apply.json");
  EXPECT_TRUE(aj["temp_outside_fitted_range"].get<bool>());
  EXPECT_NEAR(aj["temp_below_fitted_c"].get<double>(), 45.0 - 39.577569033291205, 1e-9);
  auto csv = testing::ReadGoldenCsv(dir_ + "/out.csv");
  ASSERT_EQ(csv["predicted_drift_dps"].size(), expected.size());
  auto train = testing::ReadGoldenCsv(testing::GoldenPath("svr/train.csv"));
  const auto [lo, hi] = std::minmax_element(train["drift_dps"].begin(), train["drift_dps"].end());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(csv["predicted_drift_dps"][i], expected[i], 1e-6 * (*hi - *lo)) << "T = " << grid[i];
    EXPECT_DOUBLE_EQ(csv["compensated_dps"][i], -csv["predicted_drift_dps"][i]);
  }
}

TEST_F(FitApplyCli, BadInputsExitTwoWithoutOutput) {
  std::string out;
  // Unknown target column.
  EXPECT_EQ(Run("fit -i " + testing::GoldenPath("svr/train.csv") + " --fs 1 --target nope --model poly -o " +
                    dir_ + "/m.json",
                &out),
            2);
  EXPECT_NE(out.find("no column 'nope'"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/m.json"));
  // --C with a searched model is refused, naming the options.
  EXPECT_EQ(Run("fit -i " + testing::GoldenPath("svr/train.csv") + " --fs 1 --target drift_dps --model cs-svr --C 3 -o " +
                    dir_ + "/m.json",
                &out),
            2);
  EXPECT_NE(out.find("--C/--gamma/--sigma"), std::string::npos) << out;
  // A model file from another schema version: refused, exit 2, no output file.
  ASSERT_EQ(Run("fit -i " + testing::GoldenPath("svr/train.csv") + " --fs 1 --target drift_dps --model poly -o " +
                    dir_ + "/m.json",
                &out),
            0)
      << out;
  nlohmann::json m = testing::ReadJsonFile(dir_ + "/m.json");
  m["schema_version"] = 0;
  std::ofstream(dir_ + "/old.json") << m.dump();
  EXPECT_EQ(Run("apply -m " + dir_ + "/old.json -i " + testing::GoldenPath("svr/train.csv") + " --fs 1 -o " + dir_ +
                    "/out.csv",
                &out),
            2);
  EXPECT_NE(out.find("schema version 0"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/out.csv"));
}

}  // namespace
}  // namespace gyrocomp
