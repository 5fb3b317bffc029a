// The vehicle's armed and landed state as a flight log records it, as time-stamped samples: what
// the still detector (gyrocomp/calibrate/still.h) is told besides the IMU.
//
// PX4 ULog (the topics' fields: PX4/PX4-Autopilot msg/*.msg; the reader keeps the first row of
// each subscription and every change, ULogContents::states):
//   armed   actuator_armed.armed (msg/ActuatorArmed.msg "bool armed # Set to true if system is
//           armed") and vehicle_status.arming_state (msg/VehicleStatus.msg: ARMING_STATE_ARMED =
//           2; 1 is STANDBY in older messages and DISARMED in newer ones); with both, a time is
//           armed when either says so.
//   landed  vehicle_land_detected.landed (msg/VehicleLandDetected.msg "bool landed # true if
//           vehicle is currently landed on the ground (3. stage)").
// ArduPilot DataFlash (ArduPilot/ardupilot libraries/AP_Logger/LogStructure.h: "ARM" "QBIBB"
// TimeUS,ArmState,...; "EV" "QB" TimeUS,Id; the ids: enum class LogEvent in AP_Logger.h):
//   armed   ARM.ArmState (1 armed, 0 disarmed) and EV Id 10 ARMED / 11 DISARMED (older logs have
//           the events only); with both, armed when either says so.
//   landed  EV Id 18 LAND_COMPLETE (landed) / 28 NOT_LANDED (in the air); 17 LAND_COMPLETE_MAYBE
//           is not a state change (the copter's land detector's first stage).
// A state holds from its sample until the next one. Before a log's first sample the state is not
// known: StateAtTimes gives `before_first` there (the calibrate stage: not armed, landed, so the
// IMU alone decides; its summary says from when the log's state is known).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/ulog.h"

namespace gyrocomp {

// The state from time_us on (until the next sample).
struct VehicleStateSample {
  std::uint64_t time_us = 0;  // log time, us (ULog 'timestamp', DataFlash TimeUS)
  bool value = false;  // armed / landed
};

// A log's armed and landed state, each in time order with no two equal values in a row.
struct VehicleStateLog {
  std::vector<VehicleStateSample> armed;  // true: armed (motors may spin)
  std::vector<VehicleStateSample> landed;  // true: landed; false: in the air
  std::string armed_source;   // the fields read, e.g. "actuator_armed.armed, vehicle_status.arming_state"; "" none
  std::string landed_source;  // e.g. "vehicle_land_detected.landed", "EV LAND_COMPLETE / NOT_LANDED"; "" none
  // One line: what was read and from when it is known ("armed: actuator_armed.armed from 1.00 s;
  // landed: vehicle_land_detected.landed from 1.00 s" or "no armed or landed state in the log").
  std::string BriefReport() const;
};

// The state of a ULog (the topics above; none: empty vectors and sources).
VehicleStateLog VehicleStateOfULog(const ULogContents& log);
// The state of a DataFlash log (ARM and EV records).
VehicleStateLog VehicleStateOfDataFlash(const DataFlashContents& log);

// The state at each time_s (s, the log's clock: time_us * 1e-6): the value of the last sample at
// or before it, `before_first` before the first sample (and everywhere when there is none).
// time_s need not be sorted.
std::vector<bool> StateAtTimes(const std::vector<VehicleStateSample>& samples, const std::vector<double>& time_s,
                               bool before_first);

}  // namespace gyrocomp
