// gyrocomp.fit_drift_model, load_drift_model, drift_model_from_json and the DriftModel class
// (predict, save, to_json, summary).
#include "bindings.h"

#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/drift/drift_validate.h"

namespace gyrocomp::python {
namespace {

std::vector<double> Predict(const DriftModel& model, const DoubleArray& temp_c, double fs_hz, bool causal = false) {
  const DriftInputs inputs{AsSpan(temp_c, "temp_c"), fs_hz};
  return Unwrap(WithoutGil([&] { return model.Predict(inputs, causal); }));
}

}  // namespace

py::dict FitSummaryDict(const DriftFitSummary& s) {
  py::dict d;
  d["model"] = DriftModelKindName(s.model);
  d["inputs"] = DriftInputSetName(s.inputs);
  d["target_name"] = s.target_name;
  d["num_samples"] = s.num_samples;
  d["fs_hz"] = s.fs_hz;
  d["duration_s"] = s.duration_s;
  d["num_train"] = s.num_train;
  d["train_period_s"] = s.train_period_s;
  d["temp_min_c"] = s.temp_min_c;
  d["temp_max_c"] = s.temp_max_c;
  d["C"] = s.C;
  d["gamma"] = s.gamma;
  d["sigma"] = s.sigma;
  d["epsilon"] = s.epsilon;
  d["num_support"] = s.num_support;
  d["degree"] = s.degree;
  d["cv_folds"] = s.cv_folds;
  d["cv_rmse"] = s.cv_rmse;
  d["train_rmse"] = s.train_rmse;
  d["evaluations"] = s.evaluations;
  d["generations"] = s.generations;
  d["best_cv_history"] = s.best_cv_history;
  d["fit_time_s"] = s.fit_time_s;
  d["brief_report"] = s.BriefReport();
  // What the run identifies and what it supports (excluded terms, data support, drift span).
  py::list excluded;
  for (const ExcludedTerm& e : s.excluded_terms) {
    py::dict t;
    t["term"] = e.term;
    t["reason"] = e.reason;
    t["would_identify"] = e.would_identify;
    excluded.append(t);
  }
  d["excluded_terms"] = excluded;
  d["data_support"] = s.data_support;
  d["drift_span"] = s.drift_span;
  d["selection_reason"] = s.selection_reason;
  return d;
}

namespace {

// The band's description (DriftBandModel), or None for a model without one.
py::object BandDict(const DriftModel& model) {
  if (!model.band) return py::none();
  const DriftBandModel& b = *model.band;
  py::dict d;
  d["level"] = b.level;
  d["expected_rms"] = b.expected_rms;
  d["model_form_rms"] = b.model_form_rms;
  d["unidentified_rate_gain_rms"] = b.unidentified_rate_gain_rms;
  d["noise"] = py::dict(py::arg("white") = b.noise.h0, py::arg("flicker") = b.noise.h_1,
                        py::arg("random_walk") = b.noise.h_2);
  return d;
}

}  // namespace

DriftFitOptions ReadFitOptions(Kwargs& kw) {
  DriftFitOptions o;
  kw.GetParsed("model", &o.model, ParseDriftModelKind, "not a drift model kind (docs/explanation/drift-models.md)");
  kw.GetParsed("inputs", &o.inputs, ParseDriftInputSet, "not an input set (docs/explanation/drift-models.md)");
  kw.Get("train_period_s", &o.train_period_s);
  kw.Get("max_train_samples", &o.max_train_samples);
  kw.Get("cv_folds", &o.cv_folds);
  kw.Get("cv_in_range_only", &o.cv_in_range_only);
  kw.Get("target_name", &o.target_name);
  kw.Get("degree", &o.polynomial.degree);
  kw.Get("dtemp_degree", &o.polynomial.dtemp_degree);
  kw.Get("gain_temp_degree", &o.polynomial.gain_temp_degree);
  kw.Get("num_nests", &o.search.cuckoo.num_nests);
  kw.Get("max_generations", &o.search.cuckoo.max_generations);
  kw.Get("search_generations", &o.auto_select.search_generations);  // auto's searched candidates (DriftAutoOptions)
  kw.Get("lagged_curve_gain_degree", &o.auto_select.lagged_curve_gain_degree);  // fit --auto-lagged-curve
  kw.Get("lagged_curve_pieces", &o.auto_select.lagged_curve_pieces);  // fit --auto-lagged-curve-pieces
  kw.Get("seed", &o.search.cuckoo.seed);
  return o;
}

namespace {

// DriftValidation as a dict whose keys are those of `gyrocomp validate --json` (docs/reference/cli-contract.md).
py::dict ValidationDict(const DriftValidation& v) {
  py::dict d;
  d["n_samples"] = v.num_samples;
  d["fs_hz"] = v.fs_hz;
  d["num_blocks"] = v.num_blocks;
  d["raw_drift_rms_dps"] = v.raw_drift_rms;
  d["residual_drift_rms_dps"] = v.residual_drift_rms;
  d["residual_mean_dps"] = v.residual_mean;
  d["residual_slope_vs_temp_dps_per_c"] = v.slope_vs_temp;
  d["residual_slope_vs_dtemp_dps_per_c_per_s"] = v.slope_vs_dtemp;
  d["adev_tau_s"] = v.tau_s;
  d["adev_raw_dps"] = v.adev_raw;
  d["adev_compensated_dps"] = v.adev_compensated;
  d["rmse_vs_true_drift_dps"] = v.rmse_vs_true_drift;
  d["fraction_temp_outside_fitted_range"] = v.fraction_temp_outside;
  d["fraction_dtemp_outside_fitted_range"] = v.fraction_dtemp_outside;
  d["temp_below_fitted_c"] = v.excursion.below_c;
  d["temp_above_fitted_c"] = v.excursion.above_c;
  d["band_level"] = v.band_level;
  d["band_half_width_rms_dps"] = v.band_half_width_rms;
  d["band_coverage_of_true_drift"] = v.band_coverage_truth;
  d["band_coverage_of_block_means"] = v.band_coverage_blocks;
  return d;
}

}  // namespace

void BindDrift(py::module_& m) {
  m.def(
      "validate_drift_model",
      [](const DriftModel& model, const DoubleArray& rate, const DoubleArray& temp_c, double fs_hz,
         std::optional<DoubleArray> true_drift, const py::kwargs& kwargs) {
        const DriftValidationOptions o = ReadAll(kwargs, "validate_drift_model", [](Kwargs& kw) {
          DriftValidationOptions v;
          kw.Get("block_s", &v.block_s);
          kw.Get("min_tau_s", &v.min_tau_s);
          kw.Get("causal", &v.causal);
          return v;
        });
        const std::span<const double> truth =
            true_drift ? AsSpan(*true_drift, "true_drift") : std::span<const double>{};
        const std::span<const double> r = AsSpan(rate, "rate"), t = AsSpan(temp_c, "temp_c");
        return ValidationDict(Unwrap(WithoutGil([&] { return ValidateDriftModel(model, r, t, fs_hz, truth, o); })));
      },
      py::arg("model"), py::arg("rate"), py::arg("temp_c"), py::arg("fs_hz"), py::arg("true_drift") = py::none(),
      "A saved drift model on a run it was not fitted on, as `gyrocomp validate` (one axis): residual drift, "
      "slopes, ADEV at long taus, error against the truth when given, the band's coverage. Keywords "
      "(DriftValidationOptions): block_s, min_tau_s, causal. Keys as in validate --json.");
  py::class_<DriftModel>(m, "DriftModel", "A fitted temperature-drift model (docs/explanation/drift-models.md).")
      .def(
          "predict",
          [](const DriftModel& model, const DoubleArray& temp_c, double fs_hz, bool causal) {
            return ToNumpy(Predict(model, temp_c, fs_hz, causal));
          },
          py::arg("temp_c"), py::arg("fs_hz"), py::arg("causal") = false,
          "Predicted drift (target units, deg/s) for a temperature record, what `gyrocomp apply` subtracts. "
          "causal: evaluated as firmware would (DriftEvaluator, apply --causal).")
      .def(
          "predict_band",
          [](const DriftModel& model, const DoubleArray& temp_c, double fs_hz, bool causal) {
            const DriftInputs inputs{AsSpan(temp_c, "temp_c"), fs_hz};
            DriftBand b = Unwrap(WithoutGil([&] { return model.PredictBand(inputs, causal); }));
            py::dict d;
            d["center"] = ToNumpy(std::move(b.center));
            d["lo"] = ToNumpy(std::move(b.lo));
            d["hi"] = ToNumpy(std::move(b.hi));
            d["level"] = b.level;
            return d;
          },
          py::arg("temp_c"), py::arg("fs_hz"), py::arg("causal") = false,
          "Predicted drift with its prediction band: dict center, lo, hi (numpy), level (0.9). "
          "Raises for a model loaded from a file written before the bands existed.")
      .def(
          "check_temperature_range",
          [](const DriftModel& model, const DoubleArray& temp_c) {
            const TemperatureExcursion e = model.CheckTemperatureRange(AsSpan(temp_c, "temp_c"));
            return py::dict(py::arg("outside") = e.outside, py::arg("below_c") = e.below_c,
                            py::arg("above_c") = e.above_c, py::arg("fraction_outside") = e.fraction_outside,
                            py::arg("message") = e.Message());
          },
          py::arg("temp_c"),
          "Where a record leaves the fitted temperature range (the warning of `gyrocomp apply`): dict outside, "
          "below_c, above_c, fraction_outside, message.")
      .def("save", [](const DriftModel& model, const std::string& path) { Check(SaveDriftModel(model, path)); },
           py::arg("path"), "Writes the model file (JSON, atomic).")
      .def("to_json", &DriftModelToJson)
      .def_property_readonly("kind", [](const DriftModel& model) { return DriftModelKindName(model.kind); })
      .def_property_readonly("summary", [](const DriftModel& model) { return FitSummaryDict(model.summary); })
      .def_property_readonly("band", &BandDict,
                             "The prediction band's parts: dict level, expected_rms (the expected drift "
                             "error RMS on a next run like the calibration, target units), model_form_rms, "
                             "unidentified_rate_gain_rms, noise (white, flicker, random_walk PSD); None for a "
                             "model file written before the bands existed.")
      .def("__repr__", [](const DriftModel& model) { return "<gyrocomp.DriftModel " + model.summary.BriefReport() + ">"; });

  m.def(
      "fit_drift_model",
      [](const DoubleArray& temp_c, const DoubleArray& target_dps, double fs_hz, py::object progress,
         const CancellationToken* cancel, const py::kwargs& kwargs) {
        DriftFitOptions o = ReadAll(kwargs, "fit_drift_model", ReadFitOptions);
        LongCall call(cancel);
        o.cancel = o.search.cuckoo.cancel = o.svr.cancel = call.token();
        const Hooks hooks(std::move(progress), call.token());
        const int generations = o.search.cuckoo.max_generations;
        o.search.cuckoo.on_generation = [&hooks, generations](int generation, double) {
          hooks.Poll("drift-fit (cuckoo search)", static_cast<double>(generation) / generations);
        };
        const DriftInputs inputs{AsSpan(temp_c, "temp_c"), fs_hz};
        const std::span<const double> target = AsSpan(target_dps, "target_dps");
        return Unwrap(call.Run([&] { return FitDriftModel(inputs, target, o); }));
      },
      py::arg("temp_c"), py::arg("target_dps"), py::arg("fs_hz"), py::kw_only(), py::arg("progress") = py::none(),
      py::arg("cancel") = nullptr,
      "Fits a drift model of target_dps against temperature (DriftFitOptions as keywords: model, inputs, "
      "max_train_samples, cv_folds, degree, num_nests, max_generations, seed, ...).");

  m.def("load_drift_model", [](const std::string& path) { return Unwrap(LoadDriftModel(path)); }, py::arg("path"));
  m.def(
      "drift_model_from_json",
      [](const std::string& text) { return Unwrap(DriftModelFromJson(text, "<string>")); }, py::arg("text"));
}

}  // namespace gyrocomp::python
