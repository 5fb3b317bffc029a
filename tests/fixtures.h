// Test fixtures: FileTest (a fresh folder per test for the files it writes) and CliTest, the
// fixture of the built CLI's end-to-end tests (every *_cli_test.cc: skipped with the reason when
// the CLI is not built), with the ways they run it (through /bin/sh with the output captured, or
// started in the background to be signalled).
#pragma once

#include <sys/types.h>

#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "test_support.h"

namespace gyrocomp::testing {

// Fixture of tests that write files: a fresh folder dir_ (<tmp>/<dir_prefix>_<random>) per test,
// removed after it; Put / PutGz write a file there (plain / gzip) and return its path.
class FileTest : public ::testing::Test {
 protected:
  explicit FileTest(std::string dir_prefix) : dir_prefix_(std::move(dir_prefix)) {}
  void SetUp() override { dir_ = MakeTempDir(dir_prefix_); }
  void TearDown() override;
  std::string Put(const std::string& name, const std::string& bytes) const {
    return WriteFile(dir_ + "/" + name, bytes);
  }
  std::string PutGz(const std::string& name, const std::string& bytes) const {
    return WriteGzFile(dir_ + "/" + name, bytes);
  }

  std::string dir_;

 private:
  std::string dir_prefix_;
};

// Why an end-to-end test cannot run, "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)",
// or "" when CliPath() names a built binary.
std::string CliSkipReason();

// Runs the built CLI with `args` (shell words: the caller quotes paths) through /bin/sh; returns
// its exit status (-1 when it did not exit), its stdout and stderr together in *output.
int RunCli(const std::string& args, std::string* output);

// Expects cli.md's answer to bad input: exit status 2 and ONE line of output that contains each
// of `what`.
void ExpectCliRefused(const std::string& args, const std::vector<std::string>& what);

// Starts the built CLI with `args` (its argv after the program, no shell) in the background;
// returns its pid, or -1 with a test failure when it could not be started.
pid_t StartCli(const std::vector<std::string>& args);

// Sends `sig` to `pid` (a child started by StartCli) and waits for it; returns its exit status,
// or -1 with a test failure when it was killed by a signal. The time from the signal to the exit
// is printed after `what` (printed, never asserted: tests do not assert on time).
int SignalAndWait(pid_t pid, int sig, const std::string& what);

// Fixture of the CLI's end-to-end tests: skips the test (with CliSkipReason) when the CLI is not
// built, else gives it cli_ (the binary) and, as every FileTest, dir_ (a fresh folder removed
// after the test) and Put / PutGz. A derived SetUp calls CliTest::SetUp() first and returns when
// IsSkipped().
class CliTest : public FileTest {
 protected:
  explicit CliTest(std::string dir_prefix) : FileTest(std::move(dir_prefix)) {}
  void SetUp() override;

  int Run(const std::string& args, std::string* output) const { return RunCli(args, output); }
  void ExpectRefused(const std::string& args, const std::vector<std::string>& what) const {
    ExpectCliRefused(args, what);
  }

  std::string cli_;
};

}  // namespace gyrocomp::testing
