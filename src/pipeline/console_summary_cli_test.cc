// The default console summary of each command: its shape (line count, what each line names,
// units beside every figure, no colour off a terminal) pinned, and --verbose keeping the detail.
// The guides (docs/guides/) show these summaries; Docs.GuidesRunAsShown checks them there.

#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream s(text);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  return lines;
}

bool Has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// The summary without the warnings printed before it (each is a line "gyrocomp CMD: warning: ...").
std::vector<std::string> SummaryLines(const std::string& text) {
  std::vector<std::string> lines;
  for (const std::string& line : Lines(text))
    if (!Has(line, ": warning: ")) lines.push_back(line);
  return lines;
}

class ConsoleSummaryCli : public testing::CliTest {
 protected:
  ConsoleSummaryCli() : CliTest("gyrocomp_console_summary") {}
  void SetUp() override {
    CliTest::SetUp();
    if (IsSkipped()) return;
    std::string out;
    // A short two-direction chamber run at 2 Hz (about 3 h) and a second seed as the held-out run.
    const std::string sim = "simulate --fs 2 --room-hold 1200 --hold 1200 --step 25 --ramp-rate 2 --thermal-lag 300";
    ASSERT_EQ(Run(sim + " --seed 5 -o " + dir_ + "/run.csv", &out), 0) << out;
    ASSERT_EQ(Run(sim + " --seed 6 -o " + dir_ + "/run2.csv", &out), 0) << out;
  }
};

TEST_F(ConsoleSummaryCli, ProcessPrintsWhatWasReadTheModelAndAllanBeforeAfter) {
  std::string out;
  const std::string fast = " --nests 6 --generations 3 --bandwidth-segment 4096";
  ASSERT_EQ(Run("process -i " + dir_ + "/run.csv -o " + dir_ + "/out.csv" + fast, &out), 0) << out;
  const std::vector<std::string> lines = SummaryLines(out);
  ASSERT_GE(lines.size(), 5u) << out;
  EXPECT_LE(lines.size(), 15u) << out;
  EXPECT_TRUE(Has(lines[0], "gyrocomp process: ") && Has(lines[0], "samples at") && Has(lines[0], " h)")) << out;
  EXPECT_TRUE(Has(out, "modes by VMD")) << out;
  EXPECT_TRUE(Has(out, "drift model: ") && (Has(out, "mdps") || Has(out, "deg/s"))) << out;
  EXPECT_TRUE(Has(out, "ARW ") && Has(out, " -> ") && Has(out, "deg/sqrt(h)") && Has(out, "Hz")) << out;
  EXPECT_TRUE(Has(out, "wrote " + dir_ + "/out.csv")) << out;
  EXPECT_FALSE(Has(out, "\033[")) << "colour off a terminal";
  ASSERT_EQ(Run("process -i " + dir_ + "/run.csv --verbose --json " + dir_ + "/p.json" + fast, &out), 0) << out;
  EXPECT_TRUE(Has(out, "classes:") && Has(out, "auto chose")) << "--verbose keeps every stage's detail:\n" << out;
}

TEST_F(ConsoleSummaryCli, ValidatePrintsTheResidualBesideTheUncompensatedDrift) {
  std::string out;
  ASSERT_EQ(Run("fit -i " + dir_ + "/run.csv --model poly --inputs temp,dtemp -o " + dir_ + "/m.json", &out), 0)
      << out;
  ASSERT_EQ(Run("validate -m " + dir_ + "/m.json -i " + dir_ + "/run2.csv", &out), 0) << out;
  const std::vector<std::string> lines = SummaryLines(out);
  ASSERT_GE(lines.size(), 2u) << out;
  EXPECT_LE(lines.size(), 15u) << out;
  EXPECT_TRUE(Has(lines[0], "rate_dps: residual drift ") && Has(lines[0], " RMS against ") &&
              Has(lines[0], "uncompensated") && Has(lines[0], "error against the true drift"))
      << out;
  EXPECT_TRUE(Has(out, "% band: half-width")) << out;
  ASSERT_EQ(Run("validate -m " + dir_ + "/m.json -i " + dir_ + "/run2.csv --verbose", &out), 0) << out;
  EXPECT_TRUE(Has(out, "slope vs T")) << "--verbose keeps the slopes:\n" << out;
}

// fit: the model, its range and CV error beside the drift span, each candidate term's paired gain
// +- SE, the expected next-run error, the terms left out, the file written; --verbose: every
// candidate's score and what the run identifies.
TEST_F(ConsoleSummaryCli, FitPrintsTheModelEachTermsGainAndTheExpectedError) {
  std::string out;
  ASSERT_EQ(Run("fit -i " + dir_ + "/run.csv -o " + dir_ + "/auto.json", &out), 0) << out;
  const std::vector<std::string> lines = SummaryLines(out);
  ASSERT_GE(lines.size(), 3u) << out;
  EXPECT_LE(lines.size(), 15u) << out;
  EXPECT_TRUE(Has(lines[0], "rate_dps: poly(") && Has(lines[0], "CV error") && Has(lines[0], "drift span")) << out;
  EXPECT_TRUE(Has(out, "  term +dT/dt") && Has(out, " +- ")) << "each candidate term's gain +- SE:\n" << out;
  EXPECT_TRUE(Has(out, "expected drift error on a next run like this one: ")) << out;
  EXPECT_EQ(lines.back(), "model written to " + dir_ + "/auto.json") << out;
  ASSERT_EQ(Run("fit -i " + dir_ + "/run.csv -o " + dir_ + "/auto2.json --verbose", &out), 0) << out;
  EXPECT_TRUE(Has(out, "auto chose") && Has(out, "calibration run: ")) << out;
}

// A 3-IMU board: a header, one line per sensor (3 gyros, 3 accels, a baro) and the files written.
TEST_F(ConsoleSummaryCli, CalibratePrintsAHeaderOneLinePerSensorAndTheFileWritten) {
  std::string out;
  ASSERT_EQ(Run("simulate --profile ramp --imus 3 --fs 100 --log-rate 20 --seed 3 --room-temp -10 --ramp-end 50"
                " --duration 7200 -o " + dir_ + "/board.ulg", &out), 0) << out;
  ASSERT_EQ(Run("calibrate -i " + dir_ + "/board.ulg --format px4 -o " + dir_ + "/tc.params", &out), 0) << out;
  const std::vector<std::string> lines = SummaryLines(out);
  ASSERT_EQ(lines.size(), 1u + 7u + 1u) << out;
  EXPECT_TRUE(Has(lines[0], "gyrocomp calibrate: 1 log (") && Has(lines[0], "7 of 7 sensors calibrated")) << out;
  for (int k = 1; k <= 3; ++k) {
    EXPECT_TRUE(Has(lines[k], "gyro ") && Has(lines[k], "mdps uncompensated -> ") && Has(lines[k], "expected on the next run"))
        << lines[k];
  }
  for (int k = 4; k <= 6; ++k) EXPECT_TRUE(Has(lines[k], "accel ") && Has(lines[k], " mg")) << lines[k];
  EXPECT_TRUE(Has(lines[7], "baro 0") && Has(lines[7], " Pa")) << lines[7];
  EXPECT_EQ(lines[8], "  wrote " + dir_ + "/tc.params");
  ASSERT_EQ(Run("calibrate -i " + dir_ + "/board.ulg --format px4 -o " + dir_ + "/tc2.params --verbose", &out), 0) << out;
  EXPECT_TRUE(Has(out, "static weight") && Has(out, "expected next-run error of the cubic")) << out;
}

// plan: the unit, one row per profile with the expected next-run error (predicted / simulated),
// the recommendation; --verbose keeps the full table.
TEST_F(ConsoleSummaryCli, PlanPrintsOneRowPerProfileAndTheRecommendation) {
  std::string out;
  ASSERT_EQ(Run("plan --profiles ramp,paper --seeds 1 --fs 0.2", &out), 0) << out;
  const std::vector<std::string> lines = SummaryLines(out);
  ASSERT_EQ(lines.size(), 5u) << out;
  EXPECT_TRUE(Has(lines[0], "unit: ARW ") && Has(lines[0], " C")) << out;
  EXPECT_TRUE(Has(lines[2], "  ramp ") && (Has(lines[2], "mdps") || Has(lines[2], "deg/s"))) << out;
  EXPECT_TRUE(Has(lines[3], "  paper ")) << out;
  EXPECT_TRUE(Has(lines[4], "recommended: ") && Has(lines[4], "expected on the next run")) << out;
  ASSERT_EQ(Run("plan --profiles ramp --seeds 1 --fs 0.2 --verbose", &out), 0) << out;
  EXPECT_TRUE(Has(out, "| ramp |") && Has(out, "predicted / simulated")) << out;
}

}  // namespace
}  // namespace gyrocomp
