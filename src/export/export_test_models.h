// Test helpers of the export stage: simulated chamber runs and models fitted on them.
#pragma once

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp::export_test {

// The paper's chamber run at fs_hz (default 1 Hz; 14.25 h, -40..60 C), drift = cubic bias(T) + dtemp_coeff *
// dT/dt + hysteresis (simulator.h), with `poly` as the bias coefficients when given.
inline SimulatedRun ChamberRun(std::uint64_t seed, double dtemp_coeff = 1.5, std::vector<double> poly = {},
                               double fs_hz = 1.0) {
  SimulatorOptions o;
  o.fs_hz = fs_hz;
  o.seed = seed;
  o.bias.dtemp_coeff_dps_per_c_per_s = dtemp_coeff;
  if (!poly.empty()) o.bias.poly_dps = poly;
  auto run = Simulate(o);
  EXPECT_TRUE(run.ok());
  return std::move(*run);
}

inline DriftModel Fit(const SimulatedRun& run, DriftModelKind kind, DriftInputSet inputs, int degree = 3,
                      double sigma = 0.5, double C = 10.0) {
  DriftFitOptions o;
  o.model = kind;
  o.inputs = inputs;
  o.polynomial.degree = degree;
  o.svr.sigma = sigma;
  o.svr.C = C;
  auto m = FitDriftModel(DriftInputs{run.temp_c, run.fs_hz}, run.rate_dps, o);
  EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().message);
  return std::move(*m);
}

inline double Span(const std::vector<double>& v) {
  double lo = v[0], hi = v[0];
  for (double x : v) {
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  return hi - lo;
}

}  // namespace gyrocomp::export_test
