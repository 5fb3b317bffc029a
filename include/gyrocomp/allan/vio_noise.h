// IMU noise files for two visual-inertial estimators, from the same per-axis figures as Kalibr's
// imu.yaml (gyrocomp/allan/kalibr.h; conventions and citations in docs/guides/imu-noise.md).
//
// OpenVINS (rpng/open_vins, config/*/kalibr_imu_chain.yaml, read by ov_msckf's
// parse_imu / VioManagerOptions): Kalibr's continuous-time keys and units, unchanged
// (ov_msckf/src/state/Propagator.cpp turns them into discrete covariances itself:
// Qc = sigma_w^2 / dt for the white noise, sigma_wb^2 * dt for the bias walk).
// VINS-Fusion (HKUST-Aerial-Robotics/VINS-Fusion, config/*.yaml keys acc_n, gyr_n, acc_w,
// gyr_w): vins_estimator/src/factor/integration_base.h propagates the covariance with
// V * noise * V^T where noise = diag(ACC_N^2, GYR_N^2, ..., ACC_W^2, GYR_W^2) and V multiplies
// them by dt (midPointIntegration: V.block(9, 12) = I * dt for the bias walk), i.e. ACC_N is a
// per-sample standard deviation and ACC_W a per-sample bias increment divided by dt: the
// discrete figures acc_n = N sqrt(fs), acc_w = K sqrt(fs). The file gives those as the keys and
// the continuous N, K in comments (many users paste Kalibr's continuous values, sqrt(fs) times
// smaller; docs/guides/imu-noise.md).
#pragma once

#include <string>
#include <vector>

#include "gyrocomp/allan/kalibr.h"

namespace gyrocomp {

// What the VIO noise files write besides the figures.
struct VioNoiseFileOptions {
  std::string rostopic = "/imu0";  // ROS topic of the IMU messages
  std::string source;  // a comment line: where the figures come from
};

// kalibr_imu_chain.yaml in OpenVINS' layout (imu0: T_i_b identity, the four densities, rostopic,
// time_offset 0, update_rate, model "kalibr", identity Tw / R_IMUtoGYRO / Ta / R_IMUtoACC, zero
// Tg). The largest axis of each sensor; every axis in comments. `gyro` and `accel` non-empty.
std::string OpenVinsImuChainYaml(const std::vector<KalibrAxisNoise>& gyro, const std::vector<KalibrAxisNoise>& accel,
                                 double fs_hz, const VioNoiseFileOptions& options = {});

// The IMU noise lines of a VINS-Fusion config: acc_n, gyr_n, acc_w, gyr_w (discrete, see above)
// and g_norm (9.81007, VINS-Fusion's EuRoC value, to be set for the site). `gyro` and `accel`
// non-empty.
std::string VinsFusionImuYaml(const std::vector<KalibrAxisNoise>& gyro, const std::vector<KalibrAxisNoise>& accel,
                              double fs_hz, const VioNoiseFileOptions& options = {});

}  // namespace gyrocomp
