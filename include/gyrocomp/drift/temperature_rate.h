// Robust temperature rate dT/dt from a noisy, quantized temperature signal.
//
// A chamber temperature sensor is quantized (0.0625 C or coarser) and noisy, so finite
// differences are a train of spikes. The rate here is the slope of a least-squares straight line
// through a centred window of `window_s` seconds around each sample (a first-order
// Savitzky-Golay differentiator); near the ends the window is truncated to the samples available
// (never extrapolated). Cost O(n) whatever the window (running sums).
//
// Noise: for white noise of SD s on T and a window of W samples at fs, the slope SD is
// s * fs * sqrt(12 / (W^3)); a quantization step q acts like s = q / sqrt(12). The window also
// delays nothing (centred) but averages the rate over window_s: transients faster than that are
// smoothed. Default 300 s: chamber ramps last tens of minutes.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"

namespace gyrocomp {

// How dT/dt is computed from a temperature record: a centred least-squares slope.
struct TemperatureRateOptions {
  // Length of the centred regression window, seconds (> 0). At least 2 samples are always used.
  double window_s = 300.0;
  // False with the reason in `error` when window_s is not > 0.
  bool IsValid(std::string* error) const;
};

// dT/dt in deg C per second at each sample of `temp_c` sampled uniformly at `fs_hz`. Errors:
// fewer than 2 samples, fs_hz <= 0, non-finite values, invalid options.
Result<std::vector<double>> TemperatureRate(std::span<const double> temp_c, double fs_hz,
                                            const TemperatureRateOptions& options = {});

}  // namespace gyrocomp
