// The calibrate stage (include/gyrocomp/calibrate/calibrate.h): the sensors of a log, block
// means, the fit and projection per axis of a log still throughout, the scores on a validation
// run, and CalibrateLogs. Several logs (still detection, pooled fit): calibrate_runs.cc.
#include "gyrocomp/calibrate/calibrate.h"

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <cmath>
#include <numbers>
#include <numeric>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gyrocomp/calibrate/pooled_fit.h"
#include "gyrocomp/calibrate/still.h"
#include "gyrocomp/core/format.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/param_export.h"
#include "gyrocomp/export/static_cubic.h"
#include "gyrocomp/export/static_weight.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "gyrocomp/io/flight_log.h"
#include "calibrate_internal.h"

namespace gyrocomp {
namespace calibrate_internal {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

std::vector<double> Seconds(const std::vector<std::uint64_t>& us) {
  std::vector<double> t(us.size());
  for (std::size_t i = 0; i < us.size(); ++i) t[i] = static_cast<double>(us[i]) * 1e-6;
  return t;
}

Sensor MakeSensor(std::string type, int instance, std::optional<std::uint32_t> id, const std::vector<std::uint64_t>& t_us,
                  std::vector<double> temp, std::vector<std::vector<double>> values) {
  Sensor s;
  s.type = std::move(type);
  s.instance = instance;
  s.device_id = id;
  s.time_s = Seconds(t_us);
  s.temp_c = std::move(temp);
  s.values = std::move(values);
  if (s.type == "gyro") {
    s.cols = {"x_rad_s", "y_rad_s", "z_rad_s"}, s.unit = "rad/s", s.to_model = kDegPerRad, s.model_unit = "deg/s";
  } else if (s.type == "accel") {
    s.cols = {"x_m_s2", "y_m_s2", "z_m_s2"}, s.unit = s.model_unit = "m/s^2";
  } else {
    s.cols = {"pressure_pa"}, s.unit = s.model_unit = "Pa";
  }
  if (s.temp_c.size() != s.time_s.size()) s.reason = "no temperature logged";
  return s;
}

}  // namespace
namespace {
// Rows per second of a series as logged: `rows` records over the span of its (averaged) times.
double LogRate(std::size_t rows, const std::vector<double>& time_s) {
  return rows > 1 && time_s.size() > 1 && time_s.back() > time_s.front()
             ? static_cast<double>(rows - 1) / (time_s.back() - time_s.front()) : 0.0;
}
// The 'D' rows of a ULog topic instance (every subscription of it).
std::size_t TopicRows(const ULogContents& log, const std::string& name, int multi_id) {
  std::size_t n = 0;
  for (const ULogTopic& t : log.topics)
    if (t.name == name && t.multi_id == multi_id) n += t.rows;
  return n;
}
}  // namespace
Result<std::vector<Sensor>> SensorsOfULog(const std::string& path, double fit_rate_hz, LogInfo* info) {
  // Means over 1 / fit_rate windows while reading: the full-rate rows are never held.
  ULogReadOptions read;
  read.average_window_us = static_cast<std::uint64_t>(std::llround(1e6 / fit_rate_hz));
  Result<ULogContents> log = ReadULog(path, read);
  if (!log.ok()) return log.error();
  std::vector<Sensor> out;
  for (const auto& g : log->gyros)
    out.push_back(MakeSensor("gyro", g.multi_id, g.device_id, g.timestamp_us, g.temperature_c, {g.x_rad_s, g.y_rad_s, g.z_rad_s}));
  for (const auto& a : log->accels)
    out.push_back(MakeSensor("accel", a.multi_id, a.device_id, a.timestamp_us, a.temperature_c, {a.x_m_s2, a.y_m_s2, a.z_m_s2}));
  for (const auto& b : log->baros)
    out.push_back(MakeSensor("baro", b.multi_id, b.device_id, b.timestamp_us, b.temperature_c, {b.pressure_pa}));
  for (Sensor& s : out)
    s.log_rate_hz = LogRate(TopicRows(*log, "sensor_" + s.type, s.instance), s.time_s);
  if (info) info->state = VehicleStateOfULog(*log), info->parameters = log->parameters;
  if (out.empty()) return InvalidInput(path + ": no sensor_gyro, sensor_accel or sensor_baro data (" + log->BriefReport() + ")");
  // PX4 slots: the order of the instances of each kind (at most 4).
  for (const char* type : {"gyro", "accel", "baro"}) {
    int next = 0;
    for (Sensor& s : out)
      if (s.type == type) s.slot = next++;
  }
  return out;
}
Result<std::vector<Sensor>> SensorsOfDataFlash(const std::string& path, double fit_rate_hz, std::vector<std::string>* notes_out,
                                               LogInfo* info) {
  // Means over 1 / fit_rate windows while reading (the rotation undone later is linear; the
  // thermal-correction undo is evaluated at the window's mean temperature).
  DataFlashReadOptions read;
  read.average_window_us = static_cast<std::uint64_t>(std::llround(1e6 / fit_rate_hz));
  Result<DataFlashContents> log = ReadDataFlash(path, read);
  if (!log.ok()) return log.error();
  std::vector<Sensor> out;
  for (const DataFlashImuSeries& raw : log->imus) {
    std::vector<std::string> notes;
    Result<DataFlashImuSeries> s = DataFlashImuToSensorFrame(*log, raw, &notes);  // rotation, TCAL undone
    if (!s.ok()) return s.error();
    for (const std::string& n : notes)
      if (std::find(notes_out->begin(), notes_out->end(), n) == notes_out->end()) notes_out->push_back(n);
    out.push_back(MakeSensor("gyro", s->instance, std::nullopt, s->time_us, s->temp_c,
                             {s->gyr_x_rad_s, s->gyr_y_rad_s, s->gyr_z_rad_s}));
    if (!s->acc_x_m_s2.empty())
      out.push_back(MakeSensor("accel", s->instance, std::nullopt, s->time_us, s->temp_c,
                               {s->acc_x_m_s2, s->acc_y_m_s2, s->acc_z_m_s2}));
    for (std::size_t k = out.size() - (s->acc_x_m_s2.empty() ? 1 : 2); k < out.size(); ++k)
      out[k].log_rate_hz = LogRate(raw.records, Seconds(raw.time_us));  // the rows as read, before any cut
  }
  if (info) info->state = VehicleStateOfDataFlash(*log), info->parameters = log->parameters;
  if (out.empty()) return InvalidInput(path + ": no IMU rows (" + log->BriefReport() + ")");
  for (Sensor& s : out) s.slot = s.instance + 1;  // INS_TCAL<n>
  return out;
}
namespace {

// Block means of `n` rows (the last partial block dropped): the thermal drift is slow, and the
// fit then sees the same rows whatever the log rate (tempcal_IMU.py: 2 s moving average).
void BlockMeans(Sensor* s, double fit_rate_hz) {
  const std::size_t rows = s->time_s.size();
  if (rows < 2) return;
  const double fs = static_cast<double>(rows - 1) / (s->time_s.back() - s->time_s.front());
  const auto n = static_cast<std::size_t>(std::max(1.0, std::floor(fs / fit_rate_hz)));
  auto mean = [&](const std::vector<double>& v) {
    std::vector<double> out;
    for (std::size_t b = 0; b + n <= v.size(); b += n) {
      double sum = 0.0;
      for (std::size_t i = b; i < b + n; ++i) sum += v[i];
      out.push_back(sum / static_cast<double>(n));
    }
    return out;
  };
  s->time_s = mean(s->time_s);
  s->temp_c = mean(s->temp_c);
  for (auto& v : s->values) v = mean(v);
}

// --static-weight temperature: the static part of `cubic` (the model's curve at state 0) replaced
// by the run's static curve with each temperature weighted alike; what --optimise-for adds to the
// static curve (the model's warm-up state) is kept: the projection is linear in the curve, so
// cubic = static + (projection for the condition - projection at state 0), on one range and ref.
Status StaticByTemperature(const DriftModel& m, const DriftInputs& run, const std::vector<double>& y,
                           const CubicProjectionOptions& po, TemperatureCubic* cubic) {
  CubicProjectionOptions steady = po;
  steady.condition = CubicCondition::kSteady;
  steady.ref_temp_c = cubic->ref_temp_c;
  Result<TemperatureCubic> model_static = ProjectOntoCubic(m, steady);
  if (!model_static.ok()) return model_static.error();
  StaticCubicOptions so;
  so.temp_min_c = cubic->temp_min_c, so.temp_max_c = cubic->temp_max_c, so.ref_temp_c = cubic->ref_temp_c;
  Result<TemperatureCubic> data_static = FitStaticCubicByTemperature(m, run, y, so);
  if (!data_static.ok()) return data_static.error();
  for (std::size_t j = 0; j < 4; ++j) cubic->coeff[j] = data_static->coeff[j] + (cubic->coeff[j] - model_static->coeff[j]);
  return Status::Ok();
}

// The exported cubic's steady band (CalibratedSensor::CurveBand): the expected next-run error's
// sd at each temperature, sqrt((cubic - model)^2 + band_sd^2) (cubic_score.h), firmware unit.
Sensor::CurveBand SteadyBand(const DriftModel& m, const TemperatureCubic& model_unit, double to_model) {
  Sensor::CurveBand b;
  Result<CubicErrorProfile> p = SteadyCubicErrorProfile(m, model_unit);
  if (!p.ok()) return b;
  b.level = p->level, b.z = TwoSidedZ(p->level), b.temp_c = p->temp_c;
  for (std::size_t i = 0; i < p->temp_c.size(); ++i) b.sd.push_back(std::hypot(p->projection[i], p->band_sd[i]) / to_model);
  return b;
}

// A single run's fit rows (CalibratedSensor::FitRows): every block mean, one log, one constant.
void KeepFitRows(Sensor* s) {
  s->fit_rows.time_s = s->time_s;
  s->fit_rows.temp_c = s->temp_c;
  s->fit_rows.values = s->values;
  s->fit_rows.log.assign(s->temp_c.size(), 0);
  s->fit_rows.group.assign(s->temp_c.size(), 0);
}

}  // namespace
// RMS over 201 temperatures of the range of cubic - model at state 0 and at the warm-up state
// (model unit; the cubic before any constant is removed).
std::pair<double, double> ConditionErrors(const DriftModel& m, const TemperatureCubic& c, const StateByTemperature& warm) {
  double ss_steady = 0.0, ss_warm = 0.0;
  constexpr int kPoints = 201;
  for (int i = 0; i < kPoints; ++i) {
    const double t = c.temp_min_c + (c.temp_max_c - c.temp_min_c) * i / (kPoints - 1);
    const double cubic = c.Evaluate(t);
    ss_steady += std::pow(cubic - m.PredictAt(t, 0.0), 2);
    ss_warm += std::pow(cubic - m.PredictAt(t, m.inputs == DriftInputSet::kTemp ? 0.0 : warm.At(t)), 2);
  }
  return {std::sqrt(ss_steady / kPoints), std::sqrt(ss_warm / kPoints)};
}

// Why the firmware has no place for `s` ("" when it has one): slots, ArduPilot's barometer.
std::string SlotReason(const Sensor& s, const Args& a) {
  if (s.slot < 0 || s.slot > (a.format == "px4" ? kPx4TcalSlots - 1 : 3) || (a.format == "ardupilot" && s.slot < 1))
    return a.format == "px4" ? "PX4 has 4 calibration slots per sensor kind" : "ArduPilot has INS_TCAL1..3 only";
  if (a.format == "ardupilot" && s.type == "baro") return "ArduPilot has no barometer thermal calibration";
  return "";
}
// The exported cubic in the firmware's unit, constant as the file needs it.
TemperatureCubic Firmware(const Sensor& s, const Args& a, const TemperatureCubic& model_unit) {
  TemperatureCubic fw = model_unit.Scaled(1.0 / s.to_model);
  if (a.format == "px4" && s.type != "gyro") fw.coeff[0] = 0.0;  // process_sensor_caldata.py subtracts the median
  return fw;
}
namespace {

// Fits and projects one sensor; sets `reason` when it cannot be calibrated.
void Calibrate(Sensor* s, const Args& a, std::optional<std::pair<double, double>> range = std::nullopt) {
  if (!s->reason.empty()) return;
  if (s->reason = SlotReason(*s, a); !s->reason.empty()) return;
  BlockMeans(s, a.fit_rate_hz);
  if (s->time_s.size() < a.min_rows) {
    s->reason = std::to_string(s->time_s.size()) + " rows at " + FormatNumber(a.fit_rate_hz, 4) + " Hz < " + std::to_string(a.min_rows);
    return;
  }
  const auto [lo, hi] = std::minmax_element(s->temp_c.begin(), s->temp_c.end());
  s->temp_min_c = *lo, s->temp_max_c = *hi;
  if (*hi - *lo < a.min_span_c) {
    s->reason = "temperature span " + FormatNumber(*hi - *lo, 4) + " C < " + FormatNumber(a.min_span_c, 4) + " C";
    return;
  }
  if (range) s->temp_min_c = range->first, s->temp_max_c = range->second;
  const double fs = static_cast<double>(s->time_s.size() - 1) / (s->time_s.back() - s->time_s.front());
  const DriftInputs inputs{s->temp_c, fs};
  CubicProjectionOptions po;
  po.temp_min_c = s->temp_min_c;
  po.temp_max_c = s->temp_max_c;
  po.condition = *ParseCubicCondition(a.optimise_for);
  static const DriftFitOptions kFitOptions;  // the library default (auto)
  for (std::size_t k = 0; k < s->values.size(); ++k) {
    std::vector<double> y = s->values[k];
    for (double& v : y) v *= s->to_model;
    Result<DriftModel> m = FitDriftModel(inputs, y, kFitOptions);
    if (!m.ok()) {
      s->reason = "fit of " + s->cols[k] + " failed: " + m.error().message;
      return;
    }
    m->rate_col = s->cols[k];
    m->unit = s->model_unit;
    Result<StateByTemperature> warm = StateWhileHeating(*m, inputs);
    if (!warm.ok()) {
      s->reason = "warm-up state of " + s->cols[k] + ": " + warm.error().message;
      return;
    }
    po.warm_up = *warm;
    Result<TemperatureCubic> c = ProjectOntoCubic(*m, po);
    if (!c.ok()) {
      s->reason = "projection of " + s->cols[k] + " failed: " + c.error().message;
      return;
    }
    TemperatureCubic by_temp = *c;
    if (a.static_weight != "time") {
      if (Status st = StaticByTemperature(*m, inputs, y, po, &by_temp); !st.ok()) {
        s->reason = "static curve of " + s->cols[k] + ": " + st.error().message;
        return;
      }
    }
    s->weights.push_back(a.static_weight);
    s->weight_choices.emplace_back(std::nullopt);
    if (a.static_weight == "auto") {
      Result<StaticWeightChoice> ch = ChooseStaticWeight(*m, inputs, po.temp_min_c.value(), po.temp_max_c.value(), po.condition);
      if (ch.ok()) {
        s->weights.back() = StaticWeightName(ch->chosen);
        s->weight_choices.back() = *ch;
      } else {
        s->weights.back() = "temperature";  // the robust one when the run gives no evidence
        s->weight_reason = "auto fell back to temperature: " + ch.error().message;
      }
    }
    const auto firmware = [&](const TemperatureCubic& model_unit) { return Firmware(*s, a, model_unit); };
    s->cubics_time.push_back(firmware(*c));
    s->cubics_temperature.push_back(firmware(by_temp));
    if (s->weights.back() == "temperature") *c = by_temp;
    Result<CubicProjectionCost> cost = MeasureCubicProjectionCost(*m, *c, inputs);
    TemperatureCubic fw = firmware(*c);
    s->cost_rms.push_back(cost.ok() ? cost->rms / s->to_model : NAN);
    const auto [steady, warm_up] = ConditionErrors(*m, *c, *warm);
    s->steady_rms.push_back(steady / s->to_model);
    s->warm_up_rms.push_back(warm_up / s->to_model);
    Result<CubicExpectedError> e = ExpectedCubicError(*m, *c, inputs);
    if (e.ok()) {
      s->expected.emplace_back(*e);
    } else {
      s->expected.emplace_back(std::nullopt);
      s->band_reason = e.error().message;
    }
    s->curve_bands.push_back(SteadyBand(*m, *c, s->to_model));
    s->cubics.push_back(fw);
    s->models.push_back(std::move(*m));
  }
  KeepFitRows(s);
}

}  // namespace
// The sensor of `run` that is `s`: the same type and device id when both logs give one (the
// instance number is the order in which the drivers enumerated the IMUs at that boot and can
// change between power-ons; the device id stays with the chip), else the same type and instance.
const Sensor* Match(const std::vector<Sensor>& run, const Sensor& s) {
  if (s.device_id)
    for (const Sensor& v : run)
      if (v.type == s.type && v.device_id && *v.device_id == *s.device_id) return &v;
  for (const Sensor& v : run)
    if (v.type == s.type && v.instance == s.instance && (!v.device_id || !s.device_id)) return &v;
  return nullptr;
}
namespace {

// A log of another board: both logs give device ids and none of them is in both. An error naming
// the log and the ids; ok when the logs share an id or either has none (ArduPilot's IMU rows).
Status SameBoard(const std::vector<Sensor>& primary, const std::string& primary_path, const std::vector<Sensor>& run,
                 const std::string& path) {
  std::string ids_primary, ids_run;
  bool any_primary = false, any_run = false;
  for (const Sensor& s : primary) {
    if (!s.device_id) continue;
    any_primary = true;
    ids_primary += (ids_primary.empty() ? "" : ", ") + s.type + " " + std::to_string(*s.device_id);
    for (const Sensor& v : run)
      if (v.type == s.type && v.device_id && *v.device_id == *s.device_id) return Status::Ok();
  }
  for (const Sensor& v : run)
    if (v.device_id) {
      any_run = true;
      ids_run += (ids_run.empty() ? "" : ", ") + v.type + " " + std::to_string(*v.device_id);
    }
  if (!any_primary || !any_run) return Status::Ok();
  return InvalidInput(path + ": a log of another board: no sensor device id in common with " + primary_path + " (" +
                      primary_path + ": " + ids_primary + "; " + path + ": " + ids_run + ")");
}

// Scores every axis of `s` on its match `v` of the validation run: the raw value, the exported
// cubic under the firmware's formula (float32, clamped; ArduPilot's CALTEMP = the run's first
// temperature) and the full model (causal, as the generated C runs it), as RMS of block means.
Sensor::Validation ScoreOn(const Sensor& s, const Sensor* v, const Args& a) {
  Sensor::Validation out;
  if (!v) {
    out.reason = "no " + s.type + " " + std::to_string(s.instance) + " in " + a.validation_path;
    return out;
  }
  if (!v->reason.empty()) {
    out.reason = v->reason;
    return out;
  }
  out.rows = v->time_s.size();
  if (out.rows < 2) {
    out.reason = std::to_string(out.rows) + " rows";
    return out;
  }
  const auto [lo, hi] = std::minmax_element(v->temp_c.begin(), v->temp_c.end());
  out.temp_min_c = *lo, out.temp_max_c = *hi;
  const double fs = static_cast<double>(out.rows - 1) / (v->time_s.back() - v->time_s.front());
  const auto block = static_cast<std::size_t>(std::max(1.0, std::round(a.block_s * fs)));
  const FirmwareFormula formula = a.format == "px4" ? FirmwareFormula::kPx4 : FirmwareFormula::kArduPilot;
  const std::vector<double> zero(out.rows, 0.0);
  for (std::size_t k = 0; k < s.cubics.size(); ++k) {
    const std::vector<double> fw = FirmwareCorrection(formula, s.cubics[k], v->temp_c, v->temp_c.front());
    Result<std::vector<double>> full = s.models[k].Predict({v->temp_c, fs}, /*causal=*/true);
    if (!full.ok()) {
      out.reason = "full model of " + s.cols[k] + ": " + full.error().message;
      return out;
    }
    for (double& x : *full) x /= s.to_model;
    Result<double> raw = ResidualBlockRms(v->values[k], zero, block);
    Result<double> cubic = ResidualBlockRms(v->values[k], fw, block);
    Result<double> model = ResidualBlockRms(v->values[k], *full, block);
    for (const Result<double>* r : {&raw, &cubic, &model})
      if (!r->ok()) {
        out.reason = r->error().message;
        return out;
      }
    out.raw.push_back(*raw), out.cubic.push_back(*cubic), out.full_model.push_back(*model);
  }
  return out;
}

// --validation: the second log read as the calibration log, each calibrated sensor scored on it.
Status Validate(const Args& a, LogFormat format, std::vector<Sensor>* all) {
  if (a.validation_path.empty()) return Status::Ok();
  if (DetectLogFormat(a.validation_path) != format)
    return InvalidInput(a.validation_path + ": --validation must be a log of the same kind as -i (" +
                        std::string(LogFormatName(format)) + ")");
  auto run = format == LogFormat::kULog ? SensorsOfULog(a.validation_path, a.fit_rate_hz)
                                        : SensorsOfDataFlash(a.validation_path, a.fit_rate_hz, a.notes);
  if (!run.ok()) return run.error();
  for (Sensor& v : *run) {
    if (!v.reason.empty()) continue;
    BlockMeans(&v, a.fit_rate_hz);
    if (v.time_s.size() < 2) v.reason = "fewer than 2 rows in " + a.validation_path;
  }
  if (Status st = SameBoard(*all, a.input, *run, a.validation_path); !st.ok()) return st;
  for (Sensor& s : *all)
    if (s.reason.empty()) s.validation = ScoreOn(s, Match(*run, s), a);
  return Status::Ok();
}

}  // namespace
}  // namespace calibrate_internal

bool CalibrateOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = "CalibrateOptions::" + m;
    return false;
  };
  if (format != "px4" && format != "ardupilot") return fail("format = '" + format + "': must be px4 or ardupilot");
  if (!(fit_rate_hz > 0.0)) return fail("fit_rate_hz = " + FormatNumber(fit_rate_hz, 4) + ": must be > 0 Hz");
  if (!(min_span_c >= 0.0)) return fail("min_span_c = " + FormatNumber(min_span_c, 4) + ": must be >= 0 C");
  if (!(block_s > 0.0)) return fail("block_s = " + FormatNumber(block_s, 4) + ": must be > 0 s");
  for (double lag : pooled_lags_s)
    if (!(lag > 0.0)) return fail("pooled_lags_s: a lag of " + FormatNumber(lag, 4) + " s: each must be > 0 s");
  if (!ParseCubicCondition(optimise_for)) return fail("optimise_for = '" + optimise_for + "': must be steady, warm-up or both");
  if (static_weight != "auto" && static_weight != "time" && static_weight != "temperature")
    return fail("static_weight = '" + static_weight + "': must be auto, temperature or time");
  return true;
}

bool CalibrateResult::AnyCalibrated() const {
  return std::any_of(sensors.begin(), sensors.end(), [](const CalibratedSensor& s) { return s.calibrated(); });
}

Result<CalibrateResult> CalibrateLogs(const std::vector<std::string>& logs, const CalibrateOptions& options) {
  using namespace calibrate_internal;
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (logs.empty()) return InvalidArgument("CalibrateLogs: no log given");
  CalibrateResult result;
  result.inputs = logs;
  result.options = options;
  Args a;
  static_cast<CalibrateOptions&>(a) = options;
  a.inputs = logs;
  a.input = logs.front();
  a.notes = &result.notes;
  const LogFormat format = DetectLogFormat(a.input);
  if (format == LogFormat::kCsv)
    return InvalidInput(a.input + ": not a PX4 ULog or ArduPilot DataFlash log (by its first bytes)");
  if ((format == LogFormat::kULog) != (a.format == "px4"))
    return InvalidArgument("--format " + a.format + " for a " + std::string(LogFormatName(format)) +
                           " log: PX4 parameters come from a ULog, ArduPilot's from a DataFlash log");
  // Every log: where the vehicle was still, its sensors' rows, another board refused.
  std::vector<Run> runs;
  for (const std::string& path : logs) {
    if (DetectLogFormat(path) != format) return InvalidInput(path + ": every -i must be a log of the same kind as " + a.input);
    Result<Run> run = ReadRun(path, format, a, /*keep_whole=*/logs.size() == 1);
    if (!run.ok()) return run.error();
    if (!runs.empty())
      if (Status st = SameBoard(runs.front().sensors, a.input, run->sensors, path); !st.ok()) return st.error();
    result.logs.push_back({path, run->detection, run->info.state.BriefReport()});
    runs.push_back(std::move(*run));
  }
  for (std::string& n : DifferencesBetweenLogs(runs)) result.notes.push_back(std::move(n));
  // One log still throughout: the drift model and projection; otherwise the pooled fit.
  const bool single = runs.size() == 1 && runs.front().detection.rejected.empty() && runs.front().detection.segments.size() == 1;
  std::vector<Sensor>* sensors = &runs.front().sensors;
  for (Sensor& s : *sensors) {
    if (!single) {
      CalibratePooled(&s, runs, a);
      continue;
    }
    const std::string no_temperature = s.reason;
    if (s.reason.empty()) s.identification = IdentifyRuns(s, runs, a);
    Calibrate(&s, a);
    if (!no_temperature.empty()) s.identification.statement = no_temperature;
  }
  result.sensors = std::move(*sensors);
  if (!result.AnyCalibrated()) return result;
  if (Status st = Validate(a, format, &result.sensors); !st.ok()) return st.error();
  Result<std::string> text = ParameterText(a, result.sensors);
  if (!text.ok()) return text.error();
  result.parameter_text = std::move(*text);
  return result;
}

}  // namespace gyrocomp
