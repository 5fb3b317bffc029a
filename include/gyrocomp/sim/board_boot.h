// A simulated board's log as it comes out of one particular boot: the order in which the flight
// controller's drivers enumerated its IMUs. PX4 numbers sensor_gyro / sensor_accel instances
// (multi_id) in the order the drivers started, which can change from one power-on to the next;
// the device id stays with the chip. Logs of one board from several boots then disagree on
// instance numbers and agree on device ids.
#pragma once

#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp {

// EncodeBoardULog with IMU order[k] of `board` logged as multi_id k (its data, temperature and
// device ids: BoardGyroDeviceId(order[k]), BoardAccelDeviceId(order[k])). `order` must be a
// permutation of 0..imus-1; the identity is EncodeBoardULog.
Result<std::string> EncodeBoardULogEnumerated(const BoardRun& board, double log_rate_hz, const std::vector<int>& order);

}  // namespace gyrocomp
