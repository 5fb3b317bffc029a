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
  ArduPilotTcalImu imu;
  imu.imu = options.imu;
  imu.gyro_radps = c;
  return WriteArduPilotTcalFile({imu}, comments);
}

namespace {

constexpr const char* kApAxis[3] = {"X", "Y", "Z"};

// INS_TCAL<n>_<kind><k>_<axis> for k = 1..3, from the cubics or zeros.
void WriteApCoefficients(std::ostringstream& s, const std::string& p, const char* kind,
                         const std::optional<ThreeAxisCubics>& c) {
  std::array<std::array<double, 3>, 3> g{};  // [axis][order]
  if (c) g = {ArduPilotGyrCoefficients((*c)[0]), ArduPilotGyrCoefficients((*c)[1]), ArduPilotGyrCoefficients((*c)[2])};
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) s << p << kind << (k + 1) << "_" << kApAxis[a] << "," << Float32Text(g[a][k]) << "\n";
}

Status CheckApImu(const ArduPilotTcalImu& m) {
  if (m.imu < 1 || m.imu > 3) return InvalidArgument("ArduPilotTcalImu::imu = " + std::to_string(m.imu) + ": must be 1..3");
  for (const auto* c : {&m.gyro_radps, &m.accel_m_s2})
    if (*c) {
      if (Status st = CheckAxes(**c); !st.ok()) return st;
    }
  if (m.gyro_radps && m.accel_m_s2 &&
      ((*m.gyro_radps)[0].temp_min_c != (*m.accel_m_s2)[0].temp_min_c ||
       (*m.gyro_radps)[0].temp_max_c != (*m.accel_m_s2)[0].temp_max_c))
    return InvalidArgument("INS_TCAL" + std::to_string(m.imu) + ": gyro and accel cubics on different temperature "
                           "ranges (ArduPilot has one TMIN/TMAX per IMU)");
  return Status::Ok();
}

}  // namespace

Result<std::string> WriteArduPilotTcalFile(const std::vector<ArduPilotTcalImu>& imus,
                                           const std::vector<std::string>& comments) {
  std::ostringstream s;
  WriteComments(s, comments);
  std::array<bool, 4> seen{};
  for (const ArduPilotTcalImu& m : imus) {
    if (Status st = CheckApImu(m); !st.ok()) return st.error();
    if (seen[m.imu]) return InvalidArgument("INS_TCAL" + std::to_string(m.imu) + " given twice");
    seen[m.imu] = true;
    const std::string p = "INS_TCAL" + std::to_string(m.imu) + "_";
    const bool on = m.gyro_radps || m.accel_m_s2;
    if (!on) s << "# INS_TCAL" << m.imu << " disabled: " << (m.disabled_reason.empty() ? "not calibrated" : m.disabled_reason) << "\n";
    s << p << "ENABLE," << (on ? 1 : 0) << "\n";
    if (on) {
      const ThreeAxisCubics& r = m.gyro_radps ? *m.gyro_radps : *m.accel_m_s2;
      s << p << "TMIN," << Float32Text(r[0].temp_min_c) << "\n";
      s << p << "TMAX," << Float32Text(r[0].temp_max_c) << "\n";
    }
    // AP_InertialSensor_tempcal.cpp var_info: ACC1..3 then GYR1..3 (tempcal_IMU.py's order).
    WriteApCoefficients(s, p, "ACC", m.accel_m_s2);
    WriteApCoefficients(s, p, "GYR", m.gyro_radps);
  }
  return s.str();
}

namespace {

void WritePx4Slot3D(std::ostringstream& s, const std::string& row, const std::string& p, std::uint32_t id,
                    const ThreeAxisCubics* c) {
  s << row << p << "ID\t" << id << "\t6\n";
  s << row << p << "TMAX\t" << Float32Text(c ? (*c)[0].temp_max_c : 0.0) << "\t9\n";
  s << row << p << "TMIN\t" << Float32Text(c ? (*c)[0].temp_min_c : 0.0) << "\t9\n";
  s << row << p << "TREF\t" << Float32Text(c ? (*c)[0].ref_temp_c : 0.0) << "\t9\n";
  for (int k = 0; k < 4; ++k)
    for (int a = 0; a < 3; ++a) s << row << p << "X" << k << "_" << a << "\t" << Float32Text(c ? (*c)[a].coeff[k] : 0.0) << "\t9\n";
}

template <typename Slot>
Status CheckSlots(const std::vector<Slot>& slots, const char* kind) {
  std::array<bool, kPx4TcalSlots> seen{};
  for (const Slot& sl : slots) {
    if (sl.index < 0 || sl.index >= kPx4TcalSlots)
      return InvalidArgument(std::string("TC_") + kind + " slot " + std::to_string(sl.index) + ": must be 0..3");
    if (seen[sl.index]) return InvalidArgument(std::string("TC_") + kind + std::to_string(sl.index) + " given twice");
    if (sl.device_id == 0)
      return InvalidArgument(std::string("TC_") + kind + std::to_string(sl.index) + "_ID: device id 0 matches no sensor");
    seen[sl.index] = true;
  }
  return Status::Ok();
}

}  // namespace

Result<std::string> WritePx4TcalFile(const Px4TcalFile& f, const std::vector<std::string>& comments) {
  for (auto [slots, kind] : {std::pair{&f.gyro, "G"}, std::pair{&f.accel, "A"}}) {
    if (Status st = CheckSlots(*slots, kind); !st.ok()) return st.error();
    for (const auto& sl : *slots)
      if (Status st = CheckAxes(sl.cubics); !st.ok()) return st.error();
  }
  if (Status st = CheckSlots(f.baro, "B"); !st.ok()) return st.error();
  for (const auto& b : f.baro)
    if (Status st = CheckAxes({b.cubic_pa, b.cubic_pa, b.cubic_pa}); !st.ok()) return st.error();
  std::ostringstream s;
  WriteComments(s, comments);
  s << "#\n# Vehicle-Id Component-Id Name Value Type\n";
  const std::string row = std::to_string(f.system_id) + "\t" + std::to_string(f.component_id) + "\t";
  for (auto [slots, kind] : {std::pair{&f.gyro, "G"}, std::pair{&f.accel, "A"}}) {
    s << row << "TC_" << kind << "_ENABLE\t" << (slots->empty() ? 0 : 1) << "\t6\n";
    if (slots->empty()) continue;
    for (int i = 0; i < kPx4TcalSlots; ++i) {
      const Px4TcalSlot3D* sl = nullptr;
      for (const auto& x : *slots)
        if (x.index == i) sl = &x;
      WritePx4Slot3D(s, row, std::string("TC_") + kind + std::to_string(i) + "_", sl ? sl->device_id : 0,
                     sl ? &sl->cubics : nullptr);
    }
  }
  s << row << "TC_B_ENABLE\t" << (f.baro.empty() ? 0 : 1) << "\t6\n";
  if (!f.baro.empty()) {
    for (int i = 0; i < kPx4TcalSlots; ++i) {
      const Px4TcalSlotBaro* sl = nullptr;
      for (const auto& x : f.baro)
        if (x.index == i) sl = &x;
      const std::string p = "TC_B" + std::to_string(i) + "_";
      s << row << p << "ID\t" << (sl ? sl->device_id : 0) << "\t6\n";
      s << row << p << "TMAX\t" << Float32Text(sl ? sl->cubic_pa.temp_max_c : 0.0) << "\t9\n";
      s << row << p << "TMIN\t" << Float32Text(sl ? sl->cubic_pa.temp_min_c : 0.0) << "\t9\n";
      s << row << p << "TREF\t" << Float32Text(sl ? sl->cubic_pa.ref_temp_c : 0.0) << "\t9\n";
      for (int k = 0; k < 6; ++k)
        s << row << p << "X" << k << "\t" << Float32Text(sl && k < 4 ? sl->cubic_pa.coeff[k] : 0.0) << "\t9\n";
    }
  }
  return s.str();
}

}  // namespace gyrocomp
