#include "gyrocomp/decompose/feature_classifier.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/sim/simulator.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

std::vector<ModeFeature> Features(std::initializer_list<double> se) {
  std::vector<ModeFeature> out;
  double f = 0.01;
  for (double s : se) {
    out.push_back({s, f, f * 100});
    f *= 2;
  }
  return out;
}

std::vector<FeatureClass> Classes(const ClassificationResult& r) {
  std::vector<FeatureClass> out;
  for (const auto& m : r.modes) out.push_back(m.feature);
  return out;
}

constexpr FeatureClass D = FeatureClass::kDrift, M = FeatureClass::kMixed, N = FeatureClass::kNoise;

TEST(FeatureClassifier, PaperPresetIsThePapersThresholds) {
  const auto p = ClassifierOptions::Paper();
  EXPECT_EQ(p.drift_max_se, 2.0);
  EXPECT_EQ(p.noise_min_se, 4.2);
  // The paper's Figure 9 pattern: IMF 1 drift, 2 3 5 6 mixed, 4 noise.
  auto r = ClassifyModes(Features({0.8, 2.5, 3.1, 4.6, 3.9, 2.2}), p);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(Classes(*r), (std::vector<FeatureClass>{D, M, M, N, M, M}));
  EXPECT_EQ(r->rule_text, "paper: SE < 2 drift, 2...4.2 mixed, SE > 4.2 noise");
  EXPECT_EQ(r->BriefReport(), "drift: 1; mixed: 2 3 5 6; noise: 4; (" + r->rule_text + ")");
}

TEST(FeatureClassifier, StandardThresholdsAndStrictBoundaries) {
  const auto s = ClassifierOptions::Standard();
  EXPECT_EQ(s.rule_name, "standard");
  // Boundaries: "SE < drift_max_se" is drift, "SE > noise_min_se" is noise, equal is mixed.
  auto r = ClassifyModes(Features({0.05, s.drift_max_se, 0.4, s.noise_min_se, 0.7,
                                   std::numeric_limits<double>::infinity()}), s);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(Classes(*r), (std::vector<FeatureClass>{D, M, M, M, N, N}));
  EXPECT_EQ(r->rule_text,
            "standard: SE < 0.3 drift, 0.3...0.5 mixed, SE > 0.5 noise; the lowest-frequency mode is never noise");
  EXPECT_EQ(r->modes[2].index, 3);
  EXPECT_DOUBLE_EQ(r->modes[2].center_frequency_hz, 4.0);
}

TEST(FeatureClassifier, LowestFrequencyModeIsNeverNoiseUnderTheStandardRule) {
  // Features() gives increasing centre frequencies; make mode 3 the lowest.
  auto f = Features({0.7, 0.9, 0.8});
  f[2].center_frequency_cycles_per_sample = 1e-4;
  auto r = ClassifyModes(f, ClassifierOptions::Standard());
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(Classes(*r), (std::vector<FeatureClass>{N, N, M}));
  auto o = ClassifierOptions::Standard();
  o.keep_lowest_mode = false;
  r = ClassifyModes(f, o);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(Classes(*r), (std::vector<FeatureClass>{N, N, N}));
}

TEST(FeatureClassifier, FrequencyGuardMovesFastLowEntropyModesToMixed) {
  auto o = ClassifierOptions::Standard();
  o.drift_max_frequency_hz = 2.0;  // modes at 1, 2, 4 Hz below
  auto r = ClassifyModes(Features({0.05, 0.05, 0.05}), o);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(Classes(*r), (std::vector<FeatureClass>{D, M, M}));
}

TEST(FeatureClassifier, RejectsBadRulesAndUndefinedEntropy) {
  auto o = ClassifierOptions::Paper();
  o.drift_max_se = 5;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_EQ(why, "ClassifierOptions::noise_min_se = 4.2: must be >= drift_max_se = 5");
  EXPECT_EQ(ClassifyModes(Features({1.0}), o).error().kind, ErrorKind::kInvalidArgument);
  auto nan = ClassifyModes(Features({1.0, std::nan("")}));
  ASSERT_FALSE(nan.ok());
  EXPECT_NE(nan.error().message.find("mode 2"), std::string::npos);
}

TEST(FeatureClassifier, SumFeaturesAddsTheModesOfEachClass) {
  VmdResult v;
  v.modes = {{1, 1, 1}, {2, 2, 2}, {4, 4, 4}, {8, 8, 8}};
  v.summary.center_frequency_hz = {0, 1, 2, 3};
  v.summary.center_frequency_cycles_per_sample = {0, 0.1, 0.2, 0.3};
  auto r = ClassifyModes(Features({0.01, 0.4, 0.45, 0.9}));
  ASSERT_TRUE(r.ok());
  const FeatureSignals f = SumFeatures(v, *r);
  EXPECT_EQ(f.drift, (std::vector<double>{1, 1, 1}));
  EXPECT_EQ(f.mixed, (std::vector<double>{6, 6, 6}));
  EXPECT_EQ(f.noise, (std::vector<double>{8, 8, 8}));
}

// ---- the default rule on records whose content is known (docs/explanation/classification.md) -------------

double Corr2(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) ma += a[i] / a.size(), mb += b[i] / b.size();
  double ab = 0, aa = 0, bb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ab += (a[i] - ma) * (b[i] - mb);
    aa += (a[i] - ma) * (a[i] - ma);
    bb += (b[i] - mb) * (b[i] - mb);
  }
  return ab * ab / (aa * bb);
}

TEST(FeatureClassifier, WhiteNoiseModesAreNoise) {
  // VMD modes of white noise score 0.55-0.75 (K = 6, alpha = 2000; narrow bands are smoother
  // than white noise's 2.18): all above the standard noise threshold 0.5.
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0, 1);
  std::vector<double> x(8000);
  for (double& v : x) v = g(rng);
  auto v = DecomposeVmd(x);
  ASSERT_TRUE(v.ok());
  auto r = ClassifyVmdModes(*v);
  ASSERT_TRUE(r.ok()) << r.error().message;
  for (const auto& m : r->modes) {
    // ...except the lowest-frequency mode, kept as mixed by the standard rule.
    EXPECT_EQ(m.feature, m.index == 1 ? FeatureClass::kMixed : FeatureClass::kNoise)
        << "mode " << m.index << " SE " << m.sample_entropy;
    EXPECT_GT(m.sample_entropy, 0.5);
    EXPECT_LT(m.sample_entropy, 0.8);
  }
}

TEST(FeatureClassifier, PaperChamberSimulationDriftModeIsDriftAndTheRestNoise) {
  // The paper's chamber profile (14.25 h) at 1 Hz (51,300 samples): the simulator knows the
  // temperature drift. The mode that carries it (correlation^2 with the true drift > 0.5) must
  // be the drift feature; modes with no drift in them (correlation^2 < 0.01) must be noise.
  SimulatorOptions so;
  so.fs_hz = 1.0;
  so.seed = 1;
  auto run = Simulate(so);
  ASSERT_TRUE(run.ok()) << run.error().message;
  VmdOptions vo;
  vo.fs_hz = run->fs_hz;
  auto v = DecomposeVmd(run->rate_dps, vo);
  ASSERT_TRUE(v.ok());
  auto r = ClassifyVmdModes(*v);
  ASSERT_TRUE(r.ok()) << r.error().message;
  int drift_modes = 0;
  for (const auto& m : r->modes) {
    const double c2 = Corr2(v->modes[m.index - 1], run->true_drift_dps);
    SCOPED_TRACE("mode " + std::to_string(m.index) + " SE " + std::to_string(m.sample_entropy) +
                 " corr2 " + std::to_string(c2));
    if (c2 > 0.5) {
      EXPECT_EQ(m.feature, FeatureClass::kDrift);
      ++drift_modes;
    }
    if (c2 < 0.01) {
      EXPECT_EQ(m.feature, FeatureClass::kNoise);
    }
  }
  EXPECT_EQ(drift_modes, 1);
  // The paper's preset on the same modes: nothing is noise (SE never exceeds 4.2 here).
  auto p = ClassifyVmdModes(*v, {}, ClassifierOptions::Paper());
  ASSERT_TRUE(p.ok());
  for (const auto& m : p->modes) EXPECT_NE(m.feature, FeatureClass::kNoise);
}

TEST(FeatureClassifier, AdisRecordBiasWanderIsMixedNotDrift) {
  // ADIS16405 run 1 (static, room temperature, no chamber): its lowest mode is bias wander
  // (flicker / rate random walk), not a temperature drift. 150,000 samples (25 min) of gx keep the test
  // short; docs/explanation/classification.md has the full-record numbers.
  const std::string path = testing::RealdataPath("adis16405_run1.csv.gz");
  if (path.empty()) GTEST_SKIP() << "../shared/realdata is absent (licensed data, not in the repository)";
  LogSpec spec;
  spec.time_col = "t_s";
  spec.rate_cols = {"gx_dps"};
  auto log = ReadGyroLog(path, spec);
  ASSERT_TRUE(log.ok()) << log.error().message;
  std::vector<double> x(log->rate_dps[0].begin(), log->rate_dps[0].begin() + 150000);
  VmdOptions vo;
  vo.fs_hz = log->fs_hz;
  vo.max_iterations = 200;  // classes settle long before the tolerance is met on noise
  auto v = DecomposeVmd(x, vo);
  ASSERT_TRUE(v.ok());
  auto r = ClassifyVmdModes(*v);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->modes[0].feature, FeatureClass::kMixed) << r->BriefReport();
  for (std::size_t k = 1; k < r->modes.size(); ++k) {
    EXPECT_NE(r->modes[k].feature, FeatureClass::kDrift) << r->BriefReport();
  }
}

// ---- the CLI (cli.md): decompose and entropy ----------------------------------------------------

class FeatureClassifierCli : public testing::CliTest {
 protected:
  FeatureClassifierCli() : CliTest("decompose_cli") {}
};

TEST_F(FeatureClassifierCli, DecomposeReproducesTheGoldenRunAndWritesModes) {
  std::string out;
  const int rc = Run("decompose -i " + testing::GoldenPath("vmd/gyro_like_K6.input.csv") +
                         " --rate-col x --fs 1 --modes 6 -o " + dir_ + "/m.csv --json " + dir_ + "/m.json",
                     &out);
  ASSERT_EQ(rc, 0) << out;
  const auto j = testing::ReadJsonFile(dir_ + "/m.json");
  const auto golden = testing::ReadJsonFile(testing::GoldenPath("vmd/gyro_like_K6.json"));
  EXPECT_EQ(j.at("iterations"), golden.at("iterations"));
  EXPECT_EQ(j.at("converged"), true);
  ASSERT_EQ(j.at("modes").size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    const auto& m = j.at("modes")[k];
    EXPECT_EQ(m.at("index"), k + 1);
    // --fs 1, no time column: Hz equals cycles per sample (cli.md).
    EXPECT_EQ(m.at("center_frequency_hz"), m.at("center_frequency_cycles_per_sample"));
    EXPECT_NEAR(m.at("center_frequency_cycles_per_sample").get<double>(),
                golden.at("final_center_frequency_cycles_per_sample")[k].get<double>(), 1e-12);
    EXPECT_TRUE(m.at("sample_entropy").is_number());
    const std::string c = m.at("class");
    EXPECT_TRUE(c == "drift" || c == "mixed" || c == "noise") << c;
  }
  EXPECT_EQ(j.at("modes")[0].at("class"), "drift");
  const auto modes = testing::ReadGoldenCsv(dir_ + "/m.csv");
  ASSERT_EQ(modes.size(), 6u);
  const auto golden_modes = testing::ReadGoldenCsv(testing::GoldenPath("vmd/gyro_like_K6.modes.csv"));
  for (int k = 1; k <= 6; ++k) {
    const auto& a = modes.at("mode_" + std::to_string(k));
    const auto& b = golden_modes.at("mode_" + std::to_string(k));
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); i += 97) EXPECT_NEAR(a[i], b[i], 1e-10);  // shortest round-trip CSV
  }
}

TEST_F(FeatureClassifierCli, BadInputExitsTwoWithoutOutput) {
  testing::WriteFile(dir_ + "/bad.csv", "time_s,rate_dps\n0,1\n0.01,2\n0.02,abc\n0.03,4\n");
  std::string out;
  int rc = Run("decompose -i " + dir_ + "/bad.csv --json " + dir_ + "/o.json -o " + dir_ + "/o.csv", &out);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("bad.csv:4"), std::string::npos) << out;  // file:line named
  EXPECT_FALSE(std::ifstream(dir_ + "/o.json").good());
  EXPECT_FALSE(std::ifstream(dir_ + "/o.csv").good());
  rc = Run("decompose -i " + dir_ + "/none.csv --json " + dir_ + "/o.json", &out);
  EXPECT_NE(rc, 0);
  rc = Run("decompose -i " + testing::GoldenPath("vmd/gyro_like_K6.input.csv") +
               " --rate-col x --fs 1 --alpha -3 --json " + dir_ + "/o.json",
           &out);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("alpha"), std::string::npos) << out;
  rc = Run("entropy -i " + dir_ + "/bad.csv --col rate_dps --json " + dir_ + "/e.json", &out);
  EXPECT_EQ(rc, 2) << out;
  rc = Run("entropy -i " + testing::GoldenPath("sample_entropy/signals.csv") + " --col nope --json " + dir_ + "/e.json",
           &out);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("nope"), std::string::npos) << out;
  EXPECT_FALSE(std::ifstream(dir_ + "/e.json").good());
}

TEST_F(FeatureClassifierCli, EntropyMatchesTheGoldenValue) {
  const auto golden = testing::ReadJsonFile(testing::GoldenPath("sample_entropy/sample_entropy.json"));
  for (const auto& c : golden.at("cases")) {
    if (c.at("signal") != "ar1" || c.at("m") != 2 || c.at("r_factor") != 0.2) continue;
    std::string out;
    const int rc = Run("entropy -i " + testing::GoldenPath("sample_entropy/signals.csv") +
                           " --col ar1 --m 2 --r 0.2 --json " + dir_ + "/e.json",
                       &out);
    ASSERT_EQ(rc, 0) << out;
    const auto j = testing::ReadJsonFile(dir_ + "/e.json");
    EXPECT_NEAR(j.at("sample_entropy").get<double>(), c.at("sample_entropy").get<double>(), 1e-12);
    EXPECT_EQ(j.at("m"), 2);
    EXPECT_NEAR(j.at("r").get<double>(), c.at("r").get<double>(), 1e-14);
    EXPECT_EQ(j.at("n"), 2000);
    // --r-abs with the same tolerance gives the same value.
    const int rc2 = Run("entropy -i " + testing::GoldenPath("sample_entropy/signals.csv") + " --col ar1 --r-abs " +
                            std::to_string(c.at("r").get<double>() * (1 + 1e-12)) + " --json " + dir_ + "/e2.json",
                        &out);
    ASSERT_EQ(rc2, 0) << out;
    EXPECT_NEAR(testing::ReadJsonFile(dir_ + "/e2.json").at("sample_entropy").get<double>(),
                c.at("sample_entropy").get<double>(), 1e-12);
  }
}

}  // namespace
}  // namespace gyrocomp
