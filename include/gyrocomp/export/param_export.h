// Parameter files for the autopilots' own gyro thermal compensation (docs/explanation/flight-controller-export.md, with the
// firmware sources each convention is read from).
//
// PX4 (src/modules/temperature_compensation/TemperatureCompensation.cpp, calc_thermal_offsets_3D;
// src/lib/sensor_calibration/Gyroscope.hpp, Correct):
//   dT = clamp(T, TC_G{i}_TMIN, TC_G{i}_TMAX) - TC_G{i}_TREF
//   offset[a] = X0_a + X1_a dT + X2_a dT^2 + X3_a dT^3            (rad/s, sensor frame)
//   corrected = R (raw - offset - CAL_GYRO offset)                 the offset is SUBTRACTED
// so X0..X3 are the cubic of the drift itself (the absolute bias at T), in rad/s. Written as a
// QGroundControl parameter file: "# Vehicle-Id Component-Id Name Value Type" then one
// tab-separated row per parameter, type 6 (MAV_PARAM_TYPE_INT32) for TC_G_ENABLE and
// TC_G{i}_ID, 9 (REAL32) for the rest, as PX4's Tools/process_sensor_caldata.py writes it.
//
// ArduPilot (libraries/AP_InertialSensor/AP_InertialSensor_tempcal.cpp, correct_sensor;
// AP_InertialSensor_Backend.cpp, _rotate_and_correct_gyro):
//   T, Tcal clamped to [INS_TCAL{n}_TMIN, INS_TCAL{n}_TMAX]
//   p(x) = (GYR1 x + GYR2 x^2 + GYR3 x^3) * 1e-6,  x = T - 35 C       (rad/s)
//   gyro = raw - p(T - 35) + p(Tcal - 35) - INS_GYR{n}OFFS           the correction is SUBTRACTED
// INS_GYR{n}OFFS is measured at boot at Tcal (INS_GYR{n}_CALTEMP) = drift(Tcal), so the exact
// export is p(x) = drift(35 + x) - drift(35): the cubic re-expanded about 35 C, constant dropped,
// times 1e6. Written as "NAME,VALUE" lines with '#' comments (Mission Planner's .param format,
// which pymavlink's mavparm.py load() also reads: ',' -> ' ', two fields per line).
//
// All parameters are float32 on the vehicle: values are written rounded to float32 (%.9g, which
// reads back to the same float).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/export/thermal_cubic.h"

namespace gyrocomp {

// ArduPilot's fixed reference temperature (TEMP_REFERENCE) and parameter scale (SCALE_FACTOR).
inline constexpr double kArduPilotTcalReferenceC = 35.0;
inline constexpr double kArduPilotTcalScale = 1.0e6;  // parameter scale of GYR1..GYR3 (SCALE_FACTOR)

// Which PX4 calibration slot and sensor a gyro parameter file is for.
struct Px4ThermalParamOptions {
  // Calibration slot i of TC_G{i}_* (PX4 has 4: 0..3).
  int index = 0;
  // TC_G{i}_ID: the sensor's device id (PX4 applies the slot only to the gyro whose device_id
  // matches; 0 would match none). Required.
  std::optional<std::uint32_t> device_id;
  // QGroundControl file columns.
  int system_id = 1;
  int component_id = 1;  // MAVLink component id column
  // False with the reason in `error` when index is outside 0..3 or device_id is missing or 0.
  bool IsValid(std::string* error) const;
};

// Which ArduPilot IMU a gyro parameter file is for.
struct ArduPilotThermalParamOptions {
  // IMU number n of INS_TCAL{n}_* (1..3).
  int imu = 1;
  // False with the reason in `error` when imu is outside 1..3.
  bool IsValid(std::string* error) const;
};

// The three axes (x, y, z) as cubics in rad/s sharing one range and reference temperature.
using ThreeAxisCubics = std::array<TemperatureCubic, 3>;

// `comments` become '#' lines at the top (what the model was, the unit conversion, the
// projection cost). Errors: invalid options, axes with different ranges, non-finite values.
Result<std::string> WritePx4ThermalParams(const ThreeAxisCubics& radps, const Px4ThermalParamOptions& options,
                                          const std::vector<std::string>& comments);
// The same as an ArduPilot .param file: INS_TCAL{n}_* with the gyro coefficients (GYR1..GYR3).
Result<std::string> WriteArduPilotThermalParams(const ThreeAxisCubics& radps,
                                                const ArduPilotThermalParamOptions& options,
                                                const std::vector<std::string>& comments);

// ArduPilot's GYR1..GYR3 of one axis (times 1e6, rad/s): the cubic re-expanded about 35 C,
// constant dropped. The same for ACC1..ACC3 (m/s^2): correct_accel is correct_sensor too.
std::array<double, 3> ArduPilotGyrCoefficients(const TemperatureCubic& radps);

// One IMU's complete INS_TCAL{n}_* block. WriteArduPilotThermalParams writes gyro only; the ACC
// coefficients of that IMU are then written as 0, so an older accelerometer calibration never stays
// active under ENABLE = 1 (the firmware keeps every parameter a file does not set).
struct ArduPilotTcalImu {
  int imu = 1;                                 // n of INS_TCAL{n}_ (1..3)
  std::optional<ThreeAxisCubics> gyro_radps;   // nullopt: GYR* = 0
  std::optional<ThreeAxisCubics> accel_m_s2;   // nullopt: ACC* = 0
  // Both nullopt: ENABLE = 0, TMIN/TMAX left alone, every coefficient 0; `disabled_reason` (why
  // the sensor could not be calibrated) goes in a comment.
  std::string disabled_reason;
};
// Errors: imu outside 1..3 or repeated, the gyro and accel of one IMU on different ranges (one
// TMIN/TMAX per IMU), non-finite values.
Result<std::string> WriteArduPilotTcalFile(const std::vector<ArduPilotTcalImu>& imus,
                                           const std::vector<std::string>& comments);

// PX4's TC_G / TC_A / TC_B slots (TemperatureCompensation.cpp: GYRO/ACCEL/BARO_COUNT_MAX = 4
// slots each, a slot applies to the sensor whose device_id equals TC_x{i}_ID). The file written
// holds all four slots of each kind it enables: the unused ones with ID 0 and zeros (an ID 0
// matches no sensor), so no older slot stays active; TC_x_ENABLE = 1 for a kind with a slot,
// else 0.
struct Px4TcalSlot3D {
  int index = 0;  // 0..3
  std::uint32_t device_id = 0;  // TC_G{i}_ID / TC_A{i}_ID: the sensor's device id (not 0)
  ThreeAxisCubics cubics;  // rad/s (gyro) or m/s^2 (accel), sensor frame
};
// One PX4 TC_B slot: a barometer's pressure cubic.
struct Px4TcalSlotBaro {
  int index = 0;  // 0..3
  std::uint32_t device_id = 0;  // TC_B{i}_ID: the sensor's device id (not 0)
  TemperatureCubic cubic_pa;  // X0..X3 in Pa; X4 = X5 = 0 (calc_thermal_offsets_1D is quintic)
};
// A complete PX4 TC_G / TC_A / TC_B parameter file.
struct Px4TcalFile {
  std::vector<Px4TcalSlot3D> gyro;  // TC_G slots (at most 4)
  std::vector<Px4TcalSlot3D> accel;  // TC_A slots (at most 4)
  std::vector<Px4TcalSlotBaro> baro;  // TC_B slots (at most 4)
  int system_id = 1;  // QGroundControl file column Vehicle-Id
  int component_id = 1;  // QGroundControl file column Component-Id
};
inline constexpr int kPx4TcalSlots = 4;  // slots per sensor kind (GYRO/ACCEL/BARO_COUNT_MAX)
// The QGroundControl parameter file of `file`. Errors: a slot index outside 0..3 or repeated,
// device id 0, non-finite values.
Result<std::string> WritePx4TcalFile(const Px4TcalFile& file, const std::vector<std::string>& comments);

}  // namespace gyrocomp
