// Helpers shared by the calibrate stage's tests on several runs (calibrate_flights_test.cc,
// calibrate_two_runs_test.cc): a residual RMS after the boot offset, a least-squares cubic check
// and a simulated one-IMU chamber run.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "gyrocomp/export/thermal_cubic.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp::calibrate_test {

// RMS of x - y over the temperatures, the mean difference removed (the boot calibration's share).
template <class F, class G>
inline double RmsAfterOffset(const std::vector<double>& temps, F x, G y) {
  std::vector<double> d;
  double mean = 0.0;
  for (double t : temps) d.push_back(x(t) - y(t)), mean += d.back();
  mean /= static_cast<double>(d.size());
  double ss = 0.0;
  for (double v : d) ss += (v - mean) * (v - mean);
  return std::sqrt(ss / static_cast<double>(d.size()));
}

// Expects `got` to be the least-squares cubic of f over 401 equal steps of `about`'s range, in
// `about`'s standardised u = (T - ref) / half-range, at 41 of them within `tol`.
template <class F>
void ExpectLeastSquaresCubic(const TemperatureCubic& about, F f, const TemperatureCubic& got, double tol, const std::string& what) {
  const double h = 0.5 * (about.temp_max_c - about.temp_min_c);
  const auto temp = [&](int i) { return about.temp_min_c + (about.temp_max_c - about.temp_min_c) * i / 400.0; };
  Eigen::MatrixXd A(401, 4);
  Eigen::VectorXd y(401);
  for (int i = 0; i < 401; ++i) {
    const double u = (temp(i) - about.ref_temp_c) / h;
    A.row(i) << 1.0, u, u * u, u * u * u;
    y(i) = f(temp(i));
  }
  const Eigen::Vector4d x = A.colPivHouseholderQr().solve(y);
  for (int i = 0; i <= 400; i += 10) {
    const double u = (temp(i) - about.ref_temp_c) / h;
    EXPECT_NEAR(got.Evaluate(temp(i)), x(0) + u * (x(1) + u * (x(2) + u * x(3))), tol) << what << " T " << temp(i);
  }
}

inline BoardRun Chamber(ThermalProfileKind kind, std::uint64_t seed) {
  BoardSimOptions o;
  o.chamber.profile.kind = kind;
  o.chamber.profile.room_hold_s = 600.0;
  o.chamber.profile.hold_s = 600.0;
  o.chamber.profile.ramp_end_c = 60.0;
  o.chamber.profile.hot_temp_c = 60.0;
  o.chamber.profile.cold_temp_c = 0.0;
  o.chamber.profile.step_c = 20.0;
  o.chamber.fs_hz = 10.0;
  o.chamber.seed = seed;
  o.num_imus = 1;
  Result<BoardRun> b = SimulateBoard(o);
  EXPECT_TRUE(b.ok()) << b.error().message;
  return *b;
}

}  // namespace gyrocomp::calibrate_test
