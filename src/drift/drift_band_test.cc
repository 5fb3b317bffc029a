// Prediction bands (docs/explanation/prediction-bands.md, drift_band.cc Eqs. B-1..B-4): what they
// cover, the model file, apply.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "drift_model_internal.h"
#include "gyrocomp/drift/drift_model.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

double Cubic(double t) {
  const double x = (t - 20.0) / 40.0;
  return 0.02 + 0.05 * x - 0.03 * x * x + 0.01 * x * x * x;
}

// A staircase 60 -> -40 C (1 h holds every 10 C, 10-min ramps, first-order sensor lag of 600 s)
// at 0.2 Hz.
std::vector<double> Staircase(double fs) {
  std::vector<double> temp;
  double sensor = 60.0, chamber = 60.0;
  const double dt = 1.0 / fs;
  for (double c = 60.0; c >= -40.0; c -= 10.0) {
    for (double t = 0.0; t < 4200.0; t += dt) {
      chamber = t < 600.0 && c < 60.0 ? c + 10.0 * (1.0 - t / 600.0) : c;
      sensor += (chamber - sensor) * (1.0 - std::exp(-dt / 600.0));
      temp.push_back(sensor);
    }
  }
  return temp;
}

// The drift the record carries (the truth) plus slow correlated noise (Gauss-Markov, 1500 s,
// SD 4 mdps: flicker-like wander the fit absorbs) and white noise.
std::vector<double> Measured(const std::vector<double>& temp, double fs, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const double a = std::exp(-1.0 / (fs * 1500.0));
  double gm = 0.0;
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) {
    gm = a * gm + std::sqrt(1.0 - a * a) * 0.004 * n(rng);
    y[i] = Cubic(temp[i]) + gm + 0.01 * n(rng);
  }
  return y;
}

// Over 8 noise seeds the nominal 90% band covers most of the true drift, and it is not wider
// than 3x the realised error: a band of zero width (parameter covariance or model form lost)
// covers ~0, an unscaled one far more than 3x.
TEST(DriftBand, CoversTheTrueDriftOnAnotherRunAndIsNotTooWide) {
  const double fs = 0.2;
  const std::vector<double> temp = Staircase(fs);
  std::vector<double> truth(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) truth[i] = Cubic(temp[i]);
  DriftFitOptions o;
  o.auto_select.try_svr = false;
  double inside = 0.0, count = 0.0, err2 = 0.0, half2 = 0.0;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    auto m = FitDriftModel({temp, fs}, Measured(temp, fs, seed), o);
    ASSERT_TRUE(m.ok()) << m.error().message;
    ASSERT_TRUE(m->band.has_value());
    EXPECT_GT(m->band->expected_rms, 0.0);
    auto b = m->PredictBand({temp, fs});
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_EQ(b->level, 0.9);
    for (std::size_t i = 0; i < temp.size(); ++i) {
      ASSERT_LE(b->lo[i], b->center[i]);
      ASSERT_GE(b->hi[i], b->center[i]);
      inside += truth[i] >= b->lo[i] && truth[i] <= b->hi[i] ? 1.0 : 0.0;
      count += 1.0;
      err2 += std::pow(b->center[i] - truth[i], 2);
      half2 += std::pow(0.5 * (b->hi[i] - b->lo[i]), 2);
    }
  }
  const double coverage = inside / count;
  EXPECT_GE(coverage, 0.75) << "coverage " << coverage;
  EXPECT_LE(std::sqrt(half2 / err2), 3.0) << "RMS half-width / RMS error";
}

// Eq. B-3's noise-only CV (StructuredFormCv) against a Monte Carlo of the CV itself: a cubic
// plus white noise of known SD, refitted on 400 noise draws. The realised CV of each draw is the
// fit's own score (the same plan), and its mean over the draws is what the closed form
// tr(G Sigma G') / k predicts. Without the fold refits (the held-out noise alone) the
// expectation would be sigma^2, 3.7% low here, beyond 3 SE of the Monte Carlo mean (1.8%).
TEST(DriftBand, NoiseOnlyCvMatchesAMonteCarloOfTheCv) {
  const double fs = 1.0 / 60.0, sigma = 0.01;
  std::vector<double> temp;  // two cycles: heat 2.5 C/min, hold, cool 5 C/min, hold (8 segments)
  for (int c = 0; c < 2; ++c) {
    for (int i = 0; i < 40; ++i) temp.push_back(-40.0 + 2.5 * i);
    for (int i = 0; i < 8; ++i) temp.push_back(60.0);
    for (int i = 0; i < 20; ++i) temp.push_back(60.0 - 5.0 * i);
    for (int i = 0; i < 8; ++i) temp.push_back(-40.0);
  }
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  o.cv_scheme = DriftCvScheme::kThermalSegments;
  o.band = false;
  NoisePsd white;
  white.h0 = 2.0 * sigma * sigma / fs;  // variance h0 fs / 2
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, sigma);
  std::vector<double> mse;
  drift_internal::FormCv first;
  for (int draw = 0; draw < 400; ++draw) {
    std::vector<double> y;
    for (double t : temp) y.push_back(Cubic(t) + n(rng));
    auto m = FitDriftModel({temp, fs}, y, o);
    ASSERT_TRUE(m.ok()) << m.error().message;
    auto f = drift_internal::StructuredFormCv(*m, {temp, fs}, y, o, white, 1.0 / fs);
    ASSERT_TRUE(f.ok()) << f.error().message;
    EXPECT_EQ(f->points, temp.size());  // a segment plan scores every point
    EXPECT_EQ(f->scheme, DriftCvScheme::kThermalSegments);
    if (draw == 0) first = *f;
    EXPECT_NEAR(f->noise_mse, first.noise_mse, 1e-15);  // depends on the design only
    mse.push_back(f->mse);
  }
  double mean = 0.0, ss = 0.0;
  for (double v : mse) mean += v / static_cast<double>(mse.size());
  for (double v : mse) ss += (v - mean) * (v - mean) / static_cast<double>(mse.size() - 1);
  const double se_mean = std::sqrt(ss / static_cast<double>(mse.size()));
  EXPECT_GT(first.noise_mse, 1.03 * sigma * sigma);  // the fold refits add their parameter error (1.037 sigma^2)
  EXPECT_NEAR(mean, first.noise_mse, 3.0 * se_mean) << "Monte Carlo mean vs tr(G Sigma G') / k";
}

// Eqs. B-2a and B-2b against IEEE 952's closed forms: over a run of T = n blocks, the noise
// covariance the band uses gives the record's mean the Allan variance AVAR(T) of the white and
// flicker parts (the run's offset) and the difference of its two halves' means 2 AVAR(T / 2)
// (its trend), however little of either the floored spectrum holds; odd and even block counts.
TEST(DriftBand, RunCovarianceHoldsTheRecordScaleAllanVariances) {
  NoisePsd psd;
  psd.h0 = 2.0 * 1e-6;   // white, (deg/s)^2 / Hz
  psd.h_1 = 3.0 * 1e-7;  // flicker
  psd.h_2 = 1e-11;       // random walk: not extrapolated (its AVAR is not asked for)
  for (std::size_t n : {40u, 41u, 300u}) {
    const double block_s = 30.0, duration_s = block_s * static_cast<double>(n);
    const Eigen::MatrixXd floored = drift_internal::Toeplitz(
        BlockMeanAutocovariance(psd, n, block_s, 1.0 / (2.0 * std::numbers::pi * 0.1 * duration_s)));
    const Eigen::MatrixXd sigma = drift_internal::RunCovariance(floored, psd, duration_s);
    Eigen::VectorXd mean = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(n), 1.0 / static_cast<double>(n));
    Eigen::VectorXd half = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n / 2; ++i) {
      half(static_cast<Eigen::Index>(i)) = -1.0 / static_cast<double>(n / 2);
      half(static_cast<Eigen::Index>(n - 1 - i)) = 1.0 / static_cast<double>(n / 2);
    }
    NoisePsd wf = psd;
    wf.h_2 = 0.0;
    const double avar_t = wf.h0 / (2.0 * duration_s) + 2.0 * std::log(2.0) * wf.h_1;
    const double avar_half = wf.h0 / duration_s + 2.0 * std::log(2.0) * wf.h_1;
    ASSERT_LT(mean.dot(floored * mean), avar_t) << n;  // the floored matrix alone holds less
    ASSERT_LT(half.dot(floored * half), 2.0 * avar_half) << n;
    EXPECT_NEAR(mean.dot(sigma * mean), avar_t, 1e-9 * avar_t) << n;
    EXPECT_NEAR(half.dot(sigma * half), 2.0 * avar_half, 1e-9 * avar_half) << n;
    EXPECT_EQ(sigma.llt().info(), Eigen::Success) << n;  // still a covariance
  }
}

// Eq. B-3s: a run of three segments (heat, hold, cool) makes a segment plan whose every fold is
// a whole direction; the band scores its form CV on contiguous blocks instead. Two cycles (eight
// segments ending on the cold hold, three folds) keep the segment plan.
TEST(DriftBand, FormCvLeavesOutNoWholeDirection) {
  const double fs = 1.0 / 60.0;
  auto cycles = [](int n) {
    std::vector<double> temp;
    for (int c = 0; c < n; ++c) {
      for (int i = 0; i < 100; ++i) temp.push_back(-40.0 + i);  // 1 C/min
      for (int i = 0; i < 60; ++i) temp.push_back(60.0);
      for (int i = 0; i < 100; ++i) temp.push_back(60.0 - i);
      for (int i = 0; i < 60; ++i) temp.push_back(-40.0);
    }
    return temp;
  };
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  o.cv_scheme = DriftCvScheme::kThermalSegments;
  o.cv_folds = 3;
  o.band = false;
  NoisePsd white;
  white.h0 = 2e-4 / fs;
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 0.01);
  for (int k : {1, 2}) {
    std::vector<double> temp = cycles(k), y;
    if (k == 1) temp.resize(temp.size() - 60);  // heat, hold, cool
    for (double t : temp) y.push_back(Cubic(t) + n(rng));
    auto m = FitDriftModel({temp, fs}, y, o);
    ASSERT_TRUE(m.ok()) << m.error().message;
    auto f = drift_internal::StructuredFormCv(*m, {temp, fs}, y, o, white, 1.0 / fs);
    ASSERT_TRUE(f.ok()) << f.error().message;
    EXPECT_EQ(m->summary.cv_segments, k == 1 ? 3 : 8);
    EXPECT_EQ(f->scheme, k == 1 ? DriftCvScheme::kBlocks : DriftCvScheme::kThermalSegments) << k << " cycle(s)";
  }
}

// The band is stored per axis and read back: the same band after a round trip; a version-1 file
// (written before prediction bands) has none, and PredictBand says so instead of inventing one.
TEST(DriftBand, RoundTripsThroughTheModelFileAndOldFilesHaveNone) {
  const double fs = 0.2;
  const std::vector<double> temp = Staircase(fs);
  auto m = FitDriftModel({temp, fs}, Measured(temp, fs, 3), DriftFitOptions{});
  ASSERT_TRUE(m.ok() && m->band) << (m.ok() ? "no band" : m.error().message);
  auto back = DriftModelFromJson(DriftModelToJson(*m), "mem");
  ASSERT_TRUE(back.ok()) << back.error().message;
  ASSERT_TRUE(back->band.has_value());
  auto a = m->PredictBand({temp, fs});
  auto b = back->PredictBand({temp, fs});
  ASSERT_TRUE(a.ok() && b.ok());
  for (std::size_t i = 0; i < a->lo.size(); i += 97) {
    EXPECT_NEAR(a->lo[i], b->lo[i], 1e-12);
    EXPECT_NEAR(a->hi[i], b->hi[i], 1e-12);
  }
  auto old = LoadDriftModel(testing::GoldenPath("drift_v1/poly.json"));
  ASSERT_TRUE(old.ok()) << old.error().message;
  EXPECT_FALSE(old->band.has_value());
  auto none = old->PredictBand({temp, fs});
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("no prediction band"), std::string::npos);
  // A malformed band is refused with the field named.
  std::string text = DriftModelToJson(*m);
  const std::size_t at = text.find("\"model_form_rms\"");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 16, "\"model_form_rmx\"");
  auto bad = DriftModelFromJson(text, "bad.json");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("band.model_form_rms"), std::string::npos) << bad.error().message;
}

// A heating-only chamber run at fs: 1 h at -40 C, then 1 C/min to 60 C, behind a 600 s lag.
std::vector<double> HeatingOnly(double fs) {
  std::vector<double> heat;
  double sensor = -40.0;
  for (double t = 0.0; t < 13200.0; t += 1.0 / fs) {
    const double chamber = t < 3600.0 ? -40.0 : std::min(60.0, -40.0 + (t - 3600.0) / 60.0);
    sensor += (chamber - sensor) * (1.0 - std::exp(-1.0 / fs / 600.0));
    heat.push_back(sensor);
  }
  return heat;
}

// Eq. B-4: a heating-only calibration leaves the dT/dt gain out (Eq. I-1) but the band widens on
// a run whose dT/dt differs from the calibration's at the same temperature (a cooling run).
TEST(DriftBand, WidensWhereALeftOutRateTermActs) {
  const double fs = 0.2;
  const std::vector<double> heat = HeatingOnly(fs);
  auto rate = TemperatureRate(heat, fs);
  ASSERT_TRUE(rate.ok());
  std::vector<double> y = Measured(heat, fs, 5);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] += 1.5 * (*rate)[i];
  auto m = FitDriftModel({heat, fs}, y, DriftFitOptions{});
  ASSERT_TRUE(m.ok()) << m.error().message;
  ASSERT_EQ(m->inputs, DriftInputSet::kTemp);
  ASSERT_TRUE(m->band.has_value());
  EXPECT_GT(m->band->unidentified_rate_gain_rms, 0.0);
  const std::vector<double> cool = Staircase(fs);
  auto on_heat = m->PredictBand({heat, fs});
  auto on_cool = m->PredictBand({cool, fs});
  ASSERT_TRUE(on_heat.ok() && on_cool.ok());
  auto rms_half = [](const DriftBand& b) {
    double s = 0.0;
    for (std::size_t i = 0; i < b.lo.size(); ++i) s += std::pow(0.5 * (b.hi[i] - b.lo[i]), 2);
    return std::sqrt(s / static_cast<double>(b.lo.size()));
  };
  EXPECT_GT(rms_half(*on_cool), 1.3 * rms_half(*on_heat));
}

// Eq. B-5: a heating-only calibration that identifies a dT/dt gain cannot show whether cooling
// differs from heating by more than the gain's mirror image; on a cooling run's ramps the band adds
// the model's dT/dt contribution there in quadrature (the heating run's band is unchanged), and the
// model file keeps the direction.
TEST(DriftBand, WidensOnTheDirectionTheCalibrationDidNotCover) {
  const double fs = 0.2;
  // A heating staircase -40 -> 60 C (Staircase reversed: ramps between holds identify the gain).
  std::vector<double> heat = Staircase(fs);
  for (double& t : heat) t = 20.0 - t;
  auto rate = TemperatureRate(heat, fs);
  ASSERT_TRUE(rate.ok());
  std::vector<double> y = Measured(heat, fs, 5);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] += 6.0 * (*rate)[i];  // 100 mdps at 1 C/min: Eq. I-1 keeps it
  auto m = FitDriftModel({heat, fs}, y, DriftFitOptions{});
  ASSERT_TRUE(m.ok()) << m.error().message;
  ASSERT_EQ(m->inputs, DriftInputSet::kTempAndRate) << m->summary.selection_reason;
  ASSERT_TRUE(m->band.has_value());
  EXPECT_EQ(m->band->unseen_direction, -1);
  DriftModel without = *m;
  without.band->unseen_direction = 0;
  const std::vector<double> cool = Staircase(fs);
  auto cool_with = m->PredictBand({cool, fs});
  auto cool_without = without.PredictBand({cool, fs});
  auto heat_with = m->PredictBand({heat, fs});
  auto heat_without = without.PredictBand({heat, fs});
  ASSERT_TRUE(cool_with.ok() && cool_without.ok() && heat_with.ok() && heat_without.ok());
  auto cool_rate = TemperatureRate(cool, fs);
  ASSERT_TRUE(cool_rate.ok());
  std::size_t wider = 0, ramps = 0;
  for (std::size_t i = 0; i < cool.size(); ++i) {
    const double w = cool_with->hi[i] - cool_with->lo[i], w0 = cool_without->hi[i] - cool_without->lo[i];
    EXPECT_GE(w, w0 - 1e-15) << i;  // a variance term: never narrower
    if ((*cool_rate)[i] < -2e-3) {  // on a cooling ramp (well past the 1e-3 C/s threshold)
      ++ramps;
      wider += w > w0 * (1.0 + 1e-6) ? 1 : 0;
    }
  }
  ASSERT_GT(ramps, 0u);
  EXPECT_EQ(wider, ramps);
  for (std::size_t i = 0; i < heat.size(); ++i)  // the covered direction: unchanged
    EXPECT_EQ(heat_with->hi[i] - heat_with->lo[i], heat_without->hi[i] - heat_without->lo[i]) << i;
  auto back = DriftModelFromJson(DriftModelToJson(*m), "b5");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->band->unseen_direction, -1);
}

// Eq. B-4 with a truly zero gain: a heating-only run of a plain cubic leaves the gain out, and the
// gain it estimates is noise. The band's squared gain term is g^2, whose expectation is already
// g_true^2 + Var(g); g^2 + SE^2 added the noise a second time. Measured over these 12 seeds: mean
// G^2 / SE^2 = 1.92 with |g| (the jackknife SE is below g's real scatter under slow noise), 2.92
// with g^2 + SE^2.
TEST(DriftBand, LeftOutGainTermIsNotTwiceItsNoise) {
  const double fs = 0.2;
  const std::vector<double> heat = HeatingOnly(fs);
  double ratio = 0.0;
  int count = 0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    auto m = FitDriftModel({heat, fs}, Measured(heat, fs, seed), DriftFitOptions{});
    ASSERT_TRUE(m.ok()) << m.error().message;
    ASSERT_TRUE(m->band.has_value());
    if (!m->summary.unidentified_rate_gain_se || !(*m->summary.unidentified_rate_gain_se > 0.0)) continue;
    const double se = *m->summary.unidentified_rate_gain_se;
    ratio += std::pow(m->band->unidentified_rate_gain_rms / se, 2);
    ++count;
  }
  ASSERT_GE(count, 6) << "Eq. I-1 left the gain out on too few seeds";
  EXPECT_LT(ratio / count, 2.4) << "mean of G^2 / SE^2 over " << count << " seeds";
}

// apply writes the band columns (cli.md "apply (bands)"); with a model file without a band it
// writes none and says so.
TEST(DriftBand, ApplyWritesBandColumnsOrSaysThereIsNone) {
  const std::string cli = testing::CliPath();
  if (cli.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  const std::string dir = testing::MakeTempDir("drift_band_test");
  const double fs = 0.2;
  const std::vector<double> temp = Staircase(fs);
  const std::vector<double> y = Measured(temp, fs, 2);
  {
    std::ofstream f(dir + "/cal.csv");
    f << "time_s,rate_dps,temp_c\n";
    for (std::size_t i = 0; i < temp.size(); ++i) f << i / fs << "," << y[i] << "," << temp[i] << "\n";
  }
  std::string out;
  ASSERT_EQ(testing::RunCommand(cli + " fit -i " + dir + "/cal.csv -o " + dir + "/m.json", &out), 0) << out;
  EXPECT_NE(out.find("expected drift error on a next run"), std::string::npos) << out;
  ASSERT_EQ(testing::RunCommand(cli + " apply -m " + dir + "/m.json -i " + dir + "/cal.csv -o " + dir + "/o.csv", &out), 0)
      << out;
  auto o = testing::ReadGoldenCsv(dir + "/o.csv");
  ASSERT_TRUE(o.count("predicted_drift_lo_dps") && o.count("predicted_drift_hi_dps"));
  for (std::size_t i = 0; i < o["predicted_drift_dps"].size(); ++i) {
    ASSERT_LT(o["predicted_drift_lo_dps"][i], o["predicted_drift_dps"][i]);
    ASSERT_GT(o["predicted_drift_hi_dps"][i], o["predicted_drift_dps"][i]);
  }
  ASSERT_EQ(testing::RunCommand(cli + " apply -m " + testing::GoldenPath("drift_v1/poly.json") + " -i " + dir +
                                    "/cal.csv -o " + dir + "/o1.csv",
                                &out),
            0)
      << out;
  EXPECT_NE(out.find("no prediction band"), std::string::npos) << out;
  auto o1 = testing::ReadGoldenCsv(dir + "/o1.csv");
  EXPECT_FALSE(o1.count("predicted_drift_lo_dps"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocomp
