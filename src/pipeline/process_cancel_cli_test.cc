// SIGINT / SIGTERM to `gyrocomp process` on 5 M samples (a long record: 50 000 s
// at 100 Hz) exits 130 / 143 and leaves nothing in the output folder. The time from the signal
// to the exit is printed, not asserted (tests never assert on time; the goal is 0.5 s).
#include <signal.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

class ProcessCancelCliTest : public testing::CliTest {
 protected:
  ProcessCancelCliTest() : CliTest("gyrocomp_process_cancel_test") {}
};

// time_s, rate_dps, temp_c: white noise on a slow drift over a -40..60 C staircase-like swing.
void WriteRecord(const std::string& path, std::size_t n, double fs_hz) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs("time_s,rate_dps,temp_c\n", f);
  std::mt19937 rng(24);
  std::normal_distribution<double> noise(0.0, 0.03);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / fs_hz;
    const double temp = 10.0 + 50.0 * std::sin(2.0 * M_PI * t / 40000.0);
    std::fprintf(f, "%.2f,%.6f,%.3f\n", t, 0.02 + 1.5e-3 * (temp - 25.0) + noise(rng), temp);
  }
  ASSERT_EQ(std::fclose(f), 0);
}

TEST_F(ProcessCancelCliTest, SignalStopsProcessOn5MSamplesAndLeavesNothing) {
  const std::string input = dir_ + "/in.csv";
  WriteRecord(input, 5000000, 100.0);
  const std::string outdir = dir_ + "/out";
  fs::create_directory(outdir);
  // After 6 s the record is read and the VMD runs (it takes ~25 s); the handler removes the
  // outputs' temporaries wherever the work is.
  for (const int sig : {SIGINT, SIGTERM}) {
    const pid_t pid = testing::StartCli({"process", "-i", input, "-o", outdir + "/out.csv", "--json",
                                         outdir + "/out.json", "--report", outdir + "/report.html", "-q"});
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::seconds(6));
    EXPECT_EQ(testing::SignalAndWait(pid, sig, "process, 5 M samples"), 128 + sig);
    for (const auto& entry : fs::directory_iterator(outdir)) ADD_FAILURE() << "left behind: " << entry.path();
  }
}

}  // namespace
}  // namespace gyrocomp
