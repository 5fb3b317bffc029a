// Test-only pieces shared by the ROS bag reader tests (cdr_test, mcap_test, rosbag1_test,
// bag_test, the recovery tests): little-endian bytes, the simulated IMU messages the hand-built
// bags hold, the check that a table read back holds them, and rows as bits.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/io/bag.h"
#include "gyrocomp/io/cdr.h"
#include "test_support.h"

namespace gyrocomp::testing {

// Appends v as n little-endian bytes, least significant first (bytes past the 8th are zero).
inline void Le(std::string* s, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) s->push_back(i < 8 ? static_cast<char>((v >> (8 * i)) & 0xff) : '\0');
}

// ROS 1 bag v2.0 records (wiki.ros.org/Bags/Format/2.0): a header field "name=value" with its
// int32 length, an integer field of n little-endian bytes, a record (header, data), an op field.
inline std::string Field(const std::string& name, const std::string& value) {
  std::string s;
  Le(&s, name.size() + 1 + value.size(), 4);
  return s + name + "=" + value;
}
inline std::string IntField(const std::string& name, std::uint64_t v, int n) {
  std::string b;
  Le(&b, v, n);
  return Field(name, b);
}
inline std::string Ros1Record(const std::string& header, const std::string& data) {
  std::string s;
  Le(&s, header.size(), 4);
  s += header;
  Le(&s, data.size(), 4);
  return s + data;
}
inline std::string Op(int op) { return Field("op", std::string(1, static_cast<char>(op))); }

// MCAP (mcap.dev/spec): a string with its uint32 length, a record (opcode, uint64 length, content).
inline std::string Str(const std::string& v) {
  std::string s;
  Le(&s, v.size(), 4);
  return s + v;
}
inline std::string Rec(std::uint8_t op, const std::string& content) {
  std::string s(1, static_cast<char>(op));
  Le(&s, content.size(), 8);
  return s + content;
}

// An MCAP Message record: channel id, sequence 0, log and publish time both log_time.
inline std::string McapMessage(int channel, std::uint64_t log_time, const std::string& data) {
  std::string c;
  Le(&c, channel, 2);
  Le(&c, 0, 4);
  Le(&c, log_time, 8);
  Le(&c, log_time, 8);
  return Rec(0x05, c + data);
}

// IMU message i of the simulated topic /imu0: stamps 5 ms apart from 1.7e9 s, small rates
// around k rad/s on axis k, gravity on z.
inline ImuMessage Sample(int i) {
  ImuMessage m;
  const std::int64_t ns = 1700000000000000000 + static_cast<std::int64_t>(i) * 5000000;
  m.stamp_sec = ns / 1000000000;
  m.stamp_nanosec = static_cast<std::uint32_t>(ns % 1000000000);
  for (int k = 0; k < 3; ++k) {
    m.angular_velocity_rad_s[k] = 1e-3 * (i % 7 - 3) + k;
    m.linear_acceleration_m_s2[k] = 9.81 * (k == 2) + 1e-2 * (i % 5 - 2);
  }
  return m;
}

// The table read back holds Sample(0 .. n-1) exactly, each with the temperature of the nearest
// temperature message (one every 10th IMU message, 20 + i C).
inline void ExpectSamples(const BagImuTable& t, int n) {
  ASSERT_EQ(t.table.num_rows(), static_cast<std::size_t>(n));
  ASSERT_EQ(t.table.names, (std::vector<std::string>{"time_s", "x_rad_s", "y_rad_s", "z_rad_s", "x_m_s2", "y_m_s2",
                                                      "z_m_s2", "temp_c"}));
  for (int i = 0; i < n; ++i) {
    const ImuMessage m = Sample(i);
    // Whole seconds plus the fraction (what the reader computes from the integer stamp).
    const std::int64_t ns = m.StampNs();
    EXPECT_EQ(t.table.columns[0][i], static_cast<double>(ns / 1000000000) + static_cast<double>(ns % 1000000000) / 1e9) << i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(t.table.columns[1 + k][i], m.angular_velocity_rad_s[k]) << i;
      EXPECT_EQ(t.table.columns[4 + k][i], m.linear_acceleration_m_s2[k]) << i;
    }
    // Nearest temperature (every 10th stamp; ties go to the earlier one).
    const int nearest = (i % 10 <= 5) ? i / 10 * 10 : i / 10 * 10 + 10;
    EXPECT_EQ(t.table.columns[7][i], 20.0 + std::min(nearest, (n - 1) / 10 * 10)) << i;
  }
}

// An IMU row as bits: time_s, gyro x y z, accel x y z (the joined temperature is left out: a lost
// temperature message changes which one is nearest, not the IMU message).
using BagRow = std::tuple<std::uint64_t, std::uint64_t, std::uint64_t, std::uint64_t, std::uint64_t, std::uint64_t,
                          std::uint64_t>;
inline std::uint64_t Bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
// A table's rows, sorted.
inline std::vector<BagRow> BagRows(const BagImuTable& t) {
  std::vector<BagRow> out;
  const auto& c = t.table.columns;
  for (std::size_t i = 0; i < t.table.num_rows(); ++i) {
    out.emplace_back(Bits(c[0][i]), Bits(c[1][i]), Bits(c[2][i]), Bits(c[3][i]), Bits(c[4][i]), Bits(c[5][i]), Bits(c[6][i]));
  }
  std::sort(out.begin(), out.end());
  return out;
}
// Every row of `got` is one of `all` (both sorted).
inline bool IsSubset(const std::vector<BagRow>& got, const std::vector<BagRow>& all) {
  return std::includes(all.begin(), all.end(), got.begin(), got.end());
}
// Warnings that report damage (one per file is the rule).
inline std::size_t DamageLines(const BagImuTable& t) {
  return static_cast<std::size_t>(std::count_if(t.warnings.begin(), t.warnings.end(), [](const std::string& w) {
    return w.find(": damaged: ") != std::string::npos;
  }));
}
// Rows a damage lost on `topic`.
inline std::size_t Lost(const LogDamage& d, const std::string& topic) {
  const auto it = d.rows_lost.find(topic);
  return it == d.rows_lost.end() ? 0 : it->second;
}

}  // namespace gyrocomp::testing
