#include "gyrocomp/drift/drift_model.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gyrocomp/sim/simulator.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

// A chamber-like temperature record: hold, ramp down, hold, ramp up (deg C), fs in Hz.
std::vector<double> ChamberTemp(double fs_hz, double hours) {
  const std::size_t n = static_cast<std::size_t>(hours * 3600.0 * fs_hz);
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = static_cast<double>(i) / static_cast<double>(n);  // 0..1
    if (u < 0.1) t[i] = 25.0;
    else if (u < 0.45) t[i] = 25.0 - 60.0 * (u - 0.1) / 0.35;   // to -35
    else if (u < 0.55) t[i] = -35.0;
    else if (u < 0.9) t[i] = -35.0 + 95.0 * (u - 0.55) / 0.35;  // to 60
    else t[i] = 60.0;
  }
  return t;
}

double Rmse(std::span<const double> a, std::span<const double> b) {
  double ss = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) ss += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(ss / static_cast<double>(a.size()));
}

// Polynomial of a known polynomial: the least-squares fit reproduces it to rounding. Target in
// deg/s of magnitude ~0.1; 1e-10 absolute is ~1e-9 relative, far above the ~1e-13 that QR on
// standardised inputs reaches, far below any real modelling error.
TEST(DriftModelPolynomial, RecoversKnownPolynomial) {
  const double fs_hz = 1.0;
  const std::vector<double> temp = ChamberTemp(fs_hz, 4.0);
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) {
    const double d = temp[i] - 25.0;
    y[i] = 0.02 + 1.5e-3 * d + 1.2e-5 * d * d - 2.0e-7 * d * d * d;
  }
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  o.polynomial.degree = 3;
  auto m = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  auto p = m->Predict({temp, fs_hz});
  ASSERT_TRUE(p.ok());
  for (std::size_t i = 0; i < y.size(); ++i) ASSERT_NEAR((*p)[i], y[i], 1e-10) << i;
  // The blocked CV runs on 30 s block means, and the mean of a cubic over a block is not the
  // cubic of the mean temperature (Jensen): on the 0.012 C/s ramps a block spans 0.36 C,
  // variance 0.011 C^2, times p''/2 <= 6e-5 deg/s/C^2 gives ~7e-7 deg/s. Bound 1e-5.
  EXPECT_LT(m->summary.cv_rmse, 1e-5);
  EXPECT_EQ(m->summary.degree, 3);
  EXPECT_EQ(m->summary.num_train, temp.size());
  EXPECT_DOUBLE_EQ(m->summary.temp_min_c, -35.0);
  EXPECT_DOUBLE_EQ(m->summary.temp_max_c, 60.0);
}

// With dT/dt: target = p(T) + b * dT/dt, where dT/dt is what TemperatureRate computes from the
// same record, so the model class contains the truth and the fit is exact to rounding again.
TEST(DriftModelPolynomial, RecoversTemperatureRateTerm) {
  const double fs_hz = 1.0;
  const std::vector<double> temp = ChamberTemp(fs_hz, 4.0);
  auto rate = TemperatureRate(temp, fs_hz);
  ASSERT_TRUE(rate.ok());
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) y[i] = 0.01 + 1e-3 * temp[i] + 1.5 * (*rate)[i];
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  o.inputs = DriftInputSet::kTempAndRate;
  o.polynomial.degree = 1;
  auto m = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  auto p = m->Predict({temp, fs_hz});
  ASSERT_TRUE(p.ok());
  EXPECT_LT(Rmse(*p, y), 1e-12);
  // Without the dT/dt input the same data cannot be fitted: the ramps leave a residual of about
  // 1.5 * 0.004 C/s = 0.006 deg/s during the ramps.
  o.inputs = DriftInputSet::kTemp;
  auto m2 = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(m2.ok());
  EXPECT_GT(m2->summary.train_rmse, 1e-3);
}

// A gain that varies with temperature (PolynomialOptions::gain_temp_degree): target = p(T) + (b0 +
// b1 t + b2 t^2) dT/dt, t the standardised temperature, is in the model class with degree 2 and
// fitted to rounding; the constant gain cannot follow it; the file keeps the cross terms and the
// prediction bit for bit; degree 3 is refused.
TEST(DriftModelPolynomial, GainOfDegreeTwoInTemperature) {
  const double fs_hz = 1.0;
  const std::vector<double> temp = ChamberTemp(fs_hz, 4.0);
  auto rate = TemperatureRate(temp, fs_hz);
  ASSERT_TRUE(rate.ok());
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) {
    const double t = (temp[i] - 10.0) / 40.0;
    y[i] = 0.01 + 1e-3 * temp[i] + (1.5 - 0.8 * t + 2.0 * t * t) * (*rate)[i];
  }
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  o.inputs = DriftInputSet::kTempAndRate;
  o.polynomial.gain_temp_degree = 2;
  auto m = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->summary.gain_temp_degree, 2);
  EXPECT_LT(Rmse(*m->Predict({temp, fs_hz}), y), 1e-12);
  o.polynomial.gain_temp_degree = 0;
  auto constant = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(constant.ok());
  EXPECT_GT(constant->summary.train_rmse, 1e-4);
  const std::string path = testing::MakeTempDir("drift_model_test") + "/gain_in_t.json";
  ASSERT_TRUE(SaveDriftModel(*m, path).ok());
  auto loaded = LoadDriftModel(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded->summary.gain_temp_degree, 2);
  EXPECT_EQ(*loaded->Predict({temp, fs_hz}), *m->Predict({temp, fs_hz}));
  std::string why;
  o.polynomial.gain_temp_degree = 3;
  EXPECT_FALSE(o.polynomial.IsValid(&why));
  EXPECT_NE(why.find("gain_temp_degree = 3"), std::string::npos) << why;
}

// SVR family on a nonlinear drift with white noise: all models learn it; the searched ones find
// a CV error no worse than LIBSVM's defaults; the block-mean decimation is reported.
TEST(DriftModelSvr, SearchedModelsLearnNonlinearDrift) {
  const double fs_hz = 1.0;
  const std::vector<double> temp = ChamberTemp(fs_hz, 6.0);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<double> truth(temp.size()), y(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) {
    truth[i] = 0.05 * std::tanh((temp[i] - 10.0) / 15.0) + 0.02 * std::exp(-std::pow((temp[i] + 20.0) / 8.0, 2));
    y[i] = truth[i] + noise(rng);
  }
  DriftFitOptions o;
  o.max_train_samples = 240;  // 90 s means: keeps the test fast under sanitizers
  o.search.cuckoo.num_nests = 8;
  o.search.cuckoo.max_generations = 6;
  o.search.cuckoo.seed = 5;
  double cv_default = 0.0;
  for (DriftModelKind kind : {DriftModelKind::kSvr, DriftModelKind::kGridSvr, DriftModelKind::kCsSvr}) {
    o.model = kind;
    auto m = FitDriftModel({temp, fs_hz}, y, o);
    ASSERT_TRUE(m.ok()) << m.error().message;
    SCOPED_TRACE(m->summary.BriefReport());
    EXPECT_EQ(m->summary.num_train, 240u);
    EXPECT_DOUBLE_EQ(m->summary.train_period_s, 90.0);
    auto p = m->Predict({temp, fs_hz});
    ASSERT_TRUE(p.ok());
    // Truth spans 0.1 deg/s with a 0.02 bump; after 90 s means the noise is 0.001. The
    // defaults (sigma 0.7 SD, C 1, epsilon 0.1 SD) smooth the bump; 0.006 = 6% of the span
    // still separates "learned the shape" from "fitted a line" (a line leaves ~0.012).
    EXPECT_LT(Rmse(*p, truth), 0.006);
    if (kind == DriftModelKind::kSvr) {
      cv_default = m->summary.cv_rmse;
      EXPECT_EQ(m->summary.evaluations, 0);
    } else {
      EXPECT_LE(m->summary.cv_rmse, cv_default);
      EXPECT_EQ(m->summary.evaluations, kind == DriftModelKind::kCsSvr ? 8 * 13 : 100);
      // Searched models reach a third of the defaults' error on the truth (a tighter fit of
      // the bump); measured: about 0.001.
      EXPECT_LT(Rmse(*p, truth), 0.003);
    }
  }
}

// Same seed -> same model, whatever the number of threads evaluating the nests.
TEST(DriftModelSvr, CsSvrDeterministicAcrossThreads) {
  const double fs_hz = 0.5;
  const std::vector<double> temp = ChamberTemp(fs_hz, 3.0);
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) y[i] = 1e-3 * temp[i] + 1e-4 * std::sin(0.01 * i);
  DriftFitOptions o;
  o.model = DriftModelKind::kCsSvr;
  o.max_train_samples = 120;
  o.search.cuckoo.num_nests = 6;
  o.search.cuckoo.max_generations = 3;
  o.search.cuckoo.num_threads = 1;
  auto a = FitDriftModel({temp, fs_hz}, y, o);
  o.search.cuckoo.num_threads = 3;
  auto b = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(*a->summary.C, *b->summary.C);
  EXPECT_EQ(*a->summary.sigma, *b->summary.sigma);
  EXPECT_EQ(a->summary.best_cv_history, b->summary.best_cv_history);
}

// Save -> load gives the same predictions bit for bit (shortest round-trip doubles in JSON) and
// the same training summary.
TEST(DriftModelFile, RoundTripPolynomialAndSvr) {
  const double fs_hz = 1.0;
  const std::vector<double> temp = ChamberTemp(fs_hz, 2.0);
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) y[i] = 0.03 * std::sin(temp[i] / 20.0);
  const std::string dir = testing::MakeTempDir("drift_model_test");
  for (DriftModelKind kind : {DriftModelKind::kPolynomial, DriftModelKind::kSvr}) {
    DriftFitOptions o;
    o.model = kind;
    o.inputs = DriftInputSet::kTempAndRate;
    auto m = FitDriftModel({temp, fs_hz}, y, o);
    ASSERT_TRUE(m.ok()) << m.error().message;
    const std::string path = dir + "/" + DriftModelKindName(kind) + ".json";
    ASSERT_TRUE(SaveDriftModel(*m, path).ok());
    auto loaded = LoadDriftModel(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->kind, kind);
    EXPECT_EQ(loaded->inputs, DriftInputSet::kTempAndRate);
    EXPECT_EQ(*loaded->Predict({temp, fs_hz}), *m->Predict({temp, fs_hz}));
    EXPECT_EQ(loaded->summary.cv_rmse, m->summary.cv_rmse);
    EXPECT_EQ(loaded->summary.temp_min_c, m->summary.temp_min_c);
    EXPECT_EQ(loaded->summary.fit_time_s, 0.0);  // timings are not in the file
    loaded->summary.fit_time_s = m->summary.fit_time_s;
    EXPECT_EQ(loaded->summary.BriefReport(), m->summary.BriefReport());
    EXPECT_EQ(DriftModelToJson(*loaded), DriftModelToJson(*m));
  }
}

TEST(DriftModelFile, RefusesOtherSchemaVersionsAndBrokenFiles) {
  const std::vector<double> temp = ChamberTemp(1.0, 1.0);
  std::vector<double> y(temp.size(), 0.0);
  for (std::size_t i = 0; i < temp.size(); ++i) y[i] = 1e-3 * temp[i];
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  auto m = FitDriftModel({temp, 1.0}, y, o);
  ASSERT_TRUE(m.ok());
  const nlohmann::json good = nlohmann::json::parse(DriftModelToJson(*m));
  ASSERT_TRUE(DriftModelFromJson(good.dump(), "m.json").ok());

  nlohmann::json old = good;
  old["schema_version"] = 0;
  auto r = DriftModelFromJson(old.dump(), "m.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kUnsupported);
  EXPECT_EQ(r.error().message, "m.json: model file schema version 0, this gyrocomp reads versions 1 and 2");
  nlohmann::json newer = good;
  newer["schema_version"] = 3;
  r = DriftModelFromJson(newer.dump(), "m.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message,
            "m.json: model file schema version 3, this gyrocomp reads versions 1 and 2 (a newer file: update gyrocomp)");

  nlohmann::json missing = good;
  missing["axes"][0]["structured"].erase("terms");
  r = DriftModelFromJson(missing.dump(), "m.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidInput);
  EXPECT_EQ(r.error().message, "m.json: axes[0]: missing field 'structured.terms'");

  nlohmann::json wrong = good;
  wrong["axes"][0]["training"]["temp_min_c"] = "cold";
  r = DriftModelFromJson(wrong.dump(), "m.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "m.json: axes[0]: field 'training.temp_min_c' must be a finite number");

  nlohmann::json mismatch = good;
  mismatch["axes"][0]["kind"] = "hybrid";
  r = DriftModelFromJson(mismatch.dump(), "m.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "m.json: axes[0]: fields 'structured' / 'svr' do not match kind \"hybrid\"");

  nlohmann::json twice = good;
  twice["axes"].push_back(good["axes"][0]);
  r = DriftModelFromJson(twice.dump(), "m.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "m.json: axes[1]: rate_col 'rate_dps' appears twice");

  r = DriftModelFromJson("{\"format\": \"something-else\"}", "m.json");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("not a gyrocomp drift model"), std::string::npos);
  EXPECT_FALSE(DriftModelFromJson("{not json", "m.json").ok());
  auto io = LoadDriftModel("/nonexistent/dir/model.json");
  ASSERT_FALSE(io.ok());
  EXPECT_EQ(io.error().kind, ErrorKind::kIo);
}

TEST(DriftModel, TemperatureExcursionSaysByHowMuch) {
  const std::vector<double> temp = ChamberTemp(1.0, 1.0);  // -35 .. 60
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) y[i] = 1e-3 * temp[i];
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  auto m = FitDriftModel({temp, 1.0}, y, o);
  ASSERT_TRUE(m.ok());
  EXPECT_FALSE(m->CheckTemperatureRange(temp).outside);
  EXPECT_EQ(m->CheckTemperatureRange(temp).Message(), "");
  const std::vector<double> cold = {-40.0, -30.0, 0.0, 65.5};
  const TemperatureExcursion e = m->CheckTemperatureRange(cold);
  EXPECT_TRUE(e.outside);
  EXPECT_DOUBLE_EQ(e.below_c, 5.0);
  EXPECT_DOUBLE_EQ(e.above_c, 5.5);
  EXPECT_DOUBLE_EQ(e.fraction_outside, 0.5);
  EXPECT_EQ(e.Message(),
            "temperature outside the fitted range for 50% of samples, down to 5 C below its minimum, "
            "up to 5.5 C above its maximum: the model extrapolates there");
}

TEST(DriftModel, RejectsBadInput) {
  const std::vector<double> temp = ChamberTemp(1.0, 1.0);
  std::vector<double> y(temp.size(), 0.0);
  DriftFitOptions o;
  auto r = FitDriftModel({temp, 1.0}, std::span<const double>(y).first(10), o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().kind, ErrorKind::kInvalidInput);
  // One hour in 10-minute means: 6 samples, too few for 5-fold blocked CV.
  o.train_period_s = 600.0;
  r = FitDriftModel({temp, 1.0}, y, o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("blocked CV needs at least 10"), std::string::npos);
  o = DriftFitOptions{};
  o.polynomial.degree = 7;
  r = FitDriftModel({temp, 1.0}, y, o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "PolynomialOptions::degree = 7: must be in 1..5");
  o = DriftFitOptions{};
  y[5] = std::nan("");
  r = FitDriftModel({temp, 1.0}, y, o);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "FitDriftModel: non-finite target at sample 5");
}

// Simulator round trip: a run whose drift is exactly cubic in T plus a dT/dt term (hysteresis
// and flicker off, white noise on), fitted by poly(T, dT/dt): the model recovers the true drift.
// Residual sources: white noise averaged over the record, dT/dt estimated from the noisy
// temperature (window 300 s) against the simulator's exact sensor dT/dt. Bound: 2% of the drift
// span (0.19 deg/s) = 0.004 deg/s; measured 0.0003 deg/s (seed 3).
TEST(DriftModelSimulator, PolynomialRecoversInjectedDrift) {
  SimulatorOptions so;
  so.fs_hz = 1.0;
  so.seed = 3;
  so.bias.hysteresis_width_c = 0.0;
  so.noise.bias_instability_deg_per_h = 0.0;
  so.noise.rrw_deg_per_h_per_sqrt_h = 0.0;
  auto run = Simulate(so);
  ASSERT_TRUE(run.ok()) << run.error().message;
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  o.inputs = DriftInputSet::kTempAndRate;
  o.polynomial.degree = 3;
  auto m = FitDriftModel({run->temp_c, run->fs_hz}, run->rate_dps, o);
  ASSERT_TRUE(m.ok()) << m.error().message;
  auto p = m->Predict({run->temp_c, run->fs_hz});
  ASSERT_TRUE(p.ok());
  const double rmse = Rmse(*p, run->true_drift_dps);
  std::printf("poly(T, dT/dt) vs true drift: RMSE %.3g deg/s\n", rmse);
  EXPECT_LT(rmse, 0.004);
}

// DriftFitOptions::cancel: polled between a fit's steps and handed to the SVR search;
// a cancelled fit throws Cancelled, it never returns a model.
TEST(DriftModelCancel, ACancelledTokenStopsEveryKindOfFit) {
  const std::vector<double> temp = ChamberTemp(1.0, 2.0);
  std::vector<double> target(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) target[i] = 0.001 * temp[i] + 1e-5 * temp[i] * temp[i];
  CancellationToken token;
  token.Cancel();
  for (DriftModelKind kind : {DriftModelKind::kAuto, DriftModelKind::kPolynomial, DriftModelKind::kCsSvr}) {
    DriftFitOptions o;
    o.model = kind;
    o.cancel = &token;
    EXPECT_THROW((void)FitDriftModel({temp, 1.0}, target, o), Cancelled) << static_cast<int>(kind);
  }
  // Set mid-search (after the first generation): the search, which has no token of its own,
  // stops on DriftFitOptions::cancel.
  CancellationToken later;
  DriftFitOptions o;
  o.model = DriftModelKind::kCsSvr;
  o.cancel = &later;
  int generations = 0;
  o.search.cuckoo.on_generation = [&](int, double) {
    ++generations;
    later.Cancel();
  };
  EXPECT_THROW((void)FitDriftModel({temp, 1.0}, target, o), Cancelled);
  EXPECT_EQ(generations, 1);
}

}  // namespace
}  // namespace gyrocomp
