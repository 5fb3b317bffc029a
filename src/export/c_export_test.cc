// The generated C99 evaluator, compiled with the system C compiler (-std=c99 -Wall -Wextra
// -Werror; the float build also with -Wdouble-promotion), run on a held-out record and compared
// with the library's causal prediction and with `gyrocomp apply --causal`.
#include "gyrocomp/export/c_export.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include <gtest/gtest.h>

#include "export_test_models.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

using export_test::Span;

SimulatedRun HeldOut(std::uint64_t seed, double fs_hz = 1.0);  // below

// A main() that feeds "dt temp rate..." lines to <prefix>_step and prints rate_out.
std::string Harness(const std::string& prefix, std::size_t axes) {
  std::ostringstream s;
  s << "#include <stdio.h>\n#include \"" << prefix << ".h\"\nint main(void) {\n"
    << "  " << prefix << "_state st;\n  " << prefix << "_real in[" << axes << "], out[" << axes << "];\n"
    << "  double dt, t, r;\n  int k;\n  " << prefix << "_init(&st);\n"
    << "  while (scanf(\"%lf %lf\", &dt, &t) == 2) {\n"
    << "    for (k = 0; k < " << axes << "; ++k) { if (scanf(\"%lf\", &r) != 1) return 1; in[k] = ("
    << prefix << "_real)r; }\n"
    << "    " << prefix << "_step(&st, (" << prefix << "_real)dt, (" << prefix << "_real)t, in, out);\n"
    << "    for (k = 0; k < " << axes << "; ++k) printf(\"%.17g \", (double)out[k]);\n    printf(\"\\n\");\n  }\n"
    << "  return 0;\n}\n";
  return s.str();
}

class GeneratedCTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::MakeTempDir("c_export_test"); }

  // Writes the generated files and the harness, compiles (double or float), returns the binary.
  std::string Build(const GeneratedC& gen, const std::string& prefix, std::size_t axes, bool use_float) {
    std::ofstream(dir_ + "/" + gen.header_name) << gen.header;
    std::ofstream(dir_ + "/" + gen.source_name) << gen.source;
    std::ofstream(dir_ + "/main_" + prefix + ".c") << Harness(prefix, axes);
    std::string upper;
    for (char c : prefix) upper += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    const std::string bin = dir_ + "/" + prefix + (use_float ? "_f" : "_d");
    const std::string flags = std::string(" -std=c99 -Wall -Wextra -Werror -pedantic") +
                              (use_float ? " -Wdouble-promotion -D" + upper + "_USE_FLOAT" : "");
    std::string out;
    // The generated source alone first, with the strictest flags (float: no double promotion).
    const int rc_obj = testing::RunCommand(std::string(GYROCOMP_C_COMPILER) + flags + " -c " + dir_ + "/" +
                                               gen.source_name + " -o " + bin + ".o", &out);
    EXPECT_EQ(rc_obj, 0) << out << "\n" << gen.source.substr(0, 3000);
    const int rc = testing::RunCommand(std::string(GYROCOMP_C_COMPILER) + " -std=c99 -Wall -Wextra -Werror" +
                                           (use_float ? " -D" + upper + "_USE_FLOAT" : "") + " -I" + dir_ + " " +
                                           dir_ + "/main_" + prefix + ".c " + bin + ".o -lm -o " + bin, &out);
    EXPECT_EQ(rc, 0) << out;
    return bin;
  }

  // The CLI path end to end: saves `m`, runs `apply --causal` on held-out run `seed` and
  // `export --format c [extra]` to `name`.h/.c; returns the applied CSV's columns and the C.
  struct CliRun {
    std::map<std::string, std::vector<double>> applied;
    GeneratedC gen;
  };
  CliRun ApplyCausalAndExportC(const std::string& cli, const DriftModel& m, std::uint64_t seed, const std::string& name,
                               const std::string& extra) {
    CliRun r;
    EXPECT_TRUE(SaveDriftModel(m, dir_ + "/" + name + ".json").ok());
    const SimulatedRun val = HeldOut(seed);
    {
      std::ofstream f(dir_ + "/" + name + "_val.csv");
      f.precision(17);
      f << "time_s,rate_dps,temp_c\n";
      for (std::size_t i = 0; i < val.temp_c.size(); ++i) f << i << "," << val.rate_dps[i] << "," << val.temp_c[i] << "\n";
    }
    std::string out;
    EXPECT_EQ(testing::RunCommand(cli + " apply --causal -m " + dir_ + "/" + name + ".json -i " + dir_ + "/" + name +
                                      "_val.csv -o " + dir_ + "/" + name + "_applied.csv", &out), 0) << out;
    EXPECT_EQ(testing::RunCommand(cli + " export -m " + dir_ + "/" + name + ".json --format c " + extra + " -o " + dir_ +
                                      "/" + name, &out), 0) << out;
    r.gen.header_name = name + ".h";
    r.gen.source_name = name + ".c";
    std::ifstream h(dir_ + "/" + name + ".h"), c(dir_ + "/" + name + ".c");
    r.gen.header.assign(std::istreambuf_iterator<char>(h), {});
    r.gen.source.assign(std::istreambuf_iterator<char>(c), {});
    r.applied = testing::ReadGoldenCsv(dir_ + "/" + name + "_applied.csv");
    return r;
  }

  // Runs the binary on "dt temp rate x axes" lines; returns out[sample][axis].
  std::vector<std::vector<double>> Run(const std::string& bin, double dt, const std::vector<double>& temp,
                                       const std::vector<double>& rate, std::size_t axes) {
    {
      std::ofstream in(dir_ + "/in.txt");
      char buf[64];
      for (std::size_t i = 0; i < temp.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%.17g %.17g", dt, temp[i]);
        in << buf;
        for (std::size_t k = 0; k < axes; ++k) {
          std::snprintf(buf, sizeof buf, " %.17g", rate[i]);
          in << buf;
        }
        in << "\n";
      }
    }
    std::string out;
    EXPECT_EQ(testing::RunCommand(bin + " < " + dir_ + "/in.txt > " + dir_ + "/out.txt", &out), 0) << out;
    std::vector<std::vector<double>> rows;
    std::ifstream f(dir_ + "/out.txt");
    std::string line;
    while (std::getline(f, line)) {
      std::istringstream ls(line);
      std::vector<double> row(axes);
      for (double& v : row) ls >> v;
      rows.push_back(row);
    }
    EXPECT_EQ(rows.size(), temp.size());
    return rows;
  }

  std::string dir_;
};

// Forward rounding bound of the float SVR sum at one input (0 for a polynomial): each term
// coef_j K_j, K_j = exp(-arg_j), is computed with relative error <= u (4 + (2 n + 3) arg_j)
// (n differences and squares, their sum, the product with gamma: each rounding of arg moves K by
// arg u; expf 1 ulp; the product with coef; Kahan's addition), so the sum is off by at most
// u target_scale sum_j |coef_j| K_j (4 + (2 n + 3) arg_j). Where the terms cancel this exceeds
// 1e-5 of the span: the conditioning of the expansion, not an error of the generated code.
double SvrSumRounding(const DriftModel& dm, double t, double q, double mem = 0.0) {
  if (!dm.kernel) return 0.0;
  const SvrModel* m = &*dm.kernel;
  const double u = 1.0 / (1 << 24);
  const double x[3] = {t, q, mem};
  double z[3];
  for (std::size_t j = 0; j < m->num_inputs; ++j) z[j] = (x[j] - m->input_scaler.offset[j]) / m->input_scaler.scale[j];
  double sum = 0.0;
  for (std::size_t i = 0; i < m->num_support(); ++i) {
    double d2 = 0.0;
    for (std::size_t j = 0; j < m->num_inputs; ++j) {
      const double d = z[j] - m->support_vectors[i * m->num_inputs + j];
      d2 += d * d;
    }
    const double arg = m->gamma * d2;
    sum += std::abs(m->coefficients[i]) * std::exp(-arg) * (4.0 + (2.0 * m->num_inputs + 3.0) * arg);
  }
  return u * std::abs(m->target_scale) * sum;
}

// How much the model moves when its inputs (T after the policy, the causal thermal state) move
// by what float cannot hold: `ulps` float units of each, plus, for the state, the float
// rounding of the temperature fed to its update (<= u |T| per sample, as white noise) through the
// update's noise gain: sqrt(dt / (4 tau^3)) for the rate (|H|^2 of s / (1 + s tau)^2 integrated),
// 1 for the lag excess T - T_lag, times 6 (a 6-sigma bound over ~1e5 samples); and the lags' time
// constants as float holds them (below). Plus the SVR sum's
// rounding bound. What any float evaluation must be allowed, however exact its arithmetic.
std::vector<double> InputConditioning(const DriftModel& m, const std::vector<double>& temp, double dt, double ulps) {
  const double u0 = 1.0 / (1 << 24), u = ulps * u0;
  const double tau = m.state.causal_rate_tau_s;
  const double gain = m.inputs == DriftInputSet::kTempAndRate || m.inputs == DriftInputSet::kTempRateAndMemory
                          ? std::sqrt(dt / (4.0 * tau * tau * tau))
                      : m.inputs == DriftInputSet::kTempAndLag ? 1.0
                                                               : 0.0;
  // The lag coefficient a = 1 - exp(-dt/tau) is held in float to u b / a relative (a = 1 - b is
  // exact, b is not): the float build runs the lags with tau off by ~2 u tau / dt relative.
  ThermalStateOptions lo = m.state, hi = m.state;
  const double e = 2.0 * u0 * std::max(tau, m.state.lag_tau_s) / dt;
  lo.causal_rate_tau_s *= 1.0 - e;
  hi.causal_rate_tau_s *= 1.0 + e;
  lo.lag_tau_s *= 1.0 - e;
  hi.lag_tau_s *= 1.0 + e;
  ThermalStateEvaluator ev(m.inputs, m.state), ev_lo(m.inputs, lo), ev_hi(m.inputs, hi);
  std::vector<double> out(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) {
    const double q = ev.Step(dt, temp[i]);
    const double q_lo = ev_lo.Step(dt, temp[i]), q_hi = ev_hi.Step(dt, temp[i]);
    const double t = m.EffectiveTemp(temp[i]);
    const double mem = ev.memory();  // temp,dtemp,memory: the second state (0 for the others)
    const double base = m.PredictAt(t, q, mem);
    const double dq = u * std::abs(q) + 6.0 * u0 * std::abs(temp[i]) * gain;
    double worst = std::max(std::abs(m.PredictAt(t, q_lo, ev_lo.memory()) - base),
                            std::abs(m.PredictAt(t, q_hi, ev_hi.memory()) - base));
    for (double st : {-1.0, 1.0})
      for (double sr : {-1.0, 1.0})
        worst = std::max(worst, std::abs(m.PredictAt(t * (1 + st * u), q + sr * dq, mem * (1 + sr * u)) - base));
    out[i] = worst + SvrSumRounding(m, t, q, mem);
  }
  return out;
}

// A held-out run (other seed) that also leaves the fitted range (a ramp to 75 C and one to
// -50 C at the end), so the clamps are exercised. fs_hz < 1 thins the paper profile (the bounds
// of InputConditioning cost a pass over the support vectors per sample and model).
SimulatedRun HeldOut(std::uint64_t seed, double fs_hz) {
  SimulatedRun run = export_test::ChamberRun(seed, 1.5, {}, fs_hz);
  const double last = run.temp_c.back();
  for (int i = 1; i <= 1500; ++i) {
    run.temp_c.push_back(i <= 900 ? last + (75.0 - last) * i / 900.0 : 75.0 - 125.0 * (i - 900) / 600.0);
    run.rate_dps.push_back(run.rate_dps[i % 1000]);
  }
  return run;
}

// Nine axes, nine structures: poly and SVR on (T, dT/dt); poly degree 5 on T with the clamp
// policy; SVR on T; poly on (T, lag), (T, memory) and (T, dT/dt, memory) and SVR on (T, dT/dt,
// memory); a hybrid (the poly on (T, dT/dt) plus the
// SVR on (T, dT/dt) as its kernel). Double: within 1e-12 of each axis's drift span; float: within
// 1e-5 of it plus the model's own conditioning.
TEST_F(GeneratedCTest, AgreesWithTheLibraryCausalPrediction) {
  for (std::uint64_t seed : {31u, 32u}) {
    const SimulatedRun cal = export_test::ChamberRun(seed);
    DriftModel poly5 = export_test::Fit(cal, DriftModelKind::kPolynomial, DriftInputSet::kTemp, 5);
    poly5.out_of_range = OutOfRangePolicy::kClamp;
    const DriftModel poly_rate = export_test::Fit(cal, DriftModelKind::kPolynomial, DriftInputSet::kTempAndRate);
    const DriftModel svr_rate = export_test::Fit(cal, DriftModelKind::kSvr, DriftInputSet::kTempAndRate, 3, 0.7, 30.0);
    DriftModel hybrid = poly_rate;
    hybrid.kind = DriftModelKind::kHybrid;
    hybrid.kernel = svr_rate.kernel;
    std::vector<AxisDriftModel> axes = {
        {"poly-rate", poly_rate},
        {"svr-rate", svr_rate},
        {"poly5-clamp", poly5},
        {"svr", export_test::Fit(cal, DriftModelKind::kSvr, DriftInputSet::kTemp)},
        {"poly-lag", export_test::Fit(cal, DriftModelKind::kPolynomial, DriftInputSet::kTempAndLag)},
        {"poly-memory", export_test::Fit(cal, DriftModelKind::kPolynomial, DriftInputSet::kTempAndMemory)},
        {"poly-rate-memory", export_test::Fit(cal, DriftModelKind::kPolynomial, DriftInputSet::kTempRateAndMemory)},
        {"svr-rate-memory", export_test::Fit(cal, DriftModelKind::kSvr, DriftInputSet::kTempRateAndMemory, 3, 0.7, 30.0)},
        {"hybrid-rate", hybrid}};
    // Every 4 s: the states (tau 75 s and more) are resolved as well, at a quarter of the cost.
    const double dt = 4.0;
    const SimulatedRun val = HeldOut(seed + 100, 1.0 / dt);
    CExportOptions o;
    o.prefix = "gcd_s" + std::to_string(seed);
    auto gen = GenerateCEvaluator(axes, o);
    ASSERT_TRUE(gen.ok()) << gen.error().message;
    std::vector<std::vector<double>> expected;
    for (const auto& a : axes) {
      auto d = PredictDriftCausal(a.model, DriftInputs{val.temp_c, 1.0 / dt});
      ASSERT_TRUE(d.ok()) << d.error().message;
      expected.push_back(*d);
    }
    std::vector<std::vector<double>> cond;
    for (const auto& a : axes) cond.push_back(InputConditioning(a.model, val.temp_c, dt, 16.0));
    for (bool use_float : {false, true}) {
      const std::string bin = Build(*gen, o.prefix, axes.size(), use_float);
      const auto got = Run(bin, dt, val.temp_c, val.rate_dps, axes.size());
      ASSERT_EQ(got.size(), val.temp_c.size());
      for (std::size_t k = 0; k < axes.size(); ++k) {
        // Float: 1e-5 of the span plus the model's own conditioning (16 float ulps of T and dT/dt,
        // and for an SVR the rounding bound of its sum); double: 1e-12 of the span.
        double worst = 0.0, worst_over_tol = 0.0;
        for (std::size_t i = 0; i < got.size(); ++i) {
          const double e = std::abs(got[i][k] - (val.rate_dps[i] - expected[k][i]));
          const double tol = use_float ? 1e-5 * Span(expected[k]) + cond[k][i] : 1e-12 * Span(expected[k]);
          worst = std::max(worst, e);
          worst_over_tol = std::max(worst_over_tol, e / tol);
        }
        std::printf("[ measured ] %s %s seed %d: max error / span = %.3g (%.3g of the tolerance)\n",
                    axes[k].axis.c_str(), use_float ? "float" : "double", static_cast<int>(seed),
                    worst / Span(expected[k]), worst_over_tol);
        EXPECT_LE(worst_over_tol, 1.0) << axes[k].axis << (use_float ? " float" : " double") << " seed " << seed;
      }
    }
  }
}

// The brief's contract end to end: `gyrocomp apply --causal` and the C of `gyrocomp export
// --format c` from the same model file give the same compensated rate.
TEST_F(GeneratedCTest, AgreesWithApplyCausal) {
  const std::string cli = testing::CliPath();
  if (cli.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  const SimulatedRun cal = export_test::ChamberRun(41);
  const DriftModel m = export_test::Fit(cal, DriftModelKind::kSvr, DriftInputSet::kTempAndRate, 3, 0.7, 30.0);
  ASSERT_TRUE(SaveDriftModel(m, dir_ + "/m.json").ok());
  const double dt = 4.0;  // thinned as above: the float bounds cost a pass over the support vectors per sample
  const SimulatedRun val = HeldOut(42, 1.0 / dt);
  {
    std::ofstream f(dir_ + "/val.csv");
    f.precision(17);
    f << "time_s,rate_dps,temp_c\n";
    for (std::size_t i = 0; i < val.temp_c.size(); ++i) f << dt * i << "," << val.rate_dps[i] << "," << val.temp_c[i] << "\n";
  }
  std::string out;
  ASSERT_EQ(testing::RunCommand(cli + " apply --causal -m " + dir_ + "/m.json -i " + dir_ + "/val.csv -o " + dir_ +
                                    "/applied.csv --json " + dir_ + "/apply.json", &out), 0) << out;
  const nlohmann::json aj = testing::ReadJsonFile(dir_ + "/apply.json");
  EXPECT_TRUE(aj["causal"].get<bool>());
  ASSERT_EQ(testing::RunCommand(cli + " export -m " + dir_ + "/m.json --format c -o " + dir_ + "/gcd_cli", &out), 0) << out;
  GeneratedC gen;
  gen.header_name = "gcd_cli.h";
  gen.source_name = "gcd_cli.c";
  std::ifstream h(dir_ + "/gcd_cli.h"), c(dir_ + "/gcd_cli.c");
  gen.header.assign(std::istreambuf_iterator<char>(h), {});
  gen.source.assign(std::istreambuf_iterator<char>(c), {});
  auto applied = testing::ReadGoldenCsv(dir_ + "/applied.csv");
  const auto& comp = applied["compensated_dps"];
  const auto& pred = applied["predicted_drift_dps"];
  ASSERT_EQ(comp.size(), val.temp_c.size());
  const double fs = aj["fs_hz"].get<double>();
  EXPECT_EQ(fs, 1.0 / dt);
  for (bool use_float : {false, true}) {
    const auto got = Run(Build(gen, "gcd_cli", 1, use_float), 1.0 / fs, applied["temp_c"], applied["rate_dps"], 1);
    const std::vector<double> cond = InputConditioning(m, applied["temp_c"], 1.0 / fs, 16.0);
    double worst_over_tol = 0.0;
    for (std::size_t i = 0; i < got.size(); ++i) {
      const double tol = use_float ? 1e-5 * Span(pred) + cond[i] : 1e-12 * Span(pred);
      worst_over_tol = std::max(worst_over_tol, std::abs(got[i][0] - comp[i]) / tol);
    }
    EXPECT_LE(worst_over_tol, 1.0) << (use_float ? "float" : "double");
  }
}

// --c-unit rads: rate_in / rate_out in rad/s, the drift scaled by pi/180, against apply --causal
// in deg/s. Double build, 1e-12 of the span.
TEST_F(GeneratedCTest, RadPerSecondBuildAgreesWithApplyCausal) {
  const std::string cli = testing::CliPath();
  if (cli.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  const DriftModel m = export_test::Fit(export_test::ChamberRun(43), DriftModelKind::kPolynomial,
                                        DriftInputSet::kTempAndRate);
  auto r = ApplyCausalAndExportC(cli, m, 44, "gcd_rad", "--c-unit rads");
  EXPECT_NE(r.gen.header.find("Rates in rad/s"), std::string::npos);
  const double k = std::numbers::pi / 180.0;
  std::vector<double> rate_rad;
  for (double v : r.applied["rate_dps"]) rate_rad.push_back(v * k);
  const auto got = Run(Build(r.gen, "gcd_rad", 1, false), 1.0, r.applied["temp_c"], rate_rad, 1);
  ASSERT_EQ(got.size(), r.applied["compensated_dps"].size());
  const double tol = 1e-12 * Span(r.applied["predicted_drift_dps"]);
  double worst = 0.0;
  for (std::size_t i = 0; i < got.size(); ++i) worst = std::max(worst, std::abs(got[i][0] / k - r.applied["compensated_dps"][i]));
  EXPECT_LE(worst, tol);
}

// poly(T, dT/dt, memory) end to end: the model file of `fit --inputs
// temp,dtemp,memory`, `apply --causal` and the C of `export --format c` give the same
// compensated rate (double build, 1e-12 of the drift span).
TEST_F(GeneratedCTest, TwoStateModelAgreesWithApplyCausal) {
  const std::string cli = testing::CliPath();
  if (cli.empty()) GTEST_SKIP() << "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  const DriftModel m = export_test::Fit(export_test::ChamberRun(45), DriftModelKind::kPolynomial,
                                        DriftInputSet::kTempRateAndMemory);
  auto r = ApplyCausalAndExportC(cli, m, 46, "gcd_two", "");
  EXPECT_NE(r.gen.source.find("mt = state->mem[0]"), std::string::npos);
  const auto got = Run(Build(r.gen, "gcd_two", 1, false), 1.0, r.applied["temp_c"], r.applied["rate_dps"], 1);
  ASSERT_EQ(got.size(), r.applied["compensated_dps"].size());
  const double tol = 1e-12 * Span(r.applied["predicted_drift_dps"]);
  double worst = 0.0;
  for (std::size_t i = 0; i < got.size(); ++i) worst = std::max(worst, std::abs(got[i][0] - r.applied["compensated_dps"][i]));
  EXPECT_LE(worst, tol);
}

TEST(GenerateCEvaluator, RefusesBadOptions) {
  CExportOptions o;
  o.prefix = "9bad";
  DriftModel m;
  m.structured = PolynomialModel{AffineScaler::Identity(1), {{0, 0, 1.0}}};
  EXPECT_FALSE(GenerateCEvaluator({{"x", m}}, o).ok());
  EXPECT_TRUE(GenerateCEvaluator({{"x", m}}, {}).ok());
  EXPECT_FALSE(GenerateCEvaluator({}, {}).ok());
  m.structured->terms[0].coefficient = NAN;
  EXPECT_FALSE(GenerateCEvaluator({{"x", m}}, {}).ok());
  m.structured.reset();
  EXPECT_FALSE(GenerateCEvaluator({{"x", m}}, {}).ok());  // neither part
}

}  // namespace
}  // namespace gyrocomp
