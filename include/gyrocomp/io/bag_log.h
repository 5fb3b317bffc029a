// A ROS bag behind every -i: ReadLogTable (gyrocomp/io/flight_log.h) hands a bag here
// (LogFormat::kRosBag, recognised by DetectBagFormat), which reads the IMU topic
// (gyrocomp/io/bag.h) and sets the LogSpec to its columns: time_s, the gyro rates
// x_rad_s, y_rad_s, z_rad_s (rad/s) unless `spec` names other rate columns (e.g. the
// accelerometer's x_m_s2, ...), temp_c.
#pragma once

#include <string>

#include "gyrocomp/core/status.h"
#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/flight_log.h"

namespace gyrocomp {

// BagReadOptions from a LogSpec (topic, time source).
BagReadOptions BagOptionsFromSpec(const LogSpec& spec);

// The BagImuTable as a FlightLogTable (format kRosBag, origin, warnings, damage), for convert / inspect.
FlightLogTable BagFlightLog(BagImuTable bag);

// ReadLogTable for a ROS bag: ReadBagImu, then `spec` set to the bag table's columns (time_s,
// x/y/z_rad_s in rad/s unless `spec` names rate columns, temp_c); warnings to spec.on_warning;
// temp_required without a temperature topic is an error. `strict`: BagReadOptions::strict (a
// damaged record is an error instead of skipped and listed in flight->damage).
Result<LogTableRead> ReadBagLogTable(const std::string& path, const LogSpec& spec, bool strict = false);

}  // namespace gyrocomp
