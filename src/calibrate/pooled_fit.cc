// FitPooledCubic (gyrocomp/calibrate/pooled_fit.h).
#include "gyrocomp/calibrate/pooled_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace gyrocomp {
namespace {

using Vec = std::vector<double>;
using Mat = std::vector<Vec>;

// Eq. P-1's window: a quarter of a group's rows (the cubic's three shape terms change over a
// group's temperature change; the window must span the noise's correlation at that scale).
constexpr double kHacWindowFraction = 0.25;

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

// Eq. P-1: the score covariance S of the coefficients, summed per group over windows of a quarter
// of its rows (kHacWindowFraction): the rows' noise is mostly slow (flicker, random walk), so the
// scores d_i e_i are summed over a window before their outer products are taken, not row by row.
// column(i): row i's columns; mx: each group's mean columns; c: the fitted coefficients.
template <class Column>
Mat HacScoreCovariance(const Column& column, std::size_t m, const std::vector<double>& y,
                       const std::vector<std::size_t>& group, std::size_t num_groups, const Mat& mx,
                       const Vec& group_constant, const Vec& c, const std::vector<double>& group_weight) {
  const std::size_t n = y.size();
  Mat S(m, Vec(m, 0.0));
  std::vector<std::vector<std::size_t>> rows_of(num_groups);
  for (std::size_t i = 0; i < n; ++i) rows_of[group[i]].push_back(i);
  for (std::size_t g = 0; g < num_groups; ++g) {
    const std::size_t rows = rows_of[g].size();
    if (rows < 2) continue;
    const std::size_t window = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(kHacWindowFraction * static_cast<double>(rows))));
    std::vector<Vec> prefix(rows + 1, Vec(m, 0.0));  // prefix sums of the scores
    for (std::size_t r = 0; r < rows; ++r) {
      const std::size_t i = rows_of[g][r];
      const Vec x = column(i);
      double e = y[i] - group_constant[g];
      for (std::size_t k = 0; k < m; ++k) e -= c[k] * x[k];
      const double w = group_weight.empty() ? 1.0 : group_weight[g];
      for (std::size_t k = 0; k < m; ++k) prefix[r + 1][k] = prefix[r][k] + w * (x[k] - mx[g][k]) * e;
    }
    // Eq. P-1: S_g = n_g / (n_g - B + 1) (1 / B) sum_t W_t W_t', W_t the scores' sum over rows t..t+B-1.
    const double scale = static_cast<double>(rows) / static_cast<double>(rows - window + 1) / static_cast<double>(window);
    for (std::size_t t = 0; t + window <= rows; ++t)
      for (std::size_t j = 0; j < m; ++j)
        for (std::size_t k = 0; k < m; ++k)
          S[j][k] += scale * (prefix[t + window][j] - prefix[t][j]) * (prefix[t + window][k] - prefix[t][k]);
  }
  return S;
}

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
  double ss = 0.0;
  out.group_residual_ms.assign(num_groups, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec x = column(i);
    double e = y[i] - out.group_constant[group[i]];
    for (std::size_t k = 0; k < m; ++k) e -= c[k] * x[k];
    ss += e * e;
    out.group_residual_ms[group[i]] += e * e / static_cast<double>(out.group_rows[group[i]]);
  }
  out.residual_rms = std::sqrt(ss / static_cast<double>(n));
  // The curve's 1 sigma at dT/dt = 0 from the coefficients' HAC covariance (Eq. P-1).
  const Mat S = HacScoreCovariance(column, m, y, group, num_groups, mx, out.group_constant, c, group_weight);
  constexpr int kPoints = 101;
  Mat grid;
  Vec xbar(m, 0.0);
  for (int i = 0; i < kPoints; ++i) {
    const double t = *lo + (*hi - *lo) * i / (kPoints - 1), u = (t - ref_temp_c) / s;
    grid.push_back({u, u * u, u * u * u});
    if (m == 4) grid.back().push_back(0.0);
    for (std::size_t k = 0; k < m; ++k) xbar[k] += grid.back()[k] / kPoints;
  }
  // Var(x(T)'c) = x(T)' A^-1 S A^-1 x(T) (Eq. P-1's sandwich), x(T) centred on the range's mean
  // column (the constant is the boot calibration's), RMS over 101 temperatures.
  double var_sum = 0.0;
  for (const Vec& x : grid) {
    Vec d(m), w;
    for (std::size_t k = 0; k < m; ++k) d[k] = x[k] - xbar[k];
    if (!Solve(A, d, &w)) break;
    for (std::size_t j = 0; j < m; ++j)
      for (std::size_t k = 0; k < m; ++k) var_sum += w[j] * S[j][k] * w[k];
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

// Sets fit->curve_sd to the larger of its HAC value (Eq. P-1) and the delete-one-group jackknife
// of the curve (Eq. P-2); unchanged when fewer than two groups can be left out.
static void JackknifeCurveSd(PooledCubic* fit, const std::vector<double>& temp_c, const std::vector<double>& y,
                      const std::vector<std::size_t>& group, std::size_t num_groups, const std::vector<double>& rate_c_per_s);

Result<PooledCubic> FitPooledCubic(const std::vector<double>& temp_c, const std::vector<double>& y,
                                   const std::vector<std::size_t>& group, std::size_t num_groups, double ref_temp_c,
                                   const std::vector<double>& rate_c_per_s) {
  Result<PooledCubic> fit = FitWeighted(temp_c, y, group, num_groups, ref_temp_c, rate_c_per_s, {});
  if (fit.ok() && !fit->rate_used) JackknifeCurveSd(&*fit, temp_c, y, group, num_groups, rate_c_per_s);
  if (!fit.ok() || !fit->rate_used) return fit;
  // The dT/dt term is identified; it stays only when it earns its place (Eq. A-4: its paired
  // held-out gain beats its standard error), as the default drift model admits a term.
  const TermGain gain = RateTermGain(temp_c, y, group, num_groups, ref_temp_c, rate_c_per_s);
  if (!gain.Admitted()) fit = FitWeighted(temp_c, y, group, num_groups, ref_temp_c, {}, {});
  if (fit.ok()) {
    fit->rate_term = gain;
    JackknifeCurveSd(&*fit, temp_c, y, group, num_groups, rate_c_per_s);
  }
  return fit;
}

namespace {

// The centred curve c1 dT + c2 dT^2 + c3 dT^3 at 101 temperatures over [lo, hi], mean removed.
std::vector<double> CentredCurve(const PooledCubic& f, double lo, double hi) {
  constexpr int kPoints = 101;
  std::vector<double> v(kPoints);
  double mean = 0.0;
  for (int i = 0; i < kPoints; ++i) {
    const double u = lo + (hi - lo) * i / (kPoints - 1) - f.ref_temp_c;
    v[static_cast<std::size_t>(i)] = f.slope[0] * u + f.slope[1] * u * u + f.slope[2] * u * u * u;
    mean += v[static_cast<std::size_t>(i)] / kPoints;
  }
  for (double& x : v) x -= mean;
  return v;
}

}  // namespace

static void JackknifeCurveSd(PooledCubic* fit, const std::vector<double>& temp_c, const std::vector<double>& y,
                      const std::vector<std::size_t>& group, std::size_t num_groups, const std::vector<double>& rate_c_per_s) {
  if (temp_c.empty()) return;
  const auto [lo, hi] = std::minmax_element(temp_c.begin(), temp_c.end());
  std::vector<std::vector<double>> curves;
  for (std::size_t g = 0; g < num_groups; ++g) {
    if (g >= fit->group_rows.size() || fit->group_rows[g] == 0) continue;
    std::vector<double> t, v, r;
    std::vector<std::size_t> gr;
    for (std::size_t i = 0; i < temp_c.size(); ++i) {
      if (group[i] == g) continue;
      t.push_back(temp_c[i]), v.push_back(y[i]), gr.push_back(group[i]);
      if (fit->rate_used) r.push_back(rate_c_per_s[i]);
    }
    if (t.size() < 8) return;  // a group the others cannot do without: no jackknife
    Result<PooledCubic> f = FitWeighted(t, v, gr, num_groups, fit->ref_temp_c, r, {});
    if (!f.ok()) return;
    curves.push_back(CentredCurve(*f, *lo, *hi));
  }
  const std::size_t G = curves.size();
  if (G < 2) return;
  // Eq. P-2: V(T) = (G - 1) / G sum_g (f_(g)(T) - mean_g f_(g)(T))^2, RMS over the temperatures.
  double var_sum = 0.0;
  for (std::size_t i = 0; i < curves[0].size(); ++i) {
    double mean = 0.0, ss = 0.0;
    for (const auto& c : curves) mean += c[i] / static_cast<double>(G);
    for (const auto& c : curves) ss += (c[i] - mean) * (c[i] - mean);
    var_sum += static_cast<double>(G - 1) / static_cast<double>(G) * ss / static_cast<double>(curves[0].size());
  }
  // Eq. P-3: the larger of the two (the jackknife of two or three groups has one or two degrees
  // of freedom and may fall far below the spread inside the groups by chance).
  fit->curve_sd = std::max(fit->curve_sd, std::sqrt(var_sum));
}

}  // namespace gyrocomp
