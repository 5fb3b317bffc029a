// Validation of a drift model on another run (drift_validate.h).
#include "gyrocomp/drift/drift_validate.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Dense>

#include "drift_model_internal.h"
#include "gyrocomp/allan/allan.h"

namespace gyrocomp {
namespace {

double SdAboutMean(const std::vector<double>& x) {
  double m = 0.0, ss = 0.0;
  for (double v : x) m += v;
  m /= static_cast<double>(x.size());
  for (double v : x) ss += (v - m) * (v - m);
  return std::sqrt(ss / static_cast<double>(x.size()));
}

double FractionOutside(std::span<const double> x, double lo, double hi) {
  std::size_t k = 0;
  for (double v : x) k += (v < lo || v > hi) ? 1 : 0;
  return x.empty() ? 0.0 : static_cast<double>(k) / static_cast<double>(x.size());
}

}  // namespace

bool DriftValidationOptions::IsValid(std::string* error) const {
  if (!(block_s > 0.0) || !(min_tau_s > 0.0) || !std::isfinite(block_s) || !std::isfinite(min_tau_s)) {
    if (error) *error = "DriftValidationOptions: block_s and min_tau_s must be > 0";
    return false;
  }
  return true;
}

std::string DriftValidation::BriefReport() const {
  std::ostringstream s;
  s << "validation on " << num_samples << " samples: residual drift RMS " << residual_drift_rms << " (raw "
    << raw_drift_rms << ", " << num_blocks << " block means), slope vs T " << slope_vs_temp << " /C, vs dT/dt "
    << slope_vs_dtemp << " /(C/s)";
  if (rmse_vs_true_drift) s << ", RMSE vs true drift " << *rmse_vs_true_drift;
  s << "; outside the fitted range: T " << 100.0 * fraction_temp_outside << "%, dT/dt "
    << 100.0 * fraction_dtemp_outside << "%";
  if (!band_level) {
    s << "; the model has no prediction band (the model file predates prediction bands)";
  } else {
    s << "; " << 100.0 * *band_level << "% band: half-width RMS " << *band_half_width_rms;
    if (band_coverage_truth) s << ", covers " << 100.0 * *band_coverage_truth << "% of the true drift";
    if (band_coverage_blocks)
      s << ", covers " << 100.0 * *band_coverage_blocks << "% of the rate's block means (these include the run's "
        << "noise)";
  }
  return s.str();
}

Result<DriftValidation> ValidateDriftModel(const DriftModel& model, std::span<const double> rate,
                                           std::span<const double> temp_c, double fs_hz,
                                           std::span<const double> true_drift,
                                           const DriftValidationOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  if (rate.size() != temp_c.size() || (!true_drift.empty() && true_drift.size() != rate.size()))
    return InvalidInput("validate: the rate, temperature and truth columns differ in length");
  auto predicted = model.Predict({temp_c, fs_hz}, o.causal);
  if (!predicted.ok()) return predicted.error();
  auto dtemp = TemperatureRate(temp_c, fs_hz, model.rate);
  if (!dtemp.ok()) return dtemp.error();
  DriftValidation v;
  v.num_samples = rate.size();
  v.fs_hz = fs_hz;
  std::vector<double> comp(rate.size());
  for (std::size_t i = 0; i < comp.size(); ++i) comp[i] = rate[i] - (*predicted)[i];
  // Residual drift: block means, and its regression on [1, T, dT/dt].
  const std::size_t block = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(o.block_s * fs_hz)));
  const std::vector<double> cb = drift_internal::BlockMeans(comp, block);
  const std::vector<double> rb = drift_internal::BlockMeans(rate, block);
  const std::vector<double> tb = drift_internal::BlockMeans(temp_c, block);
  const std::vector<double> db = drift_internal::BlockMeans(*dtemp, block);
  v.num_blocks = cb.size();
  v.raw_drift_rms = SdAboutMean(rb);
  v.residual_drift_rms = SdAboutMean(cb);
  for (double c : comp) v.residual_mean += c / static_cast<double>(comp.size());
  if (cb.size() >= 3) {
    Eigen::MatrixXd a(cb.size(), 3);
    Eigen::VectorXd b(cb.size());
    for (std::size_t i = 0; i < cb.size(); ++i) {
      a(i, 0) = 1.0, a(i, 1) = tb[i], a(i, 2) = db[i];
      b(i) = cb[i];
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
    if (qr.rank() == 3) {
      const Eigen::VectorXd c = qr.solve(b);
      v.slope_vs_temp = c(1);
      v.slope_vs_dtemp = c(2);
    }
  }
  // ADEV at long taus (octave grid).
  auto raw_adev = ComputeAllan(rate, fs_hz);
  auto comp_adev = ComputeAllan(comp, fs_hz);
  if (raw_adev.ok() && comp_adev.ok())
    for (std::size_t k = 0; k < raw_adev->curve.size(); ++k)
      if (raw_adev->curve.tau_s[k] >= o.min_tau_s) {
        v.tau_s.push_back(raw_adev->curve.tau_s[k]);
        v.adev_raw.push_back(raw_adev->curve.adev_dps[k]);
        v.adev_compensated.push_back(comp_adev->curve.adev_dps[k]);
      }
  if (!true_drift.empty()) v.rmse_vs_true_drift = drift_internal::Rmse(*predicted, true_drift);
  if (model.band) {
    auto band = model.PredictBand({temp_c, fs_hz}, o.causal);
    if (!band.ok()) return band.error();
    v.band_level = band->level;
    double half2 = 0.0;
    std::size_t inside = 0;
    for (std::size_t i = 0; i < band->lo.size(); ++i) {
      half2 += std::pow(0.5 * (band->hi[i] - band->lo[i]), 2);
      if (!true_drift.empty()) inside += true_drift[i] >= band->lo[i] && true_drift[i] <= band->hi[i] ? 1 : 0;
    }
    const double n = static_cast<double>(std::max<std::size_t>(1, band->lo.size()));
    v.band_half_width_rms = std::sqrt(half2 / n);
    if (!true_drift.empty()) v.band_coverage_truth = static_cast<double>(inside) / n;
    const std::vector<double> lob = drift_internal::BlockMeans(band->lo, block);
    const std::vector<double> hib = drift_internal::BlockMeans(band->hi, block);
    std::size_t in_blocks = 0;
    for (std::size_t i = 0; i < rb.size(); ++i) in_blocks += rb[i] >= lob[i] && rb[i] <= hib[i] ? 1 : 0;
    v.band_coverage_blocks = rb.empty() ? 0.0 : static_cast<double>(in_blocks) / static_cast<double>(rb.size());
  }
  v.excursion = model.CheckTemperatureRange(temp_c);
  v.fraction_temp_outside = v.excursion.fraction_outside;
  v.fraction_dtemp_outside =
      FractionOutside(*dtemp, model.summary.dtemp_min_c_per_s, model.summary.dtemp_max_c_per_s);
  return v;
}

}  // namespace gyrocomp
