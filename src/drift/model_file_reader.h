// Typed JSON field access for the drift model file readers (drift_model_io*.cc). Internal.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drift_model_internal.h"

namespace gyrocomp::drift_internal {

using nlohmann::json;
inline constexpr const char* kModelFormat = "gyrocomp-drift-model";

// Typed field access that reports the field's path on failure.
class Reader {
 public:
  // Largest magnitude of any number a model file may hold: no coefficient, scale or support-vector
  // value of a gyro drift model comes near it, and a model that holds 1e308 overflows on use.
  static constexpr double kMaxModelValue = 1e100;

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


// Shared pieces of the version 1 and 2 readers.
AffineScaler ReadInputScaler(Reader& r, const json& scaler, std::size_t num_inputs, const std::string& path);
PolynomialModel ReadPolynomialModel(Reader& r, const json& model, const AffineScaler& in_scaler,
                                    std::size_t num_inputs, const std::string& path);
SvrModel ReadSvrModel(Reader& r, const json& scaler, const json& model, const AffineScaler& in_scaler,
                      std::size_t num_inputs, const std::string& path);
// "training" (version 1 needs fit_time_s; version 2 has none and adds the thermal-state fields).
void ReadTrainingSummary(Reader& r, const json& training, int version, bool has_poly, bool has_svr,
                         DriftFitSummary* summary);
// A version 1 file (the whole model at the top level), format and version already checked.
Result<DriftModel> ReadVersion1(const json& j, const std::string& source);

}  // namespace gyrocomp::drift_internal
