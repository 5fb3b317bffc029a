// Whether a noise term read off an Allan deviation curve means what its name says
// (docs/explanation/pipeline.md, "The not-applicable rule"). A processed record's ADEV is shaped by the
// processing: a record band-limited to B carries 2B independent values per second (the sampling
// theorem), so averages over less than 1/(2B) seconds are not independent and their ADEV shows the
// filter: sigma(1 s) of a 0.17 Hz output is not an angle random walk coefficient, and a "+1/2
// region" just after the filter's minimum is the filter's roll-off, not a rate random walk. The
// report, the console tables and the JSON of `process` and `demo` all use this one rule to print
// such a figure as "not applicable" with the reason instead of a number.
//
// Rule (each clause must hold; the first that fails is the reason):
//   1. the record's bandwidth B is known (a raw record: its Nyquist frequency fs/2). An ARW
//      without its bandwidth cannot be compared with another.
//   2. the taus the term is read from lie at tau >= 1/(2B), the sampling period of the band (a raw
//      record: 1/fs, its own sample period, so a raw record always passes this clause; the demo's
//      0.175 Hz output: 2.86 s);
//   3. the free least-squares slope of ln(adev) on ln(tau) over those taus is within
//      slope_tolerance of the term's nominal slope: -1/2 for ARW (white rate noise), +1/2 for RRW.
// The taus: ARW, [arw_tau / arw_tau_span, arw_tau * arw_tau_span] around AllanOptions::arw_tau_s
// (1 s); RRW, the region its +1/2 line was fitted on (AllanNoiseTerms::rrw_fit_tau_min/max_s).
#pragma once

#include <optional>
#include <string>

#include "gyrocomp/allan/allan.h"

namespace gyrocomp {

// The tolerances of the not-applicable rule.
struct TermApplicabilityOptions {
  // |fitted slope - nominal slope| must be at most this (log-log). 0.2 = AllanOptions'
  // slope_tolerance, the band the noise terms are classified with.
  double slope_tolerance = 0.2;
  // ARW: the slope is fitted over taus within this factor of arw_tau_s (>= 1; 2 = one octave).
  double arw_tau_span = 2.0;
  // The tau at which ARW is read, s (AllanOptions::arw_tau_s).
  double arw_tau_s = 1.0;
  // Returns false and a message ("slope_tolerance must be in (0, 0.5)") when a field is out of
  // range.
  bool IsValid(std::string* error) const;
};

// The verdict for one noise term.
struct TermApplicability {
  bool applicable = false;  // true when every clause of the rule holds
  std::optional<double> fitted_slope;  // over the term's taus, when at least two
  // The taus tested: tau_min_s, the lowest, s (0 when none).
  double tau_min_s = 0.0, tau_max_s = 0.0;  // the highest tested tau, s (0 when none)
  std::string reason;                  // why not; "" when applicable
};

// Free least-squares slope of ln(adev) on ln(tau) over the curve's taus in [tau_lo, tau_hi]
// (positive adev only); nullopt with fewer than two such taus.
std::optional<double> FittedLogLogSlope(const AllanCurve& curve, double tau_lo, double tau_hi);

// The rule for the angle random walk read at options.arw_tau_s. `bandwidth_hz`: -3 dB bandwidth
// of the record (nullopt: unknown).
TermApplicability ArwApplicability(const AllanResult& allan, std::optional<double> bandwidth_hz,
                                   const TermApplicabilityOptions& options = {});
// The same for the rate random walk, over the taus its +1/2 line was fitted on (not applicable
// when the curve has no RRW term).
TermApplicability RrwApplicability(const AllanResult& allan, std::optional<double> bandwidth_hz,
                                   const TermApplicabilityOptions& options = {});

}  // namespace gyrocomp
