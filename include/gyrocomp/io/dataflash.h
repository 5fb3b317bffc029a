// ArduPilot DataFlash (.bin) logs: a compact reader of the IMU gyro rows and the parameters.
//
// Format (ArduPilot libraries/AP_Logger/LogStructure.h; reference parser: ArduPilot/pymavlink
// DFReader.py, DFReader_binary): no file header; every record is A3 95 (uint8 msg type) followed
// by a packed little-endian payload whose layout a FMT record (type 128, 89 bytes: uint8 type,
// uint8 length incl. the 3 header bytes, char name[4], char format[16], char labels[64]) defines;
// FMT defines itself. Format characters (DFReader FORMAT_TO_STRUCT): b B h H i I f d q Q, n
// (char[4]), N (char[16]), Z (char[64]), a (int16[32]), c/C (int16/uint16 x 0.01), e/E
// (int32/uint32 x 0.01), L (int32 x 1e-7), M (uint8 mode), g (half float).
//
// Gyro rows: message IMU with fields TimeUS (us), GyrX, GyrY, GyrZ (rad/s, offset-corrected and
// rotated to the board frame by ArduPilot), T (deg C), and in newer logs an instance field I;
// older logs have separate messages IMU, IMU2, IMU3 (instances 0, 1, 2).
//
// Damage: a record that does not start with A3 95 and a known message type, that is not followed
// by a valid header, or a FMT whose length disagrees with its format string, is skipped up to the
// next valid record (DataFlashReadOptions::strict: an error naming the byte offset instead).
// A last record cut by the end of the file is dropped with a warning giving its offset, as
// DFReader does.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/io/log_damage.h"

namespace gyrocomp {

// One FMT record: the layout of a message type.
struct DataFlashFormat {
  int type = 0;  // message type id (0..255)
  int length = 0;  // bytes, including the 3-byte record header
  std::string name;  // message name, e.g. "IMU"
  std::string format;  // format characters, one per field (see the top of this file)
  std::vector<std::string> labels;  // field names, e.g. TimeUS, GyrX
};

// The IMU rows of one instance, values as logged (float32 widened to double, so they
// compare exactly with pymavlink's extracts): board frame, after ArduPilot's offsets and (with
// INS_TCALn_ENABLE = 1) its thermal correction; flight_log.h undoes both.
struct DataFlashImuSeries {
  int instance = 0;  // IMU instance (field I, or 0, 1, 2 for IMU, IMU2, IMU3)
  std::string message;  // "IMU" (with field I) or "IMU", "IMU2", "IMU3" (old logs)
  std::vector<std::uint64_t> time_us;  // field TimeUS, us
  std::vector<double> gyr_x_rad_s;  // field GyrX, rad/s
  std::vector<double> gyr_y_rad_s;  // field GyrY, rad/s
  std::vector<double> gyr_z_rad_s;  // field GyrZ, rad/s
  // Fields AccX, AccY, AccZ (m/s^2, specific force); empty when the message has none.
  std::vector<double> acc_x_m_s2;  // field AccX
  std::vector<double> acc_y_m_s2;  // field AccY
  std::vector<double> acc_z_m_s2;  // field AccZ
  std::vector<double> temp_c;  // field T
  std::size_t records = 0;  // IMU records read for this instance (before any averaging)
};

// One record of a vehicle-state message gyrocomp reads (vehicle_state.h): ARM (LogStructure.h
// "QBIBB" TimeUS,ArmState,ArmChecks,Forced,Method; ArmState 1 armed, 0 disarmed) or EV ("QB"
// TimeUS,Id; Id a LogEvent of AP_Logger.h: 10 ARMED, 11 DISARMED, 18 LAND_COMPLETE, 28 NOT_LANDED).
struct DataFlashStateRecord {
  std::uint64_t time_us = 0;  // field TimeUS, us
  int value = 0;  // ARM: ArmState; EV: Id
};

// What ReadDataFlash found.
struct DataFlashContents {
  std::string source;  // the path (or the name given to ParseDataFlash), for messages
  std::vector<DataFlashFormat> formats;             // in file order (FMT records)
  std::map<std::string, std::size_t> message_counts; // records per message name
  std::map<std::string, double> parameters;          // PARM Name -> Value (last value wins)
  // Parameters whose value changed after the first IMU row (the rows before and after were logged
  // under different values): the first such change of each.
  struct ParameterChange {
    std::size_t offset = 0;   // byte offset of the PARM record
    std::uint64_t time_us = 0;  // its TimeUS (0 when it has none)
    double before = 0.0;  // PARM Value in force before the change
    double after = 0.0;  // PARM Value after it
  };
  // Parameter name -> its first change after the first IMU row.
  std::map<std::string, ParameterChange> parameters_changed_during_imu;
  std::vector<DataFlashImuSeries> imus;              // sorted by instance
  std::vector<DataFlashStateRecord> arm_states;  // every ARM record (ArmState), in file order
  std::vector<DataFlashStateRecord> events;      // every EV record (Id), in file order
  std::size_t num_records = 0;  // records read
  std::vector<std::string> warnings;  // truncated last record, damage (one line)
  // Byte ranges skipped in recovery (DataFlashReadOptions::strict false), in file order.
  std::vector<LogDamage> damage;
  // One line for logs: source, record, FMT and parameter counts, IMU instances with data.
  std::string BriefReport() const;
};

// How the IMU rows are kept (memory: a 1 h, 1 kHz, 3-IMU log in well under 1 GB).
struct DataFlashReadOptions {
  // > 0: each IMU instance is kept as the means of its rows (TimeUS, gyro, accel, T) in
  // consecutive windows of this many microseconds (window k: TimeUS in [k w, (k + 1) w)).
  // 0: every row as logged (the default).
  std::uint64_t average_window_us = 0;
  // Memory: set, the other IMU instances keep their TimeUS only (row counts stay
  // right for messages; gyro, accel and T empty).
  std::optional<int> imu_instance;
  // false (the default): a damaged record (no A3 95, a type no FMT defined, a record not followed
  // by a valid header, a FMT that does not add up) is skipped up to the next record that is valid
  // and followed by a valid header (DFReader skips bad bytes one at a time the same way); every
  // intact record is kept and DataFlashContents::damage lists what was skipped. true: the first
  // damaged record is an error naming its byte offset.
  bool strict = false;
};

// Reads a whole DataFlash file (errors: cannot open -> kIo; malformed -> kInvalidInput,
// "<file>: byte <offset>: <what>"). A regular file is memory-mapped and the parsed part given
// back as the parser moves on.
Result<DataFlashContents> ReadDataFlash(const std::string& path, const DataFlashReadOptions& options = {});

// The same on bytes in memory (`source` names them in messages); for tests and fuzzing.
Result<DataFlashContents> ParseDataFlash(const std::uint8_t* data, std::size_t size, const std::string& source,
                                         const DataFlashReadOptions& options = {});

// True when the bytes start like a DataFlash log: A3 95 80 (a FMT record first).
bool HasDataFlashMagic(const std::uint8_t* data, std::size_t size);

// A DataFlash log to write (simulated IMUs; tests): FMT (FMT, PARM, IMU), one PARM row per
// parameter, then the IMU rows of every instance interleaved by row index. IMU has ArduPilot's
// field layout (LogStructure.h, "QBffffffIIfBBHH": TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,
// T,GH,AH,GHz,AHz), so pymavlink's DFReader and tempcal_IMU.py read it; PARM is "QNff"
// (TimeUS,Name,Value,Default).
struct DataFlashImuWriteInput {
  int instance = 0;  // IMU instance (field I)
  std::vector<std::uint64_t> time_us;  // strictly increasing
  std::vector<float> gyr_x_rad_s;  // field GyrX, rad/s; same length as time_us
  std::vector<float> gyr_y_rad_s;  // field GyrY, rad/s
  std::vector<float> gyr_z_rad_s;  // field GyrZ, rad/s
  std::vector<float> acc_x_m_s2;  // field AccX, m/s^2; empty: written as 0
  std::vector<float> acc_y_m_s2;  // field AccY, m/s^2; empty: written as 0
  std::vector<float> acc_z_m_s2;  // field AccZ, m/s^2; empty: written as 0
  std::vector<float> temp_c;  // field T, deg C
  std::uint16_t sample_rate_hz = 1000;  // GHz / AHz
};
// Input of EncodeDataFlash: the parameters, the IMU instances and the vehicle's state records.
struct DataFlashWriteInput {
  std::map<std::string, float> parameters;  // written in name order, at TimeUS of the first row
  std::vector<DataFlashImuWriteInput> imus;  // same row count each
  // ARM ("QBIBB": TimeUS, ArmState, ArmChecks 0, Forced 0, Method 0) and EV ("QB": TimeUS, Id)
  // records, each written before the first IMU row later than its TimeUS; time order each.
  std::vector<DataFlashStateRecord> arm_states;
  std::vector<DataFlashStateRecord> events;  // EV records (Id: AP_Logger.h LogEvent)
};
// Errors (kInvalidArgument): lengths differ, time not increasing, a parameter name over 16 chars.
Result<std::string> EncodeDataFlash(const DataFlashWriteInput& input);

}  // namespace gyrocomp
