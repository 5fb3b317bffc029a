// Noise figures for Kalibr's IMU configuration (imu.yaml), from Allan analyses (docs/guides/imu-noise.md).
//
// Kalibr (ethz-asl/kalibr, wiki "IMU Noise Model") wants continuous-time noise densities:
//   gyroscope_noise_density  sigma_g  [rad/s/sqrt(Hz)]   = the ARW coefficient N of the ADEV,
//                                                           sigma(tau) = N / sqrt(tau);
//   gyroscope_random_walk    sigma_bg [rad/s^2/sqrt(Hz)] = the RRW coefficient K of the ADEV,
//                                                           sigma(tau) = K sqrt(tau / 3);
// and the same for the accelerometer in m/s^2/sqrt(Hz) and m/s^3/sqrt(Hz). From gyrocomp's figures:
//   sigma_g  = ARW[deg/sqrt(h)] / 60 * pi / 180               (1 deg/sqrt(h) = 2.909e-4 rad/s/sqrt(Hz))
//   sigma_bg = RRW[deg/h/sqrt(h)] / (3600 * 60) * pi / 180    (1 deg/h/sqrt(h) = 8.081e-8 rad/s^2/sqrt(Hz))
// For an accelerometer axis analysed as if its column were in deg/s (the Allan arithmetic does not
// depend on the unit), the same numbers without the pi / 180: density = sigma(1 s) in m/s^2 * sqrt(s).
#pragma once

#include <string>
#include <vector>

#include "gyrocomp/allan/allan.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp {

// One axis in Kalibr's units.
struct KalibrAxisNoise {
  std::string axis;  // axis name (the rate column)
  double noise_density = 0.0;  // gyro rad/s/sqrt(Hz); accelerometer m/s^2/sqrt(Hz)
  double random_walk = 0.0;    // gyro rad/s^2/sqrt(Hz); accelerometer m/s^3/sqrt(Hz)
  // True when the curve has no +1/2 region: random_walk is then the bound
  // min over the usable taus of sigma(tau) sqrt(3 / tau) (every other noise adds variance).
  bool random_walk_is_upper_bound = false;
};

// Which sensor an axis is: sets Kalibr's units.
enum class KalibrSensor { kGyroscope, kAccelerometer };

// The axis's figures from its AllanResult (rate column in deg/s for a gyroscope, in m/s^2 for an
// accelerometer). Error (kInvalidInput) when the curve does not reach tau = 1 s (no ARW).
Result<KalibrAxisNoise> KalibrNoiseFromAllan(const AllanResult& allan, KalibrSensor sensor,
                                             double min_edf = 10.0);

// What the Kalibr IMU YAML writes besides the figures.
struct KalibrYamlOptions {
  // ROS topic of the IMU messages (Kalibr's `rostopic`).
  std::string rostopic = "/imu0";
  // Where the figures come from (a comment line), e.g. the input file name.
  std::string source;
};

// imu.yaml text: the largest axis of each sensor as the scalar Kalibr reads, every axis in
// comments, update_rate = fs_hz. Without accelerometer axes, the accelerometer keys are left out
// with a comment saying they must be filled. `gyro` must not be empty.
std::string KalibrImuYaml(const std::vector<KalibrAxisNoise>& gyro,
                          const std::vector<KalibrAxisNoise>& accelerometer, double fs_hz,
                          const KalibrYamlOptions& options = {});

}  // namespace gyrocomp
