// Helpers for tests: where the golden vectors and the (licensed, optional) real recordings are,
// and small readers for them that do not depend on gyrocomp's own CSV reader.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gyrocomp/core/cancel.h"

namespace gyrocomp::testing {

// tests/golden/<relative> (copied from ../shared/golden; see tests/golden/README.md).
std::string GoldenPath(const std::string& relative);

// ../shared/realdata/<relative>, or "" when that folder is absent (a user's fresh clone): tests
// that need it call GTEST_SKIP() with the reason then.
std::string RealdataPath(const std::string& relative);

// n samples of white Gaussian noise of standard deviation sigma (NormalGenerator, seeded).
std::vector<double> WhiteNoise(std::size_t n, double sigma, std::uint64_t seed);

// Path of the built gyrocomp CLI (for end-to-end tests), or "" when the CLI is not built.
std::string CliPath();

// tests/fieldlogs (small public logs kept in the tree; see its README.md).
std::string FieldlogsDir();

// ../shared/fieldlogs (licensed logs made by others; absent in a user's clone).
std::string SharedFieldlogsDir();

// FieldlogsDir()/name.
std::string FieldlogPath(const std::string& name);

// Debian's python3 (its numpy, rosbag, sqlite3), whatever python3 comes first on PATH.
inline constexpr char kPython3[] = "/usr/bin/python3";

// tests/bags: rosbag2's own test bags (tests/bags/README.md) and make_imu_bags.py.
std::string BagsDir();

nlohmann::json ReadJsonFile(const std::string& path);

// Reads a plain numeric CSV with a header into name -> column. Aborts the test on error.
std::map<std::string, std::vector<double>> ReadGoldenCsv(const std::string& path);

// A fresh empty directory under the system temp dir for a test's files: <tmp>/<prefix>_<random>.
// It is removed with everything in it when the test process exits (ctest runs each test in a
// process of its own, so: when the test ends), whether the test removes it or not (before,
// hundreds of /tmp/allan_cli_*, /tmp/c_export_test_* were left behind).
std::string MakeTempDir(const std::string& prefix);

// The same, scoped: the directory is removed when the object goes out of scope (a test's body,
// a fixture's member).
class TempDir {
 public:
  explicit TempDir(const std::string& prefix) : path_(MakeTempDir(prefix)) {}
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// Writes `bytes` to `path` (plain, or gzip-compressed by zlib) and returns the path; a failed
// write fails the test.
std::string WriteFile(const std::string& path, const std::string& bytes);
std::string WriteGzFile(const std::string& path, const std::string& bytes);

// The bytes of the file at `path`, "" when it cannot be read.
std::string ReadFile(const std::string& path);

// ReadFile, failing the test (not aborting it) when the file cannot be opened.
std::string ReadExistingFile(const std::string& path);

// Runs `call` while another thread cancels `token` 50 ms in; true when `call` threw Cancelled
// (anything else propagates). The time from the cancel to the end of `call` is printed after
// `what` (printed, never asserted: tests do not assert on time).
bool CancelledWhileRunning(CancellationToken& token, const std::function<void()>& call, const std::string& what);

// Runs `command` with /bin/sh, returns its exit status; stdout+stderr captured into *output.
int RunCommand(const std::string& command, std::string* output);

// True in the sanitizer suite (scripts/test.sh --sanitize sets GYROCOMP_SANITIZED=1), where a CLI
// run costs ~20x a Release one: a test that runs the CLI hundreds of times runs a stated subset
// there and all of it in the Release suite.
bool Sanitized();

}  // namespace gyrocomp::testing
