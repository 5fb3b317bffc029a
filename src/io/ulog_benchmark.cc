// ULog reading speed: ParseULog on an in-memory sensor_gyro log (49-byte 'D' messages), and the
// whole path to a FlightLogTable. Timings are for the notes; no test depends on them.
#include <cmath>
#include <string>

#include <benchmark/benchmark.h>

#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/ulog.h"

namespace {

std::string MakeLog(std::size_t rows) {
  gyrocomp::ULogGyroWriteInput in;
  for (std::size_t i = 0; i < rows; ++i) {
    in.timestamp_us.push_back(10000 * (i + 1));
    in.x_rad_s.push_back(static_cast<float>(std::sin(1e-3 * static_cast<double>(i))));
    in.y_rad_s.push_back(0.001f);
    in.z_rad_s.push_back(-0.002f);
    in.temperature_c.push_back(25.0f);
  }
  return *gyrocomp::EncodeULogGyro(in);
}

void BM_ParseULog(benchmark::State& state) {
  const std::string bytes = MakeLog(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    auto r = gyrocomp::ParseULog(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "mem");
    benchmark::DoNotOptimize(r.ok());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(bytes.size()));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_ParseULog)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

void BM_ULogToTable(benchmark::State& state) {
  const std::string bytes = MakeLog(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    auto r = gyrocomp::ParseULog(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "mem");
    auto t = gyrocomp::FlightLogFromULog(*r, std::nullopt);
    benchmark::DoNotOptimize(t.ok());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_ULogToTable)->Arg(1000000)->Unit(benchmark::kMillisecond);

}  // namespace
