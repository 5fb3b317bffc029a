// PX4 and ArduPilot thermal-compensation parameter files (see param_export.h).
#include "gyrocomp/export/param_export.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace gyrocomp {
namespace {

// A float32 parameter value as text that reads back to the same float.
std::string Float32Text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(static_cast<float>(v)));
  return buf;
}

Status CheckAxes(const ThreeAxisCubics& c) {
  for (int a = 0; a < 3; ++a) {
    if (c[a].temp_min_c != c[0].temp_min_c || c[a].temp_max_c != c[0].temp_max_c ||
        c[a].ref_temp_c != c[0].ref_temp_c)
      return InvalidArgument("thermal parameters: the three axes must share one temperature range and "
                             "reference (the autopilots have one TMIN/TMAX per sensor)");
    for (double v : c[a].coeff)
      if (!std::isfinite(v)) return InvalidInput("thermal parameters: non-finite coefficient on axis " + std::to_string(a));
    if (!std::isfinite(c[a].temp_min_c) || !std::isfinite(c[a].temp_max_c) || !(c[a].temp_min_c < c[a].temp_max_c))
      return InvalidInput("thermal parameters: empty or non-finite temperature range");
  }
  return Status::Ok();
}

void WriteComments(std::ostringstream& s, const std::vector<std::string>& comments) {
  for (const std::string& c : comments) s << "# " << c << "\n";
}

}  // namespace

bool Px4ThermalParamOptions::IsValid(std::string* error) const {
  if (index < 0 || index > 3) {
    if (error) *error = "Px4ThermalParamOptions::index = " + std::to_string(index) + ": must be 0..3 (TC_G0..TC_G3)";
    return false;
  }
  if (!device_id || *device_id == 0) {
    if (error)
      *error = "Px4ThermalParamOptions::device_id: required and non-zero (TC_G<i>_ID must equal the gyro's "
               "device_id, logged in sensor_gyro; PX4 ignores a slot whose ID matches no sensor)";
    return false;
  }
  return true;
}

bool ArduPilotThermalParamOptions::IsValid(std::string* error) const {
  if (imu < 1 || imu > 3) {
    if (error) *error = "ArduPilotThermalParamOptions::imu = " + std::to_string(imu) + ": must be 1..3 (INS_TCAL1..3)";
    return false;
  }
  return true;
}

Result<std::string> WritePx4ThermalParams(const ThreeAxisCubics& c, const Px4ThermalParamOptions& options,
                                          const std::vector<std::string>& comments) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (Status st = CheckAxes(c); !st.ok()) return st.error();
  std::ostringstream s;
  WriteComments(s, comments);
  s << "#\n# Vehicle-Id Component-Id Name Value Type\n";
  const std::string row = std::to_string(options.system_id) + "\t" + std::to_string(options.component_id) + "\t";
  const std::string p = "TC_G" + std::to_string(options.index) + "_";
  s << row << "TC_G_ENABLE\t1\t6\n";
  s << row << p << "ID\t" << *options.device_id << "\t6\n";
  s << row << p << "TMAX\t" << Float32Text(c[0].temp_max_c) << "\t9\n";
  s << row << p << "TMIN\t" << Float32Text(c[0].temp_min_c) << "\t9\n";
  s << row << p << "TREF\t" << Float32Text(c[0].ref_temp_c) << "\t9\n";
  for (int k = 0; k < 4; ++k)
    for (int a = 0; a < 3; ++a)
      s << row << p << "X" << k << "_" << a << "\t" << Float32Text(c[a].coeff[k]) << "\t9\n";
  return s.str();
}

std::array<double, 3> ArduPilotGyrCoefficients(const TemperatureCubic& radps) {
  const TemperatureCubic about35 = radps.Recentered(kArduPilotTcalReferenceC);
  return {about35.coeff[1] * kArduPilotTcalScale, about35.coeff[2] * kArduPilotTcalScale,
          about35.coeff[3] * kArduPilotTcalScale};
}

Result<std::string> WriteArduPilotThermalParams(const ThreeAxisCubics& c, const ArduPilotThermalParamOptions& options,
                                                const std::vector<std::string>& comments) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (Status st = CheckAxes(c); !st.ok()) return st.error();
  std::ostringstream s;
  WriteComments(s, comments);
  const std::string p = "INS_TCAL" + std::to_string(options.imu) + "_";
  s << p << "ENABLE,1\n";
  s << p << "TMIN," << Float32Text(c[0].temp_min_c) << "\n";
  s << p << "TMAX," << Float32Text(c[0].temp_max_c) << "\n";
  const std::array<std::array<double, 3>, 3> g = {ArduPilotGyrCoefficients(c[0]), ArduPilotGyrCoefficients(c[1]),
                                                  ArduPilotGyrCoefficients(c[2])};
  static constexpr const char* kAxis[3] = {"X", "Y", "Z"};
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) s << p << "GYR" << (k + 1) << "_" << kAxis[a] << "," << Float32Text(g[a][k]) << "\n";
  return s.str();
}

}  // namespace gyrocomp
