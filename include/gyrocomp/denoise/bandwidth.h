// Effective bandwidth (-3 dB) and delay of any processing, measured by passing known signals
// through it (honest evaluation, method.md: report the bandwidth next to every ARW improvement).
//
// Method (works for nonlinear and adaptive processings such as thresholding and LMS, whose
// response depends on what else is in the signal): a background record b (representative noise,
// e.g. the sensor's own static record, or white noise of a given SD) is processed once; then for
// each test frequency f_k a sine of amplitude A is added, b + A sin(2 pi f_k t), and processed;
// the difference of the two outputs is the response to the sine. Its amplitude and phase at f_k
// are read by least-squares projection onto sin/cos over a central window holding an integer
// number of cycles (the ends, where extensions and start-up transients live, are skipped).
//   gain(f) = |response| / A,  phase(f) unwrapped over increasing f (each tone's phase moved by
//     whole turns to the branch nearest the delay fitted to the tones below it).
//   bandwidth_hz: the lowest f where gain falls below 1/sqrt(2) (-3 dB), interpolated linearly in
//     (log f, dB) between the two test frequencies around the crossing; nullopt when the gain
//     stays above -3 dB up to the highest test frequency (then "at least max_frequency_hz").
//   delay_s: group delay -d(phase)/d(omega) by least squares (through the origin) over the test
//     frequencies below the bandwidth (a pure delay tau gives phase = -omega tau).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"

namespace gyrocomp {

// A processing under test: maps a signal to a signal of the same length.
using SignalProcessing = std::function<Result<std::vector<double>>(std::span<const double>)>;

// How the test tones are chosen and, without a background record, what it is.
struct BandwidthOptions {
  // Sample rate of the signals (Hz), > 0.
  double fs_hz = 1.0;
  // Length of each test record when no background is given (samples). With a background, its
  // length is used.
  std::size_t num_samples = 1u << 15;
  // Number of test frequencies, log-spaced in [min_frequency_hz, max_frequency_hz] and rounded
  // to whole cycles in the analysis window (duplicates dropped).
  int num_frequencies = 32;
  // Range of test frequencies (Hz). nullopt: min = 20 cycles per analysis window, max = 0.45 fs.
  std::optional<double> min_frequency_hz;
  std::optional<double> max_frequency_hz;  // highest test frequency, Hz, < fs/2
  // Amplitude A of the test sine (signal units). nullopt = the background's SD (0 dB SNR per
  // tone), or 1 when the background is all zero.
  std::optional<double> amplitude;
  // Fraction of the record skipped at EACH end before the analysis window, in [0, 0.45).
  double edge_fraction = 0.1;
  // Background when none is passed: white Gaussian noise of this SD (signal units), >= 0, from
  // this seed. 0 = a clean (all-zero) background.
  double white_noise_sd = 0.0;
  std::uint64_t seed = 1;  // seed of that noise (std::mt19937_64)
  // Returns false and a message naming the field ("max_frequency_hz = 60: must be in (0, fs/2)").
  bool IsValid(std::string* error) const;
};

// The measured response at each test frequency and the figures read from it.
struct BandwidthResult {
  std::vector<double> frequency_hz;  // test frequencies, increasing, Hz
  std::vector<double> gain;         // |H(f)|, dimensionless
  std::vector<double> phase_rad;    // unwrapped
  std::optional<double> bandwidth_hz;  // -3 dB bandwidth, Hz; nullopt: above max_frequency_hz
  bool bandwidth_below_range = false;  // gain < -3 dB already at the lowest test frequency
                                       // (then bandwidth_hz = that frequency, an upper bound)
  double max_frequency_hz = 0.0;    // highest frequency tested
  double delay_s = 0.0;             // group delay in the passband (s)
  double dc_gain = 0.0;             // gain at the lowest test frequency
  double amplitude = 0.0;           // test amplitude used
  std::size_t num_runs = 0;         // calls of the processing
  // "-3 dB bandwidth 0.17 Hz, delay 1.2 s, gain 0.998 at 0.001 Hz (33 runs)"
  std::string BriefReport() const;
};

// Measures `processing` against `background` (empty span: white_noise_sd noise of num_samples).
// Errors: invalid options, background too short for the window (kInvalidArgument); any error of
// the processing is passed through; an output of the wrong length is kInternal.
Result<BandwidthResult> MeasureBandwidth(const SignalProcessing& processing,
                                         std::span<const double> background,
                                         const BandwidthOptions& options);

}  // namespace gyrocomp
