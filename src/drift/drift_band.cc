// Prediction bands (docs/explanation/prediction-bands.md): how far the next run's
// true drift may lie from a fitted model's prediction.
//
//   Eq. B-1  var_i = a_i' C a_i + m^2,   band_i = center_i +- z sqrt(var_i),  z = 1.6449 (90%),
//            a_i the structured part's terms at sample i (standardised T and state).
//   Eq. B-2  C = (A'A)^-1 A' Sigma A (A'A)^-1: the covariance of the ordinary least squares
//            coefficients when the residual has the covariance Sigma of the run's measured noise:
//            the Eq. G-0 model (white + flicker + random walk) fitted to the Allan variance of the
//            fit's residual (Eq. G-1), Sigma(i, j) = R(|i - j|) of block means of gls_block_s
//            (Eq. G-2, with the spectrum held flat below f_floor = 1 / (2 pi tau_max), tau_max
//            the longest Allan averaging time fitted: the 1/f and 1/f^2 terms are not extrapolated
//            below what the Allan variance measured; extrapolated, a Gauss-Markov wander of 1500 s
//            fitted as a small random walk made the band 5x the realised error), A the terms at
//            those block means. The OLS on every sample and on block
//            means give nearly the same coefficients (the drift is slow).
//   Eq. B-2a The run's offset: the noise slower than the record moves the whole run and the fit's
//            constant with it, and the floored Sigma leaves most of it out. Sigma += max(0,
//            AVAR(record) - mean(Sigma)), AVAR(record) the Eq. G-0 model's Allan variance at the
//            record length of its white and flicker parts (IEEE 952: h0 / (2 T) + 2 ln2 h_-1; the
//            random walk is not extrapolated, see above): run-to-run bias repeatability. Without
//            it the parameter part was 4.2-7.1 mdps on structure A's rate-cycles runs against a
//            realised 9-11 (bench/drift_band_coverage.py).
//   Eq. B-2b The run's trend: the same slow noise tilts the run; the difference of its two
//            halves' means has the variance 2 AVAR(T / 2) of the white and flicker parts, of
//            which the floored Sigma holds less; the rest enters Sigma as a random linear trend in
//            time. A term that is one step in time on the run (the memory, or a dT/dt that
//            reverses once: a one-cycle run) takes it into its coefficient: without it the band
//            was 0.75x the realised error of structure C's one-cycle calibrations (`plan`'s one
//            pair outside 25%), with it 0.80x (docs/explanation/calibration-design.md).
//   Eq. B-3  m^2 = min(var(y), max(0, MSE_cv - E0)): the model form's spread, e.g. a hysteresis
//            or a lag the form cannot follow. MSE_cv: the structured form refitted on every fold
//            of the plan the fit scored on, pooled over the held-out points (a next run's error is
//            pooled over its samples). E0: that MSE's expectation had the run been exactly the
//            fitted form plus its measured noise: each held-out error is linear in the target,
//            e = G y, so E0 = tr(G Sigma G') / k (StructuredFormCv; Sigma with Eqs. B-2a and B-2b:
//            the offset cancels from every held-out error, the trend does not). E0 carries everything the
//            noise does to a CV: the held-out segment's own noise, each fold fit's parameter
//            error (larger than the full fit's where a left-out segment is an extrapolation) and
//            their correlation through the slow noise. Replaces the earlier CV_balanced^2 -
//            R_seg(0) - mean a'Ca, which let one draw of slow noise on a single-segment class
//            (rate-cycles' initial soak, a third of the direction-balanced score) make m 32 mdps
//            against a realised 4-7. Measured and not kept (less upward bias from max(0, .)
//            for a right form, more under-prediction where the form is wrong): subtracting one SD
//            s of MSE_cv under the noise as well (B's coverage 71.7%, `plan` 0.68-0.75x on 5 of
//            20 structure x profile pairs), or the positive-part shrinkage max(0, d - s^2 / d)
//            (`plan` 0.70-0.74x on 3 pairs). Capped at the target's variance: a larger CV error
//            is extrapolation (flagged by the fit), not the spread inside the range.
//   Eq. B-3s On a segment plan whose every fold is one whole segment (heat-cool, stairs: 3
//            segments, each fold a whole direction) the CV of Eq. B-3 is scored on contiguous
//            blocks: the segment form gave m = 0-57 mdps by seed against a realised 7-29 on
//            structure C's heat-cool and stairs runs (`plan` 1.43x there). With both, `plan`
//            held within 25% on 19 of 20 pairs; with Eq. B-2b all 20
//            (docs/explanation/calibration-design.md "`plan` against the simulation").
//   Eq. B-3k A model without a structured part (svr, cs-svr): its CV is not linear in the target;
//            m^2 = CV^2 - R_seg(0) - mean a'Ca as before, R_seg(0) the Eq. G-2 variance of a
//            block mean of the CV period about the mean of a left-out unit (duration / segments).
//   Eq. B-4  a dT/dt gain the run does not identify (Eq. I-1) is not in the model, and poly(T)
//            absorbed g r_cal(T), r_cal the calibration run's dT/dt as a cubic in T; on another
//            run it errs by g (r_i - r_cal(T_i)): var_i += g^2 (r_i - r_cal(T_i))^2, g the gain
//            from Eq. I-1, |g| capped at drift_span / max |dT/dt| of the run (a larger gain would
//            have shown in it). A heating-only calibration applied to a cooling run: r - r_cal ~
//            -1 C/min on the cooling holds. g^2 alone: its expectation over runs is already
//            g_true^2 + Var(g); g^2 + SE^2 (Eq. I-1's jackknife SE) counted the noise twice and
//            made `plan` over-predict a plain cubic's error on heat-cool / ramp by 1.7-1.8x
//            (docs/explanation/prediction-bands.md: coverage 84.6% with g^2, 87.2% before).
#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "drift_model_internal.h"
#include "gyrocomp/core/format.h"

namespace gyrocomp {
namespace drift_internal {
namespace {

constexpr double kZ90 = 1.6448536269514722;  // standard normal 95th percentile: two-sided 90%

// Terms of the structured polynomial at one raw (T, state[, memory]) (Eq. B-1's a_i; the
// memory column of temp,dtemp,memory is one more term).
Eigen::VectorXd TermRow(const PolynomialModel& p, double temp_c, double state, double memory) {
  const double t = (temp_c - p.input_scaler.offset[0]) / p.input_scaler.scale[0];
  const double r = p.input_scaler.offset.size() > 1 ? (state - p.input_scaler.offset[1]) / p.input_scaler.scale[1] : 0.0;
  const double m = p.input_scaler.offset.size() > 2 ? (memory - p.input_scaler.offset[2]) / p.input_scaler.scale[2] : 0.0;
  Eigen::VectorXd a(static_cast<Eigen::Index>(p.terms.size()));
  for (std::size_t k = 0; k < p.terms.size(); ++k)
    a(static_cast<Eigen::Index>(k)) = std::pow(t, p.terms[k].temp_power) * std::pow(r, p.terms[k].dtemp_power) *
                                      std::pow(m, p.terms[k].memory_power);
  return a;
}

// Column j of sample i, 0 when the record has no such column.
double Col(const Columns& x, std::size_t j, std::size_t i) { return x.size() > j ? x[j][i] : 0.0; }

// The residual's noise model (Eq. G-1), or white noise of the residual's variance when the
// record is too short for an Allan fit.
NoisePsd ResidualNoise(std::span<const double> residual, double fs_hz, double min_tau_s, const NoisePsdOptions& o) {
  NoisePsdOptions po = o;
  if (!po.min_tau_s) po.min_tau_s = min_tau_s;
  auto psd = FitNoisePsd(residual, fs_hz, po);
  if (psd.ok()) return *psd;
  double ss = 0.0;
  for (double v : residual) ss += v * v;
  NoisePsd white;
  white.h0 = 2.0 * ss / static_cast<double>(std::max<std::size_t>(1, residual.size())) / fs_hz;  // var = h0 fs / 2
  return white;
}

// The Eq. G-0 model without its random walk: what Eqs. B-2a and B-2b extrapolate to the record's
// scale (a Gauss-Markov wander fitted as a random walk would be counted again; below f_floor it is
// in Sigma already).
NoisePsd WhiteAndFlicker(NoisePsd psd) {
  psd.h_2 = 0.0;
  return psd;
}

// Eq. B-2b: the run's trend. The same slow noise also tilts the run: the difference of its two
// halves' means has the variance 2 AVAR(T / 2) (IEEE 952), of which the floored Sigma holds
// w' Sigma w (w: -1/h on the first h = floor(n/2) blocks, +1/h on the last h, 0 on an odd middle
// one). The rest enters as a random linear trend in time, Sigma += v tt', t linear in the block
// index with w't = 1: what a term that is one step in time on the run (a memory or a dT/dt that
// reverses once) takes from the noise. `wf`: WhiteAndFlicker of the run's noise model.
void AddRunTrend(const NoisePsd& wf, double duration_s, Eigen::MatrixXd* sigma) {
  const Eigen::Index n = sigma->rows();
  if (n < 2) return;  // one block: no trend to tell from the offset
  Eigen::VectorXd w(n), t(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    w(i) = (2 * i + 1 < n ? -1.0 : 2 * i + 1 > n ? 1.0 : 0.0) / static_cast<double>(n / 2);
    t(i) = static_cast<double>(2 * i + 1 - n) / static_cast<double>(n);
  }
  t /= w.dot(t);
  const double v = 2.0 * ModelAllanVariance(wf, 0.5 * duration_s) - w.dot(*sigma * w);
  if (v > 0.0) *sigma += v * t * t.transpose();
}

}  // namespace

Eigen::MatrixXd Toeplitz(const std::vector<double>& r) {
  const auto n = static_cast<Eigen::Index>(r.size());
  Eigen::MatrixXd sigma(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) sigma(i, j) = r[static_cast<std::size_t>(i > j ? i - j : j - i)];
  return sigma;
}

// Declared in drift_model_internal.h. Eq. B-2a, the run's offset: the noise slower than the
// record is common to every block; its variance is the Allan variance at the record length
// (IEEE 952: N^2 / T and the flicker floor 2 ln2 h_-1, which holds at every tau). Then Eq. B-2b.
Eigen::MatrixXd RunCovariance(Eigen::MatrixXd floored, const NoisePsd& psd, double duration_s) {
  const NoisePsd wf = WhiteAndFlicker(psd);
  floored.array() += std::max(0.0, ModelAllanVariance(wf, duration_s) - floored.mean());
  AddRunTrend(wf, duration_s, &floored);
  return floored;
}

namespace {

// Terms of the structured part at every sample of a (decimated) training copy.
Eigen::MatrixXd TermMatrix(const PolynomialModel& p, const Columns& xd) {
  const std::size_t n = xd[0].size();
  Eigen::MatrixXd a(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(p.terms.size()));
  for (std::size_t i = 0; i < n; ++i) a.row(static_cast<Eigen::Index>(i)) = TermRow(p, xd[0][i], Col(xd, 1, i), Col(xd, 2, i)).transpose();
  return a;
}

// Eq. B-2 on block means of `period_s`.
Result<Eigen::MatrixXd> ParameterCovariance(const DriftModel& m, const DriftInputs& inputs, std::span<const double> target,
                                            const DriftFitOptions& o, const NoisePsd& psd, double period_s) {
  DriftFitOptions g = o;
  g.inputs = m.inputs;
  g.state = m.state;
  g.rate = m.rate;
  g.train_period_s = period_s;
  g.cv_folds = 2;  // only the block means are used here
  auto d = PrepareFitData(inputs, target, g);
  if (!d.ok()) return d.error();
  const std::size_t n = d->yd.size();
  const Eigen::MatrixXd a = TermMatrix(*m.structured, d->xd);
  const double duration_s = static_cast<double>(target.size()) / inputs.fs_hz;
  const double f_floor_hz = RedSpectrumFloorHz(o.noise_psd, duration_s);
  const std::vector<double> r = BlockMeanAutocovariance(psd, n, d->train_period_s, f_floor_hz);  // Eq. G-2, floored
  const Eigen::MatrixXd sigma = RunCovariance(Toeplitz(r), psd, duration_s);
  const Eigen::MatrixXd ata = a.transpose() * a;
  const Eigen::MatrixXd bread = ata.completeOrthogonalDecomposition().pseudoInverse();
  return Eigen::MatrixXd(bread * (a.transpose() * sigma * a) * bread);
}

}  // namespace

// Eq. B-3's CV (declared in drift_model_internal.h).
Result<FormCv> StructuredFormCv(const DriftModel& m, const DriftInputs& inputs, std::span<const double> target,
                                const DriftFitOptions& o, const NoisePsd& psd, double cv_period_s) {
  if (!m.structured) return InvalidInput("band: the model has no structured part");
  const bool gls = m.summary.noise_model == DriftNoiseModel::kAllan;
  DriftFitOptions g = o;
  g.inputs = m.inputs;
  g.state = m.state;
  g.rate = m.rate;
  g.train_period_s = gls ? m.summary.train_period_s : cv_period_s;
  auto d = PrepareFitData(inputs, target, g);
  if (!d.ok()) return d.error();
  std::string note;
  CvPlan plan = ModelCvPlan(*d, o, &note);
  // Eq. B-3s: a segment plan whose every fold is one whole segment (heat-cool, stairs: 3
  // segments) leaves out a whole direction; its CV error is that fold's extrapolation of the
  // state to a direction it never saw, not the full model's spread. Scored on contiguous blocks
  // instead (the Eq. H-1 plan, in range only).
  if (plan.scheme == DriftCvScheme::kThermalSegments && plan.segments <= plan.folds) plan = GainTestPlan(d->yd.size(), o);
  const std::size_t n = d->yd.size();
  if (n > o.max_gls_blocks) return InvalidInput("band: " + std::to_string(n) + " CV points (more than max_gls_blocks)");
  const Eigen::MatrixXd a = TermMatrix(*m.structured, d->xd);
  const double duration_s = static_cast<double>(target.size()) / inputs.fs_hz;
  // Eq. B-2's Sigma, the noise E0 is taken under with the run's offset and trend (Eqs. B-2a, B-2b;
  // the offset cancels from every held-out error, as every fold reproduces a constant, the trend
  // does not). GLS folds are weighted by the floored Sigma alone, the fit's own weights (they
  // differ only below the floor).
  const Eigen::MatrixXd sigma = Toeplitz(BlockMeanAutocovariance(psd, n, d->train_period_s, RedSpectrumFloorHz(o.noise_psd, duration_s)));
  const Eigen::MatrixXd noise = RunCovariance(sigma, psd, duration_s);
  const auto nn = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd gm = Eigen::MatrixXd::Zero(nn, nn);  // one row per scored held-out sample
  Eigen::Index rows = 0;
  for (int k = 0; k < plan.folds; ++k) {
    std::vector<Eigen::Index> tr, va;
    for (std::size_t i = 0; i < n; ++i) (plan.fold_of[i] == k ? va : tr).push_back(static_cast<Eigen::Index>(i));
    if (tr.empty() || va.empty()) continue;
    const Eigen::MatrixXd at = a(tr, Eigen::all);
    const Eigen::MatrixXd wat = gls ? Eigen::MatrixXd(sigma(tr, tr).llt().solve(at)) : at;  // W A_T
    const Eigen::MatrixXd fit = (at.transpose() * wat).completeOrthogonalDecomposition().pseudoInverse() * wat.transpose();
    double t_lo = std::numeric_limits<double>::infinity(), t_hi = -t_lo;
    for (Eigen::Index i : tr) {
      t_lo = std::min(t_lo, d->xd[0][static_cast<std::size_t>(i)]);
      t_hi = std::max(t_hi, d->xd[0][static_cast<std::size_t>(i)]);
    }
    for (Eigen::Index i : va) {
      const double t = d->xd[0][static_cast<std::size_t>(i)];
      if (plan.in_range_only && (t < t_lo || t > t_hi)) continue;  // as CrossValidate scores
      gm(rows, tr) = a.row(i) * fit;
      gm(rows, i) -= 1.0;
      ++rows;
    }
  }
  if (rows == 0) return InvalidInput("band: the CV plan scores no held-out point");
  gm.conservativeResize(rows, nn);
  const Eigen::VectorXd e = gm * Eigen::Map<const Eigen::VectorXd>(d->yd.data(), nn);
  const double k = static_cast<double>(rows);
  FormCv f;
  f.scheme = plan.scheme;
  f.points = static_cast<std::size_t>(rows);
  f.mse = e.squaredNorm() / k;
  f.noise_mse = (gm * noise).cwiseProduct(gm).sum() / k;  // tr(G Sigma G') / k, E e'e / k under the noise alone
  return f;
}

Status AttachBand(const DriftInputs& inputs, std::span<const double> target, const DriftFitOptions& o,
                  double cv_period_s, DriftModel* m) {
  auto pred = m->Predict(inputs);
  if (!pred.ok()) return pred.error();
  std::vector<double> residual(target.size());
  for (std::size_t i = 0; i < residual.size(); ++i) residual[i] = target[i] - (*pred)[i];
  const double duration_s = static_cast<double>(target.size()) / inputs.fs_hz;
  // gls_block_s (longer when the record would give more than max_gls_blocks), but at least 20
  // blocks when the record allows (a short table: every row).
  const double period_s = std::max(1.0 / inputs.fs_hz, std::min(std::max(o.gls_block_s, duration_s / static_cast<double>(o.max_gls_blocks)),
                                                                 duration_s / 20.0));
  DriftBandModel band;
  band.noise = ResidualNoise(residual, inputs.fs_hz, period_s, o.noise_psd);
  band.coverage_check = "docs/explanation/prediction-bands.md, Coverage on held-out runs: held-out simulated runs";
  double param_var = 0.0;
  Eigen::MatrixXd cov;
  if (m->structured) {
    auto c = ParameterCovariance(*m, inputs, target, o, band.noise, period_s);
    if (!c.ok()) return c.error();
    cov = *c;
    band.parameter_cov.assign(cov.data(), cov.data() + cov.size());  // symmetric: order irrelevant
    auto features = BuildFeatures(inputs, m->inputs, m->rate, m->state, /*causal=*/false);
    if (!features.ok()) return features.error();
    for (std::size_t i = 0; i < target.size(); ++i) {
      const Eigen::VectorXd a = TermRow(*m->structured, (*features)[0][i], Col(*features, 1, i), Col(*features, 2, i));
      param_var += a.dot(cov * a) / static_cast<double>(target.size());
    }
  }
  // Eq. B-3: what the thermal-segment CV shows beyond what the run's noise alone would give.
  const double cv_period = std::max(cv_period_s, 1.0 / inputs.fs_hz);
  double model_form_ms = 0.0;
  auto form = StructuredFormCv(*m, inputs, target, o, band.noise, cv_period);
  if (form.ok()) {
    model_form_ms = form->mse - form->noise_mse;
  } else {  // Eq. B-3k: a kernel model (its CV is not linear in the target), or too many CV points
    const int units = std::max(1, m->summary.cv_segments > 0 ? m->summary.cv_segments : m->summary.cv_folds);
    const auto unit_blocks = static_cast<std::size_t>(std::clamp(duration_s / units / cv_period, 1.0, 2000.0));
    model_form_ms = m->summary.cv_rmse * m->summary.cv_rmse - BlockMeanAutocovariance(band.noise, unit_blocks, cv_period)[0] - param_var;
  }
  double mean = 0.0, var_y = 0.0;
  for (double v : target) mean += v / static_cast<double>(target.size());
  for (double v : target) var_y += (v - mean) * (v - mean) / static_cast<double>(target.size());
  band.model_form_rms = std::sqrt(std::clamp(model_form_ms, 0.0, var_y));
  band.expected_rms = std::sqrt(param_var + band.model_form_rms * band.model_form_rms);
  const DriftFitSummary& fs = m->summary;
  if (fs.unidentified_rate_gain && fs.unidentified_rate_gain_se) {
    // Capped at the gain that would by itself span the run's whole drift at its fastest dT/dt:
    // a larger one would have shown in the run.
    const double r_max = std::max(std::abs(fs.dtemp_min_c_per_s), std::abs(fs.dtemp_max_c_per_s));
    const double cap = r_max > 0.0 ? fs.drift_span / r_max : 0.0;
    band.unidentified_rate_gain_rms = std::min(cap, std::abs(*fs.unidentified_rate_gain));
  }
  band.calibration_rate_vs_temp = fs.calibration_rate_vs_temp;
  if (m->structured && (m->inputs == DriftInputSet::kTempAndRate || m->inputs == DriftInputSet::kTempRateAndMemory)) {
    DriftFitOptions r = o;  // Eq. B-5: the direction the run did not cover
    r.rate = m->rate;
    band.unseen_direction = UncoveredDirection(inputs, r);
  }
  m->band = std::move(band);
  return Status::Ok();
}

}  // namespace drift_internal

double RateCurve::At(double temp_c) const {
  const double t = (temp_c - offset_c) / scale_c;
  double f = 0.0, p = 1.0;
  for (double c : coefficients) f += c * p, p *= t;
  return f;
}

Result<DriftBand> DriftModel::PredictBand(const DriftInputs& in, bool causal) const {
  if (!band) return InvalidInput("drift model: no prediction band (the model file predates prediction bands; refit it)");
  auto center = Predict(in, causal);
  if (!center.ok()) return center.error();
  DriftBand b;
  b.level = band->level;
  b.center = std::move(*center);
  b.lo.resize(b.center.size());
  b.hi.resize(b.center.size());
  // z of a two-sided normal interval at `level` (0.9 -> 1.645); other levels by bisection.
  double z = drift_internal::kZ90;
  if (std::abs(band->level - 0.9) > 1e-12) {
    double lo = 0.0, hi = 10.0;
    for (int k = 0; k < 100; ++k) {
      const double mid = 0.5 * (lo + hi);
      (std::erf(mid / std::sqrt(2.0)) < band->level ? lo : hi) = mid;
    }
    z = 0.5 * (lo + hi);
  }
  Eigen::MatrixXd cov;
  std::optional<drift_internal::Columns> features;
  if (structured && !band->parameter_cov.empty()) {
    const auto p = static_cast<Eigen::Index>(structured->terms.size());
    if (band->parameter_cov.size() != static_cast<std::size_t>(p * p))
      return InvalidInput("drift model: band.parameter_cov does not match the structured terms");
    cov = Eigen::Map<const Eigen::MatrixXd>(band->parameter_cov.data(), p, p);
    auto f = drift_internal::BuildFeatures(in, inputs, rate, state, causal);
    if (!f.ok()) return f.error();
    features = std::move(*f);
  }
  const double mf2 = band->model_form_rms * band->model_form_rms;
  std::vector<double> dtemp;
  const bool unseen = band->unseen_direction != 0 && features && features->size() > 1;
  if (band->unidentified_rate_gain_rms > 0.0 || unseen) {
    auto r = TemperatureRate(in.temp_c, in.fs_hz, rate);
    if (!r.ok()) return r.error();
    dtemp = std::move(*r);
  }
  for (std::size_t i = 0; i < b.center.size(); ++i) {
    double var = mf2;
    if (!dtemp.empty() && band->unidentified_rate_gain_rms > 0.0) {  // Eq. B-4
      const double d = dtemp[i] - band->calibration_rate_vs_temp.At(in.temp_c[i]);
      var += std::pow(band->unidentified_rate_gain_rms * d, 2);
    }
    if (features) {
      const double t = EffectiveTemp((*features)[0][i]), mem = drift_internal::Col(*features, 2, i);
      const Eigen::VectorXd a = drift_internal::TermRow(*structured, t, drift_internal::Col(*features, 1, i), mem);
      var += a.dot(cov * a);
      // Eq. B-5: moving in the direction the calibration run did not cover, the model's dT/dt
      // contribution s_i (its prediction here minus that at dT/dt = 0) is what the run measured of
      // a ramp against a hold in its own direction; the other direction's may differ from the
      // mirror image by as much (a memory, a gain that differs by direction), which the run cannot
      // show. Added as one SD.
      if (unseen && dtemp[i] * band->unseen_direction > drift_internal::kSegmentRateThreshold) {
        const Eigen::VectorXd a0 = drift_internal::TermRow(*structured, t, 0.0, mem);
        double s_i = 0.0;
        for (std::size_t k = 0; k < structured->terms.size(); ++k)
          s_i += structured->terms[k].coefficient * (a(static_cast<Eigen::Index>(k)) - a0(static_cast<Eigen::Index>(k)));
        var += s_i * s_i;
      }
    }
    const double half = z * std::sqrt(std::max(0.0, var));
    b.lo[i] = b.center[i] - half;
    b.hi[i] = b.center[i] + half;
  }
  return b;
}

}  // namespace gyrocomp
