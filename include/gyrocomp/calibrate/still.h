// Where a vehicle is still in a flight log: the samples a thermal calibration may use.
//
// The statistic is the zero-velocity detector of Skog, Handel, Nilsson & Rantakokko, "Zero-velocity
// detection: an algorithm evaluation", IEEE Trans. Biomed. Eng. 57(11), 2010, in its
// unknown-bias form: over a window of W samples,
//   T = 1 / (6 W) sum_i [ ||w_i - mean(w)||^2 / sigma_w^2 + ||a_i - mean(a)||^2 / sigma_a^2 ]
// (their moving-variance / GLRT statistic with the gyro's bias and the attitude's gravity left
// free, because a calibration log's gyro carries its thermal offset and the vehicle stands at
// any attitude), about 1 when nothing moves; a window is motion when T > threshold, when its mean
// rate exceeds max_mean_rate_dps (a slow steady turn has no variance), or when the log says the
// vehicle is armed in it (motors spinning: vibration even on the ground) or not landed (the log's
// landed state; StillLogState). The log's state only adds exclusions: a window the IMU shows
// moving is motion whatever the state says. Motion is widened by
// margin_s on both sides; still runs shorter than min_segment_s are not used. sigma_w and sigma_a
// are the sensor's own noise, estimated from the log's quietest windows unless given.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"

namespace gyrocomp {

// Settings of DetectStill (the statistic T and the rules at the top of this file).
struct StillDetectorOptions {
  double window_s = 1.0;             // the statistic's window, s
  double threshold = 3.0;            // T above it: motion (T ~ 1 still)
  double margin_s = 2.0;             // motion widened by this on each side, s
  double min_segment_s = 30.0;       // shorter still runs are not used, s
  double max_mean_rate_dps = 1.0;    // a window turning faster on average is motion, deg/s
  // The sensor's white noise per sample (1 sigma, per axis); nullopt: the 5th percentile over
  // the log's windows of each window's RMS deviation (the quietest 5 % taken as still), divided
  // by that percentile's share of the mean for still windows (chi-square, Wilson-Hilferty).
  std::optional<double> gyro_noise_rad_s;  // sigma_w, rad/s
  std::optional<double> accel_noise_m_s2;  // sigma_a, m/s^2
  // False with the field and the rule in `error` when a setting is out of range.
  bool IsValid(std::string* error) const;
};

// One still run of the log.
struct StillSegment {
  double start_s = 0.0;  // start, s (time_s of the log)
  double length_s = 0.0;  // duration, s
  double temp_min_c = 0.0;  // lowest temperature in the run, deg C (0 when no temperature was given)
  double temp_max_c = 0.0;  // highest, deg C (0 when no temperature was given)
};
// A part of the log not used, and why.
struct RejectedPart {
  double start_s = 0.0;  // start, s (time_s of the log)
  double length_s = 0.0;  // duration, s
  // "armed; in the air (log's landed state); motion (T up to 1.2e+04, threshold 3); margin 2 s
  // around motion"
  std::string reason;
};

// What DetectStill found.
struct StillDetection {
  std::vector<bool> still;  // per sample: used by the fit
  std::vector<StillSegment> segments;  // still runs used, in time order
  std::vector<RejectedPart> rejected;  // the parts not used, in time order
  double gyro_noise_rad_s = 0.0;  // sigma_w used, rad/s
  double accel_noise_m_s2 = 0.0;  // sigma_a used, m/s^2
  double still_s = 0.0;  // seconds still (in segments)
  double total_s = 0.0;  // seconds of log
  std::string BriefReport() const;  // "612 s still of 1085 s in 2 segments (...); rejected: ..."
};

// What the log itself says per sample (gyrocomp/io/vehicle_state.h mapped onto the samples);
// an empty vector: the log does not say.
struct StillLogState {
  std::vector<bool> armed;  // true: armed (a rejected part's reason "armed")
  std::vector<bool> in_air;  // true: the log's landed state says not landed ("in the air (log's landed state)")
};

// time_s increasing; gyro (rad/s) and accel (m/s^2) per axis, as long as time_s; temp_c and each
// vector of `state` may be empty (unknown).
Result<StillDetection> DetectStill(const std::vector<double>& time_s, const std::array<std::vector<double>, 3>& gyro_rad_s,
                                   const std::array<std::vector<double>, 3>& accel_m_s2, const std::vector<double>& temp_c,
                                   const StillLogState& state, const StillDetectorOptions& options = {});

}  // namespace gyrocomp
