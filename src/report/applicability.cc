#include "gyrocomp/report/applicability.h"

#include <cmath>
#include <cstdio>

namespace gyrocomp {
namespace {

std::string Format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

// Clauses 1-3 of the rule (applicability.h) for a term read over [tau_lo, tau_hi].
TermApplicability Check(const AllanCurve& curve, std::optional<double> bandwidth_hz, double tau_lo,
                        double tau_hi, double nominal, const char* term, const TermApplicabilityOptions& o) {
  TermApplicability t;
  t.tau_min_s = tau_lo;
  t.tau_max_s = tau_hi;
  t.fitted_slope = FittedLogLogSlope(curve, tau_lo, tau_hi);
  if (!bandwidth_hz || !(*bandwidth_hz > 0.0)) {
    t.reason = std::string(term) + " without the record's bandwidth is not comparable (bandwidth not measured)";
    return t;
  }
  const double band_period_s = 1.0 / (2.0 * *bandwidth_hz);  // clause 2: the band's sampling period
  if (tau_lo < band_period_s * (1.0 - 1e-9)) {  // 1e-9: tau grids are m / fs, rounding at equality
    t.reason = std::string(term) + Format(" is read over taus from %.3g s, below 1/(2 bandwidth) = %.3g s (bandwidth "
                                          "%.3g Hz): there the ADEV shows the processing's low-pass, not the sensor",
                                          tau_lo, band_period_s, *bandwidth_hz);
    return t;
  }
  if (!t.fitted_slope) {
    t.reason = std::string(term) + " has fewer than two taus to fit a slope on";
    return t;
  }
  if (std::abs(*t.fitted_slope - nominal) > o.slope_tolerance) {
    t.reason = std::string(term) + Format(": the ADEV slope there is %+.2f, not %+.1f within %.2f", *t.fitted_slope,
                                          nominal, o.slope_tolerance);
    return t;
  }
  t.applicable = true;
  return t;
}

}  // namespace

bool TermApplicabilityOptions::IsValid(std::string* error) const {
  std::string e;
  if (!(slope_tolerance > 0.0 && slope_tolerance < 0.5)) e = "slope_tolerance must be in (0, 0.5)";
  else if (!(arw_tau_span >= 1.0) || !std::isfinite(arw_tau_span)) e = "arw_tau_span must be >= 1";
  else if (!(arw_tau_s > 0.0) || !std::isfinite(arw_tau_s)) e = "arw_tau_s must be > 0";
  if (error) *error = e;
  return e.empty();
}

std::optional<double> FittedLogLogSlope(const AllanCurve& curve, double tau_lo, double tau_hi) {
  // Ordinary least squares of y = ln adev on x = ln tau.
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double eps = 1e-9;  // tau grids are m / fs: allow rounding at the ends
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const double tau = curve.tau_s[i], adev = curve.adev_dps[i];
    if (tau < tau_lo * (1 - eps) || tau > tau_hi * (1 + eps) || !(adev > 0.0)) continue;
    const double x = std::log(tau), y = std::log(adev);
    n += 1; sx += x; sy += y; sxx += x * x; sxy += x * y;
  }
  const double den = n * sxx - sx * sx;
  if (n < 2 || !(std::abs(den) > 0.0)) return std::nullopt;
  return (n * sxy - sx * sy) / den;
}

TermApplicability ArwApplicability(const AllanResult& allan, std::optional<double> bandwidth_hz,
                                   const TermApplicabilityOptions& o) {
  if (!allan.terms.arw_deg_per_sqrt_h) {
    TermApplicability t;
    t.reason = "ARW: tau = 1 s is beyond the curve";
    return t;
  }
  return Check(allan.curve, bandwidth_hz, o.arw_tau_s / o.arw_tau_span, o.arw_tau_s * o.arw_tau_span, -0.5, "ARW", o);
}

TermApplicability RrwApplicability(const AllanResult& allan, std::optional<double> bandwidth_hz,
                                   const TermApplicabilityOptions& o) {
  const AllanNoiseTerms& terms = allan.terms;
  if (!terms.rrw_deg_per_h_per_sqrt_h || !terms.rrw_fit_tau_min_s || !terms.rrw_fit_tau_max_s) {
    TermApplicability t;
    t.reason = "RRW: the curve has no +1/2 region";
    return t;
  }
  return Check(allan.curve, bandwidth_hz, *terms.rrw_fit_tau_min_s, *terms.rrw_fit_tau_max_s, 0.5, "RRW", o);
}

}  // namespace gyrocomp
