// A flight log's armed and landed state (include/gyrocomp/io/vehicle_state.h).
#include "gyrocomp/io/vehicle_state.h"

#include <algorithm>
#include <cstdio>
#include <iterator>

namespace gyrocomp {
namespace {

// Samples with the repeated values dropped (a state is a change, not a report).
std::vector<VehicleStateSample> Changes(std::vector<VehicleStateSample> v) {
  std::stable_sort(v.begin(), v.end(), [](const VehicleStateSample& a, const VehicleStateSample& b) { return a.time_us < b.time_us; });
  std::vector<VehicleStateSample> out;
  for (const VehicleStateSample& s : v) {
    if (!out.empty() && out.back().time_us == s.time_us) out.pop_back();  // the later of two at one time
    if (out.empty() || out.back().value != s.value) out.push_back(s);
  }
  return out;
}

// Several sources of one state, true when any of them says so (a source is false before its
// first sample).
std::vector<VehicleStateSample> AnyOf(const std::vector<std::vector<VehicleStateSample>>& sources) {
  std::vector<std::uint64_t> times;
  for (const auto& s : sources)
    for (const VehicleStateSample& v : s) times.push_back(v.time_us);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  std::vector<VehicleStateSample> out;
  for (std::uint64_t t : times) {
    bool any = false;
    for (const auto& s : sources) {
      const auto it = std::upper_bound(s.begin(), s.end(), t, [](std::uint64_t x, const VehicleStateSample& v) { return x < v.time_us; });
      if (it != s.begin()) any |= std::prev(it)->value;
    }
    out.push_back({t, any});
  }
  return Changes(std::move(out));
}

void AddSource(std::string* list, const std::string& name) { *list += (list->empty() ? "" : ", ") + name; }

std::string Seconds(std::uint64_t us) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f s", static_cast<double>(us) * 1e-6);
  return b;
}

}  // namespace

VehicleStateLog VehicleStateOfULog(const ULogContents& log) {
  VehicleStateLog out;
  std::vector<std::vector<VehicleStateSample>> armed;
  std::vector<VehicleStateSample> landed;
  for (const ULogStateSeries& s : log.states) {
    if (s.multi_id != 0) continue;  // one vehicle: the first instance
    std::vector<VehicleStateSample> v;
    for (std::size_t i = 0; i < s.timestamp_us.size(); ++i) {
      // msg/ActuatorArmed.msg bool armed; msg/VehicleStatus.msg ARMING_STATE_ARMED = 2;
      // msg/VehicleLandDetected.msg bool landed.
      const bool value = s.topic == "vehicle_status" ? s.value[i] == 2 : s.value[i] != 0;
      v.push_back({s.timestamp_us[i], value});
    }
    if (s.topic == "vehicle_land_detected") {
      landed = Changes(std::move(v));
      out.landed_source = s.topic + "." + s.field;
    } else {
      armed.push_back(Changes(std::move(v)));
      AddSource(&out.armed_source, s.topic + "." + s.field);
    }
  }
  out.armed = AnyOf(armed);
  out.landed = std::move(landed);
  return out;
}

VehicleStateLog VehicleStateOfDataFlash(const DataFlashContents& log) {
  // AP_Logger.h, enum class LogEvent.
  constexpr int kArmed = 10, kDisarmed = 11, kLandComplete = 18, kNotLanded = 28;
  VehicleStateLog out;
  std::vector<VehicleStateSample> arm, ev_arm, landed;
  for (const DataFlashStateRecord& r : log.arm_states) arm.push_back({r.time_us, r.value != 0});  // ArmState 1: armed
  for (const DataFlashStateRecord& r : log.events) {
    if (r.value == kArmed || r.value == kDisarmed) ev_arm.push_back({r.time_us, r.value == kArmed});
    if (r.value == kLandComplete || r.value == kNotLanded) landed.push_back({r.time_us, r.value == kLandComplete});
  }
  if (!arm.empty()) AddSource(&out.armed_source, "ARM.ArmState");
  if (!ev_arm.empty()) AddSource(&out.armed_source, "EV ARMED / DISARMED");
  if (!landed.empty()) out.landed_source = "EV LAND_COMPLETE / NOT_LANDED";
  out.armed = AnyOf({Changes(std::move(arm)), Changes(std::move(ev_arm))});
  out.landed = Changes(std::move(landed));
  return out;
}

std::vector<bool> StateAtTimes(const std::vector<VehicleStateSample>& samples, const std::vector<double>& time_s,
                               bool before_first) {
  std::vector<bool> out(time_s.size(), before_first);
  for (std::size_t i = 0; i < time_s.size(); ++i) {
    const double t_us = time_s[i] * 1e6;
    const auto it = std::upper_bound(samples.begin(), samples.end(), t_us,
                                     [](double x, const VehicleStateSample& v) { return x < static_cast<double>(v.time_us); });
    if (it != samples.begin()) out[i] = std::prev(it)->value;
  }
  return out;
}

std::string VehicleStateLog::BriefReport() const {
  if (armed_source.empty() && landed_source.empty()) return "no armed or landed state in the log: the IMU alone decides";
  std::string t;
  if (!armed_source.empty()) t += "armed: " + armed_source + " from " + Seconds(armed.front().time_us);
  if (!landed_source.empty()) t += (t.empty() ? "" : "; ") + std::string("landed: ") + landed_source + " from " + Seconds(landed.front().time_us);
  if (armed_source.empty()) t += "; no armed state";
  if (landed_source.empty()) t += "; no landed state";
  return t + " (before: not known, the IMU alone decides)";
}

}  // namespace gyrocomp
