// The drift model file: JSON with a format name and a schema version (see drift_model.h).
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "drift_model_internal.h"
#include "gyrocomp/io/io.h"

namespace gyrocomp {
namespace {

using nlohmann::json;
constexpr const char* kFormat = "gyrocomp-drift-model";

json SummaryJson(const DriftFitSummary& s) {
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
            {"cv_folds", s.cv_folds},
            {"cv_rmse", s.cv_rmse},
            {"cv_in_range_only", s.cv_in_range_only},
            {"train_rmse", s.train_rmse},
            {"evaluations", s.evaluations},
            {"generations", s.generations},
            {"best_cv_history", s.best_cv_history}};
  // No fit_time_s: a model file is reproducible, byte for byte (issue 15); timings are in --json.
  if (s.C) {
    j["C"] = *s.C;
    j["gamma"] = *s.gamma;
    j["sigma"] = *s.sigma;
    j["epsilon"] = *s.epsilon;
    j["num_support"] = s.num_support;
  } else {
    j["degree"] = s.degree;
    j["dtemp_degree"] = s.dtemp_degree;
  }
  return j;
}

// Typed field access that reports the field's path on failure.
// Largest magnitude of any number a model file may hold: no coefficient, scale or support-vector
// value of a gyro drift model comes near it, and a model that holds 1e308 overflows on use.
constexpr double kMaxModelValue = 1e100;

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}
  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  void Fail(const std::string& what) {
    if (error_.empty()) error_ = source_ + ": " + what;
  }
  const json* Get(const json& obj, const std::string& key, const std::string& path) {
    if (!obj.is_object() || !obj.contains(key)) {
      Fail("missing field '" + path + "'");
      return nullptr;
    }
    return &obj.at(key);
  }
  double Number(const json& obj, const std::string& key, const std::string& path) {
    const json* v = Get(obj, key, path);
    if (!v) return 0.0;
    if (!v->is_number() || !std::isfinite(v->get<double>())) {
      Fail("field '" + path + "' must be a finite number");
      return 0.0;
    }
    if (!(std::abs(v->get<double>()) <= kMaxModelValue)) {
      Fail("field '" + path + "' = " + v->dump() + ": must be a finite number of magnitude <= 1e100");
      return 0.0;
    }
    return v->get<double>();
  }
  long Integer(const json& obj, const std::string& key, const std::string& path) {
    const json* v = Get(obj, key, path);
    if (!v) return 0;
    if (!v->is_number_integer()) {
      Fail("field '" + path + "' must be an integer");
      return 0;
    }
    return v->get<long>();
  }
  std::string String(const json& obj, const std::string& key, const std::string& path) {
    const json* v = Get(obj, key, path);
    if (!v) return "";
    if (!v->is_string()) {
      Fail("field '" + path + "' must be a string");
      return "";
    }
    return v->get<std::string>();
  }
  std::vector<double> Numbers(const json& obj, const std::string& key, const std::string& path) {
    std::vector<double> out;
    const json* v = Get(obj, key, path);
    if (!v) return out;
    if (!v->is_array()) {
      Fail("field '" + path + "' must be an array of numbers");
      return out;
    }
    for (const json& e : *v) {
      if (!e.is_number() || !std::isfinite(e.get<double>())) {
        Fail("field '" + path + "' must be an array of finite numbers");
        return {};
      }
      if (!(std::abs(e.get<double>()) <= kMaxModelValue)) {
        Fail("field '" + path + "' = ... " + e.dump() + " ...: must hold numbers of magnitude <= 1e100");
        return {};
      }
      out.push_back(e.get<double>());
    }
    return out;
  }

 private:
  std::string source_;
  std::string error_;
};

}  // namespace

std::string DriftModelToJson(const DriftModel& m) {
  json j;
  j["format"] = kFormat;
  j["schema_version"] = kDriftModelSchemaVersion;
  j["kind"] = DriftModelKindName(m.kind);
  j["inputs"] = m.inputs == DriftInputSet::kTemp ? json::array({"temp_c"})
                                                 : json::array({"temp_c", "dtemp_c_per_s"});
  j["units"] = {{"temp_c", "deg C"},
                {"dtemp_c_per_s", "deg C / s"},
                {"output", m.summary.target_name == "rate_dps" || m.summary.target_name == "drift-mode"
                               ? "deg/s"
                               : "unit of column " + m.summary.target_name}};
  j["target"] = m.summary.target_name;
  j["temperature_rate"] = {{"method", "centred least-squares slope"}, {"window_s", m.rate.window_s}};
  json model;
  if (const auto* p = std::get_if<PolynomialModel>(&m.model)) {
    j["scaler"] = {{"input_offset", p->input_scaler.offset}, {"input_scale", p->input_scaler.scale}};
    model["type"] = "polynomial";
    model["variables"] = "standardised: t = (temp_c - offset[0]) / scale[0], r = (dtemp - offset[1]) / scale[1]";
    json terms = json::array();
    for (const PolynomialTerm& t : p->terms)
      terms.push_back({{"temp_power", t.temp_power}, {"dtemp_power", t.dtemp_power}, {"coefficient", t.coefficient}});
    model["terms"] = terms;
  } else {
    const SvrModel& s = std::get<SvrModel>(m.model);
    j["scaler"] = {{"input_offset", s.input_scaler.offset},
                   {"input_scale", s.input_scaler.scale},
                   {"target_offset", s.target_offset},
                   {"target_scale", s.target_scale}};
    model["type"] = "epsilon-svr";
    model["kernel"] = "rbf: exp(-gamma |z - sv|^2), z = scaled input";
    model["gamma"] = s.gamma;
    model["intercept"] = s.intercept;
    model["coefficients"] = s.coefficients;
    json svs = json::array();
    for (std::size_t i = 0; i < s.num_support(); ++i)
      svs.push_back(std::vector<double>(s.support_vectors.begin() + i * s.num_inputs,
                                        s.support_vectors.begin() + (i + 1) * s.num_inputs));
    model["support_vectors"] = svs;
  }
  j["model"] = model;
  j["training"] = SummaryJson(m.summary);
  return j.dump(1) + "\n";
}

namespace {

// The file's "format" and "schema_version": a file of another format or version is refused
// before any other field is read.
std::optional<Error> CheckFormatAndVersion(json& j, const std::string& source) {
  if (!j.is_object() || !j.contains("format") || j["format"] != kFormat)
    return InvalidInput(source + ": not a gyrocomp drift model (field 'format' is not \"" +
                        std::string(kFormat) + "\")");
  if (!j.contains("schema_version") || !j["schema_version"].is_number_integer())
    return InvalidInput(source + ": missing integer field 'schema_version'");
  const long version = j["schema_version"].get<long>();
  if (version != kDriftModelSchemaVersion)
    return Unsupported(source + ": model file schema version " + std::to_string(version) +
                       ", this gyrocomp reads version " + std::to_string(kDriftModelSchemaVersion) +
                       (version < kDriftModelSchemaVersion ? " (an older file: refit the model)"
                                                           : " (a newer file: update gyrocomp)"));
  return std::nullopt;
}

// "inputs": sets m->inputs and returns the number of inputs (0 after a failure).
std::size_t ReadInputs(Reader& r, const json& j, DriftModel* m) {
  const json* inputs = r.Get(j, "inputs", "inputs");
  std::size_t num_inputs = 0;
  if (inputs) {
    if (*inputs == json::array({"temp_c"})) {
      m->inputs = DriftInputSet::kTemp;
      num_inputs = 1;
    } else if (*inputs == json::array({"temp_c", "dtemp_c_per_s"})) {
      m->inputs = DriftInputSet::kTempAndRate;
      num_inputs = 2;
    } else {
      r.Fail("field 'inputs' must be [\"temp_c\"] or [\"temp_c\", \"dtemp_c_per_s\"]");
    }
  }
  return num_inputs;
}

// "scaler.input_offset/input_scale": one entry per input, scales > 0.
AffineScaler ReadInputScaler(Reader& r, const json& scaler, std::size_t num_inputs) {
  AffineScaler in_scaler;
  in_scaler.offset = r.Numbers(scaler, "input_offset", "scaler.input_offset");
  in_scaler.scale = r.Numbers(scaler, "input_scale", "scaler.input_scale");
  if (r.ok() && (in_scaler.offset.size() != num_inputs || in_scaler.scale.size() != num_inputs))
    r.Fail("fields 'scaler.input_offset/input_scale' must have one entry per input");
  for (double v : in_scaler.scale)
    if (r.ok() && !(v > 0.0)) r.Fail("field 'scaler.input_scale' must be > 0");
  return in_scaler;
}

// "model" of type "polynomial": its terms, with powers within the model's inputs and degrees.
PolynomialModel ReadPolynomialModel(Reader& r, const json& model, const AffineScaler& in_scaler,
                                    std::size_t num_inputs) {
  PolynomialModel p;
  p.input_scaler = in_scaler;
  const json* terms = r.Get(model, "terms", "model.terms");
  if (terms && !terms->is_array()) r.Fail("field 'model.terms' must be an array");
  if (r.ok()) {
    for (const json& t : *terms) {
      PolynomialTerm term;
      term.temp_power = static_cast<int>(r.Integer(t, "temp_power", "model.terms[].temp_power"));
      term.dtemp_power = static_cast<int>(r.Integer(t, "dtemp_power", "model.terms[].dtemp_power"));
      term.coefficient = r.Number(t, "coefficient", "model.terms[].coefficient");
      if (r.ok() && (term.temp_power < 0 || term.temp_power > 5 || term.dtemp_power < 0 ||
                     term.dtemp_power > 3 || (term.dtemp_power > 0 && num_inputs < 2)))
        r.Fail("a term in 'model.terms' has powers outside the model's inputs and degrees");
      p.terms.push_back(term);
    }
  }
  return p;
}

// "model" of type "epsilon-svr" and the target scaling: one support vector (one value per
// input) per coefficient, gamma > 0.
SvrModel ReadSvrModel(Reader& r, const json& scaler, const json& model, const AffineScaler& in_scaler,
                      std::size_t num_inputs) {
  SvrModel s;
  s.num_inputs = num_inputs;
  s.input_scaler = in_scaler;
  s.target_offset = r.Number(scaler, "target_offset", "scaler.target_offset");
  s.target_scale = r.Number(scaler, "target_scale", "scaler.target_scale");
  s.gamma = r.Number(model, "gamma", "model.gamma");
  s.intercept = r.Number(model, "intercept", "model.intercept");
  s.coefficients = r.Numbers(model, "coefficients", "model.coefficients");
  const json* svs = r.Get(model, "support_vectors", "model.support_vectors");
  if (r.ok() && !(s.gamma > 0.0)) r.Fail("field 'model.gamma' must be > 0");
  if (r.ok() && (!svs->is_array() || svs->size() != s.coefficients.size()))
    r.Fail("field 'model.support_vectors' must have one row per coefficient");
  if (r.ok()) {
    for (const json& row : *svs) {
      if (!row.is_array() || row.size() != num_inputs) {
        r.Fail("each row of 'model.support_vectors' must have one value per input");
        break;
      }
      for (const json& v : row) {
        if (!v.is_number()) {
          r.Fail("field 'model.support_vectors' must hold numbers");
          break;
        }
        s.support_vectors.push_back(v.get<double>());
      }
    }
  }
  return s;
}

// "training": the fit summary (model and inputs come from the already-read fields).
void ReadTrainingSummary(Reader& r, const json& training, bool want_poly, DriftFitSummary* summary) {
  DriftFitSummary& s = *summary;
  s.target_name = r.String(training, "target", "training.target");
  s.num_samples = static_cast<std::size_t>(r.Integer(training, "num_samples", "training.num_samples"));
  s.fs_hz = r.Number(training, "fs_hz", "training.fs_hz");
  s.duration_s = r.Number(training, "duration_s", "training.duration_s");
  s.num_train = static_cast<std::size_t>(r.Integer(training, "num_train", "training.num_train"));
  s.train_period_s = r.Number(training, "train_period_s", "training.train_period_s");
  s.temp_min_c = r.Number(training, "temp_min_c", "training.temp_min_c");
  s.temp_max_c = r.Number(training, "temp_max_c", "training.temp_max_c");
  s.dtemp_min_c_per_s = r.Number(training, "dtemp_min_c_per_s", "training.dtemp_min_c_per_s");
  s.dtemp_max_c_per_s = r.Number(training, "dtemp_max_c_per_s", "training.dtemp_max_c_per_s");
  s.cv_folds = static_cast<int>(r.Integer(training, "cv_folds", "training.cv_folds"));
  s.cv_rmse = r.Number(training, "cv_rmse", "training.cv_rmse");
  s.train_rmse = r.Number(training, "train_rmse", "training.train_rmse");
  if (const json* v = r.Get(training, "cv_in_range_only", "training.cv_in_range_only")) {
    if (v->is_boolean()) s.cv_in_range_only = v->get<bool>();
    else r.Fail("field 'training.cv_in_range_only' must be true or false");
  }
  s.evaluations = r.Integer(training, "evaluations", "training.evaluations");
  s.generations = static_cast<int>(r.Integer(training, "generations", "training.generations"));
  s.best_cv_history = r.Numbers(training, "best_cv_history", "training.best_cv_history");
  if (training.is_object() && training.contains("fit_time_s")) {  // files written before issue 15
    s.fit_time_s = r.Number(training, "fit_time_s", "training.fit_time_s");
  }
  if (want_poly) {
    s.degree = static_cast<int>(r.Integer(training, "degree", "training.degree"));
    s.dtemp_degree = static_cast<int>(r.Integer(training, "dtemp_degree", "training.dtemp_degree"));
  } else {
    s.C = r.Number(training, "C", "training.C");
    s.gamma = r.Number(training, "gamma", "training.gamma");
    s.sigma = r.Number(training, "sigma", "training.sigma");
    s.epsilon = r.Number(training, "epsilon", "training.epsilon");
    s.num_support = static_cast<std::size_t>(r.Integer(training, "num_support", "training.num_support"));
  }
}

}  // namespace

Result<DriftModel> DriftModelFromJson(std::string_view text, const std::string& source) {
  json j = json::parse(text.begin(), text.end(), nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return InvalidInput(source + ": not valid JSON");
  if (auto e = CheckFormatAndVersion(j, source)) return *e;
  // Top-level fields; the first problem found is the one reported.
  Reader r(source);
  DriftModel m;
  const auto kind = ParseDriftModelKind(r.String(j, "kind", "kind"));
  if (r.ok() && !kind) r.Fail("field 'kind' must be poly, svr, grid-svr or cs-svr");
  const std::size_t num_inputs = ReadInputs(r, j, &m);
  const json* rate = r.Get(j, "temperature_rate", "temperature_rate");
  if (rate) m.rate.window_s = r.Number(*rate, "window_s", "temperature_rate.window_s");
  const json* scaler = r.Get(j, "scaler", "scaler");
  const json* model = r.Get(j, "model", "model");
  const json* training = r.Get(j, "training", "training");
  if (!r.ok()) return InvalidInput(r.error());
  m.kind = *kind;

  const AffineScaler in_scaler = ReadInputScaler(r, *scaler, num_inputs);
  const std::string type = r.String(*model, "type", "model.type");
  const bool want_poly = m.kind == DriftModelKind::kPolynomial;
  if (r.ok() && want_poly != (type == "polynomial"))
    r.Fail("field 'model.type' = \"" + type + "\" does not match kind \"" + DriftModelKindName(m.kind) + "\"");
  if (r.ok() && want_poly) {
    m.model = ReadPolynomialModel(r, *model, in_scaler, num_inputs);
  } else if (r.ok()) {
    m.model = ReadSvrModel(r, *scaler, *model, in_scaler, num_inputs);
  }

  m.summary.model = m.kind;
  m.summary.inputs = m.inputs;
  ReadTrainingSummary(r, *training, want_poly, &m.summary);
  if (r.ok() && !m.rate.IsValid(nullptr)) r.Fail("field 'temperature_rate.window_s' must be > 0");
  if (r.ok() && !(m.summary.temp_min_c <= m.summary.temp_max_c)) r.Fail("training.temp_min_c > training.temp_max_c");
  if (!r.ok()) return InvalidInput(r.error());
  return m;
}

Status SaveDriftModel(const DriftModel& model, const std::string& path) {
  return WriteTextAtomic(path, DriftModelToJson(model));
}

Result<DriftModel> LoadDriftModel(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return IoError(path + ": cannot open model file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return IoError(path + ": cannot read model file");
  return DriftModelFromJson(text.str(), path);
}

}  // namespace gyrocomp
