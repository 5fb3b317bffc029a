// Polynomial baseline: least squares in standardised temperature [and dT/dt] (Eigen).
#include <cmath>

#include <Eigen/Dense>

#include "drift_model_internal.h"

namespace gyrocomp {

double PolynomialModel::PredictOne(double temp_c, double state, double memory) const {
  const double t = (temp_c - input_scaler.offset[0]) / input_scaler.scale[0];
  const double r = input_scaler.offset.size() > 1 ? (state - input_scaler.offset[1]) / input_scaler.scale[1] : 0.0;
  const double m = input_scaler.offset.size() > 2 ? (memory - input_scaler.offset[2]) / input_scaler.scale[2] : 0.0;
  double f = 0.0;
  for (const PolynomialTerm& term : terms) {
    double v = term.coefficient * std::pow(t, term.temp_power) * std::pow(r, term.dtemp_power);
    if (term.memory_power) v *= std::pow(m, term.memory_power);  // temp,dtemp,memory only
    f += v;
  }
  return f;
}

std::vector<double> PolynomialModel::Predict(const std::vector<std::vector<double>>& inputs) const {
  const std::size_t n = inputs.empty() ? 0 : inputs[0].size();
  std::vector<double> out(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = PredictOne(inputs[0][i], inputs.size() > 1 ? inputs[1][i] : 0.0, inputs.size() > 2 ? inputs[2][i] : 0.0);
  return out;
}

namespace drift_internal {

namespace {

// The terms of `options` and the scaler of x (model without coefficients), and its design matrix.
Result<PolynomialModel> PolynomialTerms(const Columns& x, std::size_t n, const PolynomialOptions& options,
                                        Eigen::MatrixXd* a) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  PolynomialModel model;
  model.input_scaler = AffineScaler::Standardize(x);
  // Terms: t^0 .. t^degree, then r^1 .. r^dtemp_degree when dT/dt is an input, then r t^1 ..
  // r t^gain_temp_degree (a gain that varies with temperature), then m (linear) when the memory
  // is a second state (temp,dtemp,memory).
  for (int p = 0; p <= options.degree; ++p) model.terms.push_back({p, 0, 0.0, 0});
  if (x.size() > 1) {
    for (int q = 1; q <= options.dtemp_degree; ++q) model.terms.push_back({0, q, 0.0, 0});
    for (int p = 1; p <= options.gain_temp_degree; ++p) model.terms.push_back({p, 1, 0.0, 0});
  }
  if (x.size() > 2) model.terms.push_back({0, 0, 0.0, 1});
  const std::size_t m = model.terms.size();
  if (n < m)
    return InvalidInput("polynomial fit: " + std::to_string(m) + " coefficients need at least " +
                        std::to_string(m) + " samples, got " + std::to_string(n));
  a->resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(m));
  for (std::size_t i = 0; i < n; ++i) {
    const double t = (x[0][i] - model.input_scaler.offset[0]) / model.input_scaler.scale[0];
    const double r = x.size() > 1 ? (x[1][i] - model.input_scaler.offset[1]) / model.input_scaler.scale[1] : 0.0;
    const double mm = x.size() > 2 ? (x[2][i] - model.input_scaler.offset[2]) / model.input_scaler.scale[2] : 0.0;
    for (std::size_t k = 0; k < m; ++k)
      (*a)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = std::pow(t, model.terms[k].temp_power) *
                                                                          std::pow(r, model.terms[k].dtemp_power) *
                                                                          std::pow(mm, model.terms[k].memory_power);
  }
  return model;
}

// Least squares a c = b by column-pivoted QR (robust when the temperature range is narrow and the
// columns nearly collinear); the coefficients into `model`.
Status SolveInto(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, int degree, PolynomialModel* model) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  const auto m = static_cast<Eigen::Index>(model->terms.size());
  if (qr.rank() < m)
    return InvalidInput("polynomial fit: degree " + std::to_string(degree) +
                        " is not identifiable from this record (rank " + std::to_string(qr.rank()) +
                        " < " + std::to_string(m) + " terms; too few distinct temperatures?)");
  const Eigen::VectorXd c = qr.solve(b);
  for (Eigen::Index k = 0; k < m; ++k) model->terms[static_cast<std::size_t>(k)].coefficient = c(k);
  return Status::Ok();
}

}  // namespace

Result<PolynomialModel> FitPolynomial(const Columns& x, std::span<const double> y,
                                      const PolynomialOptions& options) {
  Eigen::MatrixXd a;
  auto model = PolynomialTerms(x, y.size(), options, &a);
  if (!model.ok()) return model.error();
  const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(y.data(), static_cast<Eigen::Index>(y.size()));
  if (Status st = SolveInto(a, b, options.degree, &*model); !st.ok()) return st.error();
  return model;
}

Result<PolynomialModel> FitPolynomialGls(const Columns& x, std::span<const double> y,
                                         std::span<const double> autocov, std::span<const std::size_t> index,
                                         const PolynomialOptions& options) {
  const std::size_t n = y.size();
  if (index.size() != n) return InvalidArgument("FitPolynomialGls: one index per sample");
  Eigen::MatrixXd a;
  auto model = PolynomialTerms(x, n, options, &a);
  if (!model.ok()) return model.error();
  // Eq. G-3: Sigma(i, j) = R(|index_i - index_j|), plus 1e-6 R(0) on the diagonal (a floor that
  // keeps the factorisation stable when the white term is tiny); Sigma = L L'; then ordinary
  // least squares on L^-1 a, L^-1 y: the generalised least squares estimate.
  const auto ni = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd cov(ni, ni);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t lag = index[i] > index[j] ? index[i] - index[j] : index[j] - index[i];
      if (lag >= autocov.size()) return InvalidArgument("FitPolynomialGls: autocovariance shorter than the index span");
      cov(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = autocov[lag];
    }
  cov.diagonal().array() += 1e-6 * autocov[0];
  const Eigen::LLT<Eigen::MatrixXd> llt(cov);
  if (llt.info() != Eigen::Success)
    return InvalidInput("polynomial GLS fit: the noise covariance is not positive definite");
  const Eigen::MatrixXd aw = llt.matrixL().solve(a);
  const Eigen::VectorXd bw =
      llt.matrixL().solve(Eigen::Map<const Eigen::VectorXd>(y.data(), ni));
  if (Status st = SolveInto(aw, bw, options.degree, &*model); !st.ok()) return st.error();
  return model;
}

}  // namespace drift_internal
}  // namespace gyrocomp
