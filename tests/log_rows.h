// Sensor rows of a decoded flight log as exact bit patterns, for checking that recovery from a
// damaged log keeps only rows of the undamaged one (src/io/log_recovery_test.cc and the
// record-level fuzzers, fuzz/fuzz_records.h).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/ulog.h"

namespace gyrocomp::test {

// Timestamp and the value fields' bit patterns (x, y, z, temperature; a baro row: pressure, 0, 0,
// temperature; a missing temperature is 0.0).
using LogRow = std::tuple<std::uint64_t, std::uint64_t, std::uint64_t, std::uint64_t, std::uint64_t>;
// Rows per series: "sensor_gyro 0", "sensor_combined 0", "sensor_accel 1", "sensor_baro 0", "IMU 1".
using LogRows = std::map<std::string, std::vector<LogRow>>;

LogRows ULogRows(const ULogContents& log);
LogRows DataFlashRows(const DataFlashContents& log);
// Every row under one series "*" (a damaged msg id may move a row to another subscription of the
// same size, as in pyulog).
LogRows AnySeries(const LogRows& rows);
std::size_t CountRows(const LogRows& rows);

// The first series of `got` with a row that `original`'s same series does not have (or has fewer
// times, unless `allow_repeats`: a duplicated record repeats its row), or "" when none.
std::string NotASubset(const LogRows& got, const LogRows& original, bool allow_repeats = false);

}  // namespace gyrocomp::test
