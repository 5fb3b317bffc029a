// End-to-end check of the log-reading contract of cli.md through the built CLI: every malformed
// input gives exit status 2, ONE line on stderr "gyrocomp <cmd>: error: <file>:<line>:<col>: ...",
// and no output file (not even a temporary one). Uses `allan` (the first command to read -i)
// as the carrier; the reading code is shared by every subcommand.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/io/io.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

class IoCliTest : public testing::CliTest {
 protected:
  IoCliTest() : CliTest("gyrocomp_io_cli_test") {}
  std::vector<std::string> OutputsIn() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (n.rfind("out", 0) == 0 || n.rfind(".out", 0) == 0) out.push_back(n);
    }
    return out;
  }
  // Runs `allan` on `input` (with `extra` options) writing out.json and out_adev.csv.
  int Allan(const std::string& input, const std::string& extra, std::string* output) {
    return Run("allan -i '" + input + "' " + extra + " --json '" + dir_ + "/out.json' -o '" + dir_ + "/out_adev.csv'",
               output);
  }
  void ExpectRejected(const std::string& name, const std::string& bytes, const std::string& where,
                      const std::string& what, const std::string& extra = "") {
    SCOPED_TRACE(name);
    const std::string path = Put(name, bytes);
    std::string out;
    EXPECT_EQ(Allan(path, extra, &out), 2) << out;
    const std::string prefix = "gyrocomp allan: error: " + path + ":" + where + ": ";
    EXPECT_EQ(out.rfind(prefix, 0), 0u) << "expected '" << prefix << "...' got: " << out;
    EXPECT_NE(out.find(what), std::string::npos) << "'" << what << "' missing from: " << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << "not one line: " << out;
    EXPECT_TRUE(OutputsIn().empty()) << "output file left behind after an error";
  }
};

std::string GoodLog(int rows) {
  std::string s = "time_s,rate_dps,temp_c\n";
  for (int i = 0; i < rows; ++i) {
    s += std::to_string(i * 0.01) + "," + std::to_string(((i * 7919) % 101 - 50) * 1e-3) + ",25\n";
  }
  return s;
}

TEST_F(IoCliTest, EveryMalformedClassExitsTwoWithFileLineColumnAndNoOutput) {
  const std::string good = GoodLog(200);
  ExpectRejected("empty.csv", "", "1:1", "empty file");
  ExpectRejected("header_only.csv", "time_s,rate_dps,temp_c\n", "2:1", "header only");
  ExpectRejected("non_numeric.csv", "time_s,rate_dps\n0,1\n0.01,1..5\n", "3:2", "non-numeric value '1..5' in column 'rate_dps'");
  ExpectRejected("nan.csv", "time_s,rate_dps\n0,1\n0.01,nan\n", "3:2", "NaN");
  ExpectRejected("inf.csv", "time_s,rate_dps\n0,1\n0.01,-Infinity\n", "3:2", "infinite");
  ExpectRejected("ragged.csv", "time_s,rate_dps,temp_c\n0,1,2\n0.01,1\n", "3:3", "ragged row");
  ExpectRejected("garbage.bin", std::string("\x7f" "ELF\x02\x01\x01\0\0\0\0", 12) + std::string(100, '\x90'), "1:1",
                 "binary garbage");
  ExpectRejected("missing_col.csv", good, "1:1", "missing column 'gx_dps'", "--rate-col gx_dps");
  ExpectRejected("backwards.csv", "time_s,rate_dps\n0,1\n0.02,1\n0.01,1\n0.03,1\n", "4:1", "time goes backwards");
  ExpectRejected("repeat.csv", "time_s,rate_dps\n0,1\n0.01,1\n0.01,1\n0.03,1\n", "4:1", "time repeats");
  ExpectRejected("too_few.csv", "time_s,rate_dps\n0,1\n0.01,2\n", "3:1", "too few samples");
  std::string gap = "time_s,rate_dps\n";
  for (int i = 0; i < 100; ++i) gap += std::to_string(i < 50 ? i * 0.01 : i * 0.01 + 1.0) + ",0.5\n";
  ExpectRejected("gap.csv", gap, "52:1", "irregular timestamps");
  ExpectRejected("fs_mismatch.csv", good, "2:1", "disagrees", "--fs 50");
}

TEST_F(IoCliTest, GoodLogPlainGzipAndStdin) {
  const std::string body = GoodLog(500);
  const std::string plain = Put("log.csv", body);
  std::string out;
  ASSERT_EQ(Allan(plain, "", &out), 0) << out;
  ASSERT_TRUE(fs::exists(dir_ + "/out.json"));
  const auto json = testing::ReadJsonFile(dir_ + "/out.json");
  EXPECT_EQ(json["n_samples"], 500);
  const auto curve = ReadCsv(dir_ + "/out_adev.csv");
  ASSERT_TRUE(curve.ok()) << curve.error().message;  // our own output reads back
  fs::remove(dir_ + "/out.json");

  const std::string gz = PutGz("log.csv.gz", body);
  ASSERT_EQ(Allan(gz, "", &out), 0) << out;
  EXPECT_EQ(testing::ReadJsonFile(dir_ + "/out.json")["n_samples"], 500);

  ASSERT_EQ(testing::RunCommand("cat '" + plain + "' | " + cli_ + " allan -i - --json -", &out), 0) << out;
  EXPECT_NE(out.find("\"n_samples\": 500"), std::string::npos) << out;
  // Errors from stdin name "<stdin>".
  ASSERT_EQ(testing::RunCommand("printf 'time_s,rate_dps\\n0,x\\n' | " + cli_ + " allan -i - --json -", &out), 2);
  EXPECT_EQ(out.rfind("gyrocomp allan: error: <stdin>:2:2: ", 0), 0u) << out;
}

}  // namespace
}  // namespace gyrocomp
