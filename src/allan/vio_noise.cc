// OpenVINS and VINS-Fusion IMU noise files (include/gyrocomp/allan/vio_noise.h, docs/guides/imu-noise.md).
#include "gyrocomp/allan/vio_noise.h"

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <sstream>

namespace gyrocomp {
namespace {

std::string Exact(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

double LargestDensity(const std::vector<KalibrAxisNoise>& axes) {
  double m = 0;
  for (const KalibrAxisNoise& a : axes) m = std::max(m, a.noise_density);
  return m;
}

double LargestWalk(const std::vector<KalibrAxisNoise>& axes, bool* upper_bound) {
  const auto it = std::max_element(axes.begin(), axes.end(),
                                   [](const KalibrAxisNoise& a, const KalibrAxisNoise& b) { return a.random_walk < b.random_walk; });
  *upper_bound = it->random_walk_is_upper_bound;
  return it->random_walk;
}

void AxisComments(std::ostringstream& os, const char* sensor, const std::vector<KalibrAxisNoise>& axes) {
  for (const KalibrAxisNoise& a : axes) {
    os << "#   " << sensor << " " << a.axis << ": noise_density " << Exact(a.noise_density) << ", random_walk "
       << Exact(a.random_walk) << (a.random_walk_is_upper_bound ? " (upper bound)" : "") << "\n";
  }
}

}  // namespace

std::string OpenVinsImuChainYaml(const std::vector<KalibrAxisNoise>& gyro, const std::vector<KalibrAxisNoise>& accel,
                                 double fs_hz, const VioNoiseFileOptions& options) {
  assert(!gyro.empty() && !accel.empty());
  bool gb = false, ab = false;
  const double gw = LargestWalk(gyro, &gb), aw = LargestWalk(accel, &ab);
  std::ostringstream os;
  os << "%YAML:1.0\n"
     << "# OpenVINS kalibr_imu_chain.yaml, written by gyrocomp allan"
     << (options.source.empty() ? std::string() : " from " + options.source) << ".\n"
     << "# Continuous-time densities (Kalibr's convention, docs/guides/imu-noise.md); the largest axis of each sensor.\n"
     << "# Measured values: OpenVINS and Kalibr advise inflating them for estimation.\n";
  AxisComments(os, "gyroscope", gyro);
  AxisComments(os, "accelerometer", accel);
  os << "\nimu0:\n"
     << "  T_i_b:\n"
     << "    - [1.0, 0.0, 0.0, 0.0]\n    - [0.0, 1.0, 0.0, 0.0]\n    - [0.0, 0.0, 1.0, 0.0]\n    - [0.0, 0.0, 0.0, 1.0]\n"
     << "  accelerometer_noise_density: " << Exact(LargestDensity(accel)) << "  # [ m / s^2 / sqrt(Hz) ]\n"
     << "  accelerometer_random_walk: " << Exact(aw) << "  # [ m / s^3 / sqrt(Hz) ]" << (ab ? " (upper bound)" : "") << "\n"
     << "  gyroscope_noise_density: " << Exact(LargestDensity(gyro)) << "  # [ rad / s / sqrt(Hz) ]\n"
     << "  gyroscope_random_walk: " << Exact(gw) << "  # [ rad / s^2 / sqrt(Hz) ]" << (gb ? " (upper bound)" : "") << "\n"
     << "  rostopic: " << options.rostopic << "\n"
     << "  time_offset: 0.0\n"
     << "  update_rate: " << Exact(fs_hz) << "\n"
     << "  model: \"kalibr\"\n"
     << "  Tw:\n    - [1.0, 0.0, 0.0]\n    - [0.0, 1.0, 0.0]\n    - [0.0, 0.0, 1.0]\n"
     << "  R_IMUtoGYRO:\n    - [1.0, 0.0, 0.0]\n    - [0.0, 1.0, 0.0]\n    - [0.0, 0.0, 1.0]\n"
     << "  Ta:\n    - [1.0, 0.0, 0.0]\n    - [0.0, 1.0, 0.0]\n    - [0.0, 0.0, 1.0]\n"
     << "  R_IMUtoACC:\n    - [1.0, 0.0, 0.0]\n    - [0.0, 1.0, 0.0]\n    - [0.0, 0.0, 1.0]\n"
     << "  Tg:\n    - [0.0, 0.0, 0.0]\n    - [0.0, 0.0, 0.0]\n    - [0.0, 0.0, 0.0]\n";
  return os.str();
}

std::string VinsFusionImuYaml(const std::vector<KalibrAxisNoise>& gyro, const std::vector<KalibrAxisNoise>& accel,
                              double fs_hz, const VioNoiseFileOptions& options) {
  assert(!gyro.empty() && !accel.empty());
  bool gb = false, ab = false;
  const double s = std::sqrt(fs_hz);  // continuous -> per-sample (integration_base.h, see the header)
  const double gn = LargestDensity(gyro), an = LargestDensity(accel);
  const double gw = LargestWalk(gyro, &gb), aw = LargestWalk(accel, &ab);
  std::ostringstream os;
  os << "# VINS-Fusion IMU noise (config keys), written by gyrocomp allan"
     << (options.source.empty() ? std::string() : " from " + options.source) << ", topic " << options.rostopic << ".\n"
     << "# Discrete per-sample figures at " << Exact(fs_hz) << " Hz: value = continuous density x sqrt(fs)\n"
     << "# (integration_base.h scales the noise by dt; docs/guides/imu-noise.md). Continuous (Kalibr) values:\n"
     << "#   acc_n " << Exact(an) << " m/s^2/sqrt(Hz), gyr_n " << Exact(gn) << " rad/s/sqrt(Hz), acc_w " << Exact(aw)
     << " m/s^3/sqrt(Hz), gyr_w " << Exact(gw) << " rad/s^2/sqrt(Hz)\n"
     << "# Measured values; VINS-Fusion's sample configs use much larger (tuned, inflated) ones.\n";
  AxisComments(os, "gyroscope", gyro);
  AxisComments(os, "accelerometer", accel);
  os << "acc_n: " << Exact(an * s) << "   # accelerometer measurement noise standard deviation, m/s^2\n"
     << "gyr_n: " << Exact(gn * s) << "   # gyroscope measurement noise standard deviation, rad/s\n"
     << "acc_w: " << Exact(aw * s) << "   # accelerometer bias random walk, m/s^3" << (ab ? " (upper bound)" : "") << "\n"
     << "gyr_w: " << Exact(gw * s) << "   # gyroscope bias random walk, rad/s^2" << (gb ? " (upper bound)" : "") << "\n"
     << "g_norm: 9.81007   # gravity magnitude (VINS-Fusion's EuRoC value: set your site's)\n";
  return os.str();
}

}  // namespace gyrocomp
