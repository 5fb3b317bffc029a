// Parse / write throughput of the log reader: 5 million rows x 4 columns, plain and gzip.
//
// Two data sets, written once per run into a temporary directory by WriteCsvAtomic:
//   "logger": values as a data logger writes them (time to 0.01 s, rates to 1e-6 deg/s,
//             temperature to 1e-4 C): ~36 bytes per row;
//   "full":   full-precision doubles (shortest round-trip, 17 significant digits for noise):
//             ~75 bytes per row, the worst case (what gyrocomp itself writes).
// Run: build/io_benchmark --benchmark_filter=Read   (each iteration reads the whole file)
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <string>

#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/io/io.h"

namespace {

namespace fs = std::filesystem;

constexpr std::size_t kRows = 5'000'000;

gyrocomp::Table MakeTable(bool full_precision) {
  std::mt19937_64 rng(12345);
  std::normal_distribution<double> noise(0.0, 0.03);
  gyrocomp::Table t;
  std::vector<double> time_s(kRows), gx(kRows), gy(kRows), temp(kRows);
  for (std::size_t i = 0; i < kRows; ++i) {
    time_s[i] = static_cast<double>(i) / 100.0;
    gx[i] = 0.01 + noise(rng);
    gy[i] = -0.02 + noise(rng);
    temp[i] = 25.0 + 10.0 * std::sin(1e-5 * static_cast<double>(i)) + 0.01 * noise(rng);
    if (!full_precision) {
      gx[i] = std::round(gx[i] * 1e6) / 1e6;
      gy[i] = std::round(gy[i] * 1e6) / 1e6;
      temp[i] = std::round(temp[i] * 1e4) / 1e4;
    }
  }
  t.Add("time_s", std::move(time_s));
  t.Add("gx_dps", std::move(gx));
  t.Add("gy_dps", std::move(gy));
  t.Add("temp_c", std::move(temp));
  return t;
}

// The benchmark's files, created on first use and removed at exit.
class Files {
 public:
  static Files& Get() {
    static Files files;
    return files;
  }
  const std::string& Path(const std::string& kind, bool gz) {
    const std::string key = kind + (gz ? ".csv.gz" : ".csv");
    auto it = paths_.find(key);
    if (it != paths_.end()) return it->second;
    const std::string path = dir_ + "/" + key;
    const gyrocomp::Status s = gyrocomp::WriteCsvAtomic(path, MakeTable(kind == "full"));
    if (!s.ok()) {
      std::fprintf(stderr, "io_benchmark: cannot write %s: %s\n", path.c_str(), s.error().message.c_str());
      std::abort();
    }
    return paths_[key] = path;
  }
  const std::string& dir() const { return dir_; }

 private:
  Files() {
    dir_ = (fs::temp_directory_path() / ("gyrocomp_io_bench_" + std::to_string(std::random_device{}()))).string();
    fs::create_directories(dir_);
  }
  ~Files() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string dir_;
  std::map<std::string, std::string> paths_;
};

void BM_ReadCsv(benchmark::State& state, const std::string& kind, bool gz) {
  const std::string& path = Files::Get().Path(kind, gz);
  const auto bytes = static_cast<std::int64_t>(fs::file_size(path));
  for (auto _ : state) {
    auto t = gyrocomp::ReadCsv(path);
    if (!t.ok()) {
      state.SkipWithError(t.error().message.c_str());
      break;
    }
    benchmark::DoNotOptimize(t->columns.data());
  }
  state.counters["file_MB"] = static_cast<double>(bytes) / 1e6;
  state.counters["rows_per_s"] = benchmark::Counter(static_cast<double>(kRows), benchmark::Counter::kIsIterationInvariantRate);
  state.SetBytesProcessed(state.iterations() * bytes);
}

// ReadCsv + column selection + the sampling check (what every subcommand's -i does).
void BM_ReadGyroLog(benchmark::State& state, const std::string& kind, bool gz) {
  const std::string& path = Files::Get().Path(kind, gz);
  gyrocomp::LogSpec spec;
  spec.rate_cols = {"gx_dps", "gy_dps"};
  for (auto _ : state) {
    auto log = gyrocomp::ReadGyroLog(path, spec);
    if (!log.ok()) {
      state.SkipWithError(log.error().message.c_str());
      break;
    }
    benchmark::DoNotOptimize(log->time_s.data());
  }
  state.counters["rows_per_s"] = benchmark::Counter(static_cast<double>(kRows), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_WriteCsv(benchmark::State& state, const std::string& kind, bool gz) {
  const gyrocomp::Table table = MakeTable(kind == "full");
  const std::string path = Files::Get().dir() + "/write_" + kind + (gz ? ".csv.gz" : ".csv");
  for (auto _ : state) {
    const gyrocomp::Status s = gyrocomp::WriteCsvAtomic(path, table);
    if (!s.ok()) {
      state.SkipWithError(s.error().message.c_str());
      break;
    }
  }
  state.counters["rows_per_s"] = benchmark::Counter(static_cast<double>(kRows), benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK_CAPTURE(BM_ReadCsv, logger_plain_5Mx4, std::string("logger"), false)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_ReadCsv, logger_gzip_5Mx4, std::string("logger"), true)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_ReadCsv, full_plain_5Mx4, std::string("full"), false)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_ReadCsv, full_gzip_5Mx4, std::string("full"), true)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_ReadGyroLog, logger_plain_5Mx4, std::string("logger"), false)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_WriteCsv, logger_plain_5Mx4, std::string("logger"), false)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_WriteCsv, full_plain_5Mx4, std::string("full"), false)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_WriteCsv, logger_gzip_5Mx4, std::string("logger"), true)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
