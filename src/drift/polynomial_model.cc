// Polynomial baseline: least squares in standardised temperature [and dT/dt] (Eigen).
#include <cmath>

#include <Eigen/Dense>

#include "drift_model_internal.h"

namespace gyrocomp {

double PolynomialModel::PredictOne(double temp_c, double state) const {
  const double t = (temp_c - input_scaler.offset[0]) / input_scaler.scale[0];
  const double r = input_scaler.offset.size() > 1 ? (state - input_scaler.offset[1]) / input_scaler.scale[1] : 0.0;
  double f = 0.0;
  for (const PolynomialTerm& term : terms)
    f += term.coefficient * std::pow(t, term.temp_power) * std::pow(r, term.dtemp_power);
  return f;
}

std::vector<double> PolynomialModel::Predict(const std::vector<std::vector<double>>& inputs) const {
  const std::size_t n = inputs.empty() ? 0 : inputs[0].size();
  std::vector<double> out(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) out[i] = PredictOne(inputs[0][i], inputs.size() > 1 ? inputs[1][i] : 0.0);
  return out;
}

namespace drift_internal {

Result<PolynomialModel> FitPolynomial(const Columns& x, std::span<const double> y,
                                      const PolynomialOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  const std::size_t n = y.size();
  PolynomialModel model;
  model.input_scaler = AffineScaler::Standardize(x);
  // Terms: t^0 .. t^degree, then r^1 .. r^dtemp_degree when dT/dt is an input.
  for (int p = 0; p <= options.degree; ++p) model.terms.push_back({p, 0, 0.0});
  if (x.size() > 1)
    for (int q = 1; q <= options.dtemp_degree; ++q) model.terms.push_back({0, q, 0.0});
  const std::size_t m = model.terms.size();
  if (n < m)
    return InvalidInput("polynomial fit: " + std::to_string(m) + " coefficients need at least " +
                        std::to_string(m) + " samples, got " + std::to_string(n));
  Eigen::MatrixXd a(n, m);
  Eigen::VectorXd b(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = (x[0][i] - model.input_scaler.offset[0]) / model.input_scaler.scale[0];
    const double r = x.size() > 1 ? (x[1][i] - model.input_scaler.offset[1]) / model.input_scaler.scale[1] : 0.0;
    for (std::size_t k = 0; k < m; ++k)
      a(i, k) = std::pow(t, model.terms[k].temp_power) * std::pow(r, model.terms[k].dtemp_power);
    b(i) = y[i];
  }
  // Column-pivoted QR: robust when the temperature range is narrow (columns nearly collinear).
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < static_cast<Eigen::Index>(m))
    return InvalidInput("polynomial fit: degree " + std::to_string(options.degree) +
                        " is not identifiable from this record (rank " + std::to_string(qr.rank()) +
                        " < " + std::to_string(m) + " terms; too few distinct temperatures?)");
  const Eigen::VectorXd c = qr.solve(b);
  for (std::size_t k = 0; k < m; ++k) model.terms[k].coefficient = c(k);
  return model;
}

}  // namespace drift_internal
}  // namespace gyrocomp
