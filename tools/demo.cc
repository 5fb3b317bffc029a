// gyrocomp demo (temporary, until the pipeline lands here): simulate the paper's chamber run and
// print its Allan figures next to the paper's raw ones.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "gyrocomp/allan.h"
#include "gyrocomp/io.h"
#include "gyrocomp/simulator.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kName = "demo";

struct DemoArgs {
  std::string out_dir;
  SimulatorOptions sim;
};

int Run(const DemoArgs& a) {
  Result<SimulatedRun> run = Simulate(a.sim);
  if (!run.ok()) return ReportError(kName, run.error());
  Result<AllanResult> allan = ComputeAllan(run->rate_dps, run->fs_hz);
  if (!allan.ok()) return ReportError(kName, allan.error());
  allan->axis = "rate_dps";
  const AllanNoiseTerms& t = allan->terms;
  std::printf("gyrocomp demo: the paper's chamber run (Section 4.1), simulated\n  %s\n\n",
              run->summary.BriefReport().c_str());
  std::printf("  %-40s %12s %12s\n", "raw record", "simulated", "paper");
  std::printf("  %-40s %12.3f %12.3f\n", "ARW, deg/sqrt(h) [sigma(1 s) x 60]", t.arw_deg_per_sqrt_h.value_or(NAN), 1.667);
  std::printf("  %-40s %12.2f %12.2f\n", "bias stability (ADEV min), deg/h", t.adev_min_deg_per_h, 30.0);
  std::printf("  %-40s %12.1f %12s\n", "  at tau, s", t.tau_at_min_s, "-");
  std::printf("  %-40s %12.2f %12s\n", "bias instability B = min/0.664, deg/h", t.bias_instability_deg_per_h, "-");
  if (t.rrw_deg_per_h_per_sqrt_h) {
    std::printf("  %-40s %12.2f %12s\n", "RRW, deg/h/sqrt(h) [sigma(3 s), +1/2 fit]", *t.rrw_deg_per_h_per_sqrt_h, "-");
  }
  std::printf("\n  Allan deviation (%zu octave taus, %.2f s):\n  %12s %14s %14s\n", allan->curve.size(),
              allan->seconds, "tau_s", "adev_deg_per_h", "68% interval");
  for (std::size_t j = 0; j < allan->curve.size(); ++j) {
    std::printf("  %12.2f %14.3f   [%.3f, %.3f]\n", allan->curve.tau_s[j], allan->curve.adev_dps[j] * 3600.0,
                allan->curve.adev_lo_dps[j] * 3600.0, allan->curve.adev_hi_dps[j] * 3600.0);
  }
  if (!a.out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(a.out_dir, ec);
    if (ec) return ReportError(kName, IoError(a.out_dir + ": cannot create directory: " + ec.message()));
    const std::string json_path = (std::filesystem::path(a.out_dir) / "allan.json").string();
    if (Status s = WriteJson(json_path, AllanJson(*allan)); !s.ok()) return ReportError(kName, s.error());
    std::printf("\n  wrote %s\n", json_path.c_str());
  }
  return kExitOk;
}

Command Make(CLI::App& app) {
  auto a = std::make_shared<DemoArgs>();
  CLI::App* sub = app.add_subcommand(
      kName, "Simulate the paper's chamber run (14.25 h at 100 Hz) and print its Allan figures against the paper's");
  sub->add_option("--out", a->out_dir, "Also write allan.json into this directory");
  sub->add_option("--fs", a->sim.fs_hz, "Sample rate of the simulation, Hz")->check(CLI::PositiveNumber)->capture_default_str();
  sub->add_option("--seed", a->sim.seed, "Random seed of the simulation")->capture_default_str();
  return {sub, [a] { return Run(*a); }};
}

const CommandRegistrar kReg(kName, 10, &Make);

}  // namespace
}  // namespace gyrocomp::cli
