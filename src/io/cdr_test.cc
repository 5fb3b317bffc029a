// ROS message encodings against bytes laid out by hand from the specifications: CDR (ROS 2,
// XTypes / CORBA alignment) in both byte orders, the encoder's alignment for every frame_id
// length, short messages and bad headers; ROS 1 serialization.
#include "gyrocomp/io/cdr.h"

#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "bag_test_util.h"

namespace gyrocomp {
namespace {

using testing::Le;

void Be(std::string* s, std::uint64_t v, int n) {
  for (int i = n - 1; i >= 0; --i) s->push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
std::uint64_t Bits(double d) {
  std::uint64_t v;
  std::memcpy(&v, &d, 8);
  return v;
}

// ---- CDR laid out by hand (XTypes 7.4.3.5 header; CORBA 9.3.1.1 alignment from byte 4) ----

// sensor_msgs/msg/Imu with frame_id "ab": body offsets (after the 4-byte header): sec 0..3,
// nanosec 4..7, string length 8..11 (= 3: 'a' 'b' NUL), chars 12..14, pad 15, then 37 float64
// from body offset 16.
std::string HandImu(bool big_endian, const double gyro[3], const double accel[3]) {
  std::string s = {0, static_cast<char>(big_endian ? 0 : 1), 0, 0};
  auto put = [&](std::uint64_t v, int n) { big_endian ? Be(&s, v, n) : Le(&s, v, n); };
  put(1700000000, 4);
  put(123456789, 4);
  put(3, 4);
  s += std::string("ab\0", 3);
  s.push_back(0);  // padding to the next multiple of 8 from the body start
  EXPECT_EQ(s.size(), 4u + 16u);
  const double quat[4] = {0, 0, 0, 1};
  for (double v : quat) put(Bits(v), 8);
  for (int i = 0; i < 9; ++i) put(Bits(-1.0), 8);
  for (int i = 0; i < 3; ++i) put(Bits(gyro[i]), 8);
  for (int i = 0; i < 9; ++i) put(Bits(-1.0), 8);
  for (int i = 0; i < 3; ++i) put(Bits(accel[i]), 8);
  for (int i = 0; i < 9; ++i) put(Bits(-1.0), 8);
  return s;
}

TEST(CdrTest, ImuBothByteOrdersFromHandLaidBytes) {
  const double g[3] = {0.25, -1e-3, 3.5}, a[3] = {0.125, -9.81, 1e-7};
  for (bool big : {false, true}) {
    const std::string bytes = HandImu(big, g, a);
    ImuMessage m;
    auto e = DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), &m);
    ASSERT_FALSE(e) << e->what;
    EXPECT_EQ(m.stamp_sec, 1700000000);
    EXPECT_EQ(m.stamp_nanosec, 123456789u);
    EXPECT_EQ(m.StampNs(), 1700000000123456789);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(m.angular_velocity_rad_s[k], g[k]);
      EXPECT_EQ(m.linear_acceleration_m_s2[k], a[k]);
    }
  }
}

TEST(CdrTest, EncoderMatchesHandLayoutAndAlignsEveryFrameIdLength) {
  const double g[3] = {0.25, -1e-3, 3.5}, a[3] = {0.125, -9.81, 1e-7};
  ImuMessage m;
  m.stamp_sec = 1700000000;
  m.stamp_nanosec = 123456789;
  std::memcpy(m.angular_velocity_rad_s, g, sizeof g);
  std::memcpy(m.linear_acceleration_m_s2, a, sizeof a);
  // The hand layout has covariances of -1; compare the parts the encoder writes the same way.
  const std::string enc = EncodeCdrImu(m, "ab", false);
  const std::string hand = HandImu(false, g, a);
  ASSERT_EQ(enc.size(), hand.size());
  EXPECT_EQ(enc.substr(0, 20), hand.substr(0, 20));
  for (int len = 0; len < 12; ++len) {
    for (bool big : {false, true}) {
      const std::string bytes = EncodeCdrImu(m, std::string(len, 'f'), big);
      // Body: 12 bytes of stamp and length, len + 1 string bytes, padding to 8, 37 doubles.
      const std::size_t body = 12 + len + 1;
      EXPECT_EQ(bytes.size(), 4 + (body + 7) / 8 * 8 + 37 * 8) << len;
      ImuMessage back;
      ASSERT_FALSE(DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), &back));
      EXPECT_EQ(back.angular_velocity_rad_s[2], 3.5);
      EXPECT_EQ(back.linear_acceleration_m_s2[1], -9.81);
    }
  }
}

TEST(CdrTest, ShortMessagesAndBadHeadersNameTheByte) {
  const double g[3] = {1, 2, 3}, a[3] = {4, 5, 6};
  const std::string full = HandImu(false, g, a);
  ImuMessage m;
  // Cut inside linear_acceleration: body offset 16 + 8 * (4 + 9 + 3 + 9) = 216, +4 header.
  auto e = DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(full.data()), 4 + 216 + 5, &m);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->offset, 4u + 216u);
  EXPECT_NE(e->what.find("linear_acceleration"), std::string::npos) << e->what;
  std::string bad = full;
  bad[1] = 0x07;  // XCDR2 little-endian: not read
  e = DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(bad.data()), bad.size(), &m);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->offset, 0u);
  bad = full;
  bad[12] = 100;  // frame_id length 100 runs past the message? no: 100 < size; make it huge
  bad[15] = 0x7f;
  e = DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(bad.data()), bad.size(), &m);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->offset, 12u);
  EXPECT_NE(e->what.find("frame_id"), std::string::npos) << e->what;
  e = DecodeCdrImu(reinterpret_cast<const std::uint8_t*>(full.data()), 3, &m);
  ASSERT_TRUE(e);
}

// ROS 1 (wiki msg "Serialization"): seq, secs, nsecs, frame_id (length, no NUL), packed float64s.
TEST(Ros1SerializationTest, ImuAndTemperatureFromHandLaidBytes) {
  std::string s;
  Le(&s, 7, 4);
  Le(&s, 1600000000, 4);
  Le(&s, 5, 4);
  Le(&s, 3, 4);
  s += "imu";  // no padding in ROS 1
  const double values[37] = {0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.5, -0.5, 2.0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                             9.5, -1.5, 0.25, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (double v : values) Le(&s, Bits(v), 8);
  ImuMessage m;
  auto e = DecodeRos1Imu(reinterpret_cast<const std::uint8_t*>(s.data()), s.size(), &m);
  ASSERT_FALSE(e) << e->what;
  EXPECT_EQ(m.StampNs(), 1600000000000000005);
  EXPECT_EQ(m.angular_velocity_rad_s[0], 0.5);
  EXPECT_EQ(m.angular_velocity_rad_s[2], 2.0);
  EXPECT_EQ(m.linear_acceleration_m_s2[0], 9.5);
  EXPECT_EQ(m.linear_acceleration_m_s2[2], 0.25);
  EXPECT_EQ(EncodeRos1Imu(m, "imu").size(), s.size());
  e = DecodeRos1Imu(reinterpret_cast<const std::uint8_t*>(s.data()), s.size() - 1, &m);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->offset, s.size() - 8);
}

}  // namespace
}  // namespace gyrocomp
