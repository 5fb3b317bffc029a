// Several logs of one board (calibrate.h, CalibrateLogs): each log read with the still detector
// run on it, its sensors' rows cut to the still segments, and the pooled fit over every log's
// still rows with what those rows identify per sensor (pooled_fit.h). One log still throughout
// takes calibrate.cc's single-run path instead.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>
#include <utility>
#include <numeric>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "gyrocomp/calibrate/pooled_fit.h"
#include "gyrocomp/calibrate/still.h"
#include "gyrocomp/core/format.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "calibrate_internal.h"

namespace gyrocomp::calibrate_internal {
namespace {

// The log's state on the detector's rows (vehicle_state.h): armed where the log says so (not
// known before its first message: not armed), in the air where its landed state says not landed
// (not known: landed); an empty vector where the log has no such state.
StillLogState StateOnRows(const VehicleStateLog& state, const std::vector<double>& t) {
  StillLogState out;
  if (!state.armed.empty()) out.armed = StateAtTimes(state.armed, t, /*before_first=*/false);
  if (!state.landed.empty()) {
    out.in_air = StateAtTimes(state.landed, t, /*before_first=*/true);
    out.in_air.flip();
  }
  return out;
}

// The still detector on a log's first IMU (the first gyro and the first accelerometer, rows
// paired by their averaging window, k = time / window; or the gyro alone), on the sensors read
// as means over 1 / still_rate_hz, with the log's armed / landed state: the vehicle is still or
// not as a whole. A log the detector cannot take is one rejected part with the reason.
StillDetection DetectStillOf(const std::vector<Sensor>& sensors, const VehicleStateLog& state, const Args& a) {
  const Sensor* gy = nullptr;
  const Sensor* ac = nullptr;
  for (const Sensor& s : sensors) {
    if (!gy && s.type == "gyro") gy = &s;
    if (!ac && s.type == "accel") ac = &s;
  }
  const double w = 1.0 / a.still_rate_hz;
  std::vector<double> t, temp;
  std::array<std::vector<double>, 3> g, acc;
  std::string why = gy ? "" : "no gyro rows";
  if (gy) {
    std::map<long long, std::size_t> accel_row;
    if (ac)
      for (std::size_t i = 0; i < ac->time_s.size(); ++i) accel_row[std::llround(std::floor(ac->time_s[i] / w))] = i;
    for (std::size_t i = 0; i < gy->time_s.size(); ++i) {
      const auto it = accel_row.find(std::llround(std::floor(gy->time_s[i] / w)));
      if (ac && it == accel_row.end()) continue;
      t.push_back(gy->time_s[i]);
      temp.push_back(gy->temp_c.size() == gy->time_s.size() ? gy->temp_c[i] : 0.0);
      for (int k = 0; k < 3; ++k) {
        g[k].push_back(gy->values[k][i]);
        acc[k].push_back(ac ? ac->values[k][it->second] : 0.0);
      }
    }
  }
  if (why.empty()) {
    Result<StillDetection> d = DetectStill(t, g, acc, temp, StateOnRows(state, t), a.still);
    if (d.ok()) return *d;
    why = d.error().message;
  }
  StillDetection none;
  RejectedPart all;
  all.start_s = t.empty() ? 0.0 : t.front();
  all.length_s = t.empty() ? 0.0 : t.back() - t.front();
  all.reason = "still detector: " + why;
  none.rejected.push_back(all);
  none.total_s = all.length_s;
  return none;
}

// The sensor's rows as read (at most still_rate_hz) made the fit's: means of n = row rate /
// fit_rate_hz consecutive rows inside one still segment (rows outside every segment dropped, a
// segment's last partial block dropped); `segment` gets each kept row's segment, `whole_rows`
// the fit rows the whole log would give, `lagged` ([lag][fit row]) the temperature low-passed
// with each of a.pooled_lags_s over the whole log (first order, exact steps, from the first
// row's temperature). Returns the seconds of log per fit row.
double StillBlockMeans(Sensor* s, const StillDetection& d, const Args& a, std::vector<int>* segment, std::size_t* whole_rows,
                       std::vector<std::vector<double>>* lagged) {
  const std::size_t rows = s->time_s.size();
  const double rate = rows > 1 ? static_cast<double>(rows - 1) / (s->time_s.back() - s->time_s.front()) : a.fit_rate_hz;
  const auto n = static_cast<std::size_t>(std::max(1.0, std::round(rate / a.fit_rate_hz)));
  *whole_rows = rows / n;
  Sensor out = *s;
  out.time_s.clear(), out.temp_c.clear();
  for (auto& v : out.values) v.clear();
  segment->clear();
  const bool with_temp = s->temp_c.size() == s->time_s.size();
  std::vector<std::vector<double>> low;  // [lag][row as read]
  lagged->assign(with_temp ? a.pooled_lags_s.size() : 0, {});
  for (std::size_t l = 0; l < lagged->size(); ++l) {
    std::vector<double> f(rows);
    for (std::size_t i = 0; i < rows; ++i) {
      const double dt = i > 0 ? s->time_s[i] - s->time_s[i - 1] : 0.0;
      f[i] = i == 0 ? s->temp_c[0] : f[i - 1] + (s->temp_c[i] - f[i - 1]) * (1.0 - std::exp(-dt / a.pooled_lags_s[l]));
    }
    low.push_back(std::move(f));
  }
  std::size_t i = 0;
  for (std::size_t j = 0; j < d.segments.size(); ++j) {
    const double from = d.segments[j].start_s, to = from + d.segments[j].length_s;
    while (i < s->time_s.size() && s->time_s[i] < from) ++i;
    for (; i + n <= s->time_s.size() && s->time_s[i + n - 1] < to; i += n) {
      double t = 0.0, temp = 0.0;
      for (std::size_t k = i; k < i + n; ++k) t += s->time_s[k], temp += with_temp ? s->temp_c[k] : 0.0;
      out.time_s.push_back(t / static_cast<double>(n));
      if (with_temp) out.temp_c.push_back(temp / static_cast<double>(n));
      for (std::size_t l = 0; l < low.size(); ++l) {
        double sum = 0.0;
        for (std::size_t k = i; k < i + n; ++k) sum += low[l][k];
        (*lagged)[l].push_back(sum / static_cast<double>(n));
      }
      for (std::size_t c = 0; c < s->values.size(); ++c) {
        double sum = 0.0;
        for (std::size_t k = i; k < i + n; ++k) sum += s->values[c][k];
        out.values[c].push_back(sum / static_cast<double>(n));
      }
      segment->push_back(static_cast<int>(j));
    }
  }
  *s = std::move(out);
  return static_cast<double>(n) / rate;
}

// The still rows of one sensor over every log, as the pooled fit takes them: temperature, values
// (model unit, per axis) and the group of each row's constant: the log for a gyro or barometer
// (the power-on offset), the log's still segment for an accelerometer (offset + the attitude's
// share of gravity, which changes whenever the vehicle has moved).
struct Pool {
  std::vector<double> time_s;  // s, in the row's log
  std::vector<double> temp_c;
  std::vector<double> rate_c_per_s;  // dT/dt over +-30 s of the row's still segment, C/s
  std::vector<std::vector<double>> lagged_c;  // [lag][row]: Run::lagged_c (empty when a log has none)
  std::vector<std::vector<double>> y;  // per axis, model unit
  std::vector<std::size_t> group;
  std::size_t num_groups = 0;
  std::vector<std::size_t> log_of_row;  // index into the runs
  std::vector<std::size_t> primary_rows;  // rows of runs[0]'s sensor used
  std::size_t all_rows = 0;  // rows of the sensor in every log, still or not
  int logs = 0, logs_with_still = 0;
  double still_s = 0.0;  // seconds of log the rows stand for
  std::vector<std::string> missing;  // "no gyro 2 in f3.ulg"
};

// dT/dt of each row: the temperature change over +-30 s of rows inside the same still segment,
// C/s (a slope over a minute: the block means' temperature noise divided by ~60 s).
std::vector<double> HeatingRate(const Sensor& m, const std::vector<int>& seg) {
  std::vector<double> rate(m.time_s.size(), 0.0);
  for (std::size_t i = 0; i < m.time_s.size(); ++i) {
    if (seg[i] < 0) continue;
    std::size_t lo = i, hi = i;
    while (lo > 0 && seg[lo - 1] == seg[i] && m.time_s[i] - m.time_s[lo - 1] <= 30.0) --lo;
    while (hi + 1 < m.time_s.size() && seg[hi + 1] == seg[i] && m.time_s[hi + 1] - m.time_s[i] <= 30.0) ++hi;
    if (hi > lo) rate[i] = (m.temp_c[hi] - m.temp_c[lo]) / (m.time_s[hi] - m.time_s[lo]);
  }
  return rate;
}

Pool Gather(const Sensor& s, const std::vector<Run>& runs) {
  Pool p;
  p.y.resize(s.values.size());
  bool with_lags = true;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const Sensor* m = r == 0 ? &s : Match(runs[r].sensors, s);  // s is a sensor of runs[0]
    if (!m || !m->reason.empty() || m->values.size() != s.values.size()) {
      p.missing.push_back((m ? m->reason : "no such sensor") + " in " + runs[r].path);
      continue;
    }
    ++p.logs;
    const auto index = static_cast<std::size_t>(m - runs[r].sensors.data());
    p.all_rows += runs[r].whole_rows[index];
    const std::vector<int>& seg = runs[r].segment[index];
    std::map<int, std::size_t> group_of_segment;
    const std::vector<double> rate = HeatingRate(*m, seg);
    const std::vector<std::vector<double>>* lagged = index < runs[r].lagged_c.size() ? &runs[r].lagged_c[index] : nullptr;
    if (!lagged || lagged->empty()) with_lags = false;
    if (with_lags && p.lagged_c.empty()) p.lagged_c.resize(lagged->size());
    for (std::size_t i = 0; i < m->time_s.size(); ++i) {
      if (seg[i] < 0) continue;
      p.rate_c_per_s.push_back(rate[i]);
      if (with_lags)
        for (std::size_t l = 0; l < p.lagged_c.size(); ++l) p.lagged_c[l].push_back((*lagged)[l][i]);
      const int key = s.type == "accel" ? seg[i] : 0;
      if (!group_of_segment.count(key)) group_of_segment[key] = p.num_groups++;
      p.group.push_back(group_of_segment[key]);
      p.time_s.push_back(m->time_s[i]);
      p.temp_c.push_back(m->temp_c[i]);
      for (std::size_t k = 0; k < s.values.size(); ++k) p.y[k].push_back(m->values[k][i] * s.to_model);
      p.log_of_row.push_back(r);
      p.still_s += runs[r].row_s[index];
      if (r == 0) p.primary_rows.push_back(i);
    }
    if (!group_of_segment.empty()) ++p.logs_with_still;
  }
  if (!with_lags) p.lagged_c.clear();
  return p;
}

// What the pooled rows identify (calibrate.h, CalibratedSensor::Identification) and which log
// would help most.
Sensor::Identification Identify(const Sensor& s, const Pool& p, const Args& a) {
  Sensor::Identification id;
  id.logs = p.logs, id.logs_with_still = p.logs_with_still;
  id.still_s = p.still_s;
  if (p.temp_c.empty()) {
    id.statement = "no still rows in " + std::to_string(p.logs) + " log(s)";
    id.would_help = "a log in which the vehicle stands still (disarmed, untouched) for a few minutes after power-on";
    return id;
  }
  const auto [lo, hi] = std::minmax_element(p.temp_c.begin(), p.temp_c.end());
  id.temp_min_c = *lo, id.temp_max_c = *hi;
  // Identified span: the union of the groups' own ranges (only the change inside a group counts).
  std::vector<std::pair<double, double>> ranges(p.num_groups, {INFINITY, -INFINITY});
  for (std::size_t i = 0; i < p.temp_c.size(); ++i) {
    auto& r = ranges[p.group[i]];
    r.first = std::min(r.first, p.temp_c[i]), r.second = std::max(r.second, p.temp_c[i]);
  }
  std::sort(ranges.begin(), ranges.end());
  double covered_to = -INFINITY;
  for (const auto& [from, to] : ranges) {
    id.identified_span_c += std::max(0.0, to - std::max(from, covered_to));
    covered_to = std::max(covered_to, to);
  }
  // Overlap: 0.5 C bins with still rows from two or more logs.
  std::map<long, std::set<std::size_t>> logs_in_bin;
  for (std::size_t i = 0; i < p.temp_c.size(); ++i) logs_in_bin[std::lround(std::floor(p.temp_c[i] / 0.5))].insert(p.log_of_row[i]);
  for (const auto& [bin, logs] : logs_in_bin)
    if (logs.size() >= 2) id.overlap_c += 0.5;
  const char* group = s.type == "accel" ? "still segment" : "log";
  id.statement = std::to_string(p.logs_with_still) + " of " + std::to_string(p.logs) + " log(s) with still rows, " +
                 FormatNumber(id.still_s / 60.0, 3) + " min still, " + FormatNumber(id.temp_min_c, 3) + ".." +
                 FormatNumber(id.temp_max_c, 3) + " C (" + FormatNumber(id.identified_span_c, 3) +
                 " C of change inside a " + group + "), overlap between logs " + FormatNumber(id.overlap_c, 3) + " C";
  if (id.identified_span_c < a.min_span_c) {
    id.would_help = "a log that powers on below " + FormatNumber(std::floor(id.temp_min_c - (a.min_span_c - id.identified_span_c)), 3) +
                    " C and stands still while it warms (" + FormatNumber(a.min_span_c - id.identified_span_c, 3) +
                    " C more change inside one " + group + ")";
  } else if (id.still_s < a.min_still_s) {
    id.would_help = FormatNumber((a.min_still_s - id.still_s) / 60.0, 3) +
                    " min more still time: leave the vehicle untouched for a few minutes after power-on";
  } else {
    // Whole degrees: the advice is for a person choosing the next flight's morning.
    const std::string lo = FormatNumber(std::floor(id.temp_min_c), 3), hi = FormatNumber(std::ceil(id.temp_max_c), 3);
    id.would_help = "a log that powers on below " + lo + " C or warms above " + hi +
                    " C would extend the curve (the firmware clamps to the calibrated range)" +
                    (p.logs_with_still < 2 ? "; a second log would show whether the curve repeats between power-ons" : "");
  }
  return id;
}

// The cubic as a DriftModel (a temperature-only polynomial about its reference), so the model
// files, the validation's full-model score and the report treat a pooled sensor as any other.
DriftModel ModelOf(const TemperatureCubic& c, const Sensor& s, std::size_t axis, const PooledCubic& fit) {
  DriftModel m;
  m.kind = DriftModelKind::kPolynomial;
  m.inputs = DriftInputSet::kTemp;
  PolynomialModel poly;
  poly.input_scaler.offset = {c.ref_temp_c};
  poly.input_scaler.scale = {1.0};
  for (int k = 0; k < 4; ++k) poly.terms.push_back({k, 0, c.coeff[static_cast<std::size_t>(k)]});
  m.structured = poly;
  m.rate_col = s.cols[axis];
  m.unit = s.model_unit;
  m.summary.temp_min_c = c.temp_min_c, m.summary.temp_max_c = c.temp_max_c;
  m.summary.degree = 3;
  m.summary.num_samples = m.summary.num_train = fit.group_rows.empty() ? 0 : std::accumulate(fit.group_rows.begin(), fit.group_rows.end(), std::size_t{0});
  m.summary.train_rmse = fit.residual_rms;
  return m;
}

// The pooled rows as the fit saw them (CalibratedSensor::FitRows, firmware unit) and each axis's
// band of the curve: z(0.9) curve_sd at every temperature of the range (CalibratedSensor::CurveBand).
void KeepPooledRows(Sensor* s, const Pool& p) {
  s->fit_rows.time_s = p.time_s;
  s->fit_rows.temp_c = p.temp_c;
  s->fit_rows.values = p.y;
  for (auto& v : s->fit_rows.values)
    for (double& x : v) x /= s->to_model;
  s->fit_rows.log.assign(p.log_of_row.begin(), p.log_of_row.end());
  s->fit_rows.group.assign(p.group.begin(), p.group.end());
  Sensor::CurveBand b;
  b.z = TwoSidedZ(b.level);
  constexpr int kPoints = 101;
  for (int i = 0; i < kPoints; ++i) b.temp_c.push_back(s->temp_min_c + (s->temp_max_c - s->temp_min_c) * i / (kPoints - 1));
  for (double sd : s->curve_sd) {
    b.sd.assign(kPoints, sd);
    s->curve_bands.push_back(b);
  }
}

// The temperature the pooled cubic is fitted on (CalibrateOptions::pooled_lags_s): the logged one,
// or its low-passed copy whose lag predicts the held-out groups best when that lag's paired
// held-out gain over none beats its standard error. Per group, each axis's held-out RMS is
// divided by the axis's mean without a lag and the axes averaged, so one lag serves the sensor.
// The choice is nested in the pairs (Eq. A-5, term_admission.h): the lag scored on group g is
// the one (or none) with the lowest mean over the other groups, so the best of the candidates is
// never tested on the scores that chose it (the gain of the best of nine, read on its own scores,
// is biased upwards).
// Sets s->temp_lag_s, s->lag_term and adds the lag to the identification's statement.
const std::vector<double>& LagOfCurve(Sensor* s, const Pool& p, double ref, const Args& a) {
  s->temp_lag_s = 0.0, s->lag_term = TermGain{};
  if (p.lagged_c.empty() || p.lagged_c.size() != a.pooled_lags_s.size()) return p.temp_c;
  const std::size_t axes = p.y.size();
  std::vector<double> norm(axes, 0.0);
  auto per_group = [&](const std::vector<double>& temp, bool set_norm) {
    std::vector<double> score(p.num_groups, 0.0);
    for (std::size_t k = 0; k < axes; ++k) {
      const std::vector<double> e = PooledGroupHeldOutRms(temp, p.y[k], p.group, p.num_groups, ref);
      if (set_norm) {
        double sum = 0.0, count = 0.0;
        for (double v : e)
          if (std::isfinite(v)) sum += v, count += 1.0;
        norm[k] = count > 0.0 ? sum / count : NAN;
      }
      for (std::size_t g = 0; g < p.num_groups; ++g) score[g] += e[g] / norm[k] / static_cast<double>(axes);
    }
    return score;
  };
  // scores[0]: no lag; scores[l + 1]: pooled_lags_s[l].
  std::vector<std::vector<double>> scores{per_group(p.temp_c, true)};
  for (double n : norm)
    if (!(n > 0.0)) return p.temp_c;
  for (const std::vector<double>& lagged : p.lagged_c) scores.push_back(per_group(lagged, false));
  const std::size_t best = LowestMeanSetting(scores, p.num_groups);
  if (best == 0) return p.temp_c;
  const std::vector<double> nested = NestedChoiceRmse(scores);  // Eq. A-5
  s->lag_term = PairedTermGain(scores[0], nested);
  if (!s->lag_term.Admitted()) return p.temp_c;
  s->temp_lag_s = a.pooled_lags_s[best - 1];
  s->identification.statement += "; fitted on the temperature lagged " + FormatNumber(s->temp_lag_s, 3) +
                                 " s (held-out error " + FormatNumber(100.0 * s->lag_term.gain, 2) + " +- " +
                                 FormatNumber(100.0 * s->lag_term.se, 2) + " % lower than without)";
  return p.lagged_c[best - 1];
}

// CalibratedSensor::heating_state: the state every log's still rows had while heating, binned by
// the logged temperature (the one the firmware reads): dT/dt where an axis kept the dT/dt term,
// T - T_lag with a lag (fit_temp: the lagged temperature the cubic was fitted on); nothing
// without either.
void SetHeatingState(Sensor* s, const Pool& p, const std::vector<double>& fit_temp) {
  s->heating_state = StateByTemperature{}, s->heating_state_kind.clear();
  const bool lagged = s->temp_lag_s > 0.0;
  const bool gain = std::any_of(s->rate_gain.begin(), s->rate_gain.end(), [](double g) { return g != 0.0; });
  if (!lagged && !gain) return;
  std::vector<double> state(p.temp_c.size());
  for (std::size_t i = 0; i < state.size(); ++i) state[i] = lagged ? p.temp_c[i] - fit_temp[i] : p.rate_c_per_s[i];
  Result<StateByTemperature> h = HeatingStateByTemperature(p.temp_c, state, p.rate_c_per_s);
  if (!h.ok()) return;
  s->heating_state = *h;
  s->heating_state_kind = ThermalStateColumnName(lagged ? DriftInputSet::kTempAndLag : DriftInputSet::kTempAndRate);
}

// One axis's entries of a pooled sensor: the cubic for the condition (ForCondition) in the
// firmware's unit, its model, the fit's 1 sigma and dT/dt gain, what the cubic loses against
// the curve steady and along the heating state (model unit -> firmware unit).
void KeepPooledAxis(Sensor* s, const Args& a, std::size_t k, const TemperatureCubic& steady, const PooledCubic& fit) {
  DriftModel with_term = ModelOf(steady, *s, k, fit);
  const TemperatureCubic c = ForCondition(*s, a, steady, fit.rate_gain, &with_term);
  s->models.push_back(ModelOf(c, *s, k, fit));
  const TemperatureCubic fw = Firmware(*s, a, c);
  s->cubics.push_back(fw), s->cubics_time.push_back(fw), s->cubics_temperature.push_back(fw);
  s->weights.push_back("pooled");
  s->weight_choices.emplace_back(std::nullopt);
  // Without a term both are 0; steady, the cubic is the curve (0 up to rounding, said as 0).
  auto [steady_rms, warm_up_rms] = std::pair<double, double>{0.0, 0.0};
  if (with_term.inputs != DriftInputSet::kTemp) std::tie(steady_rms, warm_up_rms) = ConditionErrors(with_term, c, s->heating_state);
  if (a.optimise_for == "steady") steady_rms = 0.0;
  s->cost_rms.push_back(0.0), s->steady_rms.push_back(steady_rms / s->to_model), s->warm_up_rms.push_back(warm_up_rms / s->to_model);
  s->expected.emplace_back(std::nullopt);
  s->curve_sd.push_back(fit.curve_sd / s->to_model);
}

}  // namespace

// Reads one log: its sensors at still_rate_hz, the still detector on them, then the fit's rows.
// `keep_whole`: a log still throughout is read again at fit_rate_hz, exactly the rows a single
// chamber run has always been calibrated on; otherwise the fit's rows are the still rows' block
// means (one read of a long flight log).
Result<Run> ReadRun(const std::string& path, LogFormat format, const Args& a, bool keep_whole) {
  auto read = [&](double rate, LogInfo* info) {
    return format == LogFormat::kULog ? SensorsOfULog(path, rate, info) : SensorsOfDataFlash(path, rate, a.notes, info);
  };
  LogInfo info;
  auto sensors = read(a.still_rate_hz, &info);
  if (!sensors.ok()) return sensors.error();
  Run run{path, std::move(*sensors), {}, {}, {}, {}, {}, std::move(info)};
  run.detection = DetectStillOf(run.sensors, run.info.state, a);
  run.detection.still.clear();
  run.detection.still.shrink_to_fit();
  const bool throughout = run.detection.rejected.empty() && run.detection.segments.size() == 1;
  if (keep_whole && throughout) {
    auto whole = read(a.fit_rate_hz, nullptr);
    if (!whole.ok()) return whole.error();
    for (std::size_t k = 0; k < whole->size() && k < run.sensors.size(); ++k) (*whole)[k].log_rate_hz = run.sensors[k].log_rate_hz;
    run.sensors = std::move(*whole);
    for (const Sensor& s : run.sensors) {
      run.segment.emplace_back(s.time_s.size(), 0);
      run.lagged_c.emplace_back();
      run.row_s.push_back(1.0 / a.fit_rate_hz);
      run.whole_rows.push_back(s.time_s.size());
    }
    return run;
  }
  for (Sensor& s : run.sensors) {
    run.segment.emplace_back();
    run.whole_rows.emplace_back();
    run.lagged_c.emplace_back();
    run.row_s.push_back(StillBlockMeans(&s, run.detection, a, &run.segment.back(), &run.whole_rows.back(), &run.lagged_c.back()));
  }
  return run;
}

namespace {
// The board rotation parameters of a log: PX4 SENS_BOARD_ROT and the per-sensor CAL_GYRO<n>_ROT /
// CAL_ACC<n>_ROT; ArduPilot AHRS_ORIENTATION.
std::map<std::string, double> RotationParameters(const std::map<std::string, double>& p) {
  std::map<std::string, double> out;
  for (const auto& [name, value] : p) {
    const bool per_sensor = (name.rfind("CAL_GYRO", 0) == 0 || name.rfind("CAL_ACC", 0) == 0) && name.size() > 4 &&
                            name.compare(name.size() - 4, 4, "_ROT") == 0;
    if (name == "SENS_BOARD_ROT" || name == "AHRS_ORIENTATION" || per_sensor) out[name] = value;
  }
  return out;
}
// Why a rotation change between logs does not change the fit (flight-controller-export.md).
std::string RotationReason(const std::string& name) {
  if (name == "AHRS_ORIENTATION")
    return "each log's IMU rows are rotated back to the sensor frame with its own value (DataFlashImuToSensorFrame), "
           "the frame of INS_TCAL";
  return "PX4 logs sensor_gyro / sensor_accel before any rotation (calibration::Gyroscope / Accelerometer::Correct "
         "rotates after subtracting the thermal offset), the frame of TC_*";
}
}  // namespace

std::vector<std::string> DifferencesBetweenLogs(const std::vector<Run>& runs) {
  std::vector<std::string> notes;
  if (runs.empty()) return notes;
  const Run& first = runs.front();
  const std::map<std::string, double> rot0 = RotationParameters(first.info.parameters);
  for (std::size_t r = 1; r < runs.size(); ++r) {
    for (const auto& [name, value] : RotationParameters(runs[r].info.parameters)) {
      const auto it = rot0.find(name);
      if (it == rot0.end() || it->second == value) continue;
      notes.push_back(name + " = " + FormatNumber(it->second) + " in " + first.path + ", " + FormatNumber(value) + " in " +
                      runs[r].path + ": pooled all the same: " + RotationReason(name));
    }
    // One note per pair of rates (as printed), listing the sensors logged at them.
    std::map<std::pair<std::string, std::string>, std::string> sensors_at;
    for (const Sensor& s : first.sensors) {
      const Sensor* m = Match(runs[r].sensors, s);
      if (!m || !(s.log_rate_hz > 0.0) || !(m->log_rate_hz > 0.0)) continue;
      if (std::abs(m->log_rate_hz / s.log_rate_hz - 1.0) <= 0.05) continue;
      std::string& list = sensors_at[{FormatNumber(s.log_rate_hz, 4), FormatNumber(m->log_rate_hz, 4)}];
      list += (list.empty() ? "" : ", ") + s.type + " " + std::to_string(s.instance) +
              (s.device_id ? " (id " + std::to_string(*s.device_id) + ")" : std::string());
    }
    for (const auto& [rates, list] : sensors_at)
      notes.push_back(list + ": logged at " + rates.first + " Hz in " + first.path + ", " + rates.second + " Hz in " +
                      runs[r].path + ": pooled all the same (the still detector reads each log at its own noise " +
                      "level, the fit sees means over the same seconds)");
  }
  return notes;
}

Sensor::Identification IdentifyRuns(const Sensor& s, const std::vector<Run>& runs, const Args& a) {
  return Identify(s, Gather(s, runs), a);
}

// The pooled fit of one sensor of the first log over every log's still rows (pooled_fit.h);
// sets `reason` (and the identification says what would help) when the rows do not identify
// a curve.
void CalibratePooled(Sensor* s, const std::vector<Run>& runs, const Args& a) {
  s->fit = "pooled";
  if (!s->reason.empty()) return;
  if (s->reason = SlotReason(*s, a); !s->reason.empty()) return;
  const Pool p = Gather(*s, runs);
  s->identification = Identify(*s, p, a);
  s->runs_combined = p.logs_with_still;
  const Sensor::Identification& id = s->identification;
  if (p.all_rows < a.min_rows) {  // too short a log whether still or not: as the single-run path says it
    s->reason = std::to_string(p.all_rows) + " rows at " + FormatNumber(a.fit_rate_hz, 4) + " Hz < " + std::to_string(a.min_rows);
  } else if (p.temp_c.size() < a.min_rows) {
    s->reason = std::to_string(p.temp_c.size()) + " still rows at " + FormatNumber(a.fit_rate_hz, 4) + " Hz < " + std::to_string(a.min_rows);
  } else if (id.still_s < a.min_still_s) {
    s->reason = "still time " + FormatNumber(id.still_s, 4) + " s < " + FormatNumber(a.min_still_s, 4) + " s";
  } else if (id.identified_span_c < a.min_span_c) {
    s->reason = "temperature change inside the " + std::string(s->type == "accel" ? "still segments" : "logs") + " " +
                FormatNumber(id.identified_span_c, 4) + " C < " + FormatNumber(a.min_span_c, 4) + " C";
  }
  if (!s->reason.empty()) return;
  s->temp_min_c = id.temp_min_c, s->temp_max_c = id.temp_max_c;
  const double ref = 0.5 * (id.temp_min_c + id.temp_max_c);  // PX4's TREF convention: the middle of the range
  // The shared dT/dt gain where the rows' heating rates spread enough to identify it (SD over
  // 1e-3 C/s = 0.06 C/min; a chamber ramp at 1 C/min, a board's own warm-up at several C/min).
  double mean_rate = 0.0, ss_rate = 0.0;
  for (double r : p.rate_c_per_s) mean_rate += r / static_cast<double>(p.rate_c_per_s.size());
  for (double r : p.rate_c_per_s) ss_rate += (r - mean_rate) * (r - mean_rate);
  const std::vector<double>& temp = LagOfCurve(s, p, ref, a);
  const bool with_rate = s->temp_lag_s == 0.0 && a.pooled_dtemp && std::sqrt(ss_rate / static_cast<double>(p.rate_c_per_s.size())) > 1e-3;
  std::vector<PooledCubic> fits;
  std::vector<TemperatureCubic> steady;
  for (std::size_t k = 0; k < s->values.size(); ++k) {
    Result<PooledCubic> fit = FitPooledCubic(temp, p.y[k], p.group, p.num_groups, ref, with_rate ? p.rate_c_per_s : std::vector<double>{});
    if (!fit.ok()) {
      s->reason = "pooled fit of " + s->cols[k] + ": " + fit.error().message;
      return;
    }
    // The constant: the mean of the groups' (a gyro's offset on an average power-on; PX4 keeps
    // it as X0, TemperatureCompensation subtracts it before CAL_GYRO; the other files drop it).
    // Groups without rows (a log with no still rows for this sensor) have no constant.
    double constant = 0.0, groups = 0.0;
    for (std::size_t g = 0; g < fit->group_constant.size(); ++g) {
      if (fit->group_rows[g] > 0) constant += fit->group_constant[g], groups += 1.0;
    }
    TemperatureCubic c;
    c.ref_temp_c = ref, c.temp_min_c = id.temp_min_c, c.temp_max_c = id.temp_max_c;
    c.coeff = {constant / std::max(groups, 1.0), fit->slope[0], fit->slope[1], fit->slope[2]};
    s->rate_gain.push_back(fit->rate_gain / s->to_model);
    fits.push_back(std::move(*fit));
    steady.push_back(c);
  }
  SetHeatingState(s, p, temp);
  for (std::size_t k = 0; k < fits.size(); ++k) KeepPooledAxis(s, a, k, steady[k], fits[k]);
  s->band_reason = "pooled fit: no prediction band; the curve's 1 sigma from the fit is in curve_sd";
  KeepPooledRows(s, p);
  // The sensor's rows: the first log's still rows (what the summary's uncompensated drift reads).
  auto keep = [&](std::vector<double>& v) {
    std::vector<double> out;
    for (std::size_t i : p.primary_rows) out.push_back(v[i]);
    v = std::move(out);
  };
  keep(s->time_s), keep(s->temp_c);
  for (auto& v : s->values) keep(v);
}

}  // namespace gyrocomp::calibrate_internal
