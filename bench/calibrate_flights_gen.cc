// Writes N simulated flight logs of one 3-IMU board as PX4 ULogs for bench/calibrate_flights.sh
// (SimulateFlight + EncodeFlightULog, gyrocomp/sim/flight.h): 30 min each at 1 kHz, power-on at
// ambients spread over 0..35 C, 1..10 min still, a flight, the rest still after landing; the
// board's gyro and accelerometer drift as a cubic of temperature, a per-power-on offset.
// Not part of the CMake build (bench/*_benchmark.cc are); the script compiles it against
// build/libgyrocomp.a. Usage: calibrate_flights_gen OUT_DIR [N=20] [MINUTES=30] [RATE_HZ=1000]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "gyrocomp/sim/flight.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR [N=20] [MINUTES=30] [RATE_HZ=1000]\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const int n = argc > 2 ? std::atoi(argv[2]) : 20;
  const double minutes = argc > 3 ? std::atof(argv[3]) : 30.0, rate = argc > 4 ? std::atof(argv[4]) : 1000.0;
  for (int k = 0; k < n; ++k) {
    std::vector<gyrocomp::FlightRun> imus;
    for (int imu = 0; imu < 3; ++imu) {
      gyrocomp::FlightSimOptions o;
      o.fs_hz = rate;
      o.seed = 1000 * static_cast<std::uint64_t>(k) + static_cast<std::uint64_t>(imu) + 1;
      o.ambient_c = 35.0 * k / std::max(1, n - 1);
      o.still_before_s = 60.0 + (std::min(600.0, 0.3 * minutes * 60.0) - 60.0) * ((k * 7) % n) / std::max(1, n - 1);
      o.flight_s = 0.5 * minutes * 60.0;
      o.still_after_s = minutes * 60.0 - o.still_before_s - o.flight_s - o.armed_ground_s - o.landed_armed_s;
      o.gyro_drift_dps = {0.0, 4e-3 * (1.0 + 0.3 * imu), 2e-4, -4e-6};
      o.accel_drift_m_s2 = {0.0, 2e-3, 1e-4 * (1.0 - 0.3 * imu), -2e-6};
      gyrocomp::Result<gyrocomp::FlightRun> run = gyrocomp::SimulateFlight(o);
      if (!run.ok()) {
        std::fprintf(stderr, "%s\n", run.error().message.c_str());
        return 1;
      }
      imus.push_back(std::move(*run));
    }
    gyrocomp::Result<std::string> bytes = gyrocomp::EncodeFlightULog(imus);
    if (!bytes.ok()) {
      std::fprintf(stderr, "%s\n", bytes.error().message.c_str());
      return 1;
    }
    const std::string path = dir + "/flight" + std::to_string(k) + ".ulg";
    std::ofstream(path, std::ios::binary).write(bytes->data(), static_cast<std::streamsize>(bytes->size()));
    std::printf("%s: %.0f MB\n", path.c_str(), static_cast<double>(bytes->size()) / 1e6);
  }
  return 0;
}
