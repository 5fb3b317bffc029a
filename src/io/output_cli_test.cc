// End-to-end checks of output safety through the built CLI (docs/reference/cli-contract.md: "no
// partial output file is ever left behind"; "Writing output files"): an output naming an input,
// an empty name, a symbolic link, a FIFO, /dev/null, /dev/full, a second output that cannot be
// written, non-UTF-8 file names in JSON, and SIGINT / SIGTERM during a run.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/io/io.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

std::string WarmingLog(int rows) {
  std::string s = "time_s,rate_dps,temp_c\n";
  for (int i = 0; i < rows; ++i) {
    s += std::to_string(i * 0.01) + "," + std::to_string(((i * 7919) % 101 - 50) * 1e-3) + "," +
         std::to_string(25 + 0.01 * i) + "\n";
  }
  return s;
}

class OutputCliTest : public testing::CliTest {
 protected:
  OutputCliTest() : CliTest("gyrocomp_output_cli_test") {}
  void SetUp() override {
    CliTest::SetUp();
    if (IsSkipped()) return;
    in_ = dir_ + "/in.csv";
    std::ofstream(in_) << WarmingLog(400);
  }
  std::vector<std::string> Temporaries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (n[0] == '.' && n.find(".tmp") != std::string::npos) out.push_back(n);
    }
    return out;
  }
  std::string in_;
};

TEST_F(OutputCliTest, AnOutputNamingAnInputIsRefusedBeforeAnyWork) {
  const std::string original = testing::ReadFile(in_);
  fs::create_symlink("in.csv", dir_ + "/soft.csv");
  fs::create_hard_link(in_, dir_ + "/hard.csv");
  std::string out;
  for (const std::string& args : {"-o '" + in_ + "'", "--json '" + dir_ + "/soft.csv'",
                                  "-o '" + dir_ + "/x.csv' --json '" + dir_ + "/hard.csv'"}) {
    SCOPED_TRACE(args);
    EXPECT_EQ(Run("allan -i '" + in_ + "' " + args, &out), 2) << out;
    EXPECT_NE(out.find("is the same file as input '" + in_ + "'"), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  }
  EXPECT_EQ(testing::ReadFile(in_), original);
  EXPECT_FALSE(fs::exists(dir_ + "/x.csv"));
  EXPECT_TRUE(Temporaries().empty());

  // apply: the model file is an input too.
  const std::string sim = dir_ + "/sim.csv", model = dir_ + "/m.json";
  ASSERT_EQ(Run("simulate --fs 1 -o '" + sim + "'", &out), 0) << out;
  ASSERT_EQ(Run("fit -i '" + sim + "' --model poly --degree 1 -o '" + model + "'", &out), 0) << out;
  const std::string model_text = testing::ReadFile(model);
  EXPECT_EQ(Run("apply -i '" + sim + "' -m '" + model + "' -o '" + model + "'", &out), 2) << out;
  EXPECT_NE(out.find("same file as input"), std::string::npos) << out;
  EXPECT_EQ(testing::ReadFile(model), model_text);
  // export: every one of its several -m files is an input too.
  EXPECT_EQ(Run("export -m '" + model + "' -m '" + model + "' -m '" + model + "' --format px4 --device-id 5 -o '" +
                    model + "'", &out), 2) << out;
  EXPECT_NE(out.find("same file as input"), std::string::npos) << out;
  EXPECT_EQ(testing::ReadFile(model), model_text);
  // validate: its model file is an input, its --json an output.
  EXPECT_EQ(Run("validate -i '" + sim + "' -m '" + model + "' --json '" + model + "'", &out), 2) << out;
  EXPECT_NE(out.find("same file as input"), std::string::npos) << out;
  EXPECT_EQ(testing::ReadFile(model), model_text);
}

TEST_F(OutputCliTest, AnEmptyOutputNameIsRefused) {
  std::string out;
  EXPECT_EQ(Run("allan -i '" + in_ + "' -o ''", &out), 2) << out;
  EXPECT_NE(out.find("file name is empty"), std::string::npos) << out;
  EXPECT_EQ(Run("simulate --duration 10 -o '' ", &out), 2) << out;
}

TEST_F(OutputCliTest, ASymlinkKeepsBeingALinkAndItsTargetIsReplaced) {
  std::ofstream(dir_ + "/target.csv") << "old\n";
  fs::create_symlink("target.csv", dir_ + "/link.csv");
  std::string out;
  ASSERT_EQ(Run("allan -i '" + in_ + "' -o '" + dir_ + "/link.csv'", &out), 0) << out;
  EXPECT_TRUE(fs::is_symlink(dir_ + "/link.csv"));
  const auto table = ReadCsv(dir_ + "/target.csv");
  ASSERT_TRUE(table.ok()) << table.error().message;
  EXPECT_GE(table->Find("adev_dps"), 0);
}

TEST_F(OutputCliTest, FifoAndDevNullAreWrittenThroughNeverReplaced) {
  const std::string fifo = dir_ + "/adev.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] { got = testing::ReadFile(fifo); });
  std::string out;
  EXPECT_EQ(Run("allan -i '" + in_ + "' -o '" + fifo + "' --json /dev/null", &out), 0) << out;
  reader.join();
  EXPECT_EQ(got.rfind("tau_s,", 0), 0u) << got.substr(0, 80);
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_TRUE(Temporaries().empty());
}

TEST_F(OutputCliTest, DevFullIsExitOneNotZero) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  std::string out;
  EXPECT_EQ(Run("allan -i '" + in_ + "' -o /dev/full", &out), 1) << out;
  EXPECT_NE(out.find("No space left on device"), std::string::npos) << out;
  EXPECT_EQ(Run("allan -i '" + in_ + "' --json - > /dev/full", &out), 1) << out;
}

TEST_F(OutputCliTest, ASecondOutputThatCannotBeWrittenMeansNoFirstOutput) {
  std::string out;
  EXPECT_EQ(Run("process -i '" + in_ + "' -o '" + dir_ + "/p.csv' --json '" + dir_ + "/p.json' --report '" +
                    dir_ + "/no/such/folder/r.html'", &out), 2) << out;
  EXPECT_NE(out.find("no/such/folder"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir_ + "/p.csv"));
  EXPECT_FALSE(fs::exists(dir_ + "/p.json"));
  EXPECT_TRUE(Temporaries().empty());
}

TEST_F(OutputCliTest, NonUtf8FileNamesAreEscapedInJson) {
  const std::string odd = dir_ + "/in\xff\xfe.csv";
  fs::copy_file(in_, odd);
  std::string out;
  ASSERT_EQ(Run("allan -i '" + odd + "' --json '" + dir_ + "/o.json'", &out), 0) << out;
  const std::string text = testing::ReadFile(dir_ + "/o.json");
  EXPECT_NE(text.find("in\\\\xff\\\\xfe.csv"), std::string::npos) << text.substr(0, 400);
}

// Starts `args` with input from a FIFO we hold open (so the command is mid-run, blocked reading,
// for as long as the test wants), waits for its temporaries, sends `sig`; returns the exit status.
int InterruptMidRun(const std::string& dir, int sig, std::vector<std::string> args,
                    const std::function<std::vector<std::string>()>& temporaries) {
  const std::string fifo = dir + "/in.fifo";
  if (::mkfifo(fifo.c_str(), 0600) != 0) return -1;
  args.insert(args.begin(), {"process", "-q", "-i", fifo});
  const pid_t pid = testing::StartCli(args);
  if (pid < 0) return -1;
  const int writer = ::open(fifo.c_str(), O_WRONLY);  // the child is reading from here on
  const std::string head = "time_s,rate_dps,temp_c\n0,0.1,25\n";
  (void)!::write(writer, head.data(), head.size());
  for (int i = 0; i < 1000 && temporaries().size() < 3; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const std::size_t live = temporaries().size();
  const int code = testing::SignalAndWait(pid, sig, "process reading a FIFO");
  ::close(writer);
  if (live != 3) return -2;  // the temporaries never appeared: nothing was tested
  return code < 0 ? -3 : code;
}

TEST_F(OutputCliTest, SigintAndSigtermRemoveTemporariesAndExit128PlusSignal) {
  for (int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(sig);
    const int code =
        InterruptMidRun(dir_, sig, {"-o", dir_ + "/p.csv", "--json", dir_ + "/p.json", "--report", dir_ + "/p.html"},
                        [this] { return Temporaries(); });
    EXPECT_EQ(code, 128 + sig);
    EXPECT_TRUE(Temporaries().empty());
    EXPECT_FALSE(fs::exists(dir_ + "/p.csv"));
    fs::remove(dir_ + "/in.fifo");
  }
}

}  // namespace
}  // namespace gyrocomp
