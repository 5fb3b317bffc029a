// Tests of reading only some columns of a CSV (CsvReadOptions::columns, LogSpec::keep_cols,
// TakeGyroLog; memory): the kept values are those of a whole read, bit for bit; a bad
// cell in a dropped column is the same one-line error at the same line and column; messages
// still name the file's columns; the kept columns are reserved once, close to their size.
#include "gyrocomp/io/io.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyrocomp/io/flight_log.h"
#include "gyrocomp/io/gyro_log.h"
#include "gyrocomp/io/ulog.h"
#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

class CsvColumnsTest : public testing::FileTest {
 protected:
  CsvColumnsTest() : FileTest("gyrocomp_csv_columns_test") {}
};

CsvReadOptions Keep(std::vector<std::string> names) {
  CsvReadOptions o;
  o.columns = std::move(names);
  return o;
}

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

// The subset read of `path` holds, for every kept name, the whole read's column bit for bit,
// in file order, with the whole header in Table::header.
void ExpectSubsetOfWholeRead(const std::string& path, const std::vector<std::string>& keep) {
  SCOPED_TRACE(path);
  const Result<Table> whole = ReadCsv(path);
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  const Result<Table> part = ReadCsv(path, Keep(keep));
  ASSERT_TRUE(part.ok()) << part.error().message;
  EXPECT_EQ(part->num_rows(), whole->num_rows());
  std::vector<std::string> expected_names;
  for (const std::string& n : whole->names) {
    if (std::find(keep.begin(), keep.end(), n) != keep.end()) expected_names.push_back(n);
  }
  if (expected_names.empty()) expected_names.push_back(whole->names.front());  // documented fallback
  EXPECT_EQ(part->names, expected_names);
  EXPECT_EQ(part->FileNames(), whole->names);
  for (std::size_t j = 0; j < part->names.size(); ++j) {
    const int w = whole->Find(part->names[j]);
    ASSERT_GE(w, 0);
    EXPECT_TRUE(SameBits(part->columns[j], whole->columns[static_cast<std::size_t>(w)])) << part->names[j];
    EXPECT_EQ(part->FileColumn(j), static_cast<std::size_t>(w) + 1) << part->names[j];
  }
}

// A CSV of `rows` rows x `cols` columns (c0 = time at 100 Hz, the others random, in several
// number formats).
std::string Generated(std::size_t rows, std::size_t cols, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::string s;
  for (std::size_t j = 0; j < cols; ++j) s += (j ? ",c" : "c") + std::to_string(j);
  s += "\n";
  char buf[64];
  for (std::size_t i = 0; i < rows; ++i) {
    std::snprintf(buf, sizeof buf, "%.2f", static_cast<double>(i) / 100.0);
    s += buf;
    for (std::size_t j = 1; j < cols; ++j) {
      const double v = normal(rng) * std::pow(10.0, static_cast<double>(j % 7) - 3.0);
      const char* fmt = j % 3 == 0 ? ",%.17g" : (j % 3 == 1 ? ", %.6e " : ",%+.4f");
      std::snprintf(buf, sizeof buf, fmt, v);
      s += buf;
    }
    s += i % 5 == 0 ? "\r\n" : "\n";
  }
  return s;
}

TEST_F(CsvColumnsTest, ManyUnusedColumnsKeptValuesAreTheWholeReadsBitForBit) {
  // 40 columns, 3 kept; 20k rows (~10 MB): several 4 MiB chunks, so the reservation and the chunk
  // boundaries are crossed.
  const std::string text = Generated(20000, 40, 1);
  const std::string plain = Put("wide.csv", text);
  const std::string gz = PutGz("wide.csv.gz", text);
  for (const std::string& path : {plain, gz}) {
    ExpectSubsetOfWholeRead(path, {"c0", "c17", "c39"});
    ExpectSubsetOfWholeRead(path, {"c39", "c0"});         // order of the list does not matter
    ExpectSubsetOfWholeRead(path, {"nosuch", "c31"});     // absent names are ignored
    ExpectSubsetOfWholeRead(path, {"nosuch"});            // none: the first column stays
    ExpectSubsetOfWholeRead(path, {});
  }
}

TEST_F(CsvColumnsTest, TheRepositorysCsvFilesReadTheSameThroughAnySubset) {
  int files = 0;
  for (const std::string& dir : {testing::GoldenPath(""), testing::FieldlogsDir()}) {
    if (!fs::exists(dir)) continue;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      if (e.path().extension() != ".csv") continue;
      const Result<Table> whole = ReadCsv(e.path().string());
      ASSERT_TRUE(whole.ok()) << whole.error().message;
      // Every single column, every other column, and the last one with a name the file lacks.
      for (const std::string& n : whole->names) ExpectSubsetOfWholeRead(e.path().string(), {n});
      std::vector<std::string> odd;
      for (std::size_t j = 0; j < whole->names.size(); j += 2) odd.push_back(whole->names[j]);
      ExpectSubsetOfWholeRead(e.path().string(), odd);
      ExpectSubsetOfWholeRead(e.path().string(), {whole->names.back(), "not_in_the_file"});
      // And the independent reader of the test support agrees with the kept values.
      const auto golden = testing::ReadGoldenCsv(e.path().string());
      const Result<Table> part = ReadCsv(e.path().string(), Keep({whole->names.back()}));
      ASSERT_TRUE(part.ok());
      EXPECT_TRUE(SameBits(part->columns[0], golden.at(whole->names.back()))) << e.path();
      ++files;
    }
  }
  EXPECT_GE(files, 10) << "the repository's test CSVs were not found";
}

// Every malformation, in a dropped column, gives the error of a whole read: same message.
TEST_F(CsvColumnsTest, ABadCellInADroppedColumnIsTheSameErrorAtTheSameLineAndColumn) {
  const std::string header = "t,a,b,c\n";
  const std::string good = "0,1,2,3\n0.1,1,2,3\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"non_numeric", "0.2,1,x,3\n"},   {"empty", "0.2,1,,3\n"},       {"nan", "0.2,1,nan,3\n"},
      {"inf", "0.2,1,2,-inf\n"},        {"overflow", "0.2,1,1e999,3\n"}, {"ragged_short", "0.2,1,2\n"},
      {"ragged_long", "0.2,1,2,3,4\n"}, {"nul", std::string("0.2,1,2\0,3\n", 11)},
      {"garbage", "0.2,1,\xff\xfe,3\n"}, {"blank_inside", "\n0.2,1,2,3\n"}, {"two_numbers", "0.2,1,2 5,3\n"}};
  for (const auto& [name, bad] : cases) {
    SCOPED_TRACE(name);
    const std::string path = Put(name + ".csv", header + good + bad + good);
    const Result<Table> whole = ReadCsv(path);
    ASSERT_FALSE(whole.ok());
    for (const std::vector<std::string>& keep :
         std::vector<std::vector<std::string>>{{"t", "a"}, {"t"}, {"c"}, {}, {"a", "b", "c"}}) {
      const Result<Table> part = ReadCsv(path, Keep(keep));
      ASSERT_FALSE(part.ok()) << "a bad row was dropped silently";
      EXPECT_EQ(part.error().kind, whole.error().kind);
      EXPECT_EQ(part.error().message, whole.error().message);
      EXPECT_EQ(part.error().message.find('\n'), std::string::npos);
    }
  }
  // Header errors and "header only" name the whole header too.
  for (const std::string& text : {std::string("t,a,a\n0,1,2\n"), std::string("t,a,b\n")}) {
    const std::string path = Put("h.csv", text);
    EXPECT_EQ(ReadCsv(path, Keep({"t"})).error().message, ReadCsv(path).error().message);
  }
}

TEST_F(CsvColumnsTest, KeptColumnsAreReservedOnceCloseToTheirSize) {
  // 200k rows (~6 MB plain): the estimate from the first chunk is within a few per cent, so
  // the columns are neither regrown nor much larger than the rows (capacity is address space:
  // pages never written cost no memory, but a regrowth copies the column).
  const std::string text = Generated(200000, 4, 2);
  for (const std::string& path : {Put("long.csv", text), PutGz("long.csv.gz", text)}) {
    SCOPED_TRACE(path);
    const Result<Table> t = ReadCsv(path, Keep({"c0", "c3"}));
    ASSERT_TRUE(t.ok()) << t.error().message;
    ASSERT_EQ(t->columns.size(), 2u);
    for (const auto& c : t->columns) {
      EXPECT_EQ(c.size(), 200000u);
      EXPECT_LE(static_cast<double>(c.capacity()), 1.4 * 200000.0) << "reserved far beyond the rows";
    }
  }
}

TEST_F(CsvColumnsTest, MaxMemoryCountsTheKeptColumnsOnly) {
  const std::string path = Put("m.csv", Generated(20000, 10, 3));
  CsvReadOptions o = Keep({"c0"});
  o.max_memory_bytes = 20000 * 8 * 2;  // two columns' worth: one kept column fits
  EXPECT_TRUE(ReadCsv(path, o).ok());
  o.columns.reset();
  const Result<Table> all = ReadCsv(path, o);  // ten columns do not
  ASSERT_FALSE(all.ok());
  EXPECT_NE(all.error().message.find("(--max-memory)"), std::string::npos) << all.error().message;
}

// A log whose time, rate and temperature are columns 2, 5 and 7 of 8.
std::string LogText(std::size_t rows, double rate_at_row_5, double time_at_row_7) {
  std::string s = "pad0,time_s,pad1,pad2,rate_dps,pad3,temp_c,pad4\n";
  char buf[200];
  for (std::size_t i = 0; i < rows; ++i) {
    const double t = i == 7 ? time_at_row_7 : static_cast<double>(i) / 100.0;
    const double r = i == 5 ? rate_at_row_5 : 0.01 * std::sin(static_cast<double>(i));
    std::snprintf(buf, sizeof buf, "%zu,%.17g,1,2,%.17g,3,%.17g,4\n", i, t, r, 20.0 + 1e-4 * static_cast<double>(i));
    s += buf;
  }
  return s;
}

TEST_F(CsvColumnsTest, TakeGyroLogEqualsLoadGyroLogAndLeavesTheKeptExtras) {
  const std::string path = Put("log.csv", LogText(5000, 0.5, 0.07));
  LogSpec spec;
  spec.temp_required = true;
  const Result<Table> whole = ReadCsv(path);
  ASSERT_TRUE(whole.ok());
  const Result<GyroLog> copied = LoadGyroLog(*whole, spec);
  ASSERT_TRUE(copied.ok()) << copied.error().message;

  spec.keep_cols = std::vector<std::string>{"pad3"};
  Result<LogTableRead> read = ReadLogTable(path, spec);
  ASSERT_TRUE(read.ok()) << read.error().message;
  EXPECT_EQ(read->table.names, (std::vector<std::string>{"time_s", "rate_dps", "pad3", "temp_c"}));
  const Result<GyroLog> taken = TakeGyroLog(&read->table, read->spec);
  ASSERT_TRUE(taken.ok()) << taken.error().message;
  EXPECT_TRUE(SameBits(taken->time_s, copied->time_s));
  ASSERT_EQ(taken->rate_dps.size(), 1u);
  EXPECT_TRUE(SameBits(taken->rate_dps[0], copied->rate_dps[0]));
  EXPECT_TRUE(SameBits(taken->temp_c, copied->temp_c));
  EXPECT_EQ(taken->fs_hz, copied->fs_hz);
  EXPECT_EQ(taken->sampling.BriefReport(), copied->sampling.BriefReport());
  // What stays: the extra the caller named, with the file's header for messages.
  EXPECT_EQ(read->table.names, (std::vector<std::string>{"pad3"}));
  EXPECT_EQ(read->table.num_rows(), 5000u);
  EXPECT_EQ(read->table.FileNames(), whole->names);

  // ReadGyroLog (only the log's columns, moved) gives the same log.
  const Result<GyroLog> direct = ReadGyroLog(path, LogSpec{});
  ASSERT_TRUE(direct.ok()) << direct.error().message;
  EXPECT_TRUE(SameBits(direct->rate_dps[0], copied->rate_dps[0]));
  EXPECT_TRUE(SameBits(direct->temp_c, copied->temp_c));
}

TEST_F(CsvColumnsTest, AColumnInTwoRolesOrNamedByKeepColsIsCopiedNotMoved) {
  const std::string path = Put("log.csv", LogText(300, 0.5, 0.07));
  LogSpec spec;
  spec.temp_col = "rate_dps";  // absurd but allowed: the rate column also as temperature
  spec.keep_cols = std::vector<std::string>{"time_s"};
  Result<LogTableRead> read = ReadLogTable(path, spec);
  ASSERT_TRUE(read.ok());
  const Result<GyroLog> log = TakeGyroLog(&read->table, read->spec);
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_TRUE(SameBits(log->rate_dps[0], log->temp_c));
  EXPECT_EQ(log->rate_dps[0].size(), 300u);
  ASSERT_EQ(read->table.names, (std::vector<std::string>{"time_s"}));  // kept for the caller
  EXPECT_TRUE(SameBits(read->table.columns[0], log->time_s));
}

// The errors LoadGyroLog finds in the values name the file's line and column whether or not the
// other columns were kept, and a missing column lists the whole header.
TEST_F(CsvColumnsTest, LogErrorsNameTheSameLineAndFileColumnFromASubset) {
  const std::vector<std::string> files = {Put("rate.csv", LogText(50, 1e7, 0.07)),  // rate out of range, row 5
                                          Put("time.csv", LogText(50, 0.5, 0.01))}; // time backwards, row 7
  for (const std::string& path : files) {
    SCOPED_TRACE(path);
    LogSpec spec;
    const Result<Table> table = ReadCsv(path);
    ASSERT_TRUE(table.ok()) << table.error().message;
    const Result<GyroLog> whole = LoadGyroLog(*table, spec);
    ASSERT_FALSE(whole.ok());
    EXPECT_TRUE(whole.error().message.find(path + ":9:") == 0 || whole.error().message.find(path + ":7:") == 0)
        << whole.error().message;
    const Result<GyroLog> part = ReadGyroLog(path, spec);
    ASSERT_FALSE(part.ok());
    EXPECT_EQ(part.error().message, whole.error().message);
  }
  LogSpec spec;
  spec.rate_cols = {"Rate_dps"};
  const Result<GyroLog> missing = ReadGyroLog(files[0], spec);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("columns are: pad0, time_s, pad1, pad2, rate_dps, pad3, temp_c, pad4"),
            std::string::npos)
      << missing.error().message;
  EXPECT_EQ(missing.error().message, LoadGyroLog(*ReadCsv(files[0]), spec).error().message);
}

// ReadFlightLog keeps one gyro's values of a ULog (ULogReadOptions::keep_accel_baro = false,
// gyro_instance) and moves them into the table: the table of every instance, and the messages
// for a missing or absent instance, are those of the whole read.
TEST(FlightLogMemory, OneGyroOfAULogReadsAsFromTheWholeLog) {
  const std::string path = testing::FieldlogsDir() + "/sample_log_small.ulg";
  if (!fs::exists(path)) GTEST_SKIP() << "no " << path;
  const Result<ULogContents> whole = ReadULog(path);
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  ASSERT_GE(whole->gyros.size(), 2u) << "the fixture has several sensor_gyro instances";
  for (const ULogGyroSeries& g : whole->gyros) {
    SCOPED_TRACE(g.multi_id);
    const Result<FlightLogTable> expected = FlightLogFromULog(*whole, g.multi_id);
    const Result<FlightLogTable> got = ReadFlightLog(path, g.multi_id);
    ASSERT_EQ(expected.ok(), got.ok());
    if (!got.ok()) {
      EXPECT_EQ(got.error().message, expected.error().message);
      continue;
    }
    EXPECT_EQ(got->table.names, expected->table.names);
    for (std::size_t j = 0; j < got->table.columns.size(); ++j) {
      EXPECT_TRUE(SameBits(got->table.columns[j], expected->table.columns[j])) << got->table.names[j];
    }
    EXPECT_EQ(got->warnings, expected->warnings);
    EXPECT_EQ(got->device_id, expected->device_id);
  }
  for (const std::optional<int> instance : {std::optional<int>(), std::optional<int>(9)}) {
    const Result<FlightLogTable> expected = FlightLogFromULog(*whole, instance);
    const Result<FlightLogTable> got = ReadFlightLog(path, instance);
    ASSERT_FALSE(expected.ok());
    ASSERT_FALSE(got.ok());
    EXPECT_EQ(got.error().message, expected.error().message);
  }
}

}  // namespace
}  // namespace gyrocomp
