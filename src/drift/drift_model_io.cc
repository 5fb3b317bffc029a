// The drift model file: JSON with a format name and a schema version (see drift_model.h).
// Writes version 2 (a list of per-axis models); reads versions 1 (drift_model_io_v1.cc) and 2.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

#include "gyrocomp/io/io.h"
#include "model_file_reader.h"

namespace gyrocomp {
namespace {

using drift_internal::json;
using drift_internal::kModelFormat;
using drift_internal::Reader;

// Version 2 "training": the fit summary without timings (reproducible files).
json SummaryJson(const DriftFitSummary& s) {
  json cands = json::array();
  for (const DriftCandidateScore& c : s.candidates)
    cands.push_back({{"name", c.name},
                     {"kind", DriftModelKindName(c.kind)},
                     {"inputs", DriftInputSetName(c.inputs)},
                     {"cv_rmse", std::isfinite(c.cv_rmse) ? json(c.cv_rmse) : json()},
                     {"note", c.note}});
  json j = {{"model", DriftModelKindName(s.model)},
            {"inputs", DriftInputSetName(s.inputs)},
            {"target", s.target_name},
            {"num_samples", s.num_samples},
            {"fs_hz", s.fs_hz},
            {"duration_s", s.duration_s},
            {"num_train", s.num_train},
            {"train_period_s", s.train_period_s},
            {"temp_min_c", s.temp_min_c},
            {"temp_max_c", s.temp_max_c},
            {"dtemp_min_c_per_s", s.dtemp_min_c_per_s},
            {"dtemp_max_c_per_s", s.dtemp_max_c_per_s},
            {"state_min", s.state_min},
            {"state_max", s.state_max},
            {"cv_scheme", DriftCvSchemeName(s.cv_scheme)},
            {"cv_segments", s.cv_segments},
            {"cv_folds", s.cv_folds},
            {"cv_rmse", s.cv_rmse},
            {"cv_in_range_only", s.cv_in_range_only},
            {"train_rmse", s.train_rmse},
            {"evaluations", s.evaluations},
            {"generations", s.generations},
            {"best_cv_history", s.best_cv_history},
            {"candidates", cands},
            {"selection_reason", s.selection_reason},
            {"identifiability", s.identifiability}};
  // The excluded terms (optional on reading: older files have none).
  json excluded = json::array();
  for (const ExcludedTerm& e : s.excluded_terms)
    excluded.push_back({{"term", e.term}, {"reason", e.reason}, {"would_identify", e.would_identify}});
  j["excluded_terms"] = excluded;
  j["data_support"] = s.data_support;
  j["drift_span"] = s.drift_span;
  if (s.C) {
    j["C"] = *s.C;
    j["gamma"] = *s.gamma;
    j["sigma"] = *s.sigma;
    j["epsilon"] = *s.epsilon;
    j["num_support"] = s.num_support;
  }
  if (s.model == DriftModelKind::kPolynomial || s.model == DriftModelKind::kHybrid) {
    j["degree"] = s.degree;
    j["dtemp_degree"] = s.dtemp_degree;
    if (s.gain_temp_degree > 0) j["gain_temp_degree"] = s.gain_temp_degree;
  }
  return j;
}

const char* StateType(DriftInputSet in) {
  switch (in) {
    case DriftInputSet::kTemp: return "none";
    case DriftInputSet::kTempAndRate: return "rate";
    case DriftInputSet::kTempAndLag: return "lag";
    case DriftInputSet::kTempAndMemory: return "memory";
    case DriftInputSet::kTempRateAndMemory: return "rate+memory";
  }
  return "none";
}

// The state's definition, complete for a firmware evaluator (thermal_state.h, Eqs. TS-1..3).
json ThermalStateJson(const DriftModel& m) {
  json j = {{"type", StateType(m.inputs)}, {"column", ThermalStateColumnName(m.inputs)}};
  switch (m.inputs) {
    case DriftInputSet::kTemp: break;
    case DriftInputSet::kTempAndRate:
      j["batch"] = "centred least-squares slope over window_s (apply default)";
      j["window_s"] = m.rate.window_s;
      j["causal_rate_tau_s"] = m.state.causal_rate_tau_s;
      j["update"] = "a = 1 - exp(-dt/tau_r); L1 += a (T - L1); L2 += a (L1 - L2); s = (L1 - L2) / d, "
                    "d = dt / (exp(dt/tau_r) - 1); "
                    "L1 = L2 = T at the first sample";
      break;
    case DriftInputSet::kTempAndLag:
      j["lag_tau_s"] = m.state.lag_tau_s;
      j["update"] = "a = 1 - exp(-dt/tau); T_lag += a (T - T_lag); s = T - T_lag; T_lag = T at the first sample";
      break;
    case DriftInputSet::kTempAndMemory:
      j["causal_rate_tau_s"] = m.state.causal_rate_tau_s;
      j["memory_width_c"] = m.state.memory_width_c;
      j["memory_deadband_c_per_s"] = m.state.memory_deadband_c_per_s;
      j["update"] = "r from the rate update (L1, L2, tau_r); if |r| > deadband: m += min(1, |r| dt / width) "
                    "(sign(r) - m); s = m; m = 0 at the first sample";
      break;
    case DriftInputSet::kTempRateAndMemory:  // both states, Eqs. TS-1 and TS-3
      j["memory_column"] = kMemoryColumnName;
      j["batch"] = "s: centred least-squares slope over window_s (apply default); m: always causal";
      j["window_s"] = m.rate.window_s;
      j["causal_rate_tau_s"] = m.state.causal_rate_tau_s;
      j["memory_width_c"] = m.state.memory_width_c;
      j["memory_deadband_c_per_s"] = m.state.memory_deadband_c_per_s;
      j["update"] = "a = 1 - exp(-dt/tau_r); L1 += a (T - L1); L2 += a (L1 - L2); r = (L1 - L2) / d, "
                    "d = dt / (exp(dt/tau_r) - 1); s = r; if |r| > deadband: m += min(1, |r| dt / width) "
                    "(sign(r) - m); L1 = L2 = T, m = 0 at the first sample";
      break;
  }
  return j;
}

json AxisJson(const DriftModel& m) {
  json j;
  j["rate_col"] = m.rate_col;
  j["unit"] = m.unit;
  j["target"] = m.summary.target_name;
  j["kind"] = DriftModelKindName(m.kind);
  j["inputs"] = m.inputs == DriftInputSet::kTemp ? json::array({"temp_c"})
                                                 : json::array({"temp_c", ThermalStateColumnName(m.inputs)});
  if (HasSecondMemoryState(m.inputs)) j["inputs"].push_back(kMemoryColumnName);
  j["thermal_state"] = ThermalStateJson(m);
  j["out_of_range"] = {{"policy", OutOfRangePolicyName(m.out_of_range)},
                       {"temp_min_c", m.summary.temp_min_c},
                       {"temp_max_c", m.summary.temp_max_c}};
  j["prediction"] = "structured(T_eff, s) + svr(T_eff, s); an absent part is 0; T_eff = T, or T clamped to "
                    "[temp_min_c, temp_max_c] when the policy is clamp";
  j["structured"] = json();
  if (const auto& p = m.structured) {
    json terms = json::array();
    for (const PolynomialTerm& t : p->terms) {
      terms.push_back({{"temp_power", t.temp_power}, {"dtemp_power", t.dtemp_power}, {"coefficient", t.coefficient}});
      if (t.memory_power) terms.back()["memory_power"] = t.memory_power;  // optional
    }
    const bool mem = HasSecondMemoryState(m.inputs);
    j["structured"] = {{"type", "polynomial"},
                       {"variables", mem ? "t = (temp_c - input_offset[0]) / input_scale[0], "
                                           "r = (state - input_offset[1]) / input_scale[1], "
                                           "m = (memory - input_offset[2]) / input_scale[2]; "
                                           "sum coefficient t^temp_power r^dtemp_power m^memory_power (memory_power absent: 0)"
                                         : "t = (temp_c - input_offset[0]) / input_scale[0], "
                                           "r = (state - input_offset[1]) / input_scale[1]; sum coefficient t^temp_power r^dtemp_power"},
                       {"input_offset", p->input_scaler.offset},
                       {"input_scale", p->input_scaler.scale},
                       {"terms", terms}};
  }
  j["svr"] = json();
  if (const auto& s = m.kernel) {
    json svs = json::array();
    for (std::size_t i = 0; i < s->num_support(); ++i)
      svs.push_back(std::vector<double>(s->support_vectors.begin() + i * s->num_inputs,
                                        s->support_vectors.begin() + (i + 1) * s->num_inputs));
    j["svr"] = {{"type", "epsilon-svr"},
                {"kernel", "target_offset + target_scale (intercept + sum coefficients[i] exp(-gamma |z - sv_i|^2)), "
                           "z = (input - input_offset) / input_scale"},
                {"input_offset", s->input_scaler.offset},
                {"input_scale", s->input_scaler.scale},
                {"target_offset", s->target_offset},
                {"target_scale", s->target_scale},
                {"gamma", s->gamma},
                {"intercept", s->intercept},
                {"coefficients", s->coefficients},
                {"support_vectors", svs}};
  }
  j["training"] = SummaryJson(m.summary);
  if (const auto& b = m.band) {
    const std::size_t p = m.structured ? m.structured->terms.size() : 0;
    json cov = json::array();
    for (std::size_t r = 0; r < p && b->parameter_cov.size() == p * p; ++r)
      cov.push_back(std::vector<double>(b->parameter_cov.begin() + r * p, b->parameter_cov.begin() + (r + 1) * p));
    j["band"] = {{"level", b->level},
                 {"parameter_cov", cov},
                 {"noise", {{"white", b->noise.h0}, {"flicker", b->noise.h_1}, {"random_walk", b->noise.h_2}}},
                 {"model_form_rms", b->model_form_rms},
                 {"expected_rms", b->expected_rms},
                 {"unidentified_rate_gain_rms", b->unidentified_rate_gain_rms},
                 {"calibration_rate_vs_temp", {{"offset_c", b->calibration_rate_vs_temp.offset_c},
                                               {"scale_c", b->calibration_rate_vs_temp.scale_c},
                                               {"coefficients", b->calibration_rate_vs_temp.coefficients}}},
                 {"unseen_direction", b->unseen_direction},
                 {"coverage_check", b->coverage_check},
                 {"equation", "var_i = a_i' parameter_cov a_i + model_form_rms^2, a_i = the structured terms at sample i "
                              "(standardised inputs), + (unidentified_rate_gain_rms d_i)^2 with d_i = the sample's dT/dt - "
                              "sum coefficients[k] ((T - offset_c) / scale_c)^k of calibration_rate_vs_temp, + s_i^2 on a sample whose dT/dt "
                              "has the sign unseen_direction (+1 heating, -1 cooling), s_i = the structured prediction at its "
                              "dT/dt minus that at dT/dt = 0; band = prediction +- z(level) sqrt(var_i); noise: one-sided PSD "
                              "white + flicker / f + random_walk / f^2"}};
  }
  return j;
}

// "format" and "schema_version": a file of another format or version is refused before any
// other field is read. Returns the version (1 or 2).
Result<int> CheckFormatAndVersion(const json& j, const std::string& source) {
  if (!j.is_object() || !j.contains("format") || j["format"] != kModelFormat)
    return InvalidInput(source + ": not a gyrocomp drift model (field 'format' is not \"" +
                        std::string(kModelFormat) + "\")");
  if (!j.contains("schema_version") || !j["schema_version"].is_number_integer())
    return InvalidInput(source + ": missing integer field 'schema_version'");
  const long version = j["schema_version"].get<long>();
  if (version != 1 && version != kDriftModelSchemaVersion)
    return Unsupported(source + ": model file schema version " + std::to_string(version) +
                       ", this gyrocomp reads versions 1 and " + std::to_string(kDriftModelSchemaVersion) +
                       (version < 1 ? "" : " (a newer file: update gyrocomp)"));
  return static_cast<int>(version);
}

std::size_t ReadInputsV2(Reader& r, const json& axis, DriftModel* m) {
  const json* inputs = r.Get(axis, "inputs", "inputs");
  if (!inputs) return 0;
  for (DriftInputSet in : {DriftInputSet::kTemp, DriftInputSet::kTempAndRate, DriftInputSet::kTempAndLag,
                           DriftInputSet::kTempAndMemory, DriftInputSet::kTempRateAndMemory}) {
    json want = in == DriftInputSet::kTemp ? json::array({"temp_c"})
                                           : json::array({"temp_c", ThermalStateColumnName(in)});
    if (HasSecondMemoryState(in)) want.push_back(kMemoryColumnName);
    if (*inputs == want) {
      m->inputs = in;
      return want.size();
    }
  }
  r.Fail("field 'inputs' must be [\"temp_c\"], [\"temp_c\", \"dtemp_c_per_s\" | \"lag_excess_c\" | \"memory\"] or "
         "[\"temp_c\", \"dtemp_c_per_s\", \"memory\"]");
  return 0;
}

void ReadThermalState(Reader& r, const json& ts, DriftModel* m) {
  if (std::string(StateType(m->inputs)) != r.String(ts, "type", "thermal_state.type"))
    return r.Fail("field 'thermal_state.type' does not match 'inputs'");
  if (m->inputs == DriftInputSet::kTempAndRate) {
    m->rate.window_s = r.Number(ts, "window_s", "thermal_state.window_s");
    m->state.causal_rate_tau_s = r.Number(ts, "causal_rate_tau_s", "thermal_state.causal_rate_tau_s");
  } else if (m->inputs == DriftInputSet::kTempAndLag) {
    m->state.lag_tau_s = r.Number(ts, "lag_tau_s", "thermal_state.lag_tau_s");
    m->summary.lag_tau_s = m->state.lag_tau_s;
  } else if (m->inputs == DriftInputSet::kTempAndMemory || m->inputs == DriftInputSet::kTempRateAndMemory) {
    if (m->inputs == DriftInputSet::kTempRateAndMemory)
      m->rate.window_s = r.Number(ts, "window_s", "thermal_state.window_s");
    m->state.causal_rate_tau_s = r.Number(ts, "causal_rate_tau_s", "thermal_state.causal_rate_tau_s");
    m->state.memory_width_c = r.Number(ts, "memory_width_c", "thermal_state.memory_width_c");
    m->state.memory_deadband_c_per_s = r.Number(ts, "memory_deadband_c_per_s", "thermal_state.memory_deadband_c_per_s");
  }
  std::string why;
  if (r.ok() && (!m->rate.IsValid(&why) || !m->state.IsValid(&why))) r.Fail("thermal_state: " + why);
}

// "band" (docs/reference/model-file.md "The band"): level in (0, 1), a terms x terms covariance,
// noise and spreads >= 0.
void ReadBand(Reader& r, const json& band, DriftModel* m) {
  if (!band.is_object()) return r.Fail("field 'band' must be an object");
  DriftBandModel b;
  b.level = r.Number(band, "level", "band.level");
  const json* cov = r.Get(band, "parameter_cov", "band.parameter_cov");
  const json* noise = r.Get(band, "noise", "band.noise");
  b.model_form_rms = r.Number(band, "model_form_rms", "band.model_form_rms");
  b.coverage_check = r.String(band, "coverage_check", "band.coverage_check");
  if (band.contains("expected_rms")) b.expected_rms = r.Number(band, "expected_rms", "band.expected_rms");
  if (band.contains("unidentified_rate_gain_rms"))
    b.unidentified_rate_gain_rms = r.Number(band, "unidentified_rate_gain_rms", "band.unidentified_rate_gain_rms");
  if (band.contains("unseen_direction")) {
    const double u = r.Number(band, "unseen_direction", "band.unseen_direction");
    if (r.ok() && u != -1.0 && u != 0.0 && u != 1.0) return r.Fail("field 'band.unseen_direction' must be -1, 0 or 1");
    b.unseen_direction = static_cast<int>(u);
  }
  if (band.contains("calibration_rate_vs_temp")) {
    const json& c = band["calibration_rate_vs_temp"];
    b.calibration_rate_vs_temp.offset_c = r.Number(c, "offset_c", "band.calibration_rate_vs_temp.offset_c");
    b.calibration_rate_vs_temp.scale_c = r.Number(c, "scale_c", "band.calibration_rate_vs_temp.scale_c");
    b.calibration_rate_vs_temp.coefficients = r.Numbers(c, "coefficients", "band.calibration_rate_vs_temp.coefficients");
    if (r.ok() && !(b.calibration_rate_vs_temp.scale_c > 0.0))
      return r.Fail("field 'band.calibration_rate_vs_temp.scale_c' must be > 0");
  }
  if (!r.ok()) return;
  b.noise.h0 = r.Number(*noise, "white", "band.noise.white");
  b.noise.h_1 = r.Number(*noise, "flicker", "band.noise.flicker");
  b.noise.h_2 = r.Number(*noise, "random_walk", "band.noise.random_walk");
  if (!r.ok()) return;
  if (!(b.level > 0.0 && b.level < 1.0)) return r.Fail("field 'band.level' must be in (0, 1)");
  if (!(b.model_form_rms >= 0.0) || !std::isfinite(b.model_form_rms) || !(b.noise.h0 >= 0.0) ||
      !(b.noise.h_1 >= 0.0) || !(b.noise.h_2 >= 0.0) || !(b.unidentified_rate_gain_rms >= 0.0) ||
      !std::isfinite(b.unidentified_rate_gain_rms))
    return r.Fail("fields 'band.model_form_rms' and 'band.noise.*' must be finite and >= 0");
  const std::size_t p = m->structured ? m->structured->terms.size() : 0;
  if (!cov->is_array() || cov->size() != p) return r.Fail("field 'band.parameter_cov' must be " + std::to_string(p) + " x " + std::to_string(p));
  for (const json& row : *cov) {
    if (!row.is_array() || row.size() != p) return r.Fail("field 'band.parameter_cov' must be " + std::to_string(p) + " x " + std::to_string(p));
    for (const json& v : row) {
      if (!v.is_number() || !std::isfinite(v.get<double>())) return r.Fail("field 'band.parameter_cov' holds a non-number");
      b.parameter_cov.push_back(v.get<double>());
    }
  }
  m->band = std::move(b);
}

Result<DriftModel> ReadAxis(const json& axis, const std::string& where) {
  Reader r(where);
  DriftModel m;
  m.rate_col = r.String(axis, "rate_col", "rate_col");
  m.unit = r.String(axis, "unit", "unit");
  const auto kind = ParseDriftModelKind(r.String(axis, "kind", "kind"));
  if (r.ok() && (!kind || *kind == DriftModelKind::kAuto)) r.Fail("field 'kind' must be poly, svr, grid-svr, cs-svr or hybrid");
  const std::size_t num_inputs = ReadInputsV2(r, axis, &m);
  const json* ts = r.Get(axis, "thermal_state", "thermal_state");
  const json* oor = r.Get(axis, "out_of_range", "out_of_range");
  const json* structured = r.Get(axis, "structured", "structured");
  const json* svr = r.Get(axis, "svr", "svr");
  const json* training = r.Get(axis, "training", "training");
  if (!r.ok()) return InvalidInput(r.error());
  m.kind = *kind;
  ReadThermalState(r, *ts, &m);
  const auto policy = ParseOutOfRangePolicy(r.String(*oor, "policy", "out_of_range.policy"));
  if (r.ok() && !policy) r.Fail("field 'out_of_range.policy' must be \"extrapolate\" or \"clamp\"");
  if (policy) m.out_of_range = *policy;
  const bool want_poly = m.kind == DriftModelKind::kPolynomial || m.kind == DriftModelKind::kHybrid;
  const bool want_svr = m.kind != DriftModelKind::kPolynomial;
  if (r.ok() && (want_poly != structured->is_object() || want_svr != svr->is_object()))
    r.Fail("fields 'structured' / 'svr' do not match kind \"" + std::string(DriftModelKindName(m.kind)) + "\"");
  if (r.ok() && want_poly)
    m.structured = drift_internal::ReadPolynomialModel(
        r, *structured, drift_internal::ReadInputScaler(r, *structured, num_inputs, "structured"), num_inputs,
        "structured");
  if (r.ok() && want_svr)
    m.kernel = drift_internal::ReadSvrModel(r, *svr, *svr, drift_internal::ReadInputScaler(r, *svr, num_inputs, "svr"),
                                            num_inputs, "svr");
  m.summary.model = m.kind;
  m.summary.inputs = m.inputs;
  if (r.ok()) drift_internal::ReadTrainingSummary(r, *training, 2, want_poly, want_svr, &m.summary);
  if (r.ok() && m.inputs == DriftInputSet::kTempAndLag) m.summary.lag_tau_s = m.state.lag_tau_s;
  if (r.ok() && !(m.summary.temp_min_c <= m.summary.temp_max_c)) r.Fail("training.temp_min_c > training.temp_max_c");
  if (r.ok() && axis.contains("band")) ReadBand(r, axis["band"], &m);  // optional: older files have none
  if (!r.ok()) return InvalidInput(r.error());
  return m;
}

}  // namespace

const DriftModel* DriftModelSet::Find(std::string_view rate_col) const {
  for (const DriftModel& m : axes)
    if (m.rate_col == rate_col) return &m;
  return nullptr;
}

const DriftModel* DriftModelSet::ForAxis(std::string_view rate_col) const {
  if (const DriftModel* m = Find(rate_col)) return m;
  return axes.size() == 1 ? &axes[0] : nullptr;
}

namespace {

// The top-level "sensor" key (docs/reference/model-file.md; SensorIdentity in drift_model.h).
json SensorIdentityJson(const SensorIdentity& s) {
  json j = {{"type", s.type}, {"instance", s.instance}, {"frame", s.frame}};
  if (s.device_id) j["device_id"] = *s.device_id;
  return j;
}

Result<SensorIdentity> ReadSensorIdentity(const json& j, const std::string& where) {
  SensorIdentity s;
  if (!j.is_object()) return InvalidInput(where + ": must be an object");
  if (!j.contains("type") || !j["type"].is_string() ||
      (j["type"] != "gyro" && j["type"] != "accel" && j["type"] != "baro"))
    return InvalidInput(where + ": field 'type' must be \"gyro\", \"accel\" or \"baro\"");
  s.type = j["type"].get<std::string>();
  if (!j.contains("instance") || !j["instance"].is_number_unsigned() || j["instance"].get<std::uint64_t>() > 255)
    return InvalidInput(where + ": field 'instance' must be an integer in 0..255");
  s.instance = static_cast<int>(j["instance"].get<std::uint64_t>());
  if (j.contains("device_id")) {
    const json& id = j["device_id"];
    if (!id.is_number_unsigned() || id.get<std::uint64_t>() == 0 || id.get<std::uint64_t>() > 0xFFFFFFFFull)
      return InvalidInput(where + ": field 'device_id' must be an integer in 1..4294967295");
    s.device_id = static_cast<std::uint32_t>(id.get<std::uint64_t>());
  }
  if (j.contains("frame")) {
    if (!j["frame"].is_string()) return InvalidInput(where + ": field 'frame' must be a string");
    s.frame = j["frame"].get<std::string>();
  }
  return s;
}

}  // namespace

std::string DriftModelSetToJson(const DriftModelSet& models) {
  json j;
  j["format"] = kModelFormat;
  j["schema_version"] = kDriftModelSchemaVersion;
  j["axes"] = json::array();
  for (const DriftModel& m : models.axes) j["axes"].push_back(AxisJson(m));
  if (models.device_id) j["device_id"] = *models.device_id;
  if (models.sensor) j["sensor"] = SensorIdentityJson(*models.sensor);
  return j.dump(1) + "\n";
}

std::string DriftModelToJson(const DriftModel& model) { return DriftModelSetToJson(DriftModelSet{{model}, std::nullopt, std::nullopt}); }

namespace {

// Records the first error of a SAX parse (nlohmann's public json_sax interface): where the parser
// stopped (chars read, 1-based) and why, number overflows (out_of_range.406) included.
struct FirstJsonError : nlohmann::json_sax<json> {
  std::size_t position = 0;
  std::string what;
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t pos, const std::string&, const nlohmann::detail::exception& e) override {
    position = pos;
    what = e.what();
    return false;
  }
};

// "file:line:column: not valid JSON (why)", the place the parser stopped at and its reason
// without nlohmann's "[json.exception...] parse error at ...: " prefix. Only on the error path.
Error NotJson(std::string_view text, const std::string& source) {
  FirstJsonError sax;
  json::sax_parse(text.begin(), text.end(), &sax);
  const std::size_t at = std::min<std::size_t>(sax.position > 0 ? sax.position - 1 : 0, text.size());
  std::size_t line = 1;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < at; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  std::string why = sax.what;  // "[json.exception.<id>] " then "parse error at line L, column C: " or not
  if (const std::size_t tag = why.find("] "); !why.empty() && why.front() == '[' && tag != std::string::npos) {
    why.erase(0, tag + 2);
  }
  if (const std::size_t colon = why.find(": "); why.rfind("parse error", 0) == 0 && colon != std::string::npos) {
    why.erase(0, colon + 2);
  }
  return InvalidInput(source + ":" + std::to_string(line) + ":" + std::to_string(at - line_start + 1) +
                      ": not valid JSON (" + why + ")");
}

}  // namespace

Result<DriftModelSet> DriftModelSetFromJson(std::string_view text, const std::string& source) {
  json j = json::parse(text.begin(), text.end(), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return NotJson(text, source);
  auto version = CheckFormatAndVersion(j, source);
  if (!version.ok()) return version.error();
  DriftModelSet set;
  if (*version == 1) {
    auto m = drift_internal::ReadVersion1(j, source);
    if (!m.ok()) return m.error();
    set.axes.push_back(std::move(*m));
    return set;
  }
  if (!j.contains("axes") || !j["axes"].is_array() || j["axes"].empty())
    return InvalidInput(source + ": field 'axes' must be a non-empty array");
  if (j.contains("device_id")) {
    const json& id = j["device_id"];
    if (!id.is_number_unsigned() || id.get<std::uint64_t>() == 0 || id.get<std::uint64_t>() > 0xFFFFFFFFull)
      return InvalidInput(source + ": field 'device_id' must be an integer in 1..4294967295");
    set.device_id = static_cast<std::uint32_t>(id.get<std::uint64_t>());
  }
  if (j.contains("sensor")) {
    auto sensor = ReadSensorIdentity(j["sensor"], source + ": sensor");
    if (!sensor.ok()) return sensor.error();
    set.sensor = *sensor;
  }
  for (std::size_t k = 0; k < j["axes"].size(); ++k) {
    auto m = ReadAxis(j["axes"][k], source + ": axes[" + std::to_string(k) + "]");
    if (!m.ok()) return m.error();
    if (set.Find(m->rate_col))
      return InvalidInput(source + ": axes[" + std::to_string(k) + "]: rate_col '" + m->rate_col + "' appears twice");
    set.axes.push_back(std::move(*m));
  }
  return set;
}

Result<DriftModel> DriftModelFromJson(std::string_view text, const std::string& source) {
  auto set = DriftModelSetFromJson(text, source);
  if (!set.ok()) return set.error();
  if (set->axes.size() != 1) {
    std::string names;
    for (const DriftModel& m : set->axes) names += (names.empty() ? "" : ", ") + m.rate_col;
    return InvalidInput(source + ": holds models for " + std::to_string(set->axes.size()) + " axes (" + names +
                        "); read it as a model set");
  }
  return std::move(set->axes[0]);
}

namespace drift_internal {

Status CheckModelLoads(const DriftModel& model) {
  Result<DriftModelSet> back = DriftModelSetFromJson(DriftModelToJson(model), "model");
  if (back.ok()) return Status::Ok();
  return InvalidInput("the fit gives a model that a model file cannot hold (" + back.error().message +
                      "): the target or temperature values are beyond what a drift model represents");
}

}  // namespace drift_internal

Status SaveDriftModelSet(const DriftModelSet& models, const std::string& path) {
  return WriteTextAtomic(path, DriftModelSetToJson(models));
}

Status SaveDriftModel(const DriftModel& model, const std::string& path) {
  return WriteTextAtomic(path, DriftModelToJson(model));
}

Result<DriftModelSet> LoadDriftModelSet(const std::string& path) {
  // Read with a size limit, whatever the file is (/dev/zero, a FIFO, a huge file): a model
  // file is a few MB at most (/dev/zero was read until std::bad_alloc).
  constexpr std::size_t kMaxModelFileBytes = std::size_t{64} << 20;
  std::ifstream in(path, std::ios::binary);
  if (!in) return IoError(path + ": cannot open model file");
  std::string text;
  char chunk[1 << 16];
  bool start_checked = false;
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    const std::size_t before = text.size();
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
    const std::size_t first = start_checked ? std::string::npos : text.find_first_not_of(" \t\r\n", before);
    if (first != std::string::npos) start_checked = true;
    if (first != std::string::npos && text[first] != '{') {
      char byte[8];
      std::snprintf(byte, sizeof byte, "0x%02x", static_cast<unsigned char>(text[first]));
      return InvalidInput(path + ": byte " + std::to_string(first) + " is " + byte +
                          ": not a JSON model file (it must start with '{')");
    }
    if (text.size() > kMaxModelFileBytes) {
      return InvalidInput(path + ": larger than " + std::to_string(kMaxModelFileBytes >> 20) +
                          " MiB: not a model file (a model file is a few MB at most)");
    }
  }
  if (in.bad()) return IoError(path + ": cannot read model file");
  return DriftModelSetFromJson(text, path);
}

Result<DriftModel> LoadDriftModel(const std::string& path) {
  auto set = LoadDriftModelSet(path);
  if (!set.ok()) return set.error();
  if (set->axes.size() != 1)
    return InvalidInput(path + ": holds models for " + std::to_string(set->axes.size()) +
                        " axes; read it with LoadDriftModelSet");
  return std::move(set->axes[0]);
}

}  // namespace gyrocomp
