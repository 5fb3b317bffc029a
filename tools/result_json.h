// JSON views of library results, shared by the subcommands (allan, decompose, fit, process,
// compare, demo) so that every command writes the same keys for the same thing (cli.md).
#pragma once

#include <nlohmann/json.hpp>

#include "gyrocomp/allan/allan.h"
#include "gyrocomp/denoise/bandwidth.h"
#include "gyrocomp/pipeline/compare.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/drift/drift_validate.h"
#include "gyrocomp/pipeline/pipeline.h"

namespace gyrocomp::cli {

// cli.md `allan` keys: fs_hz, n_samples, tau_s, adev_dps, adev_error_dps, n_clusters,
// arw_deg_per_sqrt_h, adev_min_deg_per_h, tau_at_min_s, bias_instability_deg_per_h,
// rrw_deg_per_h_per_sqrt_h; plus the confidence intervals, EDF and the conventions used.
nlohmann::json AllanJson(const AllanResult& r, bool with_curve = true);

// The noise terms only (for before/after tables).
nlohmann::json AllanTermsJson(const AllanResult& r);

// modes[] as in `decompose`: index, center_frequency_hz, center_frequency_cycles_per_sample,
// sample_entropy, class.
nlohmann::json ModesJson(const std::vector<ModeReport>& modes);

nlohmann::json BandwidthJson(const BandwidthResult& b);

nlohmann::json DriftSummaryJson(const DriftFitSummary& s);
// A drift model on another run (validate, fit --validate): keys documented in docs/reference/cli-contract.md.
nlohmann::json DriftValidationJson(const DriftValidation& v);

// One row of `compare` (gyrocomp/compare.h).
nlohmann::json MethodRowJson(const MethodRow& m);

// A JSON number, or null for NaN / Inf / absent.
nlohmann::json Num(double v);
nlohmann::json Num(const std::optional<double>& v);

}  // namespace gyrocomp::cli
