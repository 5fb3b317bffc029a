// FitPooledCubic (gyrocomp/calibrate/pooled_fit.h).
#include "gyrocomp/calibrate/pooled_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace gyrocomp {
namespace {

using Vec = std::vector<double>;
using Mat = std::vector<Vec>;

// Solves the symmetric system A x = b (Eigen's rank-revealing QR); false when A is singular (a
// pivot below 1e-12 of the largest).
bool Solve(const Mat& A, const Vec& b, Vec* x) {
  const auto n = static_cast<Eigen::Index>(b.size());
  Eigen::MatrixXd a(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) a(i, j) = A[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-12);
  if (qr.rank() < n) return false;
  const Eigen::VectorXd sol = qr.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), n));
  x->assign(sol.data(), sol.data() + n);
  return true;
}

}  // namespace

namespace {

// The least-squares solve; group_weight[g] multiplies group g's rows (empty: all 1; a feasible
// generalised least squares by the groups' residual variance was tried and changed nothing on
// the two-chamber-run comparison, so the public fit is ordinary least squares).
Result<PooledCubic> FitWeighted(const std::vector<double>& temp_c, const std::vector<double>& y,
                                const std::vector<std::size_t>& group, std::size_t num_groups, double ref_temp_c,
                                const std::vector<double>& rate_c_per_s, const std::vector<double>& group_weight) {
  const std::size_t n = temp_c.size();
  if (y.size() != n || group.size() != n || (!rate_c_per_s.empty() && rate_c_per_s.size() != n))
    return InvalidInput("FitPooledCubic: temp_c, y, group (and rate_c_per_s when given) must be as long");
  if (n < 8) return InvalidInput("FitPooledCubic: " + std::to_string(n) + " rows < 8");
  for (std::size_t g : group)
    if (g >= num_groups) return InvalidInput("FitPooledCubic: a group index >= num_groups");
  PooledCubic out;
  out.ref_temp_c = ref_temp_c;
  // Columns x = ((dT / s), (dT / s)^2, (dT / s)^3[, dT/dt]), s = half the range (conditioning).
  const std::size_t m = rate_c_per_s.empty() ? 3 : 4;
  const auto [lo, hi] = std::minmax_element(temp_c.begin(), temp_c.end());
  const double s = std::max(0.5 * (*hi - *lo), 1e-6);
  auto column = [&](std::size_t i) {
    const double u = (temp_c[i] - ref_temp_c) / s;
    Vec x = {u, u * u, u * u * u};
    if (m == 4) x.push_back(rate_c_per_s[i]);
    return x;
  };
  Mat mx(num_groups, Vec(m, 0.0));
  Vec my(num_groups, 0.0), tmin(num_groups, INFINITY), tmax(num_groups, -INFINITY);
  out.group_rows.assign(num_groups, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t g = group[i];
    const Vec x = column(i);
    for (std::size_t k = 0; k < m; ++k) mx[g][k] += x[k];
    my[g] += y[i];
    ++out.group_rows[g];
    tmin[g] = std::min(tmin[g], temp_c[i]), tmax[g] = std::max(tmax[g], temp_c[i]);
  }
  for (std::size_t g = 0; g < num_groups; ++g) {
    if (out.group_rows[g] == 0) continue;
    const double rows = static_cast<double>(out.group_rows[g]);
    for (double& v : mx[g]) v /= rows;
    my[g] /= rows;
    out.within_group_span_c = std::max(out.within_group_span_c, tmax[g] - tmin[g]);
  }
  // Normal equations of the within-group deviations (Frisch-Waugh-Lovell).
  Mat A(m, Vec(m, 0.0));
  Vec b(m, 0.0), c;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec x = column(i);
    Vec d(m);
    for (std::size_t k = 0; k < m; ++k) d[k] = x[k] - mx[group[i]][k];
    const double w = group_weight.empty() ? 1.0 : group_weight[group[i]];
    for (std::size_t j = 0; j < m; ++j) {
      for (std::size_t k = 0; k < m; ++k) A[j][k] += w * d[j] * d[k];
      b[j] += w * d[j] * (y[i] - my[group[i]]);
    }
  }
  if (m == 4) {
    // dT/dt identified: at least 10 % of its within-group variance is not a cubic of the
    // temperature (a board warming towards its own equilibrium heats at a rate set by its
    // temperature alone, and then the gain cannot be told from the curve).
    Mat A3 = {{A[0][0], A[0][1], A[0][2]}, {A[1][0], A[1][1], A[1][2]}, {A[2][0], A[2][1], A[2][2]}};
    Vec z;
    const bool ok = Solve(A3, {A[0][3], A[1][3], A[2][3]}, &z);
    const double left = ok ? A[3][3] - (A[3][0] * z[0] + A[3][1] * z[1] + A[3][2] * z[2]) : 0.0;
    if (!(left > 0.1 * A[3][3])) return FitWeighted(temp_c, y, group, num_groups, ref_temp_c, {}, group_weight);
    out.rate_used = true;
  }
  if (!(out.within_group_span_c > 0.0) || !Solve(A, b, &c))
    return InvalidInput("FitPooledCubic: the temperature does not change enough inside the groups to identify a cubic");
  // b_g = mean_g(y) - sum_k c_k mean_g(x_k); back to the unit of dT: c_k / s^k.
  out.group_constant.assign(num_groups, 0.0);
  for (std::size_t g = 0; g < num_groups; ++g) {
    if (out.group_rows[g] == 0) continue;
    out.group_constant[g] = my[g];
    for (std::size_t k = 0; k < m; ++k) out.group_constant[g] -= c[k] * mx[g][k];
  }
  double ss = 0.0, ss_weighted = 0.0;
  out.group_residual_ms.assign(num_groups, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec x = column(i);
    double e = y[i] - out.group_constant[group[i]];
    for (std::size_t k = 0; k < m; ++k) e -= c[k] * x[k];
    ss += e * e;
    ss_weighted += (group_weight.empty() ? 1.0 : group_weight[group[i]]) * e * e;
    out.group_residual_ms[group[i]] += e * e / static_cast<double>(out.group_rows[group[i]]);
  }
  const auto groups_used = static_cast<double>(std::count_if(out.group_rows.begin(), out.group_rows.end(), [](std::size_t r) { return r > 0; }));
  const double dof = std::max(1.0, static_cast<double>(n) - static_cast<double>(m) - groups_used);
  out.residual_rms = std::sqrt(ss / static_cast<double>(n));
  // The curve's 1 sigma at dT/dt = 0: Var(x(T)'c) = sigma^2 x(T)' A^-1 x(T), x(T) centred on the
  // range's mean column (the constant is the boot calibration's), RMS over 101 temperatures.
  const double sigma2 = ss_weighted / dof;
  constexpr int kPoints = 101;
  Mat grid;
  Vec xbar(m, 0.0);
  for (int i = 0; i < kPoints; ++i) {
    const double t = *lo + (*hi - *lo) * i / (kPoints - 1), u = (t - ref_temp_c) / s;
    grid.push_back({u, u * u, u * u * u});
    if (m == 4) grid.back().push_back(0.0);
    for (std::size_t k = 0; k < m; ++k) xbar[k] += grid.back()[k] / kPoints;
  }
  double var_sum = 0.0;
  for (const Vec& x : grid) {
    Vec d(m), w;
    for (std::size_t k = 0; k < m; ++k) d[k] = x[k] - xbar[k];
    if (!Solve(A, d, &w)) break;
    for (std::size_t k = 0; k < m; ++k) var_sum += sigma2 * d[k] * w[k];
  }
  out.curve_sd = std::sqrt(std::max(0.0, var_sum / kPoints));
  for (int k = 0; k < 3; ++k) out.slope[static_cast<std::size_t>(k)] = c[static_cast<std::size_t>(k)] / std::pow(s, k + 1);
  if (m == 4) out.rate_gain = c[3];
  return out;
}

// RMS of a held-out group's residuals once its own constant is removed (the constant is free per
// group: only the shape inside the group is predicted).
double HeldOutRms(const PooledCubic& f, const std::vector<double>& temp_c, const std::vector<double>& y,
                  const std::vector<double>& rate_c_per_s, const std::vector<std::size_t>& rows) {
  std::vector<double> e;
  for (std::size_t i : rows) {
    const double u = temp_c[i] - f.ref_temp_c;
    double pred = f.slope[0] * u + f.slope[1] * u * u + f.slope[2] * u * u * u;
    if (f.rate_used) pred += f.rate_gain * rate_c_per_s[i];
    e.push_back(y[i] - pred);
  }
  double mean = 0.0, ss = 0.0;
  for (double v : e) mean += v / static_cast<double>(e.size());
  for (double v : e) ss += (v - mean) * (v - mean);
  return std::sqrt(ss / static_cast<double>(e.size()));
}

// The dT/dt term's paired gain over the cubic alone, each group held out in turn (both models
// fitted on the other groups; term_admission.h Eqs. A-1..A-3); groups whose held-out fit fails
// are left out of the pairs.
TermGain RateTermGain(const std::vector<double>& temp_c, const std::vector<double>& y,
                      const std::vector<std::size_t>& group, std::size_t num_groups, double ref_temp_c,
                      const std::vector<double>& rate_c_per_s) {
  std::vector<double> simpler, richer;
  for (std::size_t g = 0; g < num_groups; ++g) {
    std::vector<std::size_t> held;
    std::vector<double> t, v, r;
    std::vector<std::size_t> gr;
    for (std::size_t i = 0; i < temp_c.size(); ++i) {
      if (group[i] == g) {
        held.push_back(i);
        continue;
      }
      t.push_back(temp_c[i]), v.push_back(y[i]), r.push_back(rate_c_per_s[i]), gr.push_back(group[i]);
    }
    if (held.size() < 2) continue;
    Result<PooledCubic> a = FitWeighted(t, v, gr, num_groups, ref_temp_c, {}, {});
    Result<PooledCubic> b = FitWeighted(t, v, gr, num_groups, ref_temp_c, r, {});
    if (!a.ok() || !b.ok()) continue;
    simpler.push_back(HeldOutRms(*a, temp_c, y, rate_c_per_s, held));
    richer.push_back(HeldOutRms(*b, temp_c, y, rate_c_per_s, held));
  }
  return PairedTermGain(simpler, richer);
}

}  // namespace

std::vector<double> PooledGroupHeldOutRms(const std::vector<double>& temp_c, const std::vector<double>& y,
                                          const std::vector<std::size_t>& group, std::size_t num_groups, double ref_temp_c) {
  std::vector<double> out(num_groups, NAN);
  if (y.size() != temp_c.size() || group.size() != temp_c.size()) return out;
  std::vector<std::vector<std::size_t>> rows(num_groups);
  for (std::size_t i = 0; i < group.size(); ++i)
    if (group[i] < num_groups) rows[group[i]].push_back(i);
  for (std::size_t g = 0; g < num_groups; ++g) {
    if (rows[g].size() < 2) continue;
    std::vector<double> t, v;
    std::vector<std::size_t> gr;
    for (std::size_t i = 0; i < temp_c.size(); ++i)
      if (group[i] != g) t.push_back(temp_c[i]), v.push_back(y[i]), gr.push_back(group[i]);
    Result<PooledCubic> f = FitWeighted(t, v, gr, num_groups, ref_temp_c, {}, {});
    if (f.ok()) out[g] = HeldOutRms(*f, temp_c, y, {}, rows[g]);
  }
  return out;
}

Result<PooledCubic> FitPooledCubic(const std::vector<double>& temp_c, const std::vector<double>& y,
                                   const std::vector<std::size_t>& group, std::size_t num_groups, double ref_temp_c,
                                   const std::vector<double>& rate_c_per_s) {
  Result<PooledCubic> fit = FitWeighted(temp_c, y, group, num_groups, ref_temp_c, rate_c_per_s, {});
  if (!fit.ok() || !fit->rate_used) return fit;
  // The dT/dt term is identified; it stays only when it earns its place (Eq. A-4: its paired
  // held-out gain beats its standard error), as the default drift model admits a term.
  const TermGain gain = RateTermGain(temp_c, y, group, num_groups, ref_temp_c, rate_c_per_s);
  if (!gain.Admitted()) fit = FitWeighted(temp_c, y, group, num_groups, ref_temp_c, {}, {});
  if (fit.ok()) fit->rate_term = gain;
  return fit;
}

}  // namespace gyrocomp
