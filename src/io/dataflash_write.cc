// DataFlash writer of simulated IMU logs (include/gyrocomp/io/dataflash.h, EncodeDataFlash).
// Record layout: ArduPilot libraries/AP_Logger/LogStructure.h (FMT 0x80 "BBnNZ", 89 bytes; every
// record A3 95 <type> <packed little-endian payload>); read back by ParseDataFlash in the tests.
#include <cstring>
#include <string>

#include "gyrocomp/io/dataflash.h"

namespace gyrocomp {
namespace {

constexpr std::uint8_t kParmType = 64;
constexpr std::uint8_t kImuType = 65;
constexpr std::uint8_t kArmType = 66;
constexpr std::uint8_t kEvType = 67;

template <typename T>
void Put(std::string* s, T v) {
  // Little-endian hosts only write the bytes as they are (x86, ARM); the reader is portable.
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s->append(b, sizeof(T));
}

void PutText(std::string* s, const std::string& text, std::size_t n) {
  std::string t = text.substr(0, n);
  t.resize(n, '\0');
  s->append(t);
}

void PutHeader(std::string* s, std::uint8_t type) {
  s->push_back(static_cast<char>(0xA3));
  s->push_back(static_cast<char>(0x95));
  s->push_back(static_cast<char>(type));
}

void PutFmt(std::string* s, std::uint8_t type, std::uint8_t length, const std::string& name, const std::string& format,
            const std::string& labels) {
  PutHeader(s, 0x80);
  Put<std::uint8_t>(s, type);
  Put<std::uint8_t>(s, length);
  PutText(s, name, 4);
  PutText(s, format, 16);
  PutText(s, labels, 64);
}

Status CheckImu(const DataFlashImuWriteInput& m, std::size_t rows) {
  const std::size_t n = m.time_us.size();
  const std::string what = "DataFlashImuWriteInput (instance " + std::to_string(m.instance) + ")";
  if (n != rows) return InvalidArgument(what + ": every IMU must have the same number of rows");
  for (const auto* v : {&m.gyr_x_rad_s, &m.gyr_y_rad_s, &m.gyr_z_rad_s, &m.temp_c})
    if (v->size() != n) return InvalidArgument(what + ": gyro and temperature need one value per row");
  for (const auto* v : {&m.acc_x_m_s2, &m.acc_y_m_s2, &m.acc_z_m_s2})
    if (!v->empty() && v->size() != n) return InvalidArgument(what + ": accel needs one value per row or none");
  for (std::size_t i = 1; i < n; ++i)
    if (m.time_us[i] <= m.time_us[i - 1]) return InvalidArgument(what + ": time_us not increasing at row " + std::to_string(i));
  if (m.instance < 0 || m.instance > 255) return InvalidArgument(what + ": instance must be 0..255");
  return Status::Ok();
}

void PutImuRow(std::string* s, const DataFlashImuWriteInput& m, std::size_t i) {
  auto acc = [&](const std::vector<float>& v) { return v.empty() ? 0.0f : v[i]; };
  PutHeader(s, kImuType);
  Put<std::uint64_t>(s, m.time_us[i]);
  Put<std::uint8_t>(s, static_cast<std::uint8_t>(m.instance));
  Put<float>(s, m.gyr_x_rad_s[i]);
  Put<float>(s, m.gyr_y_rad_s[i]);
  Put<float>(s, m.gyr_z_rad_s[i]);
  Put<float>(s, acc(m.acc_x_m_s2));
  Put<float>(s, acc(m.acc_y_m_s2));
  Put<float>(s, acc(m.acc_z_m_s2));
  Put<std::uint32_t>(s, 0);  // EG
  Put<std::uint32_t>(s, 0);  // EA
  Put<float>(s, m.temp_c[i]);
  Put<std::uint8_t>(s, 1);  // GH
  Put<std::uint8_t>(s, 1);  // AH
  Put<std::uint16_t>(s, m.sample_rate_hz);
  Put<std::uint16_t>(s, m.sample_rate_hz);
}

}  // namespace

Result<std::string> EncodeDataFlash(const DataFlashWriteInput& in) {
  const std::size_t rows = in.imus.empty() ? 0 : in.imus.front().time_us.size();
  for (const auto& m : in.imus)
    if (Status st = CheckImu(m, rows); !st.ok()) return st.error();
  for (const auto& [name, value] : in.parameters)
    if (name.empty() || name.size() > 16) return InvalidArgument("DataFlashWriteInput: parameter name '" + name + "' must be 1..16 characters");
  std::string s;
  PutFmt(&s, 0x80, 89, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns");
  PutFmt(&s, kParmType, 3 + 8 + 16 + 4 + 4, "PARM", "QNff", "TimeUS,Name,Value,Default");
  PutFmt(&s, kImuType, 3 + 8 + 1 + 6 * 4 + 2 * 4 + 4 + 2 + 2 * 2, "IMU", "QBffffffIIfBBHH",
         "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,GHz,AHz");
  if (!in.arm_states.empty() || !in.events.empty()) {  // LogStructure.h's layouts
    PutFmt(&s, kArmType, 3 + 8 + 1 + 4 + 1 + 1, "ARM", "QBIBB", "TimeUS,ArmState,ArmChecks,Forced,Method");
    PutFmt(&s, kEvType, 3 + 8 + 1, "EV", "QB", "TimeUS,Id");
  }
  const std::uint64_t t0 = rows > 0 ? in.imus.front().time_us.front() : 0;
  for (const auto& [name, value] : in.parameters) {
    PutHeader(&s, kParmType);
    Put<std::uint64_t>(&s, t0);
    PutText(&s, name, 16);
    Put<float>(&s, value);
    Put<float>(&s, value);
  }
  std::size_t next_arm = 0, next_ev = 0;
  // The state records up to time_us (all of them at the end).
  auto put_states = [&](std::uint64_t time_us, bool all) {
    for (; next_arm < in.arm_states.size() && (all || in.arm_states[next_arm].time_us <= time_us); ++next_arm) {
      PutHeader(&s, kArmType);
      Put<std::uint64_t>(&s, in.arm_states[next_arm].time_us);
      Put<std::uint8_t>(&s, static_cast<std::uint8_t>(in.arm_states[next_arm].value));
      Put<std::uint32_t>(&s, 0);  // ArmChecks
      Put<std::uint8_t>(&s, 0);   // Forced
      Put<std::uint8_t>(&s, 0);   // Method
    }
    for (; next_ev < in.events.size() && (all || in.events[next_ev].time_us <= time_us); ++next_ev) {
      PutHeader(&s, kEvType);
      Put<std::uint64_t>(&s, in.events[next_ev].time_us);
      Put<std::uint8_t>(&s, static_cast<std::uint8_t>(in.events[next_ev].value));
    }
  };
  for (std::size_t i = 0; i < rows; ++i) {
    put_states(in.imus.front().time_us[i], false);
    for (const auto& m : in.imus) PutImuRow(&s, m, i);
  }
  put_states(0, true);
  return s;
}

}  // namespace gyrocomp
