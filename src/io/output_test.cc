// Tests of the output transaction (include/gyrocomp/io/output.h): each class of destination, the
// input-identity check across symbolic and hard links, the all-or-nothing commit, write errors,
// the non-finite guard and the signal-handler table.
#include "gyrocomp/io/output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

class OutputSetTest : public testing::FileTest {
 protected:
  OutputSetTest() : FileTest("gyrocomp_output_test") {}
  std::string P(const std::string& name) const { return dir_ + "/" + name; }
  // Names in the folder (temporaries included: they start with '.').
  std::vector<std::string> Names() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }
};

TEST_F(OutputSetTest, RefusesAnOutputThatIsAnInputBySameNameSymlinkOrHardLink) {
  Put("in.csv", "a\n1\n");
  fs::create_symlink("in.csv", P("soft.csv"));
  fs::create_hard_link(P("in.csv"), P("hard.csv"));
  for (const std::string& out_name : {P("in.csv"), dir_ + "/./in.csv", P("soft.csv"), P("hard.csv")}) {
    SCOPED_TRACE(out_name);
    OutputSet out;
    out.AddInput(P("in.csv"));
    const Status s = out.Declare(out_name);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().kind, ErrorKind::kInvalidArgument);
    EXPECT_NE(s.error().message.find(out_name), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find(P("in.csv")), std::string::npos) << s.error().message;
  }
  // The input reached through a link is protected too.
  OutputSet out;
  out.AddInput(P("soft.csv"));
  EXPECT_FALSE(out.Declare(P("in.csv")).ok());
  EXPECT_EQ(testing::ReadFile(P("in.csv")), "a\n1\n");
  EXPECT_EQ(Names(), (std::vector<std::string>{"hard.csv", "in.csv", "soft.csv"}));
}

TEST_F(OutputSetTest, RefusesEmptyNamesFoldersAndTwoOutputsOnOneFile) {
  OutputSet out;
  EXPECT_EQ(out.Declare("").error().kind, ErrorKind::kInvalidArgument);
  EXPECT_EQ(out.Declare(dir_).error().kind, ErrorKind::kInvalidArgument);
  ASSERT_TRUE(out.Declare(P("a.csv")).ok());
  fs::create_symlink("a.csv", P("b.csv"));
  const Status twice = out.Declare(P("b.csv"));
  ASSERT_FALSE(twice.ok());
  EXPECT_NE(twice.error().message.find("same file"), std::string::npos) << twice.error().message;
}

TEST_F(OutputSetTest, ReplacesASymlinksTargetAndKeepsTheLink) {
  Put("target.csv", "old\n");
  fs::create_symlink("target.csv", P("link.csv"));
  fs::permissions(P("target.csv"), fs::perms(0640));
  OutputSet out;
  ASSERT_TRUE(out.Declare(P("link.csv")).ok());
  ASSERT_TRUE(out.StageText(P("link.csv"), "new\n").ok());
  ASSERT_TRUE(out.Commit().ok());
  EXPECT_TRUE(fs::is_symlink(P("link.csv")));
  EXPECT_EQ(fs::read_symlink(P("link.csv")), "target.csv");
  EXPECT_EQ(testing::ReadFile(P("target.csv")), "new\n");
  EXPECT_EQ(fs::status(P("target.csv")).permissions() & fs::perms::all, fs::perms(0640));  // mode kept
  // A dangling link: its target is created.
  fs::create_symlink("later.csv", P("dangling.csv"));
  ASSERT_TRUE(WriteTextAtomic(P("dangling.csv"), "x\n").ok());
  EXPECT_TRUE(fs::is_symlink(P("dangling.csv")));
  EXPECT_EQ(testing::ReadFile(P("later.csv")), "x\n");
}

TEST_F(OutputSetTest, WritesThroughAFifoAndDevNullWithoutReplacingThem) {
  ASSERT_EQ(::mkfifo(P("fifo").c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] { got = testing::ReadFile(P("fifo")); });  // opening blocks until the writer comes
  OutputSet out;
  ASSERT_TRUE(out.Declare(P("fifo")).ok());
  ASSERT_TRUE(out.Declare("/dev/null").ok());
  ASSERT_TRUE(out.StageText(P("fifo"), "through\n").ok());
  ASSERT_TRUE(out.StageText("/dev/null", "gone\n").ok());
  ASSERT_TRUE(out.Commit().ok());
  reader.join();
  EXPECT_EQ(got, "through\n");
  EXPECT_TRUE(fs::is_fifo(P("fifo")));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_EQ(Names(), std::vector<std::string>{"fifo"});
}

TEST_F(OutputSetTest, DevFullIsAWriteErrorNotASuccess) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  OutputSet out;
  ASSERT_TRUE(out.Declare("/dev/full").ok());
  ASSERT_TRUE(out.StageText("/dev/full", std::string(1 << 16, 'x')).ok());
  const Status s = out.Commit();
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().kind, ErrorKind::kIo);
  EXPECT_NE(s.error().message.find("/dev/full"), std::string::npos) << s.error().message;
}

TEST_F(OutputSetTest, NothingAppearsUntilCommitAndAnUncommittedSetLeavesNothing) {
  Put("keep.csv", "old\n");
  {
    OutputSet out;
    ASSERT_TRUE(out.Declare(P("keep.csv")).ok());
    ASSERT_TRUE(out.Declare(P("new.csv")).ok());
    // The second destination's folder does not exist: refused before any work.
    const Status s = out.Declare(P("no/such/x.json"));
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().kind, ErrorKind::kIo);
    ASSERT_TRUE(out.StageText(P("keep.csv"), "new\n").ok());
    EXPECT_EQ(testing::ReadFile(P("keep.csv")), "old\n");  // staged, not yet visible
    EXPECT_EQ(Names().size(), 3u);           // keep.csv + two temporaries
  }
  EXPECT_EQ(Names(), std::vector<std::string>{"keep.csv"});
  EXPECT_EQ(testing::ReadFile(P("keep.csv")), "old\n");
}

TEST_F(OutputSetTest, CommitWritesEveryStagedFileAndSkipsUnstagedOnes) {
  OutputSet out;
  ASSERT_TRUE(out.Declare(P("a.csv")).ok());
  ASSERT_TRUE(out.Declare(P("b.json")).ok());
  ASSERT_TRUE(out.Declare(P("unused.html")).ok());
  Table t;
  t.Add("x", {1.5, -2});
  ASSERT_TRUE(out.StageCsv(P("a.csv"), t).ok());
  ASSERT_TRUE(out.StageText(P("b.json"), "{}\n").ok());
  EXPECT_FALSE(out.StageText(P("b.json"), "{}\n").ok());  // one Stage per destination
  ASSERT_TRUE(out.Commit().ok());
  EXPECT_EQ(Names(), (std::vector<std::string>{"a.csv", "b.json"}));
  EXPECT_EQ(testing::ReadFile(P("a.csv")), "x\n1.5\n-2\n");
}

TEST_F(OutputSetTest, RefusesNonFiniteNumbersNamingColumnAndLine) {
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Table t;
    t.Add("time_s", {0, 1, 2});
    t.Add("rate_dps", {0.5, bad, 0.5});
    const Status s = WriteCsvAtomic(P("nan.csv"), t);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("nan.csv:3: column 'rate_dps'"), std::string::npos) << s.error().message;
    EXPECT_TRUE(Names().empty());
  }
}

TEST_F(OutputSetTest, AnOverlongButLegalNameIsWritten) {
  const std::string name = std::string(250, 'n') + ".csv";  // 254 bytes: NAME_MAX is 255
  ASSERT_TRUE(WriteTextAtomic(P(name), "a\n1\n").ok());
  EXPECT_EQ(Names(), std::vector<std::string>{name});
}

TEST_F(OutputSetTest, GzipRoundTrip) {
  Table t;
  t.Add("x", {1, 2, 3});
  ASSERT_TRUE(WriteCsvAtomic(P("t.csv.gz"), t).ok());
  const auto back = ReadCsv(P("t.csv.gz"));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->columns[0], (std::vector<double>{1, 2, 3}));
}

TEST_F(OutputSetTest, LargeTablesFormattedInPartsGiveTheRowByRowBytes) {
  // 1 column x 200,003 rows: more than two parts of ~87k rows (several batches, a short last
  // part); 6 columns x 20,000 rows: one batch of two parts. Expected: each row formatted in turn.
  for (const auto& [cols, rows] : {std::pair<int, std::size_t>{1, 200003}, {6, 20000}, {3, 5}}) {
    SCOPED_TRACE(std::to_string(cols) + " x " + std::to_string(rows));
    Table t;
    for (int c = 0; c < cols; ++c) {
      std::vector<double> v(rows);
      for (std::size_t i = 0; i < rows; ++i) v[i] = std::ldexp(static_cast<double>(i * 2654435761u % 1000003), -c * 7) - 3.5;
      t.Add("c" + std::to_string(c), std::move(v));
    }
    std::string expected;
    for (int c = 0; c < cols; ++c) expected += (c ? ",c" : "c") + std::to_string(c);
    expected += "\n";
    char cell[64];
    for (std::size_t i = 0; i < rows; ++i) {
      for (int c = 0; c < cols; ++c) {
        if (c) expected += ',';
        expected.append(cell, std::to_chars(cell, cell + sizeof cell, t.columns[c][i]).ptr);
      }
      expected += "\n";
    }
    ASSERT_TRUE(WriteCsvAtomic(P("big.csv"), t).ok());
    EXPECT_TRUE(testing::ReadFile(P("big.csv")) == expected);
  }
}

TEST_F(OutputSetTest, RemoveLiveTemporaryFilesRemovesThemInAChild) {
  // What the CLI's signal handler does, in a forked child so the parent's sets are untouched.
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    auto* out = new OutputSet;  // never destroyed: the handler must do the cleaning
    if (!out->Declare(P("a.csv")).ok() || !out->Declare(P("b.csv")).ok()) _exit(3);
    RemoveLiveTemporaryFiles();
    _exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_TRUE(Names().empty());
}

}  // namespace
}  // namespace gyrocomp
