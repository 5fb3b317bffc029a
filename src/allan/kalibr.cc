// Kalibr imu.yaml from Allan analyses (include/gyrocomp/allan/kalibr.h, docs/guides/imu-noise.md).
#include "gyrocomp/allan/kalibr.h"

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <sstream>

#include "gyrocomp/core/units.h"

namespace gyrocomp {
namespace {

// Shortest text that reads back to the same double.
std::string Exact(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

const KalibrAxisNoise& Largest(const std::vector<KalibrAxisNoise>& axes, bool density) {
  return *std::max_element(axes.begin(), axes.end(), [&](const KalibrAxisNoise& a, const KalibrAxisNoise& b) {
    return density ? a.noise_density < b.noise_density : a.random_walk < b.random_walk;
  });
}

void WriteSensor(std::ostringstream& os, const std::vector<KalibrAxisNoise>& axes, const std::string& key,
                 const std::string& density_unit, const std::string& walk_unit) {
  os << "# " << key << " axes (" << density_unit << ", " << walk_unit << "):\n";
  for (const KalibrAxisNoise& a : axes) {
    os << "#   " << (a.axis.empty() ? std::string("rate") : a.axis) << ": noise_density " << Exact(a.noise_density)
       << ", random_walk " << Exact(a.random_walk)
       << (a.random_walk_is_upper_bound ? " (upper bound: no +1/2 region on the ADEV curve)" : "") << "\n";
  }
  const KalibrAxisNoise& d = Largest(axes, true);
  const KalibrAxisNoise& w = Largest(axes, false);
  os << key << "_noise_density: " << Exact(d.noise_density) << "  # largest axis: " << d.axis << "\n";
  os << key << "_random_walk: " << Exact(w.random_walk) << "  # largest axis: " << w.axis
     << (w.random_walk_is_upper_bound ? " (upper bound)" : "") << "\n";
}

}  // namespace

Result<KalibrAxisNoise> KalibrNoiseFromAllan(const AllanResult& allan, KalibrSensor sensor, double min_edf) {
  const AllanNoiseTerms& t = allan.terms;
  if (!t.arw_deg_per_sqrt_h) {
    return InvalidInput("Kalibr noise of '" + allan.axis + "': the Allan curve does not reach tau = 1 s (record too short)");
  }
  // The Allan figures were computed as if the column were in deg/s: undo the datasheet units to
  // get N (unit * sqrt(s)) and K (unit / sqrt(s)), then deg -> rad for a gyroscope.
  const double angle = sensor == KalibrSensor::kGyroscope ? 1.0 / units::kDegPerRad : 1.0;
  KalibrAxisNoise k;
  k.axis = allan.axis;
  k.noise_density = units::DegPerSqrtHourToDegPerSqrtSec(*t.arw_deg_per_sqrt_h) * angle;
  if (t.rrw_deg_per_h_per_sqrt_h) {
    k.random_walk = units::DphPerSqrtHourToDpsPerSqrtSec(*t.rrw_deg_per_h_per_sqrt_h) * angle;
  } else {
    // sigma^2(tau) >= K^2 tau / 3 at every tau (the noise terms add in variance).
    const AllanCurve& c = allan.curve;
    double bound = INFINITY;
    for (std::size_t j = 0; j < c.size(); ++j) {
      if (c.edf.size() == c.size() && c.edf[j] < min_edf) continue;
      bound = std::min(bound, c.adev_dps[j] * std::sqrt(3.0 / c.tau_s[j]));
    }
    if (!std::isfinite(bound)) {
      for (std::size_t j = 0; j < c.size(); ++j) bound = std::min(bound, c.adev_dps[j] * std::sqrt(3.0 / c.tau_s[j]));
    }
    k.random_walk = bound * angle;
    k.random_walk_is_upper_bound = true;
  }
  return k;
}

std::string KalibrImuYaml(const std::vector<KalibrAxisNoise>& gyro, const std::vector<KalibrAxisNoise>& accelerometer,
                          double fs_hz, const KalibrYamlOptions& options) {
  assert(!gyro.empty());
  std::ostringstream os;
  os << "# IMU noise for Kalibr, written by gyrocomp allan"
     << (options.source.empty() ? std::string() : " from " + options.source) << ".\n"
     << "# Continuous-time densities from the Allan deviation (docs/guides/imu-noise.md):\n"
     << "#   noise_density = N, sigma_ADEV(tau) = N / sqrt(tau)  (gyro: ARW deg/sqrt(h) / 60 * pi/180)\n"
     << "#   random_walk   = K, sigma_ADEV(tau) = K sqrt(tau / 3) (gyro: RRW deg/h/sqrt(h) / 216000 * pi/180)\n"
     << "# Kalibr reads one scalar per sensor: the largest axis is given. These are measured values;\n"
     << "# Kalibr's documentation advises inflating them for real use (unmodelled effects).\n";
  WriteSensor(os, gyro, "gyroscope", "rad/s/sqrt(Hz)", "rad/s^2/sqrt(Hz)");
  if (accelerometer.empty()) {
    os << "# accelerometer_noise_density and accelerometer_random_walk (m/s^2/sqrt(Hz), m/s^3/sqrt(Hz))\n"
       << "# must be filled: no accelerometer column was given (gyrocomp allan --accel-col ax,ay,az).\n";
  } else {
    WriteSensor(os, accelerometer, "accelerometer", "m/s^2/sqrt(Hz)", "m/s^3/sqrt(Hz)");
  }
  os << "rostopic: " << options.rostopic << "\n";
  os << "update_rate: " << Exact(fs_hz) << "  # Hz\n";
  return os.str();
}

}  // namespace gyrocomp
