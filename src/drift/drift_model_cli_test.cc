// End-to-end tests of `gyrocomp fit` and `gyrocomp apply` (cli.md contract).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

class FitApplyCli : public testing::CliTest {
 protected:
  FitApplyCli() : CliTest("drift_cli_test") {}
};

// The golden SVR cases through the CLI: fit on train.csv (no time column: --fs 1), apply on the
// golden temperature grid, compare with scikit-learn's predictions. No --train-period: the 300-row
// table fits under --max-train and must never be block-averaged (docs/reference/cli/fit.md,
// --max-train; before, it was fitted on 14 block means, 1e-1 of the span off). Tolerance 1e-6 of
// the target's span, as in svr_test (same solver, same KKT tolerance; the CSV round trip is exact:
// shortest round-trip formatting).
TEST_F(FitApplyCli, GoldenSvrCasesEndToEnd) {
  const nlohmann::json golden = testing::ReadJsonFile(testing::GoldenPath("svr/svr.json"));
  auto train = testing::ReadGoldenCsv(testing::GoldenPath("svr/train.csv"));
  const auto [lo, hi] = std::minmax_element(train["drift_dps"].begin(), train["drift_dps"].end());
  for (std::size_t k = 0; k < golden["cases"].size(); ++k) {
    const auto& c = golden["cases"][k];
    const auto grid = c["grid_temp_c"].get<std::vector<double>>();
    const auto expected = c["grid_prediction"].get<std::vector<double>>();
    {
      std::ofstream f(dir_ + "/grid.csv");
      f.precision(17);
      f << "temp_c,rate_dps\n";
      for (double t : grid) f << t << ",0\n";
    }
    std::ostringstream args;
    args.precision(17);
    args << "fit -i " << testing::GoldenPath("svr/train.csv") << " --fs 1 --target drift_dps --model svr --scale none"
         << " --C " << c["C"].get<double>() << " --gamma " << c["gamma"].get<double>() << " --epsilon "
         << c["epsilon"].get<double>() << " --svr-tol 1e-6 -o " << dir_ << "/m.json --json " << dir_ << "/fit.json";
    std::string out;
    ASSERT_EQ(Run(args.str(), &out), 0) << out;
    const nlohmann::json fj = testing::ReadJsonFile(dir_ + "/fit.json");
    EXPECT_EQ(fj["num_train"].get<std::size_t>(), train["drift_dps"].size()) << "case " << k;  // not averaged
    EXPECT_EQ(fj["num_support"].get<int>(), c["n_support"].get<int>()) << "case " << k;
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
    for (std::size_t i = 0; i < expected.size(); ++i) {
      EXPECT_NEAR(csv["predicted_drift_dps"][i], expected[i], 1e-6 * (*hi - *lo)) << "case " << k << " T = " << grid[i];
      EXPECT_DOUBLE_EQ(csv["compensated_dps"][i], -csv["predicted_drift_dps"][i]);
    }
  }
}

// Several axes: fit --rate-col a,b writes one model per axis in one file; apply uses each
// axis's own model; validate reports every axis; --validate adds the validation to fit's JSON.
TEST_F(FitApplyCli, SeveralAxesFitApplyValidate) {
  {
    std::ofstream f(dir_ + "/run.csv");
    f.precision(17);
    f << "temp_c,a,b,true_drift_dps\n";
    for (int i = 0; i < 4000; ++i) {
      const double t = 20.0 + 30.0 * std::sin(i / 400.0);
      f << t << "," << 1e-3 * t << "," << -2e-3 * t << "," << 1e-3 * t << "\n";
    }
  }
  std::string out;
  ASSERT_EQ(Run("fit -i " + dir_ + "/run.csv --fs 1 --rate-col a,b --model poly --degree 1 -o " + dir_ +
                    "/m.json --json " + dir_ + "/fit.json --validate " + dir_ + "/run.csv",
                &out),
            0)
      << out;
  const nlohmann::json m = testing::ReadJsonFile(dir_ + "/m.json");
  ASSERT_EQ(m["axes"].size(), 2u);
  EXPECT_EQ(m["axes"][1]["rate_col"], "b");
  const nlohmann::json fj = testing::ReadJsonFile(dir_ + "/fit.json");
  ASSERT_EQ(fj["validation"].size(), 2u);
  // Linear drift, linear model: nothing left (rounding only).
  EXPECT_LT(fj["validation"][1]["residual_drift_rms_dps"].get<double>(), 1e-12);
  ASSERT_EQ(Run("apply -m " + dir_ + "/m.json -i " + dir_ + "/run.csv --fs 1 --rate-col a,b -o " + dir_ + "/out.csv",
                &out),
            0)
      << out;
  auto csv = testing::ReadGoldenCsv(dir_ + "/out.csv");
  for (std::size_t i = 0; i < csv["b"].size(); i += 500) {
    EXPECT_NEAR(csv["b_predicted_drift"][i], csv["b"][i], 1e-12);
    EXPECT_NEAR(csv["a_compensated"][i], 0.0, 1e-12);
  }
  ASSERT_EQ(Run("validate -m " + dir_ + "/m.json -i " + dir_ + "/run.csv --fs 1 --rate-col a,b --json " + dir_ +
                    "/v.json",
                &out),
            0)
      << out;
  const nlohmann::json vj = testing::ReadJsonFile(dir_ + "/v.json");
  EXPECT_EQ(vj["axes"].size(), 2u);
  EXPECT_NEAR(vj["axes"][0]["rmse_vs_true_drift_dps"].get<double>(), 0.0, 1e-12);
  EXPECT_EQ(vj["fraction_temp_outside_fitted_range"].get<double>(), 0.0);
  // A rate column the file has no model for: exit 2.
  EXPECT_EQ(Run("apply -m " + dir_ + "/m.json -i " + dir_ + "/run.csv --fs 1 --rate-col true_drift_dps,a -o " + dir_ +
                    "/out2.csv",
                &out),
            2);
  EXPECT_NE(out.find("no model for rate column 'true_drift_dps'"), std::string::npos) << out;
}

TEST_F(FitApplyCli, HybridSaysWhetherItKeptItsKernel) {
  // A simulated paper run at 0.2 Hz (the default gyro: its residual is flicker and hysteresis).
  // Whatever Eq. H-1 decides, the file's kind and the JSON's model agree and kernel_decision
  // names the decision; --keep-kernel keeps the kernel and reports no decision.
  std::string out;
  ASSERT_EQ(Run("simulate --fs 0.2 --seed 5 -o " + dir_ + "/run.csv", &out), 0) << out;
  const std::string fit = "fit -i " + dir_ + "/run.csv --model hybrid --inputs temp,dtemp --nests 4 --generations 1 ";
  ASSERT_EQ(Run(fit + "-o " + dir_ + "/h.json --json " + dir_ + "/h.fit.json", &out), 0) << out;
  const nlohmann::json fj = testing::ReadJsonFile(dir_ + "/h.fit.json");
  const nlohmann::json mj = testing::ReadJsonFile(dir_ + "/h.json");
  const std::string decision = fj["kernel_decision"].get<std::string>();
  const bool kept = decision.find("kernel kept") != std::string::npos;
  EXPECT_TRUE(kept || decision.find("kernel dropped") != std::string::npos) << decision;
  EXPECT_EQ(fj["model"].get<std::string>(), kept ? "hybrid" : "poly");
  EXPECT_EQ(mj["axes"][0]["kind"].get<std::string>(), kept ? "hybrid" : "poly");
  EXPECT_EQ(mj["axes"][0]["svr"].is_null(), !kept);
  ASSERT_EQ(Run(fit + "--keep-kernel -o " + dir_ + "/k.json --json " + dir_ + "/k.fit.json", &out), 0) << out;
  const nlohmann::json kj = testing::ReadJsonFile(dir_ + "/k.fit.json");
  EXPECT_EQ(kj["model"].get<std::string>(), "hybrid");
  EXPECT_EQ(kj["kernel_decision"].get<std::string>(), "");
  EXPECT_FALSE(testing::ReadJsonFile(dir_ + "/k.json")["axes"][0]["svr"].is_null());
}

TEST_F(FitApplyCli, NoiseModelAllanFitsByGlsAndKeepsTheFileSchema) {
  // A simulated paper run at 0.5 Hz. --noise-model allan: the fit JSON names the noise model and
  // its fitted coefficients (bias instability near the simulator's 44 deg/h: the residual is
  // mostly its flicker), the model file is a plain poly of the same terms (only the coefficients
  // differ from the OLS fit's), and apply reads it. With another model it is refused (exit 2).
  std::string out;
  ASSERT_EQ(Run("simulate --fs 0.5 --seed 3 -o " + dir_ + "/run.csv", &out), 0) << out;
  const std::string fit = "fit -i " + dir_ + "/run.csv --model poly --inputs temp,dtemp ";
  ASSERT_EQ(Run(fit + "-o " + dir_ + "/ols.json --json " + dir_ + "/ols.fit.json", &out), 0) << out;
  ASSERT_EQ(Run(fit + "--noise-model allan --verbose -o " + dir_ + "/gls.json --json " + dir_ + "/gls.fit.json", &out), 0)
      << out;
  EXPECT_NE(out.find("noise model allan (generalised least squares)"), std::string::npos) << out;
  const nlohmann::json oj = testing::ReadJsonFile(dir_ + "/ols.fit.json");
  const nlohmann::json gj = testing::ReadJsonFile(dir_ + "/gls.fit.json");
  EXPECT_EQ(oj["noise_model"].get<std::string>(), "white");
  EXPECT_FALSE(oj.contains("noise_psd"));
  EXPECT_EQ(gj["noise_model"].get<std::string>(), "allan");
  EXPECT_EQ(gj["train_period_s"].get<double>(), 60.0);
  EXPECT_NEAR(gj["noise_psd"]["bias_instability_deg_per_h"].get<double>(), 44.0, 0.3 * 44.0);
  const nlohmann::json om = testing::ReadJsonFile(dir_ + "/ols.json")["axes"][0];
  const nlohmann::json gm = testing::ReadJsonFile(dir_ + "/gls.json")["axes"][0];
  EXPECT_EQ(gm["kind"], om["kind"]);
  EXPECT_EQ(gm["structured"]["terms"].size(), om["structured"]["terms"].size());
  EXPECT_NE(gm["structured"]["terms"], om["structured"]["terms"]);
  ASSERT_EQ(Run("apply -m " + dir_ + "/gls.json -i " + dir_ + "/run.csv -o " + dir_ + "/out.csv", &out), 0) << out;
  EXPECT_EQ(Run("fit -i " + dir_ + "/run.csv --model cs-svr --noise-model allan -o " + dir_ + "/x.json", &out), 2);
  EXPECT_NE(out.find("--noise-model allan: with --model poly only"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/x.json"));
}

// --auto-lagged-curve-pieces: the lagged curve's Eq. A-4 test pairs on every thermal segment cut
// into that many pieces (fewer only where a piece would hold < 2 samples): with 1 it pairs on the
// segments, as the memory test does; with 4 on more pairs, at most 4 per segment. 0 is refused
// (exit 2, no output).
TEST_F(FitApplyCli, LaggedCurvePiecesSetItsPairs) {
  std::string out;
  ASSERT_EQ(Run("simulate --profile heat-cool --fs 0.015 --seed 2 -o " + dir_ + "/run.csv", &out), 0) << out;
  const auto pairs = [&](int pieces) -> std::pair<long, long> {
    std::string o;
    const std::string json = dir_ + "/p" + std::to_string(pieces) + ".fit.json";
    EXPECT_EQ(Run("fit -i " + dir_ + "/run.csv --auto-generations 1 --auto-lagged-curve 2 --auto-lagged-curve-pieces " +
                      std::to_string(pieces) + " -o " + dir_ + "/m.json --json " + json, &o), 0) << o;
    long memory = -1, lagged = -1;
    const nlohmann::json fit = testing::ReadJsonFile(json);
    for (const auto& t : fit["term_admissions"]) {
      if (t["term"] == "lagged curve") lagged = t.value("segments", -1L);
      if (t["term"] == "memory") memory = t.value("segments", -1L);
    }
    return {memory, lagged};
  };
  const std::pair<long, long> one = pairs(1), four = pairs(4);
  ASSERT_GE(one.first, 2) << "the heat-cool run has no segment pairs";
  EXPECT_EQ(one.second, one.first);
  EXPECT_GT(four.second, one.second);
  EXPECT_LE(four.second, 4 * one.first);
  EXPECT_EQ(Run("fit -i " + dir_ + "/run.csv --auto-lagged-curve 2 --auto-lagged-curve-pieces 0 -o " + dir_ + "/x.json", &out), 2);
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/x.json"));
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
