// Fitting one drift model of a given kind and inputs (FitDriftModel; --model auto is in
// drift_auto.cc): training data, cross-validation plan, structured / kernel / hybrid fits.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "drift_model_internal.h"
#include "gyrocomp/core/format.h"

namespace gyrocomp {
namespace drift_internal {
namespace {

// Range of a column.
void MinMax(const std::vector<double>& c, double* lo, double* hi) {
  const auto [a, b] = std::minmax_element(c.begin(), c.end());
  *lo = *a;
  *hi = *b;
}

FitPredict PolyFitPredict(const PolynomialOptions& p) {
  return [p](const Columns& tx, std::span<const double> ty, const Columns& vx) -> Result<std::vector<double>> {
    auto m = FitPolynomial(tx, ty, p);
    if (!m.ok()) return m.error();
    return m->Predict(vx);
  };
}

// Hybrid fold: the polynomial on the training rows, the SVR on its residual there.
MakeFitPredict HybridFitPredict(const PolynomialOptions& p) {
  return [p](const SvrOptions& o) -> FitPredict {
    return [p, o](const Columns& tx, std::span<const double> ty, const Columns& vx) -> Result<std::vector<double>> {
      auto poly = FitPolynomial(tx, ty, p);
      if (!poly.ok()) return poly.error();
      std::vector<double> residual = poly->Predict(tx);
      for (std::size_t i = 0; i < residual.size(); ++i) residual[i] = ty[i] - residual[i];
      auto svr = FitSvr(tx, residual, o);
      if (!svr.ok()) return svr.error();
      std::vector<double> f = poly->Predict(vx);
      const std::vector<double> k = svr->Predict(vx);
      for (std::size_t i = 0; i < f.size(); ++i) f[i] += k[i];
      return f;
    };
  };
}

// Folds the kernel's constant (target offset + scale * intercept) into the polynomial's constant
// term, so the kernel part tends to 0 away from its support vectors.
void FoldIntercept(PolynomialModel* poly, SvrModel* svr) {
  const double constant = svr->target_offset + svr->target_scale * svr->intercept;
  for (PolynomialTerm& t : poly->terms)
    if (t.temp_power == 0 && t.dtemp_power == 0 && t.memory_power == 0) t.coefficient += constant;
  svr->target_offset = 0.0;
  svr->intercept = 0.0;
}

// The SVR part: parameters given (svr) or searched (cs-svr, grid-svr, hybrid), then the final fit
// on the decimated copy of `yd`.
Status FitKernel(const FitData& d, std::span<const double> yd, DriftModelKind kind, const DriftFitOptions& o,
                 const CvPlan& plan, DriftModel* model, SvrOptions* chosen_out) {
  DriftFitSummary& s = model->summary;
  SvrOptions chosen = o.svr;
  if (kind == DriftModelKind::kSvr) {
    auto cv = CrossValidate(d.xd, yd, plan, SvrFitPredict(chosen));
    if (!cv.ok()) return cv.error();
    s.cv_rmse = *cv;
  } else {
    const MakeFitPredict make = kind == DriftModelKind::kHybrid ? HybridFitPredict(o.polynomial) : SvrFitPredict;
    // The hybrid's search scores the whole model on the original target.
    auto choice = kind == DriftModelKind::kGridSvr ? SearchSvrGrid(d.xd, d.yd, o, plan, make)
                                                   : SearchSvrCuckoo(d.xd, d.yd, o, plan, make);
    if (!choice.ok()) return choice.error();
    chosen = choice->options;
    s.cv_rmse = choice->cv_rmse;
    s.evaluations = choice->evaluations;
    s.generations = choice->generations;
    s.best_cv_history = choice->history;
  }
  auto svr = FitSvr(d.xd, yd, chosen);
  if (!svr.ok()) return svr.error();
  s.num_train = yd.size();
  s.C = chosen.C;
  s.gamma = svr->gamma;
  s.sigma = 1.0 / std::sqrt(2.0 * svr->gamma);  // Eq. (20)
  s.epsilon = chosen.epsilon;
  s.num_support = svr->num_support();
  model->kernel = std::move(*svr);
  *chosen_out = chosen;
  return Status::Ok();
}

// Eq. H-1, the hybrid's kernel test. Over cv_folds contiguous blocks (wider than the thermal
// segments the search scored on, so a held-out block's flicker wander is nearly independent of
// the training blocks'; a different split than the search's, so its optimism does not carry
// over), g_k = RMSE_k(structured) - RMSE_k(hybrid) on block k's in-range samples. Keep the
// kernel iff mean(g) > SD(g): its gain exceeds its block-to-block spread (t > sqrt(K)).
struct KernelTest {
  bool keep = true;
  std::string decision;
};

Result<KernelTest> TestKernel(const FitData& d, const DriftFitOptions& o, const SvrOptions& chosen) {
  const CvPlan blocks = GainTestPlan(d.yd.size(), o);
  std::vector<double> structured, hybrid;
  auto a = CrossValidate(d.xd, d.yd, blocks, PolyFitPredict(o.polynomial), &structured);
  if (!a.ok()) return a.error();
  auto b = CrossValidate(d.xd, d.yd, blocks, HybridFitPredict(o.polynomial)(chosen), &hybrid);
  if (!b.ok()) return b.error();
  const TermGain g = PairedTermGain(structured, hybrid);
  KernelTest t;
  t.keep = KernelWins(g);
  std::ostringstream m;
  m << "hybrid: kernel " << (t.keep ? "kept" : "dropped") << ": its CV gain over the structured part on "
    << g.pairs << " contiguous blocks is " << FormatNumber(g.gain) << " +- " << FormatNumber(g.Sd()) << " (mean +- block-to-block SD; SE "
    << FormatNumber(g.se) << "; kept only when mean > SD)";
  if (!t.keep) m << "; the model is its structured part: the kernel would learn noise (flicker wander), not drift";
  t.decision = m.str();
  return t;
}

// The hybrid without its kernel: its structured part (kind poly), scored on the search's plan.
Status DropKernel(const FitData& d, const DriftFitOptions& o, const CvPlan& plan, DriftModel* model) {
  DriftFitSummary& s = model->summary;
  auto cv = CrossValidate(d.xd, d.yd, plan, PolyFitPredict(o.polynomial));
  if (!cv.ok()) return cv.error();
  model->kind = s.model = DriftModelKind::kPolynomial;
  model->kernel.reset();
  s.cv_rmse = *cv;
  s.C = s.gamma = s.sigma = s.epsilon = std::nullopt;
  s.num_support = 0;
  s.num_train = d.y.size();
  return Status::Ok();
}

// A GLS fold: the training rows carry their block index as the last column (stripped before the
// polynomial sees them), so the covariance of exactly those rows is used (Eq. G-3).
FitPredict GlsFitPredict(std::vector<double> autocov, const PolynomialOptions& p) {
  return [autocov = std::move(autocov), p](const Columns& tx, std::span<const double> ty,
                                           const Columns& vx) -> Result<std::vector<double>> {
    Columns x(tx.begin(), tx.end() - 1), v(vx.begin(), vx.end() - 1);
    std::vector<std::size_t> index(tx.back().size());
    for (std::size_t i = 0; i < index.size(); ++i) index[i] = static_cast<std::size_t>(tx.back()[i]);
    auto m = FitPolynomialGls(x, ty, autocov, index, p);
    if (!m.ok()) return m.error();
    return m->Predict(v);
  };
}

// noise_model allan: replaces the OLS polynomial of `model` by the GLS fit on block means of
// gls_block_s (Eq. G-1 .. G-3), scored by the same CV scheme on those block means.
Status FitPolynomialAllan(const FitData& d, const DriftInputs& inputs, const DriftFitOptions& o, DriftModel* model) {
  DriftFitSummary& s = model->summary;
  std::vector<double> residual = model->structured->Predict(d.x);
  for (std::size_t i = 0; i < residual.size(); ++i) residual[i] = d.y[i] - residual[i];
  DriftFitOptions g = o;
  g.train_period_s = std::max(o.gls_block_s, s.duration_s / static_cast<double>(o.max_gls_blocks));
  auto gd = PrepareFitData(inputs, d.y, g);
  if (!gd.ok()) return gd.error();
  NoisePsdOptions po = o.noise_psd;
  if (!po.min_tau_s) po.min_tau_s = gd->train_period_s;  // fitted where it is used
  auto psd = FitNoisePsd(residual, inputs.fs_hz, po);  // Eq. G-1
  if (!psd.ok()) return psd.error();
  const std::size_t n = gd->yd.size();
  const std::vector<double> autocov = BlockMeanAutocovariance(*psd, n, gd->train_period_s);  // Eq. G-2
  std::vector<std::size_t> index(n);
  Columns indexed = gd->xd;
  indexed.emplace_back(n);
  for (std::size_t i = 0; i < n; ++i) index[i] = i, indexed.back()[i] = static_cast<double>(i);
  const CvPlan plan = MakeCvPlan(*gd, o, DriftModelKind::kPolynomial);
  auto cv = CrossValidate(indexed, gd->yd, plan, GlsFitPredict(autocov, o.polynomial));
  if (!cv.ok()) return cv.error();
  auto poly = FitPolynomialGls(gd->xd, gd->yd, autocov, index, o.polynomial);  // Eq. G-3
  if (!poly.ok()) return poly.error();
  model->structured = std::move(*poly);
  s.noise_psd = *psd;
  s.cv_rmse = *cv;
  s.cv_folds = plan.folds;
  s.cv_scheme = plan.scheme;
  s.cv_segments = plan.segments;
  s.cv_in_range_only = plan.in_range_only;
  s.num_train = n;
  s.train_period_s = gd->train_period_s;
  return Status::Ok();
}

}  // namespace

CvPlan GainTestPlan(std::size_t n, const DriftFitOptions& o) { return BlockPlan(n, o.cv_folds, /*in_range_only=*/true); }

Result<FitData> PrepareFitData(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o) {
  ThrowIfCancelled(o.cancel);
  FitData d;
  auto features = BuildFeatures(inputs, o.inputs, o.rate, o.state, /*causal=*/false);
  if (!features.ok()) return features.error();
  d.x = std::move(*features);
  d.y.assign(target.begin(), target.end());
  const std::size_t n = d.y.size();
  const double duration_s = static_cast<double>(n) / inputs.fs_hz;
  // Decimated training copy: block means over train_period_s (the mean is the anti-alias filter;
  // the drift varies over minutes to hours). A record that fits under the cap is never averaged.
  const double period_s = o.train_period_s.value_or(
      n <= o.max_train_samples ? 1.0 / inputs.fs_hz
                               : std::max(30.0, duration_s / static_cast<double>(o.max_train_samples)));
  d.block = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(period_s * inputs.fs_hz)));
  for (const auto& c : d.x) d.xd.push_back(BlockMeans(c, d.block));
  d.yd = BlockMeans(d.y, d.block);
  d.train_period_s = static_cast<double>(d.block) / inputs.fs_hz;
  if (d.yd.size() < 2 * static_cast<std::size_t>(o.cv_folds))
    return InvalidInput("FitDriftModel: the record gives " + std::to_string(d.yd.size()) + " training samples of " +
                        FormatNumber(d.train_period_s) + " s; " + std::to_string(o.cv_folds) +
                        "-fold blocked CV needs at least " + std::to_string(2 * o.cv_folds) +
                        " (shorter train_period_s or a longer record)");
  // The segment plan reads the centred dT/dt whatever the model's state.
  auto rate = TemperatureRate(inputs.temp_c, inputs.fs_hz, o.rate);
  if (!rate.ok()) return rate.error();
  d.rate_d = BlockMeans(*rate, d.block);
  MinMax(*rate, &d.dtemp_min_c_per_s, &d.dtemp_max_c_per_s);
  return d;
}

CvPlan MakeCvPlan(const FitData& d, const DriftFitOptions& o, DriftModelKind kind) {
  const DriftCvScheme scheme = o.cv_scheme.value_or(
      kind == DriftModelKind::kHybrid || kind == DriftModelKind::kAuto ? DriftCvScheme::kThermalSegments
                                                                       : DriftCvScheme::kBlocks);
  if (scheme == DriftCvScheme::kBlocks) return BlockPlan(d.yd.size(), o.cv_folds, o.cv_in_range_only);
  return SegmentPlan(d.rate_d, o.cv_folds, kSegmentRateThreshold);
}

Result<DriftModel> FitPrepared(const FitData& d, const DriftInputs& inputs, DriftModelKind kind,
                               const DriftFitOptions& o, const CvPlan& plan) {
  ThrowIfCancelled(o.cancel);
  DriftModel model;
  model.kind = kind;
  model.inputs = o.inputs;
  model.rate = o.rate;
  model.state = o.state;
  model.out_of_range = o.out_of_range;
  DriftFitSummary& s = model.summary;
  s.model = kind;
  s.inputs = o.inputs;
  s.target_name = o.target_name;
  s.num_samples = d.y.size();
  s.fs_hz = inputs.fs_hz;
  s.duration_s = static_cast<double>(d.y.size()) / inputs.fs_hz;
  s.cv_folds = plan.folds;
  s.cv_scheme = plan.scheme;
  s.cv_segments = plan.segments;
  s.cv_in_range_only = plan.in_range_only;
  s.train_period_s = d.train_period_s;
  MinMax(d.x[0], &s.temp_min_c, &s.temp_max_c);
  {
    double lo = 0.0, hi = 0.0;
    MinMax(d.yd, &lo, &hi);
    s.drift_span = hi - lo;
  }
  s.dtemp_min_c_per_s = d.dtemp_min_c_per_s;  // centred dT/dt, whatever the state
  s.dtemp_max_c_per_s = d.dtemp_max_c_per_s;
  if (o.inputs != DriftInputSet::kTemp) MinMax(d.x[1], &s.state_min, &s.state_max);
  if (o.inputs == DriftInputSet::kTempAndLag) s.lag_tau_s = o.state.lag_tau_s;

  if (kind == DriftModelKind::kPolynomial || kind == DriftModelKind::kHybrid) {
    // Fitted on every sample (cheap).
    auto poly = FitPolynomial(d.x, d.y, o.polynomial);
    if (!poly.ok()) return poly.error();
    s.degree = o.polynomial.degree;
    s.dtemp_degree = d.x.size() > 1 ? o.polynomial.dtemp_degree : 0;
    s.gain_temp_degree = d.x.size() > 1 ? o.polynomial.gain_temp_degree : 0;
    model.structured = std::move(*poly);
  }
  if (kind == DriftModelKind::kPolynomial) s.noise_model = o.noise_model;
  if (kind == DriftModelKind::kPolynomial && o.noise_model == DriftNoiseModel::kAllan) {
    if (Status st = FitPolynomialAllan(d, inputs, o, &model); !st.ok()) return st.error();
  } else if (kind == DriftModelKind::kPolynomial) {
    auto cv = CrossValidate(d.xd, d.yd, plan, PolyFitPredict(o.polynomial));
    if (!cv.ok()) return cv.error();
    s.cv_rmse = *cv;
    s.num_train = d.y.size();
    s.train_period_s = 1.0 / inputs.fs_hz;
  } else if (kind == DriftModelKind::kHybrid && o.hybrid_kernel_test && !MemoryIdentifiable(inputs, o)) {
    // Eq. H-1 scores the kernel on blocks of the run, i.e. on the direction(s) it covers. On the
    // simulated paper-profile runs (one short heating leg) it kept 5 kernels of 24, and all 5 were
    // worse than the polynomial on the next heating run (1.04-2.13x; docs/explanation/drift-models.md): not
    // searched, the model is its structured part.
    if (Status st = DropKernel(d, o, plan, &model); !st.ok()) return st.error();
    s.kernel_decision =
        "hybrid: kernel dropped (not searched): the calibration run does not both heat and cool over enough of its "
        "range, so a kernel in (T, state) cannot be validated on the other direction (--keep-kernel keeps it)";
    s.train_period_s = 1.0 / inputs.fs_hz;
  } else {
    std::vector<double> yd = d.yd;  // hybrid: the residual of the structured part
    if (kind == DriftModelKind::kHybrid) {
      const std::vector<double> p = model.structured->Predict(d.xd);
      for (std::size_t i = 0; i < yd.size(); ++i) yd[i] -= p[i];
    }
    SvrOptions chosen;
    if (Status st = FitKernel(d, yd, kind, o, plan, &model, &chosen); !st.ok()) return st.error();
    KernelTest test;
    if (kind == DriftModelKind::kHybrid && o.hybrid_kernel_test) {
      auto t = TestKernel(d, o, chosen);
      if (!t.ok()) return t.error();
      test = *t;
      s.kernel_decision = test.decision;
    }
    if (!test.keep) {
      if (Status st = DropKernel(d, o, plan, &model); !st.ok()) return st.error();
      s.train_period_s = 1.0 / inputs.fs_hz;
    } else if (kind == DriftModelKind::kHybrid) {
      FoldIntercept(&*model.structured, &*model.kernel);
    }
  }
  auto fitted = model.Predict(inputs);
  if (!fitted.ok()) return fitted.error();
  s.train_rmse = Rmse(*fitted, d.y);
  return model;
}

Status CheckFitArguments(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  if (!(inputs.fs_hz > 0.0) || !std::isfinite(inputs.fs_hz))
    return InvalidArgument("FitDriftModel: fs_hz = " + FormatNumber(inputs.fs_hz) + ": must be > 0");
  if (target.size() != inputs.temp_c.size())
    return InvalidInput("FitDriftModel: " + std::to_string(target.size()) + " target values for " +
                        std::to_string(inputs.temp_c.size()) + " temperature samples");
  for (std::size_t i = 0; i < target.size(); ++i)
    if (!std::isfinite(target[i]))
      return InvalidInput("FitDriftModel: non-finite target at sample " + std::to_string(i));
  return Status::Ok();
}

}  // namespace drift_internal

Result<DriftModel> FitDriftModel(const DriftInputs& inputs, std::span<const double> target,
                                 const DriftFitOptions& caller_options) {
  const auto t0 = std::chrono::steady_clock::now();
  ThrowIfCancelled(caller_options.cancel);
  // DriftFitOptions::cancel reaches the SVR search and fits unless they have their own token.
  DriftFitOptions options = caller_options;
  if (options.search.cuckoo.cancel == nullptr) options.search.cuckoo.cancel = options.cancel;
  if (options.svr.cancel == nullptr) options.svr.cancel = options.cancel;
  if (Status st = drift_internal::CheckFitArguments(inputs, target, options); !st.ok()) return st.error();
  Result<DriftModel> model = Error{};
  if (options.model == DriftModelKind::kAuto || (options.inputs == DriftInputSet::kTempAndLag && options.fit_lag_tau)) {
    model = drift_internal::FitSelected(inputs, target, options);
  } else {
    auto data = drift_internal::PrepareFitData(inputs, target, options);
    if (!data.ok()) return data.error();
    const drift_internal::CvPlan plan = drift_internal::MakeCvPlan(*data, options, options.model);
    model = drift_internal::FitPrepared(*data, inputs, options.model, options, plan);
  }
  if (!model.ok()) return model.error();
  ThrowIfCancelled(options.cancel);
  if (options.band) {
    // The CV's training copy: PrepareFitData's automatic block period.
    const double n = static_cast<double>(target.size());
    const double cv_period_s = options.train_period_s.value_or(
        target.size() <= options.max_train_samples ? 1.0 / inputs.fs_hz
                                                   : std::max(30.0, n / inputs.fs_hz / static_cast<double>(options.max_train_samples)));
    // A band that cannot be computed leaves the model without one (apply says so); never fails the fit.
    if (Status st = drift_internal::AttachBand(inputs, target, options, cv_period_s, &*model); !st.ok()) {
      model->band.reset();
      model->summary.data_support += std::string(model->summary.data_support.empty() ? "" : "; ") +
                                     "no prediction band: " + st.error().message;
    }
  }
  if (Status st = drift_internal::CheckModelLoads(*model); !st.ok()) {
    // A band whose numbers no model file may hold is dropped (the fit stands without it).
    if (!model->band) return st.error();
    model->band.reset();
    model->summary.data_support += std::string(model->summary.data_support.empty() ? "" : "; ") +
                                   "no prediction band: " + st.error().message;
    if (Status again = drift_internal::CheckModelLoads(*model); !again.ok()) return again.error();
  }
  model->summary.identifiability = drift_internal::DescribeIdentifiability(inputs, options);
  model->summary.fit_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return model;
}

}  // namespace gyrocomp
