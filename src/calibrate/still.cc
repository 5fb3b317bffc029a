// DetectStill (gyrocomp/calibrate/still.h).
#include "gyrocomp/calibrate/still.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "gyrocomp/core/format.h"

namespace gyrocomp {
namespace {

enum Why : unsigned { kArmed = 1, kMotion = 2, kTurning = 4, kMargin = 8, kShort = 16, kInAir = 32 };

struct Window {
  std::size_t begin = 0, end = 0;
  double gyro_ms = 0.0, accel_ms = 0.0;  // mean squared deviation per axis
  double mean_rate_rad_s = 0.0;
  bool armed = false;  // the log says armed at a sample of the window
  bool in_air = false;  // the log's landed state says not landed at a sample of the window
};

std::vector<Window> Windows(const std::array<std::vector<double>, 3>& g, const std::array<std::vector<double>, 3>& a,
                            const StillLogState& state, std::size_t w) {
  std::vector<Window> out;
  const std::size_t n = g[0].size();
  for (std::size_t b = 0; b < n; b += w) {
    Window win;
    win.begin = b, win.end = std::min(n, b + w);
    const double m = static_cast<double>(win.end - win.begin);
    double rate2 = 0.0;
    for (int ax = 0; ax < 3; ++ax) {
      double sg = 0.0, sa = 0.0;
      for (std::size_t i = win.begin; i < win.end; ++i) sg += g[ax][i], sa += a[ax][i];
      const double mg = sg / m, ma = sa / m;
      rate2 += mg * mg;
      for (std::size_t i = win.begin; i < win.end; ++i)
        win.gyro_ms += (g[ax][i] - mg) * (g[ax][i] - mg), win.accel_ms += (a[ax][i] - ma) * (a[ax][i] - ma);
    }
    win.gyro_ms /= 3.0 * m, win.accel_ms /= 3.0 * m;
    win.mean_rate_rad_s = std::sqrt(rate2);
    for (std::size_t i = win.begin; i < win.end; ++i) {
      if (!state.armed.empty()) win.armed = win.armed || state.armed[i];
      if (!state.in_air.empty()) win.in_air = win.in_air || state.in_air[i];
    }
    out.push_back(win);
  }
  return out;
}

// The p-quantile of v (nearest rank).
double Quantile(std::vector<double> v, double p) {
  const auto k = static_cast<std::size_t>(std::floor(p * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// The 5th percentile of a chi-square with nu degrees of freedom over its mean, nu (Wilson &
// Hilferty 1931: chi2_p / nu ~ (1 - 2 / (9 nu) + z_p sqrt(2 / (9 nu)))^3, z_0.05 = -1.645). The
// quietest 5 % of still windows read this much below the true noise variance: 0.60 with 1 s
// windows at 10 Hz (nu = 27), 0.82 at 50 Hz (nu = 147); without this, a slow log's noise is
// underestimated and its ordinary windows pass the threshold.
double FifthPercentileOverMean(double nu) {
  const double v = 2.0 / (9.0 * nu);
  return std::pow(std::max(1.0 - v - 1.645 * std::sqrt(v), 0.05), 3);
}

}  // namespace

bool StillDetectorOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = "StillDetectorOptions::" + m;
    return false;
  };
  if (!(window_s > 0.0)) return fail("window_s = " + FormatNumber(window_s, 4) + ": must be > 0 s");
  if (!(threshold > 0.0)) return fail("threshold = " + FormatNumber(threshold, 4) + ": must be > 0");
  if (!(margin_s >= 0.0)) return fail("margin_s: must be >= 0 s");
  if (!(min_segment_s >= 0.0)) return fail("min_segment_s: must be >= 0 s");
  if (!(max_mean_rate_dps > 0.0)) return fail("max_mean_rate_dps: must be > 0");
  if (gyro_noise_rad_s && !(*gyro_noise_rad_s > 0.0)) return fail("gyro_noise_rad_s: must be > 0");
  if (accel_noise_m_s2 && !(*accel_noise_m_s2 > 0.0)) return fail("accel_noise_m_s2: must be > 0");
  return true;
}

Result<StillDetection> DetectStill(const std::vector<double>& time_s, const std::array<std::vector<double>, 3>& gyro_rad_s,
                                   const std::array<std::vector<double>, 3>& accel_m_s2, const std::vector<double>& temp_c,
                                   const StillLogState& state, const StillDetectorOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  const std::size_t n = time_s.size();
  if (n < 2) return InvalidInput("DetectStill: fewer than 2 samples");
  for (int ax = 0; ax < 3; ++ax)
    if (gyro_rad_s[ax].size() != n || accel_m_s2[ax].size() != n)
      return InvalidInput("DetectStill: gyro and accel columns must be as long as time_s");
  if ((!temp_c.empty() && temp_c.size() != n) || (!state.armed.empty() && state.armed.size() != n) ||
      (!state.in_air.empty() && state.in_air.size() != n))
    return InvalidInput("DetectStill: temp_c, state.armed and state.in_air must be empty or as long as time_s");
  const double fs = static_cast<double>(n - 1) / (time_s.back() - time_s.front());
  if (!(fs > 0.0)) return InvalidInput("DetectStill: time_s must increase");
  const auto w = static_cast<std::size_t>(std::max(2.0, std::round(o.window_s * fs)));
  const std::vector<Window> wins = Windows(gyro_rad_s, accel_m_s2, state, w);
  StillDetection d;
  // The sensor's own noise: the quietest windows of the log (disarmed, landed ones when the log says).
  std::vector<double> gq, aq;
  for (const Window& win : wins)
    if (!win.armed && !win.in_air && win.end - win.begin == w) gq.push_back(win.gyro_ms), aq.push_back(win.accel_ms);
  if (gq.empty())
    for (const Window& win : wins) gq.push_back(win.gyro_ms), aq.push_back(win.accel_ms);
  // Per window and sensor, 3 axes of w - 1 degrees of freedom each (the window's mean removed).
  const double bias = FifthPercentileOverMean(3.0 * static_cast<double>(w - 1));
  d.gyro_noise_rad_s = o.gyro_noise_rad_s.value_or(std::sqrt(std::max(Quantile(gq, 0.05) / bias, 1e-30)));
  d.accel_noise_m_s2 = o.accel_noise_m_s2.value_or(std::sqrt(std::max(Quantile(aq, 0.05) / bias, 1e-30)));
  const double sg2 = d.gyro_noise_rad_s * d.gyro_noise_rad_s, sa2 = d.accel_noise_m_s2 * d.accel_noise_m_s2;
  const double max_rate = o.max_mean_rate_dps * std::numbers::pi / 180.0;
  std::vector<unsigned> reason(n, 0);
  std::vector<double> stat(n, 0.0);
  for (const Window& win : wins) {
    const double t = 0.5 * (win.gyro_ms / sg2 + win.accel_ms / sa2);  // Skog et al. (2010): T ~ 1 still
    unsigned r = 0;
    if (win.armed) r |= kArmed;
    if (win.in_air) r |= kInAir;
    if (t > o.threshold) r |= kMotion;
    if (win.mean_rate_rad_s > max_rate) r |= kTurning;
    for (std::size_t i = win.begin; i < win.end; ++i) reason[i] = r, stat[i] = t;
  }
  // The margin: samples within margin_s of a motion sample.
  const auto margin = static_cast<std::size_t>(std::ceil(o.margin_s * fs));
  std::vector<unsigned> widened = reason;
  for (std::size_t i = 0; i < n; ++i) {
    if (!reason[i] || (i > 0 && reason[i - 1] && i + 1 < n && reason[i + 1])) continue;
    const std::size_t lo = i > margin ? i - margin : 0, hi = std::min(n - 1, i + margin);
    for (std::size_t j = lo; j <= hi; ++j)
      if (!widened[j]) widened[j] = kMargin;
  }
  // Still runs shorter than min_segment_s.
  d.still.assign(n, false);
  for (std::size_t i = 0; i < n;) {
    if (widened[i]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < n && !widened[j]) ++j;
    const double len = (time_s[j - 1] - time_s[i]) + 1.0 / fs;
    if (len < o.min_segment_s) {
      for (std::size_t k = i; k < j; ++k) widened[k] = kShort;
    } else {
      StillSegment s;
      s.start_s = time_s[i], s.length_s = len;
      if (!temp_c.empty()) {
        const auto [lo, hi] = std::minmax_element(temp_c.begin() + static_cast<std::ptrdiff_t>(i), temp_c.begin() + static_cast<std::ptrdiff_t>(j));
        s.temp_min_c = *lo, s.temp_max_c = *hi;
      }
      for (std::size_t k = i; k < j; ++k) d.still[k] = true;
      d.segments.push_back(s);
      d.still_s += len;
    }
    i = j;
  }
  // The rejected parts, each with the reasons found in it.
  for (std::size_t i = 0; i < n;) {
    if (d.still[i]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    unsigned all = 0;
    double t_max = 0.0;
    while (j < n && !d.still[j]) all |= widened[j], t_max = std::max(t_max, stat[j]), ++j;
    std::vector<std::string> parts;
    if (all & kArmed) parts.push_back("armed");
    if (all & kInAir) parts.push_back("in the air (log's landed state)");
    if (all & kMotion) parts.push_back("motion (T up to " + FormatNumber(t_max, 3) + ", threshold " + FormatNumber(o.threshold, 3) + ")");
    if (all & kTurning) parts.push_back("turning (mean rate > " + FormatNumber(o.max_mean_rate_dps, 3) + " deg/s)");
    if (all & kMargin) parts.push_back("margin " + FormatNumber(o.margin_s, 3) + " s around motion");
    if (all & kShort) parts.push_back("still for less than " + FormatNumber(o.min_segment_s, 3) + " s");
    RejectedPart p;
    p.start_s = time_s[i], p.length_s = (time_s[j - 1] - time_s[i]) + 1.0 / fs;
    for (const std::string& s : parts) p.reason += (p.reason.empty() ? "" : "; ") + s;
    d.rejected.push_back(p);
    i = j;
  }
  d.total_s = (time_s.back() - time_s.front()) + 1.0 / fs;
  return d;
}

std::string StillDetection::BriefReport() const {
  std::string t = FormatNumber(still_s, 4) + " s still of " + FormatNumber(total_s, 4) + " s in " +
                  std::to_string(segments.size()) + " segment(s)";
  for (const StillSegment& s : segments)
    t += "\n  still " + FormatNumber(s.start_s, 5) + " s + " + FormatNumber(s.length_s, 4) + " s, " +
         FormatNumber(s.temp_min_c, 4) + ".." + FormatNumber(s.temp_max_c, 4) + " C";
  for (const RejectedPart& p : rejected)
    t += "\n  rejected " + FormatNumber(p.start_s, 5) + " s + " + FormatNumber(p.length_s, 4) + " s: " + p.reason;
  return t;
}

}  // namespace gyrocomp
