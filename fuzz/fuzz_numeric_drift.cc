// libFuzzer harness: finite doubles of the shapes in fuzz_numeric_support.h as the
// temperature and the target of the drift stage: FitDriftModel (poly, svr, cs-svr and grid-svr
// with tiny budgets, every input set), batch and causal prediction, the model file round trip
// (what fit writes, apply must load), thermal states, the noise model, the cubic projection, the
// PX4 / ArduPilot parameter files and the generated C (its text; the C++ evaluator stands for
// the C it mirrors, c_export_test.cc compiles and compares the C itself).
// Invariant: a Status error with a message, or every result finite and every model loadable.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_numeric_support.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/drift/noise_model.h"
#include "gyrocomp/drift/thermal_state.h"
#include "gyrocomp/export/c_export.h"
#include "gyrocomp/export/param_export.h"
#include "gyrocomp/export/thermal_cubic.h"

namespace gyrocomp::fuzz {
namespace {

constexpr double kSampleRates[] = {1.0, 0.2, 100.0, 1e-3, 5.0};

DriftFitOptions FitOptions(ByteReader& in) {
  DriftFitOptions o;
  const DriftModelKind kinds[] = {DriftModelKind::kPolynomial, DriftModelKind::kSvr, DriftModelKind::kCsSvr,
                                  DriftModelKind::kGridSvr, DriftModelKind::kPolynomial};
  o.model = kinds[in.Byte() % std::size(kinds)];
  o.inputs = static_cast<DriftInputSet>(in.Byte() % 4);
  o.fit_lag_tau = false;
  o.polynomial.degree = 1 + in.Byte() % 5;
  o.polynomial.dtemp_degree = 1 + in.Byte() % 3;
  o.max_train_samples = 20 + in.Byte() % 60;
  o.cv_folds = 2 + in.Byte() % 2;
  o.svr.C = std::ldexp(1.0, static_cast<int>(in.Byte() % 40) - 20);
  o.svr.gamma = std::ldexp(1.0, static_cast<int>(in.Byte() % 40) - 20);
  o.svr.epsilon = (in.Byte() % 8) * 0.05;
  o.search.cuckoo.num_nests = 2;
  o.search.cuckoo.max_generations = in.Byte() % 2;
  o.search.cuckoo.num_threads = 1;
  o.search.grid_budget = 4;
  o.noise_model = in.Byte() % 4 == 0 && o.model == DriftModelKind::kPolynomial ? DriftNoiseModel::kAllan
                                                                               : DriftNoiseModel::kWhite;
  return o;
}

void CheckModel(const DriftModel& m, std::span<const double> temp_c, double fs) {
  for (bool causal : {false, true}) {
    auto p = m.Predict(DriftInputs{temp_c, fs}, causal);
    if (OkOrMessage(p, "Predict")) CheckFinite(*p, causal ? "causal prediction" : "prediction");
  }
  DriftEvaluator eval(m);
  for (double t : temp_c.subspan(0, std::min<std::size_t>(temp_c.size(), 64))) {
    CheckFinite(eval.Step(1.0 / fs, t), "DriftEvaluator::Step");
  }
  // What fit writes, apply must read back.
  DriftModelSet set;
  set.axes.push_back(m);
  const std::string text = DriftModelSetToJson(set);
  auto back = DriftModelSetFromJson(text, "fuzz.json");
  if (!back.ok()) Fail("a fitted model does not load: " + back.error().message);
  // Exporters. A model fitted on a temperature span of ~1e-303 C projected onto infinite
  // coefficients with a success status (c3 ~ drift / span^3); now an error naming the span
  // (param_export_test.cc ThermalCubic.SpanTooNarrowForACubicIsAnErrorNamingIt; reproducer
  // fuzz/regressions/fuzz_numeric_drift/).
  auto cubic = ProjectOntoCubic(m);
  if (OkOrMessage(cubic, "ProjectOntoCubic")) {
    CheckFinite(std::span<const double>(cubic->coeff.data(), 4), "cubic");
    const ThreeAxisCubics three = {cubic->Scaled(0.0174532925), cubic->Scaled(0.0174532925), cubic->Scaled(0.0174532925)};
    Px4ThermalParamOptions px4;
    px4.device_id = 1;
    (void)OkOrMessage(WritePx4ThermalParams(three, px4, {}), "WritePx4ThermalParams");
    (void)OkOrMessage(WriteArduPilotThermalParams(three, ArduPilotThermalParamOptions{}, {}),
                      "WriteArduPilotThermalParams");
    auto cost = MeasureCubicProjectionCost(m, *cubic, DriftInputs{temp_c, fs});
    if (OkOrMessage(cost, "MeasureCubicProjectionCost")) CheckFinite(cost->rms, "projection rms");
  }
  auto c = GenerateCEvaluator({AxisDriftModel{"x", m}});
  if (OkOrMessage(c, "GenerateCEvaluator")) {
    for (const char* bad : {"nan", "inf"}) {
      for (std::size_t at = c->source.find(bad); at != std::string::npos; at = c->source.find(bad, at + 1)) {
        // A number printed as nan / inf (not a word that contains the letters).
        const char before = at > 0 ? c->source[at - 1] : ' ';
        const char after = at + 3 < c->source.size() ? c->source[at + 3] : ' ';
        if ((before == ' ' || before == '-' || before == '(' || before == ',') &&
            (after == ',' || after == ';' || after == ')' || after == ' ' || after == '\n') && !std::isalnum(after)) {
          Fail("generated C holds '" + std::string(bad) + "'");
        }
      }
    }
  }
}

}  // namespace
}  // namespace gyrocomp::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gyrocomp;
  using namespace gyrocomp::fuzz;
  ByteReader in(data, size);
  const std::size_t n = MakeLength(in, 300);
  const std::vector<double> temp_c = MakeSeries(in, n);
  const std::vector<double> target = MakeSeries(in, n);
  const double fs = kSampleRates[in.Byte() % std::size(kSampleRates)];
  const std::uint8_t stages = in.Byte();

  if (stages & 1) {
    const auto inputs = static_cast<DriftInputSet>(in.Byte() % 4);
    for (bool causal : {false, true}) {
      auto s = ComputeThermalState(temp_c, fs, inputs, TemperatureRateOptions{}, ThermalStateOptions{}, causal);
      if (OkOrMessage(s, "ComputeThermalState")) CheckFinite(*s, "thermal state");
    }
  }
  if (stages & 2) {
    auto psd = FitNoisePsd(target, fs, NoisePsdOptions{});
    if (OkOrMessage(psd, "FitNoisePsd")) {
      CheckFinite(psd->h0, "h0");
      CheckFinite(psd->h_1, "h_1");
      CheckFinite(psd->h_2, "h_2");
      CheckFinite(BlockMeanAutocovariance(*psd, 16, 10.0), "block-mean autocovariance");
    }
  }
  if (stages & 4) {
    const DriftFitOptions o = FitOptions(in);
    std::string why;
    if (!o.IsValid(&why)) Fail("the harness's options are invalid: " + why);
    auto m = FitDriftModel(DriftInputs{temp_c, fs}, target, o);
    if (OkOrMessage(m, "FitDriftModel")) CheckModel(*m, temp_c, fs);
  }
  return 0;
}
