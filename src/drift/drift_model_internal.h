// Internals shared by drift_model.cc, polynomial_model.cc, cs_svr.cc and drift_model_io.cc.
// Not installed; not part of the public API.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "gyrocomp/drift/drift_model.h"

namespace gyrocomp::drift_internal {

using Columns = std::vector<std::vector<double>>;  // columns[j][i]

// Model inputs at every sample: column 0 temperature (deg C), column 1 dT/dt (deg C/s) when the
// input set includes it.
Result<Columns> BuildFeatures(const DriftInputs& inputs, DriftInputSet set,
                              const TemperatureRateOptions& rate);

// Means of consecutive blocks of `block` samples (the last block may be shorter).
std::vector<double> BlockMeans(std::span<const double> x, std::size_t block);

// A model fitted on training columns/target, returning predictions at other columns.
using FitPredict = std::function<Result<std::vector<double>>(
    const Columns& train_x, std::span<const double> train_y, const Columns& test_x)>;

// Blocked cross-validation: `folds` contiguous blocks; each is predicted by a model fitted on the
// others. Returns the RMSE over the held-out predictions (only those whose temperature, column 0,
// lies within the training blocks' range when in_range_only; an error if none does).
Result<double> BlockedCvRmse(const Columns& x, std::span<const double> y, int folds,
                             bool in_range_only, const FitPredict& fit_predict);

// Least squares polynomial (Eigen) on the standardised inputs.
Result<PolynomialModel> FitPolynomial(const Columns& x, std::span<const double> y,
                                      const PolynomialOptions& options);

// Outcome of a parameter search for the SVR family.
struct SvrChoice {
  SvrOptions options;      // with C, sigma (and epsilon) chosen
  double cv_rmse = 0.0;
  long evaluations = 0;
  int generations = 0;
  std::vector<double> history;
};

// cs-svr: cuckoo search over (C, sigma[, epsilon]) minimising the blocked CV RMSE.
Result<SvrChoice> SearchSvrCuckoo(const Columns& x, std::span<const double> y,
                                  const DriftFitOptions& options);
// grid-svr: log-spaced square grid over (C, sigma) at the same budget.
Result<SvrChoice> SearchSvrGrid(const Columns& x, std::span<const double> y,
                                const DriftFitOptions& options);

// Evaluations the cuckoo search makes: num_nests * (1 + 2 * max_generations), capped.
long CuckooBudget(const CuckooSearchOptions& o);

}  // namespace gyrocomp::drift_internal
