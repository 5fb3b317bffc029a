// gyrocomp calibrate: every gyro, accelerometer (and PX4 barometer) of a flight log fitted and
// written as ONE parameter file the autopilot loads (issue 22; docs/export.md, docs/cli.md).
//
// Per sensor: the rows in the sensor frame (the readers undo ArduPilot's board rotation and
// thermal correction), block means at --fit-rate, the library's default FitDriftModel (auto), the
// static curve projected onto the firmware's cubic over the sensor's temperature range, and the
// constant the firmware leaves to its offset calibration removed:
//   PX4 gyro: X0..X3 = the drift itself (TemperatureCompensation subtracts it before CAL_GYRO);
//   PX4 accel / baro: X0 = 0 (process_sensor_caldata.py subtracts the median: gravity and the
//     constant go to CAL_ACC / the baro offset, recalibrated after loading, its step 12);
//   ArduPilot gyro / accel: re-expanded about 35 C, constant dropped (correct_sensor is relative
//     to INS_*_CALTEMP; tempcal_IMU.py drops it too).
// A sensor that cannot be calibrated keeps its row (status skipped, the reason) and its slot is
// disabled in the file.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "commands.h"
#include "calibrate_report.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/param_export.h"
#include "gyrocomp/export/static_cubic.h"
#include "gyrocomp/export/static_weight.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/report/report.h"
#include "result_json.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kName = "calibrate";
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

struct CalibrateArgs {
  std::string input;                      // the first -i (the primary run: models, bands, cost)
  std::vector<std::string> inputs;        // every -i: runs of one board, their cubics averaged
  std::string format;
  std::string output;
  std::string models_dir;
  std::string json_path;
  std::string validation_path;  // a second log of the same board: every exported cubic scored on it
  std::string report_path;      // HTML report
  double block_s = 10.0;        // validation: residual block means, s (bench/imu_calibration_side_by_side.py)
  double fit_rate_hz = 1.0;   // block means of the rows before fitting
  double min_span_c = 10.0;   // ArduPilot's TEMP_RANGE_MIN (AP_InertialSensor_tempcal.cpp)
  std::size_t min_rows = 60;  // after the block means
  std::string optimise_for = "steady";  // CubicCondition of the exported cubic
  // How the static curve is estimated: "temperature" (each temperature alike: the run's data,
  // the model's dynamic part removed, in equal-width temperature bins; static_cubic.h), "time"
  // (the fitted model's own curve at state 0, fitted on every sample) or "auto" (per axis, the
  // one with the lower expected next-run error; static_weight.h).
  std::string static_weight = "auto";
};

// One sensor instance of the log, in its sensor frame and firmware unit.
struct Sensor {
  std::string type;  // gyro | accel | baro
  int instance = 0;
  std::optional<std::uint32_t> device_id;
  std::vector<double> time_s, temp_c;
  std::vector<std::vector<double>> values;  // per axis, firmware unit (rad/s, m/s^2, Pa)
  std::vector<std::string> cols;            // x_rad_s | x_m_s2 | pressure_pa
  std::string unit;                         // firmware unit
  double to_model = 1.0;                    // firmware unit -> model unit (gyro: deg/s)
  std::string model_unit;
  // Outcome.
  std::string reason;  // non-empty: skipped
  int slot = -1;       // PX4 slot / ArduPilot IMU n
  std::vector<DriftModel> models;
  std::vector<TemperatureCubic> cubics;  // firmware unit, constant handled as the file needs
  // Both candidates of --static-weight (firmware unit, as `cubics`; the temperature one only
  // when computed), the weighting each axis's exported cubic has, and --static-weight auto's
  // comparison (nullopt: not auto, or no band; then weight_reason says why).
  std::vector<TemperatureCubic> cubics_time, cubics_temperature;
  std::vector<std::string> weights;
  std::vector<std::optional<StaticWeightChoice>> weight_choices;
  std::string weight_reason;
  std::vector<double> cost_rms;          // projection cost on the run, firmware unit
  // RMS over the range of cubic - full model at state 0 (steady) and along the run's warm-up
  // state (warm-up), firmware unit: what the exported cubic loses in each condition.
  std::vector<double> steady_rms, warm_up_rms;
  // Expected next-run error of each axis's cubic (model band + projection), per condition.
  std::vector<std::optional<CubicExpectedError>> expected;
  std::string band_reason;  // why `expected` is missing (a model without a band)
  double temp_min_c = 0.0, temp_max_c = 0.0;
  // --validation: per axis RMS of the residual block means on the validation run, firmware unit.
  struct Validation {
    std::string reason;  // non-empty: not validated
    std::size_t rows = 0;
    double temp_min_c = 0.0, temp_max_c = 0.0;
    std::vector<double> raw, cubic, full_model;
  };
  std::optional<Validation> validation;
  int runs_combined = 1;  // -i logs whose cubics were averaged
};

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

Result<std::vector<Sensor>> SensorsOfULog(const std::string& path, double fit_rate_hz) {
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
  if (out.empty()) return InvalidInput(path + ": no sensor_gyro, sensor_accel or sensor_baro data (" + log->BriefReport() + ")");
  // PX4 slots: the order of the instances of each kind (at most 4).
  for (const char* type : {"gyro", "accel", "baro"}) {
    int next = 0;
    for (Sensor& s : out)
      if (s.type == type) s.slot = next++;
  }
  return out;
}

Result<std::vector<Sensor>> SensorsOfDataFlash(const std::string& path, double fit_rate_hz) {
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
    for (const std::string& n : notes) Note(kName, n);
    out.push_back(MakeSensor("gyro", s->instance, std::nullopt, s->time_us, s->temp_c,
                             {s->gyr_x_rad_s, s->gyr_y_rad_s, s->gyr_z_rad_s}));
    if (!s->acc_x_m_s2.empty())
      out.push_back(MakeSensor("accel", s->instance, std::nullopt, s->time_us, s->temp_c,
                               {s->acc_x_m_s2, s->acc_y_m_s2, s->acc_z_m_s2}));
  }
  if (out.empty()) return InvalidInput(path + ": no IMU rows (" + log->BriefReport() + ")");
  for (Sensor& s : out) s.slot = s.instance + 1;  // INS_TCAL<n>
  return out;
}

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

std::string Num(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

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

// Fits and projects one sensor; sets `reason` when it cannot be calibrated.
void Calibrate(Sensor* s, const CalibrateArgs& a, std::optional<std::pair<double, double>> range = std::nullopt) {
  if (!s->reason.empty()) return;
  if (s->slot < 0 || s->slot > (a.format == "px4" ? kPx4TcalSlots - 1 : 3) || (a.format == "ardupilot" && s->slot < 1)) {
    s->reason = a.format == "px4" ? "PX4 has 4 calibration slots per sensor kind" : "ArduPilot has INS_TCAL1..3 only";
    return;
  }
  if (a.format == "ardupilot" && s->type == "baro") {
    s->reason = "ArduPilot has no barometer thermal calibration";
    return;
  }
  BlockMeans(s, a.fit_rate_hz);
  if (s->time_s.size() < a.min_rows) {
    s->reason = std::to_string(s->time_s.size()) + " rows at " + Num(a.fit_rate_hz) + " Hz < " + std::to_string(a.min_rows);
    return;
  }
  const auto [lo, hi] = std::minmax_element(s->temp_c.begin(), s->temp_c.end());
  s->temp_min_c = *lo, s->temp_max_c = *hi;
  if (*hi - *lo < a.min_span_c) {
    s->reason = "temperature span " + Num(*hi - *lo) + " C < " + Num(a.min_span_c) + " C";
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
    const auto firmware = [&](const TemperatureCubic& model_unit) {
      TemperatureCubic fw = model_unit.Scaled(1.0 / s->to_model);
      if (a.format == "px4" && s->type != "gyro") fw.coeff[0] = 0.0;  // the script subtracts the median
      return fw;
    };
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
    s->cubics.push_back(fw);
    s->models.push_back(std::move(*m));
  }
}

// The validation run's sensor of the same type and instance (PX4: and device id, when both log one).
const Sensor* Match(const std::vector<Sensor>& run, const Sensor& s) {
  for (const Sensor& v : run)
    if (v.type == s.type && v.instance == s.instance && (!v.device_id || !s.device_id || *v.device_id == *s.device_id))
      return &v;
  return nullptr;
}

// Scores every axis of `s` on its match `v` of the validation run: the raw value, the exported
// cubic under the firmware's formula (float32, clamped; ArduPilot's CALTEMP = the run's first
// temperature) and the full model (causal, as the generated C runs it), as RMS of block means.
Sensor::Validation ScoreOn(const Sensor& s, const Sensor* v, const CalibrateArgs& a) {
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
Status Validate(const CalibrateArgs& a, LogFormat format, std::vector<Sensor>* all) {
  if (a.validation_path.empty()) return Status::Ok();
  if (DetectLogFormat(a.validation_path) != format)
    return InvalidInput(a.validation_path + ": --validation must be a log of the same kind as -i (" +
                        std::string(LogFormatName(format)) + ")");
  auto run = format == LogFormat::kULog ? SensorsOfULog(a.validation_path, a.fit_rate_hz)
                                        : SensorsOfDataFlash(a.validation_path, a.fit_rate_hz);
  if (!run.ok()) return run.error();
  for (Sensor& v : *run) {
    if (!v.reason.empty()) continue;
    BlockMeans(&v, a.fit_rate_hz);
    if (v.time_s.size() < 2) v.reason = "fewer than 2 rows in " + a.validation_path;
  }
  for (Sensor& s : *all)
    if (s.reason.empty()) s.validation = ScoreOn(s, Match(*run, s), a);
  return Status::Ok();
}

ThreeAxisCubics Three(const Sensor& s) { return {s.cubics[0], s.cubics[1], s.cubics[2]}; }

const Sensor* Find(const std::vector<Sensor>& all, const std::string& type, int slot) {
  for (const Sensor& s : all)
    if (s.type == type && s.slot == slot && s.reason.empty()) return &s;
  return nullptr;
}

// "steady 1e-4 2e-4 3e-4" (firmware unit) or the reason no band is available.
std::string ExpectedText(const Sensor& s, bool warm_up) {
  std::string t = warm_up ? "warm-up" : "steady";
  for (const auto& e : s.expected) {
    if (!e) return t + " n/a (" + s.band_reason + ")";
    if (warm_up && !e->warm_up) return t + " n/a (the run has no heating sample)";
    t += " " + Num((warm_up ? e->warm_up->total_rms : e->steady.total_rms) / s.to_model);
  }
  return t;
}

// "static weight temperature time time (auto: expected error time 1e-4/..., temperature ...)".
std::string WeightText(const Sensor& s) {
  std::string t = "static weight";
  for (const std::string& w : s.weights) t += " " + w;
  bool any = false;
  std::string time = "time", temp = "temperature";
  for (const auto& c : s.weight_choices) {
    if (!c) continue;
    time += (any ? "/" : " ") + Num(c->time.total_rms / s.to_model);
    temp += (any ? "/" : " ") + Num(c->temperature.total_rms / s.to_model);
    any = true;
  }
  if (any) t += " (auto, expected error " + time + ", " + temp + " " + s.unit + ")";
  if (!s.weight_reason.empty()) t += " (" + s.weight_reason + ")";
  return t;
}

std::string ValidationText(const Sensor::Validation& v) {
  if (!v.reason.empty()) return "validation: not scored, " + v.reason;
  std::string t = "validation run (" + std::to_string(v.rows) + " rows): RMS raw / cubic / full model";
  for (std::size_t k = 0; k < v.raw.size(); ++k) t += " " + Num(v.raw[k]) + "/" + Num(v.cubic[k]) + "/" + Num(v.full_model[k]);
  return t;
}

std::string Joined(const std::vector<std::string>& v) {
  std::string t;
  for (const std::string& x : v) t += (t.empty() ? "" : " + ") + x;
  return v.size() > 1 ? t + " (cubics averaged over the runs; models and bands from the first)" : t;
}

std::vector<std::string> Comments(const CalibrateArgs& a, const std::vector<Sensor>& all) {
  std::vector<std::string> c = {
      "Thermal calibration generated by gyrocomp calibrate --format " + a.format + " from " + Joined(a.inputs),
      "(docs/export.md). Every sensor of the log: the library's default drift model (auto) fitted on",
      "block means at " + Num(a.fit_rate_hz) + " Hz, its curve projected onto the firmware's cubic over the",
      "sensor's range, optimised for: " + a.optimise_for + " (steady: dT/dt = 0; warm-up: the state the run had while heating;",
      "both: their mean); static curve weighted by: " + a.static_weight + " (temperature: each temperature alike,",
      "the run's data with the model's dynamic part removed, 2000 bins; time: the model's own curve; auto: per",
      "axis the one with the lower expected next-run error of the estimator, docs/export.md).",
      "Units: gyro rad/s, accel m/s^2, baro Pa; sensor frame. Per sensor: model, projection cost",
      "(RMS full model - cubic on this run, firmware unit) and, per axis, the expected next-run error of the",
      "exported cubic: RMS of sqrt((cubic - model)^2 + sd^2), sd the model's prediction band / z (docs/export.md),",
      "at steady temperature and along this run's own heating (warm-up), constant excluded."};
  for (const Sensor& s : all) {
    std::ostringstream l;
    l << "  " << s.type << " " << s.instance << (s.device_id ? " (device_id " + std::to_string(*s.device_id) + ")" : "");
    if (!s.reason.empty()) {
      l << ": SKIPPED, " << s.reason;
      c.push_back(l.str());
      continue;
    }
    l << ": " << DriftModelKindName(s.models[0].kind) << ", " << Num(s.temp_min_c) << ".." << Num(s.temp_max_c) << " C, cost";
    for (double v : s.cost_rms) l << " " << Num(v);
    c.push_back(l.str());
    c.push_back("    expected error " + ExpectedText(s, false) + "; " + ExpectedText(s, true));
    c.push_back("    " + WeightText(s));
    if (s.validation) c.push_back("    " + ValidationText(*s.validation));
  }
  return c;
}

Result<std::string> WriteFile(const CalibrateArgs& a, const std::vector<Sensor>& all) {
  const auto comments = Comments(a, all);
  if (a.format == "px4") {
    Px4TcalFile f;
    for (const Sensor& s : all) {
      if (!s.reason.empty()) continue;
      if (!s.device_id) return InvalidInput(a.input + ": " + s.type + " " + std::to_string(s.instance) + " logs no device_id");
      if (s.type == "gyro") f.gyro.push_back({s.slot, *s.device_id, Three(s)});
      if (s.type == "accel") f.accel.push_back({s.slot, *s.device_id, Three(s)});
      if (s.type == "baro") f.baro.push_back({s.slot, *s.device_id, s.cubics[0]});
    }
    return WritePx4TcalFile(f, comments);
  }
  std::vector<ArduPilotTcalImu> imus;
  for (int n = 1; n <= 3; ++n) {
    ArduPilotTcalImu m;
    m.imu = n;
    const Sensor* g = Find(all, "gyro", n);
    const Sensor* acc = Find(all, "accel", n);
    if (g) m.gyro_radps = Three(*g);
    if (acc) m.accel_m_s2 = Three(*acc);
    if (!g && !acc) {
      m.disabled_reason = "IMU " + std::to_string(n - 1) + " not calibrated";
      for (const Sensor& s : all)
        if (s.slot == n && !s.reason.empty()) m.disabled_reason = s.type + ": " + s.reason;
      bool in_log = false;
      for (const Sensor& s : all) in_log |= s.slot == n;
      if (!in_log) m.disabled_reason = "IMU " + std::to_string(n - 1) + " not in the log";
    }
    imus.push_back(m);
  }
  return WriteArduPilotTcalFile(imus, comments);
}

nlohmann::json ConditionJson(const CubicConditionError& e, double to_model) {
  return {{"total_rms", e.total_rms / to_model}, {"projection_rms", e.projection_rms / to_model},
          {"band_sd_rms", e.band_sd_rms / to_model}, {"samples", e.num_samples}};
}

// Per axis, firmware unit: the exported cubic's expected next-run error in each condition.
nlohmann::json ExpectedJson(const CalibrateArgs& a, const Sensor& s) {
  nlohmann::json steady = nlohmann::json::array(), warm = nlohmann::json::array(), axes = nlohmann::json::array();
  nlohmann::json proj_steady = nlohmann::json::array(), proj_warm = nlohmann::json::array();
  nlohmann::json level = nullptr;
  for (std::size_t k = 0; k < s.models.size(); ++k) {
    proj_steady.push_back(s.steady_rms[k]);
    proj_warm.push_back(s.warm_up_rms[k]);
    const auto& e = s.expected[k];
    if (e) level = e->level;
    steady.push_back(e ? nlohmann::json(e->steady.total_rms / s.to_model) : nlohmann::json(nullptr));
    warm.push_back(e && e->warm_up ? nlohmann::json(e->warm_up->total_rms / s.to_model) : nlohmann::json(nullptr));
    nlohmann::json ax = {{"col", s.cols[k]}};
    if (e) {
      ax["steady"] = ConditionJson(e->steady, s.to_model);
      ax["warm_up"] = e->warm_up ? ConditionJson(*e->warm_up, s.to_model) : nlohmann::json(nullptr);
    }
    axes.push_back(ax);
  }
  nlohmann::json j = {{"optimised_for", a.optimise_for}, {"band_level", level}, {"steady", steady}, {"warm_up", warm},
                      {"projection_steady", proj_steady}, {"projection_warm_up", proj_warm}, {"axes", axes}};
  if (!s.band_reason.empty()) j["steady_reason"] = j["warm_up_reason"] = s.band_reason;
  j["note"] = "per axis, firmware unit: expected next-run RMS error of the exported cubic, RMS of sqrt((cubic - "
              "model)^2 + sd^2) with sd the model's prediction band / z(band_level), at steady temperature (a "
              "slow ramp over the range) and along this run's heating samples (warm_up); projection_*: the "
              "cubic - model part alone, over the range";
  return j;
}

nlohmann::json EstimatorJson(const StaticEstimatorError& e, double to_model) {
  return {{"total_rms", e.total_rms / to_model}, {"rate_gain_rms", e.rate_gain_rms / to_model},
          {"noise_rms", e.noise_rms / to_model}};
}

// --static-weight auto's comparison for axis k (firmware unit), or null with the reason.
nlohmann::json WeightChoiceJson(const Sensor& s, std::size_t k) {
  const auto& c = s.weight_choices[k];
  if (!c) return s.weight_reason.empty() ? nlohmann::json(nullptr) : nlohmann::json({{"reason", s.weight_reason}});
  return {{"chosen", StaticWeightName(c->chosen)}, {"time", EstimatorJson(c->time, s.to_model)},
          {"temperature", EstimatorJson(c->temperature, s.to_model)},
          {"unidentified_rate_gain_rms", c->rate_gain_rms / s.to_model}, {"reason", c->reason},
          {"note", "expected next-run RMS error of each estimator of the static cubic (constant removed): the left-out "
                   "dT/dt gain G (Eq. B-4) times what the estimator makes of the run's dT/dt, and the run's noise "
                   "(the band's Eq. G-0) through the estimator; over the --optimise-for conditions"}};
}

nlohmann::json ValidationJson(const Sensor::Validation& v) {
  if (!v.reason.empty()) return {{"status", "not scored"}, {"reason", v.reason}};
  return {{"status", "scored"}, {"rows", v.rows}, {"temp_min_c", v.temp_min_c}, {"temp_max_c", v.temp_max_c},
          {"raw_rms", v.raw}, {"cubic_rms", v.cubic}, {"full_model_rms", v.full_model}};
}

nlohmann::json SensorJson(const CalibrateArgs& a, const Sensor& s) {
  nlohmann::json j = {{"type", s.type}, {"instance", s.instance}, {"slot", s.slot},
                      {"status", s.reason.empty() ? "calibrated" : "skipped"}};
  if (a.format == "px4") j["device_id"] = s.device_id ? nlohmann::json(*s.device_id) : nlohmann::json(nullptr);
  else j["imu"] = s.slot;
  if (!s.reason.empty()) {
    j["reason"] = s.reason;
    return j;
  }
  j["temp_min_c"] = s.temp_min_c;
  j["temp_max_c"] = s.temp_max_c;
  j["runs_combined"] = s.runs_combined;
  j["kind"] = DriftModelKindName(s.models[0].kind);
  j["unit"] = s.unit;
  nlohmann::json axes = nlohmann::json::array();
  for (std::size_t k = 0; k < s.models.size(); ++k) {
    const TemperatureCubic& c = s.cubics[k];
    axes.push_back({{"col", s.cols[k]}, {"kind", DriftModelKindName(s.models[k].kind)},
                    {"cubic", {{"ref_temp_c", c.ref_temp_c}, {"temp_min_c", c.temp_min_c}, {"temp_max_c", c.temp_max_c},
                               {"coeff", c.coeff}}},
                    {"projection_cost_rms", s.cost_rms[k]}, {"fit_rmse", s.models[k].summary.train_rmse / s.to_model},
                    {"static_weight", s.weights[k]}, {"static_weight_choice", WeightChoiceJson(s, k)}});
  }
  j["axes"] = axes;
  j["expected_error"] = ExpectedJson(a, s);
  if (s.validation) j["validation"] = ValidationJson(*s.validation);
  return j;
}

Status WriteModels(const CalibrateArgs& a, const std::vector<Sensor>& all) {
  if (a.models_dir.empty()) return Status::Ok();
  std::error_code ec;
  std::filesystem::create_directories(a.models_dir, ec);
  if (ec) return IoError(a.models_dir + ": cannot create the directory: " + ec.message());
  for (const Sensor& s : all) {
    if (!s.reason.empty()) continue;
    DriftModelSet set;
    set.axes = s.models;
    set.device_id = s.device_id;
    set.sensor = SensorIdentity{s.type, s.instance, s.device_id, "sensor"};
    const std::string path = (std::filesystem::path(a.models_dir) / (s.type + std::to_string(s.instance) + ".json")).string();
    if (Status st = SaveDriftModelSet(set, path); !st.ok()) return st;
  }
  return Status::Ok();
}

void PrintTable(const std::vector<Sensor>& all) {
  std::ostringstream t;
  t << "sensor  inst  slot  span_c         model          cost (RMS full - cubic, per axis)\n";
  for (const Sensor& s : all) {
    t << s.type << std::string(8 - std::min<std::size_t>(7, s.type.size()), ' ') << s.instance << "     " << s.slot << "     ";
    if (!s.reason.empty()) {
      t << "skipped: " << s.reason << "\n";
      continue;
    }
    std::string span = Num(s.temp_min_c) + ".." + Num(s.temp_max_c);
    t << span << std::string(span.size() < 15 ? 15 - span.size() : 1, ' ') << DriftModelKindName(s.models[0].kind)
      << std::string(15 - std::min<std::size_t>(14, std::string(DriftModelKindName(s.models[0].kind)).size()), ' ');
    for (double v : s.cost_rms) t << Num(v) << " ";
    t << s.unit << "\n";
    t << "                  expected next-run error of the cubic: " << ExpectedText(s, false) << "; "
      << ExpectedText(s, true) << " " << s.unit << "\n";
    t << "                  " << WeightText(s) << "\n";
  }
  bool any_validation = false;
  for (const Sensor& s : all) any_validation |= s.validation.has_value();
  if (any_validation) {
    t << "validation run: RMS of block means, mean removed, per axis (raw / exported cubic, firmware formula / "
         "full model, causal)\n";
    for (const Sensor& s : all) {
      if (!s.validation) continue;
      t << s.type << std::string(8 - std::min<std::size_t>(7, s.type.size()), ' ') << s.instance << "     ";
      const Sensor::Validation& v = *s.validation;
      if (!v.reason.empty()) {
        t << "not scored: " << v.reason << "\n";
        continue;
      }
      for (std::size_t k = 0; k < v.raw.size(); ++k)
        t << s.cols[k] << " " << Num(v.raw[k]) << " / " << Num(v.cubic[k]) << " / " << Num(v.full_model[k]) << "   ";
      t << s.unit << "\n";
    }
  }
  std::cerr << t.str();
}

// The gyro cubics for the report's chart (deg/s).
std::vector<CalibrateCurve> CubicCurves(const std::vector<Sensor>& all) {
  std::vector<CalibrateCurve> out;
  for (const Sensor& s : all) {
    if (s.type != "gyro" || !s.reason.empty()) continue;
    for (std::size_t k = 0; k < s.cubics.size(); ++k)
      out.push_back({s.type + " " + std::to_string(s.instance) + " " + s.cols[k], s.cubics[k], s.to_model});
  }
  return out;
}

// Several -i logs of one board: each sensor of the first log is matched in the others (type,
// instance, device id), every match calibrated over the range all of them cover, and the cubics
// averaged coefficient by coefficient (one range and reference): the calibration runs' noise
// averages out as 1/sqrt(runs) (docs/export.md). Models, bands and costs stay the first run's.
Status CombineRuns(const CalibrateArgs& a, LogFormat format, std::vector<Sensor>* primary) {
  if (a.inputs.size() < 2) return Status::Ok();
  std::vector<std::vector<Sensor>> others;
  for (std::size_t r = 1; r < a.inputs.size(); ++r) {
    if (DetectLogFormat(a.inputs[r]) != format)
      return InvalidInput(a.inputs[r] + ": every -i must be a log of the same kind as " + a.input);
    auto run = format == LogFormat::kULog ? SensorsOfULog(a.inputs[r], a.fit_rate_hz) : SensorsOfDataFlash(a.inputs[r], a.fit_rate_hz);
    if (!run.ok()) return run.error();
    for (Sensor& v : *run) Calibrate(&v, a);
    others.push_back(std::move(*run));
  }
  for (Sensor& s : *primary) {
    if (!s.reason.empty()) continue;
    std::vector<Sensor*> runs;
    double lo = s.temp_min_c, hi = s.temp_max_c;
    for (std::size_t r = 0; r < others.size(); ++r) {
      const Sensor* m = Match(others[r], s);
      if (!m || !m->reason.empty()) {
        s.reason = "not calibrated in " + a.inputs[r + 1] + (m ? ": " + m->reason : ": no such sensor");
        break;
      }
      runs.push_back(const_cast<Sensor*>(m));
      lo = std::max(lo, m->temp_min_c), hi = std::min(hi, m->temp_max_c);
    }
    if (!s.reason.empty()) continue;
    if (hi - lo < a.min_span_c) {
      s.reason = "the -i logs share only " + Num(lo) + ".." + Num(hi) + " C < --min-span";
      continue;
    }
    runs.insert(runs.begin(), &s);
    for (Sensor* r : runs) {  // again over the common range (the block means are kept: n = 1)
      r->models.clear(), r->cubics.clear(), r->cost_rms.clear(), r->steady_rms.clear(), r->warm_up_rms.clear();
      r->expected.clear(), r->cubics_time.clear(), r->cubics_temperature.clear(), r->weights.clear();
      r->weight_choices.clear();
      Calibrate(r, a, std::pair{lo, hi});
      if (!r->reason.empty()) {
        s.reason = r->reason;
        break;
      }
    }
    if (!s.reason.empty()) continue;
    for (std::size_t k = 0; k < s.cubics.size(); ++k) {
      // auto: one weighting for the axis over all runs, from their combined expected errors; a
      // run given twice (the same values) is one run's noise, counted once.
      std::vector<StaticWeightChoice> choices;
      bool all = true;
      for (std::size_t r = 0; r < runs.size(); ++r) {
        all &= runs[r]->weight_choices[k].has_value();
        bool repeat = false;
        for (std::size_t q = 0; q < r; ++q)
          repeat |= runs[q]->values[k] == runs[r]->values[k] && runs[q]->temp_c == runs[r]->temp_c;
        if (runs[r]->weight_choices[k] && !repeat) choices.push_back(*runs[r]->weight_choices[k]);
      }
      if (a.static_weight == "auto" && all) {
        s.weight_choices[k] = CombineStaticWeightChoices(choices);
        s.weights[k] = StaticWeightName(s.weight_choices[k]->chosen);
      }
      for (std::size_t j = 0; j < 4; ++j) {
        double sum = 0.0;
        for (const Sensor* r : runs)
          sum += (s.weights[k] == "time" ? r->cubics_time[k] : r->cubics_temperature[k]).coeff[j];
        s.cubics[k].coeff[j] = sum / static_cast<double>(runs.size());
      }
    }
    s.runs_combined = static_cast<int>(runs.size());
  }
  return Status::Ok();
}

int Run(const CalibrateArgs& a) {
  if (!(a.fit_rate_hz > 0.0) || !(a.min_span_c >= 0.0) || !(a.block_s > 0.0))
    return ReportError(kName, InvalidArgument("--fit-rate must be > 0 Hz, --min-span >= 0 C and --block > 0 s"));
  const LogFormat format = DetectLogFormat(a.input);
  if (format == LogFormat::kCsv)
    return ReportError(kName, InvalidInput(a.input + ": not a PX4 ULog or ArduPilot DataFlash log (by its first bytes)"));
  if ((format == LogFormat::kULog) != (a.format == "px4"))
    return ReportError(kName, InvalidArgument("--format " + a.format + " for a " + std::string(LogFormatName(format)) +
                                              " log: PX4 parameters come from a ULog, ArduPilot's from a DataFlash log"));
  auto sensors = format == LogFormat::kULog ? SensorsOfULog(a.input, a.fit_rate_hz) : SensorsOfDataFlash(a.input, a.fit_rate_hz);
  if (!sensors.ok()) return ReportError(kName, sensors.error());
  for (Sensor& s : *sensors) Calibrate(&s, a);
  if (Status st = CombineRuns(a, format, &*sensors); !st.ok()) return ReportError(kName, st.error());
  const bool any = std::any_of(sensors->begin(), sensors->end(), [](const Sensor& s) { return s.reason.empty(); });
  if (any)
    if (Status st = Validate(a, format, &*sensors); !st.ok()) return ReportError(kName, st.error());
  PrintTable(*sensors);
  if (!any) return ReportError(kName, InvalidInput(a.input + ": no sensor could be calibrated (reasons above)"));
  Result<std::string> text = WriteFile(a, *sensors);
  if (!text.ok()) return ReportError(kName, text.error());
  if (Status st = WriteModels(a, *sensors); !st.ok()) return ReportError(kName, st.error());
  if (Status st = WriteText(a.output, *text); !st.ok()) return ReportError(kName, st.error());
  nlohmann::json j = {{"input", a.input}, {"format", a.format}, {"output", a.output}, {"fit_rate_hz", a.fit_rate_hz},
                      {"min_span_c", a.min_span_c}, {"optimised_for", a.optimise_for},
                      {"static_weight", a.static_weight}};
  j["models_dir"] = a.models_dir.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.models_dir);
  j["inputs"] = a.inputs;
  j["validation_run"] = a.validation_path.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.validation_path);
  j["block_s"] = a.block_s;
  j["sensors"] = nlohmann::json::array();
  for (const Sensor& s : *sensors) j["sensors"].push_back(SensorJson(a, s));
  if (!a.json_path.empty())
    if (Status st = WriteJson(a.json_path, j); !st.ok()) return ReportError(kName, st.error());
  if (!a.report_path.empty()) {
    const ReportData report = BuildCalibrateReport(j, CubicCurves(*sensors));
    if (Status st = WriteText(a.report_path, RenderReportHtml(report)); !st.ok()) return ReportError(kName, st.error());
  }
  Note(kName, "-> " + a.output);
  return kExitOk;
}

Command Make(CLI::App& app) {
  auto a = std::make_shared<CalibrateArgs>();
  CLI::App* sub = app.add_subcommand(kName, "Thermal calibration of every IMU sensor of a flight log, as one parameter file");
  sub->footer(
      "px4 (ULog): every sensor_gyro, sensor_accel and sensor_baro instance -> TC_G / TC_A / TC_B slots by\n"
      "  device_id, all four slots of each kind written (unused: ID 0), TC_x_ENABLE. QGroundControl format.\n"
      "ardupilot (DataFlash): every IMU, rotated back by AHRS_ORIENTATION and with any INS_TCAL correction the\n"
      "  log ran undone -> INS_TCAL1..3 ENABLE, TMIN, TMAX, ACC1..3, GYR1..3 (an IMU not calibrated: ENABLE 0).\n"
      "A sensor that cannot be calibrated (span < --min-span, too few rows) is listed with the reason.\n"
      "Expected error: per axis, the cubic's expected next-run RMS at steady temperature and on the run's warm-up\n"
      "  (the model's prediction band and the projection). --validation RUN: the cubics, with the firmware's\n"
      "  formula, and the full model scored on RUN (RMS of --block s means, mean removed).\n"
      "Example: gyrocomp calibrate -i heat.ulg --format px4 -o tc.params --models models/ --json cal.json\n"
      "           --validation cool.ulg --report cal.html");
  AddInputOption(sub, "-i,--input", &a->inputs,
                 "Flight log: PX4 ULog or ArduPilot DataFlash; repeated: runs of the same board, each sensor's cubics "
                 "averaged over them (models and bands from the first)")
      ->required();
  sub->add_option("--format", a->format, "px4 | ardupilot")->required()->check(CLI::IsMember({"px4", "ardupilot"}));
  AddOutputOption(sub, "-o,--output", &a->output, "Parameter file to write")->required();
  sub->add_option("--models", a->models_dir, "Directory for each sensor's model file (<type><instance>.json) for apply / validate / export");
  AddOutputOption(sub, "--json", &a->json_path, "Write the per-sensor summary as JSON ('-' = stdout)");
  AddInputOption(sub, "--validation", &a->validation_path,
                 "A second log of the same board (same format as -i): every exported cubic (firmware formula) and "
                 "the full model scored on it, per axis");
  AddOutputOption(sub, "--report", &a->report_path, "Write an HTML report to FILE (self-contained, opens offline)");
  sub->add_option("--block", a->block_s, "--validation: residual block means, s")->capture_default_str();
  sub->add_option("--fit-rate", a->fit_rate_hz, "Rows per second the fit sees (block means), Hz")->capture_default_str();
  sub->add_option("--optimise-for", a->optimise_for,
                  "What the exported cubic is optimised for: steady (dT/dt = 0, the static curve) | warm-up (the state the "
                  "run had while heating, at each temperature) | both (their mean)")
      ->check(CLI::IsMember({"steady", "warm-up", "both"}))
      ->capture_default_str();
  sub->add_option("--static-weight", a->static_weight,
                  "How the static curve is estimated: auto (per axis, the one of the two below with the lower "
                  "expected next-run error: a left-out dT/dt gain against the holds' information) | temperature (each "
                  "temperature alike: the run's data with the model's dynamic part removed, in 2000 equal temperature "
                  "bins, as PX4's script bins) | time (the fitted model's curve, every sample alike)")
      ->check(CLI::IsMember({"auto", "temperature", "time"}))
      ->capture_default_str();
  sub->add_option("--min-span", a->min_span_c, "Smallest temperature span calibrated, deg C (ArduPilot's TEMP_RANGE_MIN)")
      ->capture_default_str();
  return {sub, [a] {
            a->input = a->inputs.front();
            return Run(*a);
          }};
}

const CommandRegistrar kReg(kName, 67, &Make);

}  // namespace
}  // namespace gyrocomp::cli
