// Drift model: options, features, decimation, fitting and prediction (see drift_model.h).
#include "gyrocomp/drift/drift_model.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "drift_model_internal.h"

namespace gyrocomp {
namespace {

std::string Num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

bool ValidDimension(const SearchDimension& d, const std::string& field, std::string* error) {
  if (!std::isfinite(d.lower) || !std::isfinite(d.upper) || !(d.lower > 0.0) || !(d.lower < d.upper)) {
    if (error)
      *error = "SvrSearchOptions::" + field + " = [" + Num(d.lower) + ", " + Num(d.upper) +
               "]: must satisfy 0 < lower < upper";
    return false;
  }
  return true;
}

double Rmse(std::span<const double> a, std::span<const double> b) {
  double ss = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) ss += (a[i] - b[i]) * (a[i] - b[i]);
  return a.empty() ? 0.0 : std::sqrt(ss / static_cast<double>(a.size()));
}

}  // namespace

std::optional<DriftModelKind> ParseDriftModelKind(std::string_view name) {
  if (name == "poly") return DriftModelKind::kPolynomial;
  if (name == "svr") return DriftModelKind::kSvr;
  if (name == "grid-svr") return DriftModelKind::kGridSvr;
  if (name == "cs-svr") return DriftModelKind::kCsSvr;
  return std::nullopt;
}

const char* DriftModelKindName(DriftModelKind kind) {
  switch (kind) {
    case DriftModelKind::kPolynomial: return "poly";
    case DriftModelKind::kSvr: return "svr";
    case DriftModelKind::kGridSvr: return "grid-svr";
    case DriftModelKind::kCsSvr: return "cs-svr";
  }
  return "?";
}

std::optional<DriftInputSet> ParseDriftInputSet(std::string_view name) {
  if (name == "temp") return DriftInputSet::kTemp;
  if (name == "temp,dtemp") return DriftInputSet::kTempAndRate;
  return std::nullopt;
}

const char* DriftInputSetName(DriftInputSet inputs) {
  return inputs == DriftInputSet::kTemp ? "temp" : "temp,dtemp";
}

bool PolynomialOptions::IsValid(std::string* error) const {
  if (degree < 1 || degree > 5) {
    if (error) *error = "PolynomialOptions::degree = " + std::to_string(degree) + ": must be in 1..5";
    return false;
  }
  if (dtemp_degree < 1 || dtemp_degree > 3) {
    if (error)
      *error = "PolynomialOptions::dtemp_degree = " + std::to_string(dtemp_degree) + ": must be in 1..3";
    return false;
  }
  return true;
}

bool SvrSearchOptions::IsValid(std::string* error) const {
  if (!ValidDimension(C, "C", error) || !ValidDimension(sigma, "sigma", error)) return false;
  if (epsilon && !ValidDimension(*epsilon, "epsilon", error)) return false;
  if (!cuckoo.IsValid(error)) return false;
  if (grid_budget && *grid_budget < 4) {
    if (error) *error = "SvrSearchOptions::grid_budget = " + std::to_string(*grid_budget) + ": must be >= 4";
    return false;
  }
  return true;
}

bool DriftFitOptions::IsValid(std::string* error) const {
  if (!rate.IsValid(error) || !polynomial.IsValid(error) || !svr.IsValid(error) ||
      !search.IsValid(error))
    return false;
  if (train_period_s && (!(*train_period_s > 0.0) || !std::isfinite(*train_period_s))) {
    if (error) *error = "DriftFitOptions::train_period_s = " + Num(*train_period_s) + ": must be > 0";
    return false;
  }
  if (max_train_samples < 10) {
    if (error)
      *error = "DriftFitOptions::max_train_samples = " + std::to_string(max_train_samples) + ": must be >= 10";
    return false;
  }
  if (cv_folds < 2) {
    if (error) *error = "DriftFitOptions::cv_folds = " + std::to_string(cv_folds) + ": must be >= 2";
    return false;
  }
  return true;
}

std::string DriftFitSummary::BriefReport() const {
  std::ostringstream s;
  s << "drift model " << DriftModelKindName(model) << " (" << DriftInputSetName(inputs) << " -> "
    << target_name << "): " << num_samples << " samples at " << fs_hz << " Hz, trained on "
    << num_train << " (" << train_period_s << " s means), T in [" << temp_min_c << ", "
    << temp_max_c << "] C";
  if (C) s << ", C = " << *C << ", sigma = " << *sigma << ", epsilon = " << *epsilon
           << ", " << num_support << " SVs";
  if (model == DriftModelKind::kPolynomial) {
    s << ", degree " << degree;
    if (inputs == DriftInputSet::kTempAndRate) s << " (+ dT/dt degree " << dtemp_degree << ")";
  }
  s << "; blocked CV RMSE (" << cv_folds << " folds) = " << cv_rmse << ", train RMSE = " << train_rmse;
  if (evaluations > 0) s << ", " << evaluations << " parameter sets tried";
  s << ", " << fit_time_s << " s";
  return s.str();
}

std::string TemperatureExcursion::Message() const {
  if (!outside) return "";
  std::ostringstream s;
  s << "temperature outside the fitted range for " << 100.0 * fraction_outside << "% of samples";
  if (below_c > 0.0) s << ", down to " << below_c << " C below its minimum";
  if (above_c > 0.0) s << ", up to " << above_c << " C above its maximum";
  s << ": the model extrapolates there";
  return s.str();
}

namespace drift_internal {

Result<Columns> BuildFeatures(const DriftInputs& inputs, DriftInputSet set,
                              const TemperatureRateOptions& rate) {
  if (inputs.temp_c.empty()) return InvalidInput("drift model: empty temperature record");
  for (std::size_t i = 0; i < inputs.temp_c.size(); ++i)
    if (!std::isfinite(inputs.temp_c[i]))
      return InvalidInput("drift model: non-finite temperature at sample " + std::to_string(i));
  Columns x = {std::vector<double>(inputs.temp_c.begin(), inputs.temp_c.end())};
  if (set == DriftInputSet::kTempAndRate) {
    auto r = TemperatureRate(inputs.temp_c, inputs.fs_hz, rate);
    if (!r.ok()) return r.error();
    x.push_back(std::move(*r));
  }
  return x;
}

std::vector<double> BlockMeans(std::span<const double> x, std::size_t block) {
  std::vector<double> out;
  if (block <= 1) return std::vector<double>(x.begin(), x.end());
  for (std::size_t a = 0; a < x.size(); a += block) {
    const std::size_t b = std::min(x.size(), a + block);
    double s = 0.0;
    for (std::size_t i = a; i < b; ++i) s += x[i];
    out.push_back(s / static_cast<double>(b - a));
  }
  return out;
}

}  // namespace drift_internal

using drift_internal::Columns;

Result<DriftModel> FitDriftModel(const DriftInputs& inputs, std::span<const double> target,
                                 const DriftFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (!(inputs.fs_hz > 0.0) || !std::isfinite(inputs.fs_hz))
    return InvalidArgument("FitDriftModel: fs_hz = " + Num(inputs.fs_hz) + ": must be > 0");
  const std::size_t n = inputs.temp_c.size();
  if (target.size() != n)
    return InvalidInput("FitDriftModel: " + std::to_string(target.size()) + " target values for " +
                        std::to_string(n) + " temperature samples");
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(target[i]))
      return InvalidInput("FitDriftModel: non-finite target at sample " + std::to_string(i));
  auto features = drift_internal::BuildFeatures(inputs, options.inputs, options.rate);
  if (!features.ok()) return features.error();
  const Columns& x = *features;

  DriftModel model;
  model.kind = options.model;
  model.inputs = options.inputs;
  model.rate = options.rate;
  DriftFitSummary& s = model.summary;
  s.model = options.model;
  s.inputs = options.inputs;
  s.target_name = options.target_name;
  s.num_samples = n;
  s.fs_hz = inputs.fs_hz;
  s.duration_s = static_cast<double>(n) / inputs.fs_hz;
  s.cv_folds = options.cv_folds;
  s.cv_in_range_only = options.cv_in_range_only;
  const auto [tmin, tmax] = std::minmax_element(x[0].begin(), x[0].end());
  s.temp_min_c = *tmin;
  s.temp_max_c = *tmax;
  if (x.size() > 1) {
    const auto [rmin, rmax] = std::minmax_element(x[1].begin(), x[1].end());
    s.dtemp_min_c_per_s = *rmin;
    s.dtemp_max_c_per_s = *rmax;
  }

  // Decimated training copy: block means over train_period_s (the mean is the anti-alias filter;
  // the drift varies over minutes to hours, far slower than the default 30 s).
  const double period_s = options.train_period_s.value_or(
      std::max(30.0, s.duration_s / static_cast<double>(options.max_train_samples)));
  const std::size_t block = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(period_s * inputs.fs_hz)));
  Columns xd;
  for (const auto& c : x) xd.push_back(drift_internal::BlockMeans(c, block));
  const std::vector<double> yd = drift_internal::BlockMeans(target, block);
  s.train_period_s = static_cast<double>(block) / inputs.fs_hz;
  if (yd.size() < 2 * static_cast<std::size_t>(options.cv_folds))
    return InvalidInput("FitDriftModel: the record gives " + std::to_string(yd.size()) +
                        " training samples of " + Num(s.train_period_s) + " s; " +
                        std::to_string(options.cv_folds) + "-fold blocked CV needs at least " +
                        std::to_string(2 * options.cv_folds) + " (shorter train_period_s or a longer record)");

  if (options.model == DriftModelKind::kPolynomial) {
    // Fitted on every sample (cheap); scored by blocked CV on the decimated copy like the SVRs.
    auto poly = drift_internal::FitPolynomial(x, target, options.polynomial);
    if (!poly.ok()) return poly.error();
    auto cv = drift_internal::BlockedCvRmse(
        xd, yd, options.cv_folds, options.cv_in_range_only,
        [&](const Columns& tx, std::span<const double> ty, const Columns& vx) -> Result<std::vector<double>> {
          auto m = drift_internal::FitPolynomial(tx, ty, options.polynomial);
          if (!m.ok()) return m.error();
          return m->Predict(vx);
        });
    if (!cv.ok()) return cv.error();
    s.cv_rmse = *cv;
    s.degree = options.polynomial.degree;
    s.dtemp_degree = x.size() > 1 ? options.polynomial.dtemp_degree : 0;
    s.num_train = n;
    model.model = std::move(*poly);
  } else {
    SvrOptions chosen = options.svr;
    if (options.model == DriftModelKind::kSvr) {
      auto cv = drift_internal::BlockedCvRmse(
          xd, yd, options.cv_folds, options.cv_in_range_only,
          [&](const Columns& tx, std::span<const double> ty, const Columns& vx) -> Result<std::vector<double>> {
            auto m = FitSvr(tx, ty, chosen);
            if (!m.ok()) return m.error();
            return m->Predict(vx);
          });
      if (!cv.ok()) return cv.error();
      s.cv_rmse = *cv;
    } else {
      auto choice = options.model == DriftModelKind::kCsSvr
                        ? drift_internal::SearchSvrCuckoo(xd, yd, options)
                        : drift_internal::SearchSvrGrid(xd, yd, options);
      if (!choice.ok()) return choice.error();
      chosen = choice->options;
      s.cv_rmse = choice->cv_rmse;
      s.evaluations = choice->evaluations;
      s.generations = choice->generations;
      s.best_cv_history = choice->history;
    }
    auto svr = FitSvr(xd, yd, chosen);
    if (!svr.ok()) return svr.error();
    s.num_train = yd.size();
    s.C = chosen.C;
    s.gamma = svr->gamma;
    s.sigma = 1.0 / std::sqrt(2.0 * svr->gamma);  // Eq. (20)
    s.epsilon = chosen.epsilon;
    s.num_support = svr->num_support();
    model.model = std::move(*svr);
  }
  if (options.model == DriftModelKind::kPolynomial) s.train_period_s = 1.0 / inputs.fs_hz;

  auto fitted = model.Predict(inputs);
  if (!fitted.ok()) return fitted.error();
  s.train_rmse = Rmse(*fitted, target);
  s.fit_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return model;
}

Result<std::vector<double>> DriftModel::Predict(const DriftInputs& in) const {
  auto features = drift_internal::BuildFeatures(in, inputs, rate);
  if (!features.ok()) return features.error();
  if (const auto* poly = std::get_if<PolynomialModel>(&model)) return poly->Predict(*features);
  return std::get<SvrModel>(model).Predict(*features);
}

TemperatureExcursion DriftModel::CheckTemperatureRange(std::span<const double> temp_c) const {
  TemperatureExcursion e;
  std::size_t count = 0;
  for (double t : temp_c) {
    if (t < summary.temp_min_c) {
      ++count;
      e.below_c = std::max(e.below_c, summary.temp_min_c - t);
    } else if (t > summary.temp_max_c) {
      ++count;
      e.above_c = std::max(e.above_c, t - summary.temp_max_c);
    }
  }
  e.outside = count > 0;
  e.fraction_outside = temp_c.empty() ? 0.0 : static_cast<double>(count) / static_cast<double>(temp_c.size());
  return e;
}

}  // namespace gyrocomp
