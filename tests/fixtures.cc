#include "fixtures.h"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "test_support.h"

extern char** environ;

namespace gyrocomp::testing {

std::string CliSkipReason() {
  const std::string cli = CliPath();
  if (cli.empty() || !std::filesystem::exists(cli)) return "the gyrocomp CLI is not built (GYROCOMP_BUILD_CLI=OFF)";
  return "";
}

int RunCli(const std::string& args, std::string* output) { return RunCommand(CliPath() + " " + args, output); }

void ExpectCliRefused(const std::string& args, const std::vector<std::string>& what) {
  SCOPED_TRACE(args);
  std::string out;
  EXPECT_EQ(RunCli(args, &out), 2) << out;
  for (const std::string& w : what) EXPECT_NE(out.find(w), std::string::npos) << "'" << w << "' missing from: " << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << "not one line: " << out;
}

pid_t StartCli(const std::vector<std::string>& args) {
  std::vector<std::string> words = {CliPath()};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int error = posix_spawn(&pid, words[0].c_str(), nullptr, nullptr, argv.data(), environ);
  if (error != 0) {
    ADD_FAILURE() << "cannot start " << words[0] << ": error " << error;
    return -1;
  }
  return pid;
}

int SignalAndWait(pid_t pid, int sig, const std::string& what) {
  const auto sent = std::chrono::steady_clock::now();
  if (::kill(pid, sig) != 0) {
    ADD_FAILURE() << "cannot signal " << pid;
    return -1;
  }
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) {
    ADD_FAILURE() << "cannot wait for " << pid;
    return -1;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  std::printf("%s, signal %d: exited %.3f s after it\n", what.c_str(), sig, seconds);
  if (!WIFEXITED(status)) {
    ADD_FAILURE() << "killed by signal " << WTERMSIG(status);
    return -1;
  }
  return WEXITSTATUS(status);
}

void FileTest::TearDown() {
  if (!dir_.empty()) std::filesystem::remove_all(dir_);
}

void CliTest::SetUp() {
  if (const std::string why = CliSkipReason(); !why.empty()) GTEST_SKIP() << why;
  cli_ = CliPath();
  FileTest::SetUp();
}

}  // namespace gyrocomp::testing
