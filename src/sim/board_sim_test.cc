// The simulated board (docs/guides/calibrate-board.md): accelerometers with gravity and their own drift, several IMUs,
// a barometer, written as ULog and DataFlash logs the readers (and the autopilots' scripts) read.
#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

#include "gyrocomp/io/dataflash.h"
#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/ulog.h"
#include "gyrocomp/sim/simulator.h"

namespace gyrocomp {
namespace {

BoardSimOptions SmallBoard() {
  BoardSimOptions o;
  o.chamber.fs_hz = 5.0;
  o.chamber.profile.kind = ThermalProfileKind::kRamp;
  o.chamber.profile.room_hold_s = 300;
  o.chamber.profile.hold_s = 300;
  o.chamber.profile.ramp_end_c = 45;
  return o;
}

double Mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); }

TEST(BoardSim, AccelHasGravityOnZAndItsOwnDrift) {
  auto b = SimulateBoard(SmallBoard());
  ASSERT_TRUE(b.ok()) << b.error().message;
  ASSERT_EQ(b->imus.size(), 3u);
  const BoardImuRun& r = b->imus[1];
  EXPECT_NEAR(Mean(r.accel_m_s2[2]), -9.80665 + Mean(r.true_accel_bias_m_s2[2]), 0.01);
  EXPECT_NEAR(Mean(r.accel_m_s2[0]), Mean(r.true_accel_bias_m_s2[0]), 0.01);
  // Bias follows the polynomial in T: it changes over the 25 -> 45 C ramp.
  const auto& bias = r.true_accel_bias_m_s2[0];
  EXPECT_GT(std::abs(bias.back() - bias.front()), 0.01);
  // The white noise matches the VRW: sigma at fs = VRW / 60 * sqrt(fs).
  AccelAxisOptions a;
  a.bias_poly_m_s2 = {0.0};
  a.bias_instability_m_s2 = 0.0;
  SimulatorOptions soak = SmallBoard().chamber;
  soak.profile.kind = ThermalProfileKind::kSoak;
  soak.profile.soak_duration_s = 2000;
  auto flat = SimulateAccelAxis(soak, a);
  ASSERT_TRUE(flat.ok());
  double ss = 0;
  for (double v : flat->accel_m_s2) ss += v * v;
  EXPECT_NEAR(std::sqrt(ss / flat->accel_m_s2.size()), a.vrw_m_s_per_sqrt_h / 60.0 * std::sqrt(5.0), 0.003);
  AccelAxisOptions bad;
  bad.vrw_m_s_per_sqrt_h = -1;
  EXPECT_FALSE(SimulateAccelAxis(soak, bad).ok());
}

TEST(BoardSim, UlogHoldsEverySensorWithRealisticDeviceIds) {
  auto b = SimulateBoard(SmallBoard());
  ASSERT_TRUE(b.ok());
  auto bytes = EncodeBoardULog(*b, 5.0);
  ASSERT_TRUE(bytes.ok());
  auto log = ParseULog(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size(), "b.ulg");
  ASSERT_TRUE(log.ok()) << log.error().message;
  ASSERT_EQ(log->gyros.size(), 3u);
  ASSERT_EQ(log->accels.size(), 3u);
  ASSERT_EQ(log->baros.size(), 1u);
  // PX4 DeviceStructure: SPI (2), bus 1, address 0, devtype 0x3C (ICM20689).
  EXPECT_EQ(*log->gyros[0].device_id, 0x3C000Au);
  EXPECT_EQ(*log->gyros[2].device_id, Px4DeviceId(2, 4, 0, 0x42));
  EXPECT_EQ(*log->accels[2].device_id, Px4DeviceId(2, 4, 0, 0x41));
  EXPECT_EQ(log->accels[1].z_m_s2[10], static_cast<double>(static_cast<float>(b->imus[1].accel_m_s2[2][10])));
  EXPECT_NEAR(log->baros[0].pressure_pa[0], 101325.0, 200.0);
  EXPECT_EQ(log->parameters.at("TC_A_ENABLE"), 0.0);
}

TEST(BoardSim, DataFlashIsRotatedAndTheReaderUndoesIt) {
  auto b = SimulateBoard(SmallBoard());
  ASSERT_TRUE(b.ok());
  auto bytes = EncodeBoardDataFlash(*b, 5.0, 12);  // PITCH_180
  ASSERT_TRUE(bytes.ok());
  auto log = ParseDataFlash(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size(), "b.bin");
  ASSERT_TRUE(log.ok()) << log.error().message;
  ASSERT_EQ(log->imus.size(), 3u);
  EXPECT_NEAR(log->imus[0].acc_z_m_s2[0], 9.80665, 0.2);  // board frame: z flipped
  std::vector<std::string> notes;
  auto s = DataFlashImuToSensorFrame(*log, log->imus[2], &notes);
  ASSERT_TRUE(s.ok());
  EXPECT_NEAR(s->acc_z_m_s2[7], b->imus[2].accel_m_s2[2][7], 1e-5);
  EXPECT_NEAR(s->gyr_x_rad_s[7], b->imus[2].gyro_rad_s[0][7], 1e-9);
  EXPECT_FALSE(EncodeBoardDataFlash(*b, 5.0, 100).ok());
}

}  // namespace
}  // namespace gyrocomp
