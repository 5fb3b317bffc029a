// Planning a calibration run: which chamber profile leaves the smallest drift error on the next
// run, per hour of chamber time (`gyrocomp plan`, `gyrocomp.plan`;
// docs/explanation/calibration-design.md, docs/guides/plan-chamber-run.md).
//
// The unit: its noise (IEEE 952 figures) and its drift family (the simulator's BiasModelOptions),
// stated by the caller (datasheet numbers) or read from recordings (PlanUnitFromRecordings):
//   an Allan run (a static recording): ARW from sigma(1 s), B = ADEV minimum / 0.664, RRW from the
//     +1/2 region (0 without one), as `allan` reads them;
//   a pilot chamber run: the structured model auto fits on it (no kernel) as the drift family
//     (FamilyFromModel), the noise of its residual (unless an Allan run is given; without the
//     RRW, which a chamber run's residual overstates), its temperature range as cold .. hot.
// A figure the caller stated (PlanStated) keeps its value over what a recording gives.
//
// For each profile and seed k = 1..seeds (PlanChamberRun): simulate the calibration run with the
// unit (seed k), fit the default drift model, and on two held-out runs (a heating ramp cold ->
// hot, seed k + 100, and the paper's cooling staircase, seed k + 200):
//   predicted = RMS over the run of the band's standard deviation (half-width / z(0.9)),
//   simulated = RMSE of the prediction against the true drift (the check of the prediction).
// The recommendation: the lowest of max(predicted, simulated); within 10% of it, the shortest.
//
// Messages name the options by the flags of `gyrocomp plan` (--profiles, --pilot, --rrw, ...),
// which the Python keywords mirror (docs/reference/cli/plan.md).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/drift/drift_model.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp {

// Which of the unit's figures the caller stated (a datasheet, a flag): each keeps the value in
// PlanOptions::unit over what a pilot run or an Allan run reads.
struct PlanStated {
  bool arw = false;               // noise.arw_deg_per_sqrt_h
  bool bias_instability = false;  // noise.bias_instability_deg_per_h
  bool rrw = false;               // noise.rrw_deg_per_h_per_sqrt_h
  bool drift_poly = false;        // bias.poly_dps
  bool dtemp_coeff = false;       // bias.dtemp_coeff_dps_per_c_per_s
  bool hysteresis_width = false;  // bias.hysteresis_width_c
  bool hysteresis_coeff = false;  // bias.hysteresis_coeff_dps_per_c
  bool cold = false;              // profile.cold_temp_c
  bool hot = false;               // profile.hot_temp_c
};

// One rate axis of a recording the unit is read from (not owned: the spans must outlive the call).
struct PlanRecording {
  std::string name;                  // the file or a label, for messages and the sources
  std::span<const double> rate_dps;  // rate, deg/s
  std::span<const double> temp_c;    // temperature, deg C (a pilot run needs it; an Allan run not)
  double fs_hz = 0.0;                // sample rate, Hz
};

// How PlanChamberRun compares profiles (defaults: `gyrocomp plan`'s).
struct PlanOptions {
  // The unit: noise, drift family (bias), sensor thermal lag, the profiles' cold / hot extremes and
  // cycles. Each run sets its own profile kind, seed and fs_hz (below). Defaults: the simulator's.
  SimulatorOptions unit;
  // The unit's figures stated by the caller (see PlanStated); none by default.
  PlanStated stated;
  // Sample rate of the simulated runs, Hz. 1 Hz resolves the chamber's minutes-long drift.
  double fs_hz = 1.0;
  // Profiles compared (ParseThermalProfileKind names, not "user"). rate-cycles is the design of
  // the least calibration-noise error, and with 10 seeds the predictions hold within 25% of the
  // simulated error on all structure x profile pairs for A, B, C, E; stairs on request only (its
  // simulated error is above rate-cycles', A: 19.8 against 12.5 mdps; docs/explanation/drift-models.md
  // "What any estimator can reach").
  std::vector<std::string> profiles = {"paper", "heat-cool", "rate-cycles", "cycle", "ramp"};
  // Noise seeds per profile, 1..50. One run's error is mostly the calibration run's slow noise on
  // the drift's constant: its SE is up to a third for 3 seeds; 20-30 seeds give 10%.
  int seeds = 3;
  // The least temperature span a pilot run must cover to give a drift family, deg C.
  double min_pilot_span_c = 5.0;
  // False with the reason in `error` when seeds is outside 1..50, profiles is empty or names an
  // unknown profile, fs_hz or min_pilot_span_c is not finite and > 0.
  bool IsValid(std::string* error) const;
};

// The unit as plan simulates it and where each part came from.
struct PlanUnit {
  // Noise, drift family (bias, reference_temp_c), thermal lag, cold / hot extremes, cycles.
  SimulatorOptions sim;
  // Where the noise figures came from ("Allan run x.csv (4 h; ...)").
  std::string noise_source = "datasheet flags (or the simulator's defaults)";
  // Where the drift family came from ("pilot x.csv (poly(temp,dtemp,memory))").
  std::string family_source = "flags (or the simulator's defaults)";
  // What the recordings could not give (left-out terms, extrapolation beyond a pilot's range).
  std::vector<std::string> notes;
  // "unit: noise ARW .. deg/sqrt(h), bias instability .., RRW .. from ..; drift: bias(T) about ..
  // C [..] deg/s per C^k, dT/dt gain .., hysteresis .., sensor lag .., from ..; range .. C; notes".
  std::string BriefReport() const;
};

// One profile's outcome over the seeds.
struct PlanProfileOutcome {
  std::string profile;  // its name, as given
  double hours = 0.0;   // length of the calibration run, h
  std::vector<std::string> models;    // the model(s) the default fit chose, "kind(inputs)"
  std::vector<std::string> excluded;  // terms the fit left out (ExcludedTerm::term), any seed
  // RMS over the seeds of the band's standard deviation on the heating ramp, deg/s.
  double predicted_heat_dps = 0.0;
  // The same on the cooling staircase, deg/s.
  double predicted_cool_dps = 0.0;
  // RMS over the seeds of the prediction's error against the true drift on the heating ramp, deg/s.
  double simulated_heat_dps = 0.0;
  // The same on the cooling staircase, deg/s.
  double simulated_cool_dps = 0.0;
  // Per seed: the simulated mean square error over the two held-out runs, (deg/s)^2.
  std::vector<double> simulated_ms_per_seed;
  // RMS of the heating and cooling predicted errors, deg/s.
  double predicted_dps() const;
  // RMS of the heating and cooling simulated errors, deg/s.
  double simulated_dps() const;
  // What the recommendation ranks: max(predicted, simulated), deg/s, so that a profile must both
  // say and reach a small error (by the predicted error alone, 5 seeds of structure B
  // recommended heat-cool, predicted 14.3 mdps and simulated 22.8, over rate-cycles' 14.1 /
  // 10.5; docs/explanation/drift-models.md).
  double score_dps() const;
  // Relative standard error of simulated_dps() from the seed-to-seed scatter of the per-seed mean
  // squares (delta method: SE(sqrt m) / sqrt m = SE(m) / (2 m)); NaN with one seed.
  double simulated_rel_se() const;
};

// What PlanChamberRun found.
struct PlanResult {
  PlanUnit unit;                             // the unit simulated
  std::vector<PlanProfileOutcome> profiles;  // one per PlanOptions::profiles entry, in order
  std::size_t recommended = 0;               // index into profiles of the recommendation
  int seeds = 0;                             // noise seeds per profile
  // The recommended outcome.
  const PlanProfileOutcome& Recommended() const { return profiles.at(recommended); }
  // "recommended: paper (14.2 h of 2 profiles, 1 seed): next-run drift error predicted .. deg/s,
  // simulated .. deg/s".
  std::string BriefReport() const;
};

// The simulator's drift family (BiasModelOptions, deg/s) that `m`'s structured polynomial
// describes: its temperature polynomial re-expanded about bias->reference_temp_c; a dT/dt gain
// as dtemp_coeff; a lag state (T - T_lag ~ tau dT/dt on a ramp) as the gain c tau; a memory
// (m in [-1, 1], width w) as the play hysteresis of width w and coefficient 2 h / w (the same
// +-h at saturation). What the simulator cannot represent (a kernel residual, dT/dt powers > 1)
// is left out and named in *notes. Errors (kInvalidInput): no structured part, a unit other than
// deg/s or rad/s, a family BiasModelOptions::IsValid refuses.
Status FamilyFromModel(const DriftModel& m, BiasModelOptions* bias, std::vector<std::string>* notes);

// The unit of `options` completed from the recordings (either may be null): an Allan run's noise,
// then a pilot run's family, noise (without an Allan run) and range, each figure PlanStated
// keeps as given. Errors: a recording too short for sigma(1 s), a pilot spanning less than
// min_pilot_span_c or without temperature, a pilot model with no structured part.
Result<PlanUnit> PlanUnitFromRecordings(const PlanOptions& options, const PlanRecording* pilot,
                                        const PlanRecording* noise_run);

// Compares options.profiles for the unit of PlanUnitFromRecordings(options, pilot, noise_run)
// (see the top of this file). Errors: those of PlanUnitFromRecordings, options that IsValid
// refuses, a simulation or fit that fails.
Result<PlanResult> PlanChamberRun(const PlanOptions& options, const PlanRecording* pilot = nullptr,
                                  const PlanRecording* noise_run = nullptr);

}  // namespace gyrocomp
