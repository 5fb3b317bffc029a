// libFuzzer harness: finite doubles of the shapes in fuzz_numeric_support.h into the
// signal stages: Allan (every deviation kind), VMD (N <= 256, at most 24 iterations, one thread,
// so each run is bounded), sample entropy, the feature classifier, wavelet / FLP / WFLP.
// Invariant: a Status error with a message, or every result finite (sample entropy may be +inf
// when defined, as documented: no match of length m+1).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_numeric_support.h"
#include "gyrocomp/allan/allan.h"
#include "gyrocomp/allan/deviations.h"
#include "gyrocomp/decompose/feature_classifier.h"
#include "gyrocomp/decompose/sample_entropy.h"
#include "gyrocomp/decompose/vmd.h"
#include "gyrocomp/denoise/flp.h"
#include "gyrocomp/denoise/wavelet_denoise.h"
#include "gyrocomp/denoise/wflp.h"

namespace gyrocomp::fuzz {
namespace {

constexpr double kSampleRates[] = {100.0, 1.0, 1e-6, 1e9, 0.37, 8000.0};

void FuzzAllan(std::span<const double> x, double fs, ByteReader& in) {
  AllanOptions o;
  o.grid = in.Byte() % 3 == 0 ? TauGrid::kAll : TauGrid::kOctave;
  auto r = ComputeAllan(x, fs, o);
  if (OkOrMessage(r, "ComputeAllan")) {
    CheckFinite(r->curve.adev_dps, "adev");
    CheckFinite(r->curve.tau_s, "tau");
    CheckFinite(r->curve.adev_lo_dps, "adev_lo");
    CheckFinite(r->curve.adev_hi_dps, "adev_hi");
    const AllanNoiseTerms& t = r->terms;
    if (t.arw_deg_per_sqrt_h) CheckFinite(*t.arw_deg_per_sqrt_h, "arw");
    if (t.arw_fit_deg_per_sqrt_h) CheckFinite(*t.arw_fit_deg_per_sqrt_h, "arw_fit");
    if (t.rrw_deg_per_h_per_sqrt_h) CheckFinite(*t.rrw_deg_per_h_per_sqrt_h, "rrw");
    CheckFinite(t.adev_min_deg_per_h, "adev_min");
    CheckFinite(t.bias_instability_deg_per_h, "bias_instability");
  }
  for (DeviationKind k : {DeviationKind::kAdev, DeviationKind::kMdev, DeviationKind::kHdev, DeviationKind::kOhdev,
                          DeviationKind::kTotdev}) {
    auto d = ComputeDeviation(x, fs, k, AllanOptions{});
    if (!OkOrMessage(d, "ComputeDeviation")) continue;
    const std::string name = DeviationKindName(k);
    CheckFinite(d->dev_dps, name);
    CheckFinite(d->lo_dps, name + " lo");
    CheckFinite(d->hi_dps, name + " hi");
    CheckFinite(d->edf, name + " edf");
  }
}

void FuzzEntropyAndClassifier(std::span<const double> x, ByteReader& in) {
  SampleEntropyOptions o;
  o.m = 1 + in.Byte() % 3;
  o.num_threads = 1;
  auto r = SampleEntropy(x, o);
  if (OkOrMessage(r, "SampleEntropy")) {
    if (r->defined && std::isnan(r->sample_entropy)) Fail("SampleEntropy: defined but NaN");
    CheckFinite(r->r, "sample entropy r");
  }
  std::vector<ModeFeature> modes;
  for (std::size_t i = 0; i < 1 + in.Byte() % 8; ++i) {
    const double se = i < x.size() ? x[i] : in.Finite();
    modes.push_back({std::abs(se), std::abs(in.Finite()), std::abs(in.Finite())});
  }
  auto c = ClassifyModes(modes, in.Byte() & 1 ? ClassifierOptions::Paper() : ClassifierOptions::Standard());
  (void)OkOrMessage(c, "ClassifyModes");
}

void FuzzVmd(std::span<const double> x, double fs, ByteReader& in) {
  VmdOptions o;
  o.num_modes = 1 + in.Byte() % 4;
  o.max_iterations = 2 + in.Byte() % 23;
  o.alpha = std::ldexp(1.0, static_cast<int>(in.Byte() % 40) - 10);
  o.tau = (in.Byte() % 3) * 0.5;
  o.dc = in.Byte() & 1;
  o.init = static_cast<VmdInit>(in.Byte() % 3);
  o.stopping_rule = in.Byte() & 1 ? VmdStoppingRule::kRelative : VmdStoppingRule::kAbsolute;
  o.fs_hz = fs;
  o.num_threads = 1;
  auto r = DecomposeVmd(x.subspan(0, std::min<std::size_t>(x.size(), 256)), o);
  if (!OkOrMessage(r, "DecomposeVmd")) return;
  for (std::size_t k = 0; k < r->modes.size(); ++k) CheckFinite(r->modes[k], "vmd mode " + std::to_string(k));
  CheckFinite(r->summary.center_frequency_hz, "vmd centre frequencies");
}

void FuzzDenoise(std::span<const double> x, ByteReader& in) {
  WaveletDenoiseOptions w;
  w.level = in.Byte() % 6;
  w.extension = static_cast<ExtensionMode>(in.Byte() % 6);
  w.threshold = static_cast<ThresholdRule>(in.Byte() % 3);
  w.threshold_mode = in.Byte() & 1 ? ThresholdMode::kHard : ThresholdMode::kSoft;
  auto a = WaveletDenoise(x, w);
  if (OkOrMessage(a, "WaveletDenoise")) CheckFinite(*a, "wavelet denoised");
  FlpOptions f;
  f.order = 1 + in.Byte() % 16;
  auto b = FlpDenoise(x, f);
  if (OkOrMessage(b, "FlpDenoise")) CheckFinite(*b, "flp filtered");
  WflpOptions o;
  o.level = in.Byte() % 6;
  o.flp.order = 1 + in.Byte() % 16;
  o.details = static_cast<DetailHandling>(in.Byte() % 3);
  auto c = WflpDenoise(x, o);
  if (OkOrMessage(c, "WflpDenoise")) CheckFinite(*c, "wflp denoised");
}

}  // namespace
}  // namespace gyrocomp::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gyrocomp::fuzz;
  ByteReader in(data, size);
  const std::size_t n = MakeLength(in, 2048);
  const std::vector<double> x = MakeSeries(in, n);
  const double fs = kSampleRates[in.Byte() % std::size(kSampleRates)];
  const std::uint8_t stages = in.Byte();
  if (stages & 1) FuzzAllan(x, fs, in);
  if (stages & 2) FuzzEntropyAndClassifier(x, in);
  if (stages & 4) FuzzVmd(x, fs, in);
  if (stages & 8) FuzzDenoise(x, in);
  return 0;
}
