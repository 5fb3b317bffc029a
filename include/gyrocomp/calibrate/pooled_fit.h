// One thermal curve from several power-ons: the least-squares cubic in temperature shared by all
// rows, with one constant per group of rows (a log's power-on offset for a gyro or barometer; a
// still segment's gravity share and offset for an accelerometer):
//   y_i = b_g(i) + c1 dT_i + c2 dT_i^2 + c3 dT_i^3,   dT_i = T_i - ref_temp_c,
// the firmware's polynomial (PX4 TC_*_X1..X3 about TC_*_TREF, TemperatureCompensation; ArduPilot
// INS_TCALn_GYR/ACC, AP_InertialSensor_tempcal.cpp) with the constant left free per group, since
// the firmware's boot calibration removes a power-on's constant anyway. The constants are
// eliminated by removing each group's means (Frisch-Waugh-Lovell): c1..c3 are the least squares
// of the within-group deviations, so only the temperature change inside a group identifies the
// curve; two groups at different temperatures with no change inside either identify nothing.
// With rate_c_per_s given, a shared term g dT/dt can be fitted too (the board's temperature lags the
// die's while it heats: a drift that depends on the heating rate, the single-run model's
// dT/dt state) and the cubic is the curve at dT/dt = 0, the steady state the firmware's
// formula has (docs/explanation/flight-controller-export.md).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/term_admission.h"

namespace gyrocomp {

// The fit's result.
struct PooledCubic {
  double ref_temp_c = 0.0;  // dT origin, deg C
  std::array<double, 3> slope{};  // c1, c2, c3: target unit / C^k
  std::vector<double> group_constant;  // b_g per group, target unit (groups without rows: 0)
  std::vector<std::size_t> group_rows;  // rows per group
  double residual_rms = 0.0;  // RMS of y - fit, target unit
  std::vector<double> group_residual_ms;  // mean squared residual per group, target unit^2
  // 1 sigma of the fitted curve's change over the rows' temperature range (centred, at dT/dt = 0),
  // RMS over 101 temperatures, target unit. The rows' noise is mostly slow (flicker, random walk),
  // so neighbouring rows are far from independent (taken as independent, the 1 sigma was 9-16x
  // below the actual error of two chamber runs). FitPooledCubic gives the larger of
  //   Eq. P-1 (HAC, overlapping batch means; Newey & West 1987 with a Bartlett kernel):
  //     Cov(c) = A^-1 S A^-1, A = sum_i d_i d_i', S = sum_g n_g / (n_g - B_g + 1) / B_g sum_t W_t W_t',
  //     W_t = sum_{i = t}^{t + B_g - 1} d_i e_i over group g's rows in order, B_g = n_g / 4,
  //     d_i the row's within-group columns, e_i its residual; Var(curve(T)) = x(T)' Cov(c) x(T);
  //   Eq. P-2 (delete-one-group jackknife, Quenouille / Tukey; each group refitted out):
  //     Var(curve(T)) = (G - 1) / G sum_g (f_(g)(T) - mean_g f_(g)(T))^2, f_(g) the centred curve
  //     without group g, over the G >= 2 groups that can be left out;
  //   Eq. P-3: curve_sd = max(P-1, P-2); P-1 alone with fewer than two groups to leave out.
  // P-2 takes every correlation inside a log into account (a log's noise is independent of
  // another's) but with two logs has one degree of freedom; P-1 falls short by up to 2x under a
  // random walk (the residuals are fitted) but is steady. Functions of the rows (the lag search,
  // the dT/dt admission, PooledGroupHeldOutRms) fit without P-2.
  double curve_sd = 0.0;
  double within_group_span_c = 0.0;  // largest temperature change inside one group, deg C
  // g, target unit per (C/s); 0 when not fitted: no rate_c_per_s, dT/dt not identified (less
  // than 10 % of its within-group variance left once the cubic's columns explain what they can),
  // or its held-out gain not above its standard error (rate_term).
  double rate_gain = 0.0;
  bool rate_used = false;  // the dT/dt term was fitted
  // The dT/dt term's paired held-out gain over the cubic alone, each group held out in turn
  // (term_admission.h, Eqs. A-1..A-3); the term is kept only when Admitted() (Eq. A-4), as the
  // default drift model admits a term. pairs 0 when the term was not identified or not asked for.
  TermGain rate_term;
};

// temp_c, y, group (and rate_c_per_s unless empty) as long as each other; group[i] < num_groups.
// Errors: lengths differ, fewer than 8 rows, no temperature change inside any group, a singular
// system (kInvalidInput).
Result<PooledCubic> FitPooledCubic(const std::vector<double>& temp_c, const std::vector<double>& y,
                                   const std::vector<std::size_t>& group, std::size_t num_groups, double ref_temp_c,
                                   const std::vector<double>& rate_c_per_s = {});

// Each group held out in turn: the pooled cubic (no dT/dt term) fitted on the other groups, the
// RMS of the held-out group's residuals once its own constant is removed (only the shape inside
// the group is predicted), target unit; NaN for a group with fewer than 2 rows or whose fit
// failed. Arguments as FitPooledCubic's.
std::vector<double> PooledGroupHeldOutRms(const std::vector<double>& temp_c, const std::vector<double>& y,
                                          const std::vector<std::size_t>& group, std::size_t num_groups, double ref_temp_c);

}  // namespace gyrocomp
