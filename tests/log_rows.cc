// Sensor rows of a decoded flight log as bit patterns (log_rows.h).
#include "log_rows.h"

#include <algorithm>
#include <cstring>
#include <set>

namespace gyrocomp::test {
namespace {

std::uint64_t Bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
double At(const std::vector<double>& v, std::size_t i) { return i < v.size() ? v[i] : 0.0; }

}  // namespace

LogRows ULogRows(const ULogContents& log) {
  LogRows out;
  for (const auto* list : {&log.gyros, &log.combined}) {
    for (const ULogGyroSeries& g : *list) {
      auto& rows = out[g.topic + " " + std::to_string(g.multi_id)];
      for (std::size_t i = 0; i < g.timestamp_us.size() && i < g.x_rad_s.size(); ++i) {
        rows.emplace_back(g.timestamp_us[i], Bits(g.x_rad_s[i]), Bits(g.y_rad_s[i]), Bits(g.z_rad_s[i]),
                          Bits(At(g.temperature_c, i)));
      }
    }
  }
  for (const ULogAccelSeries& a : log.accels) {
    auto& rows = out["sensor_accel " + std::to_string(a.multi_id)];
    for (std::size_t i = 0; i < a.timestamp_us.size(); ++i) {
      rows.emplace_back(a.timestamp_us[i], Bits(a.x_m_s2[i]), Bits(a.y_m_s2[i]), Bits(a.z_m_s2[i]),
                        Bits(At(a.temperature_c, i)));
    }
  }
  for (const ULogBaroSeries& b : log.baros) {
    auto& rows = out["sensor_baro " + std::to_string(b.multi_id)];
    for (std::size_t i = 0; i < b.timestamp_us.size(); ++i) {
      rows.emplace_back(b.timestamp_us[i], Bits(b.pressure_pa[i]), 0, 0, Bits(At(b.temperature_c, i)));
    }
  }
  return out;
}

LogRows DataFlashRows(const DataFlashContents& log) {
  LogRows out;
  for (const DataFlashImuSeries& s : log.imus) {
    auto& rows = out["IMU " + std::to_string(s.instance)];
    for (std::size_t i = 0; i < s.time_us.size(); ++i) {
      rows.emplace_back(s.time_us[i], Bits(s.gyr_x_rad_s[i]), Bits(s.gyr_y_rad_s[i]), Bits(s.gyr_z_rad_s[i]),
                        Bits(At(s.temp_c, i)));
    }
  }
  return out;
}

LogRows AnySeries(const LogRows& rows) {
  LogRows out;
  auto& all = out["*"];
  for (const auto& [series, r] : rows) all.insert(all.end(), r.begin(), r.end());
  return out;
}

std::size_t CountRows(const LogRows& rows) {
  std::size_t n = 0;
  for (const auto& [series, r] : rows) n += r.size();
  return n;
}

std::string NotASubset(const LogRows& got, const LogRows& original, bool allow_repeats) {
  for (const auto& [series, rows] : got) {
    const auto it = original.find(series);
    if (it == original.end()) return series + " (absent from the undamaged log)";
    std::multiset<LogRow> pool(it->second.begin(), it->second.end());
    for (const LogRow& r : rows) {
      const auto p = pool.find(r);
      if (p == pool.end()) {
        if (allow_repeats && it->second.end() != std::find(it->second.begin(), it->second.end(), r)) continue;
        return series + " (a row the undamaged log does not have, timestamp " + std::to_string(std::get<0>(r)) + ")";
      }
      pool.erase(p);
    }
  }
  return "";
}

}  // namespace gyrocomp::test
