// Noise terms read off an Allan curve (ARW, bias instability, RRW) and the support each needs
// (paper Section 4.3.1, method.md section 6; include/gyrocomp/allan/allan.h, ExtractNoiseTerms).
// A term the curve cannot carry is null with its reason key, never projected past the record.
#include "gyrocomp/allan/allan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "gyrocomp/core/units.h"

namespace gyrocomp {
namespace {

// Log-log interpolation of the curve at tau (tau inside [tau_s.front(), tau_s.back()]).
double InterpolateLogLog(const AllanCurve& c, double tau, bool* on_grid) {
  for (std::size_t j = 0; j < c.size(); ++j) {
    if (std::abs(c.tau_s[j] - tau) <= 1e-9 * tau) {
      *on_grid = true;
      return c.adev_dps[j];
    }
  }
  *on_grid = false;
  const auto it = std::upper_bound(c.tau_s.begin(), c.tau_s.end(), tau);
  const std::size_t j = static_cast<std::size_t>(it - c.tau_s.begin());  // tau_s[j-1] < tau < tau_s[j]
  const double f = std::log(tau / c.tau_s[j - 1]) / std::log(c.tau_s[j] / c.tau_s[j - 1]);
  const double lo = c.adev_dps[j - 1], hi = c.adev_dps[j];
  // A zero deviation (a constant or quantised record) has no logarithm: interpolate linearly in
  // log tau instead, which keeps the result finite and 0 between two zeros.
  if (!(lo > 0.0) || !(hi > 0.0)) return lo + f * (hi - lo);
  return std::exp(std::log(lo) + f * std::log(hi / lo));
}


}  // namespace

namespace {

std::string FormatTau(double tau_s) {
  std::ostringstream os;
  os.precision(4);
  os << tau_s << " s";
  return os.str();
}

// The record length (s) whose overlapping ADEV reaches tau: m = tau fs needs N >= 2 m + 1 samples
// (n = N + 1 - 2m >= 2 terms, as allantools keeps), i.e. (N - 1) / fs >= 2 tau.
double RecordForTau(double tau_s) { return 2.0 * tau_s; }

// AllanNoiseTerms::unsupported (see allan.h for the minimums).
void MarkUnsupported(const AllanCurve& c, const AllanOptions& options, bool usable_qualified, std::size_t jmin,
                     AllanNoiseTerms* t) {
  auto mark = [&](const char* key, std::string reason, std::string text, std::optional<double> needs = std::nullopt) {
    t->unsupported.try_emplace(key, AllanNoiseTerms::Unsupported{std::move(reason), std::move(text), needs});
  };
  const bool all_zero = std::all_of(c.adev_dps.begin(), c.adev_dps.end(), [](double a) { return a == 0.0; });
  const double dt = c.m.empty() || c.m.front() <= 0 ? 0.0 : c.tau_s.front() / static_cast<double>(c.m.front());
  if (c.size() < kMinTausForMinimum) {
    // Octave grid: the third tau is 4 samples; 2 * 4 + 1 samples reach it.
    const std::string text = std::to_string(c.size()) + " tau" + (c.size() == 1 ? "" : "s") + ", a minimum needs " +
                             std::to_string(kMinTausForMinimum) + " (at least 9 samples)";
    const std::optional<double> needs = dt > 0 ? std::optional<double>(8.0 * dt) : std::nullopt;
    mark("adev_min_deg_per_h", "fewer_than_3_taus", text, needs);
    mark("bias_instability_deg_per_h", "fewer_than_3_taus", text, needs);
  }
  const bool have_edf = c.edf.size() == c.size();
  if (have_edf && !usable_qualified) {
    std::ostringstream text;
    text << "no tau has EDF >= " << options.min_edf_for_terms << " (largest EDF "
         << (c.edf.empty() ? 0.0 : *std::max_element(c.edf.begin(), c.edf.end())) << ")";
    for (const char* key : {"adev_min_usable_deg_per_h", "arw_deg_per_sqrt_h", "arw_fit_deg_per_sqrt_h",
                            "rrw_deg_per_h_per_sqrt_h"}) {
      mark(key, "no_tau_with_edf_ge_min_edf", text.str());
    }
  }
  if (!t->arw_deg_per_sqrt_h) {
    mark("arw_deg_per_sqrt_h", "record_too_short_for_tau", "sigma(" + FormatTau(options.arw_tau_s) + ") is past the record",
         RecordForTau(options.arw_tau_s));
  }
  if (all_zero) return;  // a constant record: ARW and RRW are known to be 0 (set above)
  // The -1/2 fit region: usable taus up to the minimum with slope -1/2.
  std::size_t arw_taus = 0, rrw_taus = 0;
  for (std::size_t j = 0; j < c.size(); ++j) {
    const bool usable = !have_edf || !usable_qualified || c.edf[j] >= options.min_edf_for_terms;
    if (!usable) continue;
    if (j <= jmin && std::abs(c.slope[j] + 0.5) <= options.slope_tolerance) ++arw_taus;
    if (j > jmin && std::abs(c.slope[j] - 0.5) <= options.slope_tolerance) ++rrw_taus;
  }
  if (t->arw_fit_deg_per_sqrt_h && arw_taus < kMinTausForFit) {
    mark("arw_fit_deg_per_sqrt_h", "fit_over_fewer_than_2_taus",
         "the -1/2 region has " + std::to_string(arw_taus) + " tau, a fit needs " + std::to_string(kMinTausForFit));
  }
  if (!t->arw_fit_deg_per_sqrt_h) {
    mark("arw_fit_deg_per_sqrt_h", "no_minus_half_region", "no -1/2 region: no usable tau before the minimum has a slope near -1/2");
  }
  if (!t->rrw_deg_per_h_per_sqrt_h) {
    mark("rrw_deg_per_h_per_sqrt_h", "no_plus_half_region", "no +1/2 region: no usable tau after the minimum has a slope near +1/2");
  } else {
    if (rrw_taus < kMinTausForFit) {
      mark("rrw_deg_per_h_per_sqrt_h", "fit_over_fewer_than_2_taus",
           "the +1/2 region has " + std::to_string(rrw_taus) + " tau, a fit needs " + std::to_string(kMinTausForFit));
    } else if (options.rrw_tau_s > c.tau_s.back() * (1.0 + 1e-9)) {
      mark("rrw_deg_per_h_per_sqrt_h", "record_too_short_for_tau",
           "sigma(" + FormatTau(options.rrw_tau_s) + ") is past the longest tau " + FormatTau(c.tau_s.back()),
           RecordForTau(options.rrw_tau_s));
    }
  }
}

}  // namespace

AllanNoiseTerms ExtractNoiseTerms(const AllanCurve& c, const AllanOptions& options) {
  AllanNoiseTerms t;
  if (c.size() == 0) return t;
  const double tol = options.slope_tolerance;

  // Minimum ("bias stability") of the whole curve, and B = min / 0.664 (IEEE 952 flicker floor).
  std::size_t jall = 0;
  for (std::size_t j = 1; j < c.size(); ++j) {
    if (c.adev_dps[j] < c.adev_dps[jall]) jall = j;
  }
  t.adev_min_deg_per_h = units::DpsToDph(c.adev_dps[jall]);
  t.tau_at_min_s = c.tau_s[jall];
  t.min_at_longest_tau = jall + 1 == c.size();
  t.bias_instability_deg_per_h = t.adev_min_deg_per_h / 0.664;

  // The EDF-qualified minimum, which also anchors the fits: only taus with at least min_edf
  // degrees of freedom (all taus when none qualifies, or when the curve carries no EDFs). The
  // last octaves of a record have a handful of degrees of freedom and their random dips would
  // pass for a minimum or bend a fit.
  const bool have_edf = c.edf.size() == c.size();
  std::vector<std::size_t> usable;
  for (std::size_t j = 0; j < c.size(); ++j) {
    if (!have_edf || c.edf[j] >= options.min_edf_for_terms) usable.push_back(j);
  }
  const bool usable_qualified = !usable.empty();
  if (usable.empty()) {
    for (std::size_t j = 0; j < c.size(); ++j) usable.push_back(j);
  }
  std::size_t jmin = usable.front();
  for (std::size_t j : usable) {
    if (c.adev_dps[j] < c.adev_dps[jmin]) jmin = j;
  }
  t.min_edf = options.min_edf_for_terms;
  t.num_taus_used = usable.size();
  t.adev_min_usable_deg_per_h = units::DpsToDph(c.adev_dps[jmin]);
  t.tau_at_min_usable_s = c.tau_s[jmin];
  t.min_usable_at_longest_usable_tau = jmin == usable.back();

  // ARW: sigma(arw_tau) read off the curve, N = sigma(tau) sqrt(tau) (method.md 6).
  const double ta = options.arw_tau_s;
  std::optional<double> sigma_a;
  if (ta < c.tau_s.front() * (1.0 - 1e-9)) {
    sigma_a = c.adev_dps.front() * std::sqrt(c.tau_s.front() / ta);  // along -1/2
    t.arw_method = "extrapolated along -1/2";
  } else if (ta <= c.tau_s.back() * (1.0 + 1e-9)) {
    bool on_grid = false;
    sigma_a = InterpolateLogLog(c, std::min(ta, c.tau_s.back()), &on_grid);
    t.arw_method = on_grid ? "on grid" : "log-log interpolation";
  }
  if (sigma_a) {
    t.arw_deg_per_sqrt_h = units::DegPerSqrtSecToDegPerSqrtHour(*sigma_a * std::sqrt(ta));
  }

  // Second ARW: fit of the -1/2 line over the white-rate region before the minimum.
  // Weighted by 2 EDF, the inverse variance of ln(sigma) (unweighted when there are no EDFs): the
  // long-tau points carry few degrees of freedom and, near the minimum, a downward bias.
  auto weight = [&](std::size_t j) { return have_edf ? 2.0 * c.edf[j] : 1.0; };
  double sum = 0.0, wsum = 0.0;
  for (std::size_t j : usable) {
    if (j <= jmin && std::abs(c.slope[j] + 0.5) <= tol) {
      sum += weight(j) * (std::log(c.adev_dps[j]) + 0.5 * std::log(c.tau_s[j]));  // ln N
      wsum += weight(j);
    }
  }
  if (wsum > 0.0) t.arw_fit_deg_per_sqrt_h = units::DegPerSqrtSecToDegPerSqrtHour(std::exp(sum / wsum));

  // RRW: fit of the +1/2 line sigma = K sqrt(tau / rrw_tau) after the minimum; K = sigma(rrw_tau).
  sum = 0.0;
  wsum = 0.0;
  for (std::size_t j : usable) {
    if (j > jmin && std::abs(c.slope[j] - 0.5) <= tol) {
      sum += weight(j) * (std::log(c.adev_dps[j]) - 0.5 * std::log(c.tau_s[j] / options.rrw_tau_s));  // ln K
      wsum += weight(j);
      if (!t.rrw_fit_tau_min_s) t.rrw_fit_tau_min_s = c.tau_s[j];
      t.rrw_fit_tau_max_s = c.tau_s[j];
    }
  }
  // A rate with no noise at all (every ADEV exactly 0: a constant record) has no -1/2 or +1/2
  // region to fit, but its white and random-walk terms are known: 0 (not null).
  const bool all_zero = std::all_of(c.adev_dps.begin(), c.adev_dps.end(), [](double a) { return a == 0.0; });
  if (all_zero) {
    t.arw_fit_deg_per_sqrt_h = 0.0;
    t.rrw_deg_per_h_per_sqrt_h = 0.0;
  }
  if (wsum > 0.0) {
    // K in deg/s/sqrt(s) (numerically sigma(3 s) in deg/s for rrw_tau = 3 s) -> deg/h/sqrt(h).
    const double k_dps_per_sqrt_s = std::exp(sum / wsum) / std::sqrt(options.rrw_tau_s / 3.0);
    t.rrw_deg_per_h_per_sqrt_h = units::DpsPerSqrtSecToDphPerSqrtHour(k_dps_per_sqrt_s);
  }
  MarkUnsupported(c, options, usable_qualified, jmin, &t);
  return t;
}

}  // namespace gyrocomp
