// Readers shared by both schema versions, and the version 1 reader (one model at the top level,
// written by earlier gyrocomp).
#include <limits>

#include "model_file_reader.h"

namespace gyrocomp::drift_internal {
namespace {

// "inputs" of a version 1 file: sets m->inputs and returns the number of inputs (0 after a failure).
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


// Version 2 additions to "training".
void ReadVersion2Training(Reader& r, const json& training, DriftFitSummary& s) {
  const auto scheme = ParseDriftCvScheme(r.String(training, "cv_scheme", "training.cv_scheme"));
  if (r.ok() && !scheme) r.Fail("field 'training.cv_scheme' must be \"blocks\" or \"segments\"");
  if (scheme) s.cv_scheme = *scheme;
  s.cv_segments = static_cast<int>(r.Integer(training, "cv_segments", "training.cv_segments"));
  s.state_min = r.Number(training, "state_min", "training.state_min");
  s.state_max = r.Number(training, "state_max", "training.state_max");
  s.selection_reason = r.String(training, "selection_reason", "training.selection_reason");
  s.identifiability = r.String(training, "identifiability", "training.identifiability");
  // Optional (older files have none).
  if (training.contains("drift_span")) s.drift_span = r.Number(training, "drift_span", "training.drift_span");
  if (training.contains("data_support")) s.data_support = r.String(training, "data_support", "training.data_support");
  if (training.contains("excluded_terms")) {
    const json& ex = training["excluded_terms"];
    if (!ex.is_array()) return r.Fail("field 'training.excluded_terms' must be an array");
    for (const json& e : ex) {
      ExcludedTerm t;
      t.term = r.String(e, "term", "training.excluded_terms[].term");
      t.reason = r.String(e, "reason", "training.excluded_terms[].reason");
      t.would_identify = r.String(e, "would_identify", "training.excluded_terms[].would_identify");
      if (!r.ok()) return;
      s.excluded_terms.push_back(std::move(t));
    }
  }
  const json* cands = r.Get(training, "candidates", "training.candidates");
  if (cands && !cands->is_array()) r.Fail("field 'training.candidates' must be an array");
  if (!r.ok()) return;
  for (const json& c : *cands) {
    DriftCandidateScore k;
    k.name = r.String(c, "name", "training.candidates[].name");
    const auto kind = ParseDriftModelKind(r.String(c, "kind", "training.candidates[].kind"));
    const auto inputs = ParseDriftInputSet(r.String(c, "inputs", "training.candidates[].inputs"));
    const json* cv = r.Get(c, "cv_rmse", "training.candidates[].cv_rmse");
    k.note = r.String(c, "note", "training.candidates[].note");
    if (!r.ok()) return;
    if (!kind || !inputs) return r.Fail("a candidate in 'training.candidates' has an unknown kind or inputs");
    k.kind = *kind;
    k.inputs = *inputs;
    if (cv->is_number()) k.cv_rmse = cv->get<double>();
    else if (cv->is_null()) k.cv_rmse = std::numeric_limits<double>::infinity();
    else return r.Fail("field 'training.candidates[].cv_rmse' must be a number or null");
    s.candidates.push_back(std::move(k));
  }
}

}  // namespace

// "scaler.input_offset/input_scale": one entry per input, scales > 0.
AffineScaler ReadInputScaler(Reader& r, const json& scaler, std::size_t num_inputs, const std::string& path) {
  AffineScaler in_scaler;
  in_scaler.offset = r.Numbers(scaler, "input_offset", path + ".input_offset");
  in_scaler.scale = r.Numbers(scaler, "input_scale", path + ".input_scale");
  if (r.ok() && (in_scaler.offset.size() != num_inputs || in_scaler.scale.size() != num_inputs))
    r.Fail("fields '" + path + ".input_offset/input_scale' must have one entry per input");
  for (double v : in_scaler.scale)
    if (r.ok() && !(v > 0.0)) r.Fail("field '" + path + ".input_scale' must be > 0");
  return in_scaler;
}

// "model" of type "polynomial": its terms, with powers within the model's inputs and degrees.
PolynomialModel ReadPolynomialModel(Reader& r, const json& model, const AffineScaler& in_scaler,
                                    std::size_t num_inputs, const std::string& path) {
  PolynomialModel p;
  p.input_scaler = in_scaler;
  const json* terms = r.Get(model, "terms", path + ".terms");
  if (terms && !terms->is_array()) r.Fail("field '" + path + ".terms' must be an array");
  if (r.ok()) {
    for (const json& t : *terms) {
      PolynomialTerm term;
      term.temp_power = static_cast<int>(r.Integer(t, "temp_power", path + ".terms[].temp_power"));
      term.dtemp_power = static_cast<int>(r.Integer(t, "dtemp_power", path + ".terms[].dtemp_power"));
      term.coefficient = r.Number(t, "coefficient", path + ".terms[].coefficient");
      // Optional: the memory of temp,dtemp,memory, linear, with 3 inputs only.
      if (r.ok() && t.is_object() && t.contains("memory_power"))
        term.memory_power = static_cast<int>(r.Integer(t, "memory_power", path + ".terms[].memory_power"));
      if (r.ok() && (term.temp_power < 0 || term.temp_power > 5 || term.dtemp_power < 0 ||
                     term.dtemp_power > 3 || (term.dtemp_power > 0 && num_inputs < 2) || term.memory_power < 0 ||
                     term.memory_power > 1 || (term.memory_power > 0 && num_inputs < 3)))
        r.Fail("a term in '" + path + ".terms' has powers outside the model's inputs and degrees");
      p.terms.push_back(term);
    }
  }
  return p;
}

// "model" of type "epsilon-svr" and the target scaling: one support vector (one value per
// input) per coefficient, gamma > 0.
SvrModel ReadSvrModel(Reader& r, const json& scaler, const json& model, const AffineScaler& in_scaler,
                      std::size_t num_inputs, const std::string& path) {
  SvrModel s;
  s.num_inputs = num_inputs;
  s.input_scaler = in_scaler;
  const std::string scaler_path = &scaler == &model ? path : "scaler";
  s.target_offset = r.Number(scaler, "target_offset", scaler_path + ".target_offset");
  s.target_scale = r.Number(scaler, "target_scale", scaler_path + ".target_scale");
  s.gamma = r.Number(model, "gamma", path + ".gamma");
  s.intercept = r.Number(model, "intercept", path + ".intercept");
  s.coefficients = r.Numbers(model, "coefficients", path + ".coefficients");
  const json* svs = r.Get(model, "support_vectors", path + ".support_vectors");
  if (r.ok() && !(s.gamma > 0.0)) r.Fail("field '" + path + ".gamma' must be > 0");
  if (r.ok() && (!svs->is_array() || svs->size() != s.coefficients.size()))
    r.Fail("field '" + path + ".support_vectors' must have one row per coefficient");
  if (r.ok()) {
    for (const json& row : *svs) {
      if (!row.is_array() || row.size() != num_inputs) {
        r.Fail("each row of '" + path + ".support_vectors' must have one value per input");
        break;
      }
      for (const json& v : row) {
        if (!v.is_number()) {
          r.Fail("field '" + path + ".support_vectors' must hold numbers");
          break;
        }
        // The documented rule for every model number (Reader::kMaxModelValue), here too.
        if (!(std::abs(v.get<double>()) <= Reader::kMaxModelValue)) {
          r.Fail("field '" + path + ".support_vectors' = ... " + v.dump() + " ...: must hold numbers of magnitude <= 1e100");
          break;
        }
        s.support_vectors.push_back(v.get<double>());
      }
    }
  }
  return s;
}

// "training": the fit summary (model and inputs come from the already-read fields).
void ReadTrainingSummary(Reader& r, const json& training, int version, bool has_poly, bool has_svr,
                         DriftFitSummary* summary) {
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
  if (version == 1) s.fit_time_s = r.Number(training, "fit_time_s", "training.fit_time_s");
  else ReadVersion2Training(r, training, s);
  if (has_poly) {
    s.degree = static_cast<int>(r.Integer(training, "degree", "training.degree"));
    s.dtemp_degree = static_cast<int>(r.Integer(training, "dtemp_degree", "training.dtemp_degree"));
    // Optional (written only when the state's gain varies with T; its terms carry the model).
    if (training.contains("gain_temp_degree"))
      s.gain_temp_degree = static_cast<int>(r.Integer(training, "gain_temp_degree", "training.gain_temp_degree"));
  }
  if (has_svr) {
    s.C = r.Number(training, "C", "training.C");
    s.gamma = r.Number(training, "gamma", "training.gamma");
    s.sigma = r.Number(training, "sigma", "training.sigma");
    s.epsilon = r.Number(training, "epsilon", "training.epsilon");
    s.num_support = static_cast<std::size_t>(r.Integer(training, "num_support", "training.num_support"));
  }
}


Result<DriftModel> ReadVersion1(const json& j, const std::string& source) {
  // Top-level fields; the first problem found is the one reported.
  Reader r(source);
  DriftModel m;
  const auto kind = ParseDriftModelKind(r.String(j, "kind", "kind"));
  if (r.ok() && (!kind || *kind == DriftModelKind::kAuto || *kind == DriftModelKind::kHybrid))
    r.Fail("field 'kind' must be poly, svr, grid-svr or cs-svr");
  const std::size_t num_inputs = ReadInputs(r, j, &m);
  const json* rate = r.Get(j, "temperature_rate", "temperature_rate");
  if (rate) m.rate.window_s = r.Number(*rate, "window_s", "temperature_rate.window_s");
  const json* scaler = r.Get(j, "scaler", "scaler");
  const json* model = r.Get(j, "model", "model");
  const json* training = r.Get(j, "training", "training");
  if (!r.ok()) return InvalidInput(r.error());
  m.kind = *kind;

  const AffineScaler in_scaler = ReadInputScaler(r, *scaler, num_inputs, "scaler");
  const std::string type = r.String(*model, "type", "model.type");
  const bool want_poly = m.kind == DriftModelKind::kPolynomial;
  if (r.ok() && want_poly != (type == "polynomial"))
    r.Fail("field 'model.type' = \"" + type + "\" does not match kind \"" + DriftModelKindName(m.kind) + "\"");
  if (r.ok() && want_poly) {
    m.structured = ReadPolynomialModel(r, *model, in_scaler, num_inputs, "model");
  } else if (r.ok()) {
    m.kernel = ReadSvrModel(r, *scaler, *model, in_scaler, num_inputs, "model");
  }
  m.summary.model = m.kind;
  m.summary.inputs = m.inputs;
  ReadTrainingSummary(r, *training, 1, want_poly, !want_poly, &m.summary);
  if (r.ok() && !m.rate.IsValid(nullptr)) r.Fail("field 'temperature_rate.window_s' must be > 0");
  if (r.ok() && !(m.summary.temp_min_c <= m.summary.temp_max_c)) r.Fail("training.temp_min_c > training.temp_max_c");
  if (!r.ok()) return InvalidInput(r.error());
  m.summary.state_min = m.summary.dtemp_min_c_per_s;
  m.summary.state_max = m.summary.dtemp_max_c_per_s;
  return m;
}

}  // namespace gyrocomp::drift_internal
