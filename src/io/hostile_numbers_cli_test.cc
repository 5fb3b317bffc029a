// docs/reference/cli-contract.md "Numbers and options that can only fail" through the built CLI:
// option values that can only fail are refused before any work (exit 2, one line naming the option
// and its valid range), outputs that collide are refused before any work, an unknown subcommand is
// an error even with --help, a model file is read with a size limit and every number in it is
// bounded, a constant rate has ARW 0 and a figure that cannot be computed is null with a reason,
// and a link to /dev/stdout is written through.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

class HostileNumbersCliTest : public testing::CliTest {
 protected:
  HostileNumbersCliTest() : CliTest("gyrocomp_hostile_numbers_test") {}
  // A 2000-row log at 100 Hz: rate = `rate(i)`, temperature ramp.
  template <typename F>
  std::string Log(const std::string& name, F rate) {
    const std::string path = dir_ + "/" + name;
    std::ofstream out(path);
    out << "time_s,rate_dps,temp_c\n";
    for (int i = 0; i < 2000; ++i) {
      char line[128];
      std::snprintf(line, sizeof line, "%.2f,%.17g,%.3f\n", i * 0.01, rate(i), 20.0 + 0.01 * i);
      out << line;
    }
    return path;
  }
  std::string NoisyLog() {
    return Log("noisy.csv", [](int i) { return (((i * 7919) % 101) - 50) / 50.0; });
  }
  // Only `keep` is left in the folder (no output, no temporary).
  void ExpectOnly(const std::set<std::string>& keep) {
    for (const auto& entry : fs::directory_iterator(dir_)) {
      EXPECT_TRUE(keep.count(entry.path().filename().string())) << "left behind: " << entry.path();
    }
  }
};

// Before: `fit --model svr --gamma 1e300` (also --epsilon, --C) exited 0 with a model that
// `apply` refused; `decompose --tau 1e300` ran VMD to NaN.
TEST_F(HostileNumbersCliTest, SvrAndVmdParametersOutsideTheirRangeAreRefusedBeforeWork) {
  const std::string log = NoisyLog();
  const std::string o = " -o '" + dir_ + "/m.json'";
  ExpectRefused("fit -i '" + log + "' --model svr --gamma 1e300" + o, {"--gamma", "(0, 1e+06]"});
  ExpectRefused("fit -i '" + log + "' --model svr --epsilon 1e300" + o, {"--epsilon", "[0, 1e+06]"});
  ExpectRefused("fit -i '" + log + "' --model svr --C 1e300" + o, {"--C", "(0, 1e+06]"});
  ExpectRefused("fit -i '" + log + "' --model svr --sigma 1e-9" + o, {"--sigma", "[0.001, 1000]"});
  ExpectRefused("fit -i '" + log + "' --model cs-svr --C-max 1e9" + o, {"--C-max", "(0, 1e+06]"});
  ExpectRefused("decompose -i '" + log + "' --tau 1e300 -o '" + dir_ + "/d.csv'", {"--tau", "[0, 2]"});
  ExpectRefused("process -i '" + log + "' --tau 5 -o '" + dir_ + "/p.csv'", {"--tau", "[0, 2]"});
  ExpectOnly({"noisy.csv"});
}

TEST_F(HostileNumbersCliTest, ModelFilesAreReadWithASizeLimitAndBoundedSupportVectors) {
  const std::string sim = dir_ + "/sim.csv", model = dir_ + "/m.json";
  std::string out;
  ASSERT_EQ(Run("simulate --fs 1 --duration 7200 -o '" + sim + "'", &out), 0) << out;
  const std::string apply = "apply -i '" + sim + "' -o '" + dir_ + "/a.csv' -m ";
  // /dev/zero was read until std::bad_alloc (exit 1) or the OOM killer.
  ExpectRefused(apply + "/dev/zero", {"/dev/zero: byte 0 is 0x00: not a JSON model file"});
  // A file past the limit (sparse: '{' then zeros).
  const std::string huge = dir_ + "/huge.json";
  std::ofstream(huge) << "{";
  fs::resize_file(huge, (std::size_t{64} << 20) + 2);
  ExpectRefused(apply + "'" + huge + "'", {"larger than 64 MiB: not a model file"});
  fs::remove(huge);
  // Support vectors beyond 1e100 (the documented rule for every model number) were accepted.
  ASSERT_EQ(Run("fit -i '" + sim + "' --model svr -o '" + model + "'", &out), 0) << out;
  nlohmann::json j = testing::ReadJsonFile(model);
  nlohmann::json* svs = nullptr;
  for (auto& [key, value] : j["axes"][0].items()) {
    if (value.is_object() && value.contains("support_vectors")) svs = &value["support_vectors"];
  }
  ASSERT_NE(svs, nullptr) << j.dump();
  ASSERT_FALSE(svs->empty());
  (*svs)[0][0] = 1e300;
  std::ofstream(dir_ + "/sv.json") << j.dump(1);
  ExpectRefused(apply + "'" + dir_ + "/sv.json'", {"support_vectors' = ... 1e+300 ...: must hold numbers of magnitude <= 1e100"});
  EXPECT_FALSE(fs::exists(dir_ + "/a.csv"));
}

// `allan -o same --json same` and `--json - -o -` ran, then said "written twice" (exit 1).
TEST_F(HostileNumbersCliTest, CollidingOutputsAreRefusedBeforeWork) {
  const std::string log = NoisyLog();
  const std::string same = "'" + dir_ + "/same'";
  const std::string in = " -i '" + log + "' ";
  const std::vector<std::string> cases = {
      "allan" + in + "-o " + same + " --json " + same,
      "allan" + in + "--json - -o -",
      "allan" + in + "--json /dev/stdout -o -",
      "decompose" + in + "-o " + same + " --json " + same,
      "denoise --method wavelet" + in + "-o " + same + " --json " + same,
      "process --model poly" + in + "-o " + same + " --json " + same,
      "fit --model poly" + in + "-o " + same + " --json " + same,
  };
  for (const std::string& c : cases) ExpectRefused(c, {"are the same destination"});
  // Two names of one new file (a link to it): the same destination too.
  ASSERT_EQ(::symlink((dir_ + "/new.csv").c_str(), (dir_ + "/alias.csv").c_str()), 0);
  ExpectRefused("allan" + in + "-o '" + dir_ + "/new.csv' --json '" + dir_ + "/alias.csv'", {"are the same"});
  fs::remove(dir_ + "/alias.csv");
  ExpectOnly({"noisy.csv"});
  // /dev/null takes any number of outputs.
  std::string out;
  EXPECT_EQ(Run("allan" + in + "-o /dev/null --json /dev/null", &out), 0) << out;
}

// `gyrocomp nosuch --help` printed the top-level help and exited 0.
TEST_F(HostileNumbersCliTest, UnknownSubcommandIsAnErrorEvenWithHelp) {
  for (const char* args : {"nosuch --help", "nosuch", "nosuch -h"}) {
    ExpectRefused(args, {"unknown subcommand 'nosuch'"});
  }
  std::string out;
  EXPECT_EQ(Run("allan --help", &out), 0) << out;
  EXPECT_EQ(Run("--help", &out), 0) << out;
}

// A constant rate gave ARW -nan on the console and null without a reason in the JSON.
TEST_F(HostileNumbersCliTest, ConstantRateHasZeroNoiseAndNullsHaveReasons) {
  const std::string log = Log("const.csv", [](int) { return 0.1; });
  std::string out;
  ASSERT_EQ(Run("allan -i '" + log + "' --json '" + dir_ + "/c.json'", &out), 0) << out;
  EXPECT_EQ(out.find("nan"), std::string::npos) << out;
  EXPECT_NE(out.find("ARW 0 deg/sqrt(h)"), std::string::npos) << out;
  const nlohmann::json j = testing::ReadJsonFile(dir_ + "/c.json");
  EXPECT_EQ(j["arw_deg_per_sqrt_h"], 0.0);
  EXPECT_EQ(j["arw_fit_deg_per_sqrt_h"], 0.0);
  EXPECT_EQ(j["rrw_deg_per_h_per_sqrt_h"], 0.0);
  // The noisy log: every null figure has its reason beside it.
  ASSERT_EQ(Run("allan -i '" + NoisyLog() + "' --json '" + dir_ + "/n.json'", &out), 0) << out;
  for (const char* file : {"/c.json", "/n.json"}) {
    const nlohmann::json k = testing::ReadJsonFile(dir_ + file);
    for (const auto& [key, value] : k.items()) {
      const bool null_figure = value.is_null() || (value.is_array() && !value.empty() && value[0].is_null());
      if (null_figure) {
        EXPECT_TRUE(k.contains(key + "_reason")) << file << ": " << key << " is null without a reason";
      }
    }
  }
}

// `--json link`, link -> /dev/stdout, stdout a pipe: "folder '/proc/self/fd/' does not exist".
TEST_F(HostileNumbersCliTest, LinkToStdoutIsWrittenThrough) {
  const std::string link = dir_ + "/link";
  ASSERT_EQ(::symlink("/dev/stdout", link.c_str()), 0);
  std::string out;
  // RunCommand's stdout is a pipe.
  ASSERT_EQ(Run("allan -i '" + NoisyLog() + "' --json '" + link + "'", &out), 0) << out;
  EXPECT_NE(out.find("\"adev_dps\""), std::string::npos) << out;
  EXPECT_TRUE(fs::is_symlink(link));
  // ... and is the same destination as "-".
  ExpectRefused("allan -i '" + dir_ + "/noisy.csv' --json '" + link + "' -o -", {"are the same destination"});
}

// SIGINT / SIGTERM during a long `fit --model cs-svr`: exit 130 / 143, nothing left in the output
// folder. The time from the signal to the exit is printed, not asserted (tests never assert on
// time; the issue's goal is 0.5 s).
TEST_F(HostileNumbersCliTest, SignalStopsALongFitAndLeavesNothing) {
  const std::string sim = dir_ + "/sim.csv";
  std::string out;
  ASSERT_EQ(Run("simulate --fs 5 --duration 50000 -o '" + sim + "'", &out), 0) << out;
  const std::string outdir = dir_ + "/out";
  fs::create_directory(outdir);
  for (const int sig : {SIGINT, SIGTERM}) {
    const std::string model = outdir + "/m.json", json = outdir + "/fit.json";
    const pid_t pid = testing::StartCli(
        {"fit", "-i", sim, "--model", "cs-svr", "--nests", "25", "--generations", "50", "-o", model, "--json", json});
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // into the search
    EXPECT_EQ(testing::SignalAndWait(pid, sig, "fit --model cs-svr"), 128 + sig);
    for (const auto& entry : fs::directory_iterator(outdir)) ADD_FAILURE() << "left behind: " << entry.path();
  }
}

// `demo --fs 1e-5 --out new` was refused after creating `new`, which stayed, empty.
TEST_F(HostileNumbersCliTest, RefusedDemoLeavesNoFolderItCreated) {
  std::string out;
  EXPECT_EQ(Run("demo --fs 1e-5 --out '" + dir_ + "/new'", &out), 2) << out;
  EXPECT_FALSE(fs::exists(dir_ + "/new"));
  fs::create_directory(dir_ + "/old");
  EXPECT_EQ(Run("demo --fs 1e-5 --out '" + dir_ + "/old'", &out), 2) << out;
  EXPECT_TRUE(fs::is_directory(dir_ + "/old"));
}

// A signal mid-run removes the --out folder `demo` created (found by the soak: it stayed, empty):
// the signal handler's RemoveLiveTemporaryFiles removes listed folders once their temporaries are
// gone. `demo --fs 50` runs for seconds; the signal is sent once the folder exists.
TEST_F(HostileNumbersCliTest, SignalMidDemoLeavesNoFolderItCreated) {
  std::string outdir = dir_ + "/demo-new";
  const pid_t pid = testing::StartCli({"demo", "--fs", "50", "--quiet", "--out", outdir});
  ASSERT_GT(pid, 0);
  for (int i = 0; i < 1000 && !fs::exists(outdir); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(fs::exists(outdir)) << "demo did not create its folder within 10 s";
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // into the work
  ASSERT_EQ(testing::SignalAndWait(pid, SIGINT, "demo"), 130) << "demo finished before the signal: make it longer";
  EXPECT_FALSE(fs::exists(outdir));
}

// ---- every numeric option of every subcommand ----------------------------------------------

struct NumericOption {
  std::string command, name, type;
};

// The FLOAT / INT / UINT options of each subcommand, read from its --help (so a new option is
// covered without editing this test).
std::vector<NumericOption> NumericOptions(const std::string& cli) {
  std::string top;
  testing::RunCommand(cli + " --help", &top);
  std::vector<std::string> commands;
  std::istringstream lines(top.substr(top.find("Subcommands:")));
  std::string line;
  std::getline(lines, line);
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string word;
    if (words >> word) commands.push_back(word);
  }
  std::vector<NumericOption> out;
  const std::regex option(R"(^\s+(?:-\w,)?(--[\w-]+) ((?:FLOAT|INT|UINT)\S*))");
  for (const std::string& c : commands) {
    std::string help;
    testing::RunCommand(cli + " " + c + " --help", &help);
    std::istringstream in(help);
    while (std::getline(in, line)) {
      std::smatch m;
      if (std::regex_search(line, m, option)) out.push_back({c, m[1], m[2]});
    }
  }
  return out;
}

TEST_F(HostileNumbersCliTest, EveryNumericOptionRefusesNonFiniteAndHugeValuesBeforeWork) {
  const std::vector<NumericOption> options = NumericOptions(cli_);
  ASSERT_GT(options.size(), 150u) << "the --help parser found too few options";
  int cases = 0;
  for (const NumericOption& o : options) {
    // Seeds are integers in [0, 2^64 - 1] (hostile_input_cli_test.cc).
    const bool seed = o.name.size() >= 4 && o.name.compare(o.name.size() - 4, 4, "seed") == 0;
    std::vector<std::string> bad = {"nan", "inf", "-inf", "1e300", "-1e300", "NaN"};
    if (seed) bad = {"nan", "1e300", "-1"};
    // Under the sanitizers: one non-finite and one huge value per option (the parse path each
    // class takes); the Release suite runs every value.
    if (testing::Sanitized()) bad = {"nan", "1e300"};
    for (const std::string& v : bad) {
      // No input at all: a refusal must come from the option, before any file is looked at.
      SCOPED_TRACE(o.command + " " + o.name + " " + v + " (" + o.type + ")");
      std::string out;
      EXPECT_EQ(Run(o.command + " " + o.name + " " + v + " -o '" + dir_ + "/x' -i '" + dir_ + "/none.csv'", &out), 2)
          << out;
      EXPECT_NE(out.find(o.name), std::string::npos) << out;
      EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
      EXPECT_EQ(out.find("none.csv"), std::string::npos) << "the input was looked at first: " << out;
      ++cases;
    }
  }
  std::printf("numeric option cases: %d (%zu options)\n", cases, options.size());
  ExpectOnly({});
}

TEST_F(HostileNumbersCliTest, RangedOptionsNameTheirRange) {
  struct Case {
    const char* option;
    const char* value;
    const char* range;
  };
  const Case cases[] = {
      {"--C", "0", "(0, 1e+06]"},          {"--C", "-1", "(0, 1e+06]"},         {"--gamma", "0", "(0, 1e+06]"},
      {"--gamma", "1e7", "(0, 1e+06]"},    {"--sigma", "0", "[0.001, 1000]"},  {"--epsilon", "-1", "[0, 1e+06]"},
      {"--svr-tol", "0", "(0, 1]"},        {"--svr-tol", "2", "(0, 1]"},        {"--tau", "-0.5", "[0, 2]"},
      {"--tau", "2.5", "[0, 2]"},          {"--alpha", "0", "(0, 1e+15]"},      {"--alpha", "-5", "(0, 1e+15]"},
      {"--tol", "0", "(0, 1e+15]"},        {"--modes", "0", "[1, 1000]"},       {"--modes", "1e6", "[1, 1000]"},
      {"--max-iter", "1", "[2, 1e+09]"},   {"--m", "0", "[1, 10]"},             {"--m", "11", "[1, 10]"},
      {"--r", "0", "(0, 1e+15]"},          {"--flp-order", "0", "[1, 4096]"},   {"--flp-beta", "2", "(0, 2)"},
      {"--flp-beta", "0", "(0, 2)"},       {"--flp-alpha", "0", "(0, 1e+15]"},  {"--pa", "1.5", "[0, 1]"},
      {"--pa", "-0.1", "[0, 1]"},          {"--nests", "1", "[2, 1e+06]"},      {"--generations", "-1", "[0, 1e+06]"},
      {"--fs", "0", "[1e-06, 1e+09]"},     {"--fs", "-1", "[1e-06, 1e+09]"},    {"--fs", "1e10", "[1e-06, 1e+09]"},
      {"--max-memory", "0", "(0, 1e+15]"}, {"--resample", "0", "[1e-06, 1e+09]"},
  };
  for (const char* command : {"process", "compare"}) {
    for (const Case& c : cases) {
      if (std::string(c.option) == "--max-memory" || std::string(c.option) == "--resample" ||
          std::string(c.option) == "--flp-forgetting") {
        continue;
      }
      ExpectRefused(std::string(command) + " " + c.option + " " + c.value + " -i '" + dir_ + "/none.csv' -o '" + dir_ +
                        "/x'",
                    {c.option, c.range});
    }
  }
  ExpectRefused("allan --max-memory 0 -i '" + dir_ + "/none.csv' --json -", {"--max-memory", "(0, 1e+15]"});
  ExpectRefused("allan --resample 0 -i '" + dir_ + "/none.csv' --json -", {"--resample", "[1e-06, 1e+09]"});
  ExpectRefused("denoise --flp-forgetting 1 -i '" + dir_ + "/none.csv' -o -", {"--flp-forgetting", "[0, 1)"});
  ExpectRefused("fit --C-min 0 -i '" + dir_ + "/none.csv' -o -", {"--C-min", "(0, 1e+06]"});
  ExpectRefused("fit --sigma-max 1e4 -i '" + dir_ + "/none.csv' -o -", {"--sigma-max", "[0.001, 1000]"});
  ExpectOnly({});
}

// `denoise --bandwidth-segment 0` and `--bandwidth-frequencies 0` ran (an all-zero background)
// and exited 0. Integer counts are refused at parse time (the input is not looked at), exit 2,
// one line naming the option and its range.
TEST_F(HostileNumbersCliTest, IntegerCountsOutsideTheirRangeAreRefusedAtParseTime) {
  struct Case {
    const char* command;
    const char* option;
    const char* range;
  };
  const Case cases[] = {
      {"denoise --method wavelet --bandwidth", "--bandwidth-segment", "[256, 1e+09]"},
      {"denoise --method flp --bandwidth", "--bandwidth-frequencies", "[2, 10000]"},
      {"process", "--bandwidth-segment", "[1024, 1e+09]"},
      {"compare", "--bandwidth-segment", "[1024, 1e+09]"},
      {"process", "--entropy-max-samples", "[100, 1e+12]"},
      {"process", "--degree", "[1, 5]"},
      {"process", "--cv-folds", "[2, 1e+06]"},
      {"process", "--level", "[0, 64]"},
  };
  int count = 0;
  for (const Case& c : cases) {
    for (const char* value : {"0", "-1", "1e300", "nan", "2.5", "99999999999999999999"}) {
      if (std::string(c.option) == "--level" && std::string(value) == "0") continue;  // level 0: no DWT, valid
      const std::string args = std::string(c.command) + " " + c.option + " " + value + " -i '" + dir_ +
                               "/none.csv' -o '" + dir_ + "/x.csv'";
      ExpectRefused(args, {std::string(c.option) + ": " + value + ": must be an integer in " + c.range});
      std::string out;
      Run(args, &out);
      EXPECT_EQ(out.find("none.csv"), std::string::npos) << "the input was looked at first: " << out;
      ++count;
    }
  }
  std::printf("integer count cases: %d\n", count);
  // In range: accepted by the parser (the run then stops at the missing input).
  std::string out;
  EXPECT_EQ(Run("denoise --method wavelet --bandwidth --bandwidth-segment 256 --bandwidth-frequencies 2 -i '" + dir_ +
                    "/none.csv' -o '" + dir_ + "/x.csv'",
                &out),
            2);
  EXPECT_NE(out.find("none.csv"), std::string::npos) << out;
  ExpectOnly({});
}

}  // namespace
}  // namespace gyrocomp
