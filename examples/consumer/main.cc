// Simulates one hour of a gyro with known noise, measures its Allan deviation and checks the
// recovered angle random walk. Exit 0 when the figure is within 10% of the injected one.
#include <cmath>
#include <cstdio>

#include "gyrocomp/gyrocomp.h"

int main() {
  gyrocomp::SimulatorOptions sim;
  sim.duration_s = 3600.0;
  sim.fs_hz = 100.0;
  sim.noise.arw_deg_per_sqrt_h = 1.0;
  gyrocomp::Result<gyrocomp::SimulatedRun> run = gyrocomp::Simulate(sim);
  if (!run.ok()) {
    std::fprintf(stderr, "consumer: %s\n", run.error().message.c_str());
    return 1;
  }
  gyrocomp::Result<gyrocomp::AllanResult> allan = gyrocomp::ComputeAllan(run->rate_dps, run->fs_hz);
  if (!allan.ok()) {
    std::fprintf(stderr, "consumer: %s\n", allan.error().message.c_str());
    return 1;
  }
  std::printf("%s\n", allan->BriefReport().c_str());
  const double arw = allan->terms.arw_deg_per_sqrt_h.value_or(0.0);
  if (std::abs(arw - 1.0) > 0.1) {
    std::fprintf(stderr, "consumer: ARW %g deg/sqrt(h), injected 1\n", arw);
    return 1;
  }
  return 0;
}
