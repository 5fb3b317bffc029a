// Tests of ReadCsv / WriteCsvAtomic / WriteTextAtomic: every malformed-input class, gzip, the
// accepted variations (CRLF, BOM, blanks), chunk boundaries, bit-exact round trips, atomicity.
#include "gyrocomp/io/io.h"

#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fixtures.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

namespace fs = std::filesystem;

class IoTest : public testing::FileTest {
 protected:
  IoTest() : FileTest("gyrocomp_io_test") {}
  std::vector<std::string> Files() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    return out;
  }

  // Reads `path`, expects a kInvalidInput error whose message starts with
  // "<path>:<line>:<column>: " and contains every string of `words`.
  void ExpectBad(const std::string& path, int line, int column, const std::vector<std::string>& words) {
    SCOPED_TRACE(path);
    const Result<Table> t = ReadCsv(path);
    ASSERT_FALSE(t.ok()) << "accepted a malformed file";
    EXPECT_EQ(t.error().kind, ErrorKind::kInvalidInput) << t.error().message;
    const std::string prefix = path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
    EXPECT_EQ(t.error().message.rfind(prefix, 0), 0u) << "expected prefix '" << prefix << "' in: " << t.error().message;
    for (const std::string& w : words) {
      EXPECT_NE(t.error().message.find(w), std::string::npos) << "'" << w << "' missing from: " << t.error().message;
    }
    EXPECT_EQ(t.error().message.find('\n'), std::string::npos) << "error message must be one line";
  }
};

TEST_F(IoTest, ReadsSimpleTable) {
  const auto t = ReadCsv(Put("a.csv", "time_s,rate_dps,temp_c\n0,1.5,20\n0.01,-2.25e-3,20.5\n"));
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_EQ(t->names, (std::vector<std::string>{"time_s", "rate_dps", "temp_c"}));
  ASSERT_EQ(t->num_rows(), 2u);
  EXPECT_EQ(t->columns[1][1], -2.25e-3);  // exact: from_chars is correctly rounded
  EXPECT_EQ(t->Find("temp_c"), 2);
  EXPECT_EQ(t->Find("nope"), -1);
  EXPECT_EQ(t->source, dir_ + "/a.csv");
}

TEST_F(IoTest, AcceptsCrlfBomBlanksAndTrailingEmptyLines) {
  const std::string body = "\xEF\xBB\xBF time_s , rate_dps\t,\"temp_c\"\r\n0, +1.0 ,2\r\n1,-3,4\r\n\r\n\n";
  const auto t = ReadCsv(Put("crlf.csv", body));
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_EQ(t->names, (std::vector<std::string>{"time_s", "rate_dps", "temp_c"}));
  ASSERT_EQ(t->num_rows(), 2u);
  EXPECT_EQ(t->columns[1][0], 1.0);
  EXPECT_EQ(t->columns[1][1], -3.0);
  EXPECT_EQ(t->columns[2][1], 4.0);
  // No final newline at all.
  const auto u = ReadCsv(Put("nonl.csv", "a,b\n1,2"));
  ASSERT_TRUE(u.ok()) << u.error().message;
  EXPECT_EQ(u->columns[1][0], 2.0);
}

TEST_F(IoTest, UnderflowReadsAsZeroLikeStrtod) {
  const auto t = ReadCsv(Put("u.csv", "a\n1e-400\n4.9e-324\n"));
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_EQ(t->columns[0][0], 0.0);
  EXPECT_EQ(t->columns[0][1], std::numeric_limits<double>::denorm_min());
}

// ---- every malformed-input class: file, line, column and what --------------------------------

TEST_F(IoTest, EmptyFile) {
  ExpectBad(Put("empty.csv", ""), 1, 1, {"empty file"});
  ExpectBad(Put("blank.csv", "\n  \r\n\n"), 1, 1, {"empty file"});
}

TEST_F(IoTest, HeaderOnly) {
  ExpectBad(Put("h.csv", "time_s,rate_dps\n"), 2, 1, {"header only", "time_s, rate_dps"});
  ExpectBad(Put("h2.csv", "time_s,rate_dps"), 2, 1, {"header only"});
}

TEST_F(IoTest, NonNumericCell) {
  ExpectBad(Put("n.csv", "time_s,rate_dps,temp_c\n0,1,2\n0.1,abc,2\n"), 3, 2,
            {"non-numeric", "'abc'", "column 'rate_dps'", "line 3", "column 2"});
  ExpectBad(Put("n2.csv", "a,b\n1,2x\n"), 2, 2, {"non-numeric", "'2x'", "column 'b'"});
  ExpectBad(Put("n3.csv", "a,b\n1,\"2\"\n"), 2, 2, {"non-numeric"});
  ExpectBad(Put("n4.csv", "a,b\n1,0x10\n"), 2, 2, {"non-numeric"});
  ExpectBad(Put("n5.csv", "a,b\n1,+-2\n"), 2, 2, {"non-numeric", "'+-2'"});
  ExpectBad(Put("n6.csv", "a,b\n1,2 3\n"), 2, 2, {"non-numeric", "'2 3'"});
}

TEST_F(IoTest, EmptyCell) {
  ExpectBad(Put("e.csv", "a,b,c\n1,,3\n"), 2, 2, {"empty cell", "column 'b'"});
}

TEST_F(IoTest, NanAndInf) {
  ExpectBad(Put("nan.csv", "a,b\n1,2\n2,NaN\n"), 3, 2, {"NaN", "column 'b'"});
  ExpectBad(Put("inf.csv", "a,b\n1,2\n-inf,3\n"), 3, 1, {"infinite", "column 'a'"});
  ExpectBad(Put("ovf.csv", "a,b\n1,1e999\n"), 2, 2, {"overflows", "column 'b'"});
  // Allowed when the caller asks for it.
  CsvReadOptions keep;
  keep.reject_non_finite = false;
  const auto t = ReadCsv(Put("nan_ok.csv", "a,b\n1,nan\n2,inf\n"), keep);
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_TRUE(std::isnan(t->columns[1][0]));
  EXPECT_TRUE(std::isinf(t->columns[1][1]));
}

TEST_F(IoTest, RaggedRow) {
  ExpectBad(Put("short.csv", "a,b,c\n1,2,3\n4,5\n"), 3, 3, {"ragged", "2 fields", "header has 3"});
  ExpectBad(Put("long.csv", "a,b,c\n1,2,3\n4,5,6,7\n"), 3, 4, {"ragged", "4 fields", "header has 3"});
  ExpectBad(Put("trail.csv", "a,b\n1,2,\n"), 2, 3, {"ragged"});
}

TEST_F(IoTest, BinaryGarbage) {
  std::string junk = "\x1f\x8b\x00\xff\xfe\x01garbage";  // starts like gzip, but is not
  junk += std::string(64, '\0');
  const auto t = ReadCsv(Put("junk.bin", junk));
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.error().kind, ErrorKind::kInvalidInput) << t.error().message;
  EXPECT_EQ(t.error().message.rfind(dir_ + "/junk.bin:1:1: ", 0), 0u) << t.error().message;

  std::mt19937 rng(7);
  std::string noise(4096, '\0');
  for (char& c : noise) c = static_cast<char>(rng());
  ExpectBad(Put("noise.bin", noise), 1, 1, {"binary garbage"});
  ExpectBad(Put("latin1.csv", "temp\xb0" "C,b\n1,2\n"), 1, 1, {"binary garbage", "UTF-8"});
  ExpectBad(Put("nul.csv", std::string("a,b\n1,2\n3,\0\0\n", 14)), 3, 2, {"binary garbage", "NUL"});
  ExpectBad(Put("ctl.csv", "a,b\n1,\x01\x02\n"), 2, 2, {"binary garbage"});
  // Random bytes hold 0x0d too: still binary garbage (with the first bad byte), not old Mac line
  // ends; a file named like a log says its first bytes are not that log's header.
  ExpectBad(Put("cr_noise.ulg", std::string("\x9c\r\x00\x17\xfe", 5)), 1, 1,
            {"binary garbage", "0x9c at byte 0 of the line", "not a ULog, DataFlash or ROS bag header"});
  ExpectBad(Put("mac.csv", "a,b\r1,2\r3,4\r"), 1, 1, {"carriage returns", "CR-only"});
  const auto plain = ReadCsv(Put("latin1b.csv", "temp\xb0" "C,b\n1,2\n"));
  ASSERT_FALSE(plain.ok());
  EXPECT_NE(plain.error().message.find("0xb0 at byte 4 of the line"), std::string::npos) << plain.error().message;
  EXPECT_EQ(plain.error().message.find("named like a flight log"), std::string::npos) << plain.error().message;
}

TEST_F(IoTest, BadHeaders) {
  ExpectBad(Put("dup.csv", "a,b,a\n1,2,3\n"), 1, 3, {"duplicate", "'a'", "column 1"});
  ExpectBad(Put("emptyname.csv", "a,,c\n1,2,3\n"), 1, 2, {"empty column name"});
  ExpectBad(Put("nohdr.csv", "0,1.5,20\n0.01,1.6,20\n"), 1, 1, {"not a header"});
  ExpectBad(Put("semi.csv", "time_s;rate_dps\n0;1\n"), 1, 1, {"';'-separated"});
  ExpectBad(Put("tab.csv", "time_s\trate_dps\n0\t1\n"), 1, 1, {"tab-separated"});
}

TEST_F(IoTest, BlankLineInsideData) {
  ExpectBad(Put("gap.csv", "a,b\n1,2\n\n3,4\n"), 3, 1, {"blank line", "line 4"});
}

TEST_F(IoTest, MissingFileIsIoError) {
  const auto t = ReadCsv(dir_ + "/does_not_exist.csv");
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.error().kind, ErrorKind::kIo);
  EXPECT_NE(t.error().message.find("does_not_exist.csv"), std::string::npos);
  const auto d = ReadCsv(dir_);
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.error().kind, ErrorKind::kIo);
  EXPECT_NE(d.error().message.find("directory"), std::string::npos) << d.error().message;
}

// ---- gzip ---------------------------------------------------------------------------------

TEST_F(IoTest, GzipDetectedByContentNotName) {
  const std::string body = "t,x\n0,1\n1,2\n";
  for (const char* name : {"a.csv.gz", "a_gzip_without_suffix.csv"}) {
    const auto t = ReadCsv(PutGz(name, body));
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->num_rows(), 2u);
    EXPECT_EQ(t->columns[1][1], 2.0);
  }
  // A plain file with a .gz name is read as plain text.
  const auto p = ReadCsv(Put("plain.csv.gz", body));
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(p->num_rows(), 2u);
}

TEST_F(IoTest, TruncatedGzipIsAnError) {
  std::string body = "t,x\n";
  for (int i = 0; i < 20000; ++i) body += std::to_string(i) + "," + std::to_string(i * 0.37) + "\n";
  const std::string path = PutGz("full.csv.gz", body);
  std::ifstream in(path, std::ios::binary);
  std::string gz((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(gz.size(), 1000u);
  const std::string cut = Put("cut.csv.gz", gz.substr(0, gz.size() / 2));
  const auto t = ReadCsv(cut);
  ASSERT_FALSE(t.ok()) << "a truncated gzip file was accepted";
  EXPECT_EQ(t.error().kind, ErrorKind::kInvalidInput) << t.error().message;
  EXPECT_NE(t.error().message.find("gzip data (unexpected end of file)"), std::string::npos) << t.error().message;
  EXPECT_EQ(t.error().message.find(cut, 1), std::string::npos) << "file named twice: " << t.error().message;
  EXPECT_EQ(t.error().message.rfind(cut + ":", 0), 0u) << t.error().message;
}

// ---- chunk boundaries ----------------------------------------------------------------------

TEST_F(IoTest, LineNumbersStayRightAcrossChunks) {
  // ~9 MB of text: the reader's 4 MiB chunks split lines; the bad cell is far past the first.
  std::string body = "time_s,rate_dps,temp_c\n";
  const int rows = 200000;
  const int bad_row = 150000;
  for (int i = 0; i < rows; ++i) {
    body += std::to_string(i * 0.0123456789012345) + "," +
            (i == bad_row ? std::string("oops") : std::to_string(std::sin(i) * 1e-3)) + ",21.123456789\n";
  }
  ExpectBad(Put("big_bad.csv", body), bad_row + 2, 2, {"'oops'", "column 'rate_dps'"});
}

TEST_F(IoTest, LineLongerThanAChunk) {
  const std::string pad(5u << 20, ' ');  // 5 MiB of blanks inside one cell: buffer must grow
  const auto t = ReadCsv(Put("long_line.csv", "a,b\n1," + pad + "2" + pad + "\n3,4\n"));
  ASSERT_TRUE(t.ok()) << t.error().message;
  ASSERT_EQ(t->num_rows(), 2u);
  EXPECT_EQ(t->columns[1][0], 2.0);
  EXPECT_EQ(t->columns[0][1], 3.0);
}

// ---- writing -------------------------------------------------------------------------------

Table RandomTable(std::size_t rows, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  Table t;
  std::vector<double> bits(rows), normal(rows), special;
  for (std::size_t i = 0; i < rows; ++i) {
    // Random finite bit patterns: every exponent range, subnormals included.
    double v;
    do {
      const std::uint64_t b = rng();
      std::memcpy(&v, &b, sizeof v);
    } while (!std::isfinite(v));
    bits[i] = v;
    normal[i] = std::normal_distribution<double>(0.0, 0.01)(rng);
  }
  const double edge[] = {0.0, -0.0, 1.0, 0.1, 1.0 / 3.0, 5e-324, 2.2250738585072014e-308,
                         1.7976931348623157e308, -1.7976931348623157e308, 123456789012345680.0,
                         9007199254740993.0, 1e-7, 0.3};
  for (std::size_t i = 0; i < rows; ++i) special.push_back(edge[i % std::size(edge)]);
  t.Add("bits", std::move(bits));
  t.Add("rate_dps", std::move(normal));
  t.Add("edge", std::move(special));
  return t;
}

void ExpectBitIdentical(const Table& a, const Table& b) {
  ASSERT_EQ(a.names, b.names);
  ASSERT_EQ(a.num_rows(), b.num_rows());
  for (std::size_t j = 0; j < a.columns.size(); ++j) {
    // Bit-exact, not approximately equal: shortest round-trip formatting guarantees it (and
    // keeps -0.0 and subnormals).
    ASSERT_EQ(std::memcmp(a.columns[j].data(), b.columns[j].data(), a.num_rows() * sizeof(double)), 0)
        << "column " << a.names[j];
  }
}

TEST_F(IoTest, RoundTripIsBitExactPlainAndGzip) {
  const Table t = RandomTable(20000, 42);
  for (const char* name : {"rt.csv", "rt.csv.gz"}) {
    const std::string path = dir_ + "/" + name;
    ASSERT_TRUE(WriteCsvAtomic(path, t).ok());
    const auto back = ReadCsv(path);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ExpectBitIdentical(t, *back);
  }
  // The .gz output really is gzip (magic bytes 1f 8b).
  std::ifstream in(dir_ + "/rt.csv.gz", std::ios::binary);
  unsigned char magic[2] = {0, 0};
  in.read(reinterpret_cast<char*>(magic), 2);
  EXPECT_EQ(magic[0], 0x1f);
  EXPECT_EQ(magic[1], 0x8b);
  EXPECT_LT(fs::file_size(dir_ + "/rt.csv.gz"), fs::file_size(dir_ + "/rt.csv"));
}

TEST_F(IoTest, WriteUsesShortestFormatting) {
  Table t;
  t.Add("x", {0.1, 1e-5, 100.0, -0.0, 0.30000000000000004});
  const std::string path = dir_ + "/short.csv";
  ASSERT_TRUE(WriteCsvAtomic(path, t).ok());
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "x\n0.1\n1e-05\n100\n-0\n0.30000000000000004\n");
}

TEST_F(IoTest, WriteIsAtomicAndLeavesNoTemporaryFiles) {
  const std::string path = dir_ + "/out.csv";
  Table t;
  t.Add("a", {1, 2, 3});
  ASSERT_TRUE(WriteTextAtomic(path, "old contents\n").ok());
  ASSERT_TRUE(WriteCsvAtomic(path, t).ok());  // replaces the old file
  EXPECT_EQ(Files(), std::vector<std::string>{"out.csv"});
  const auto back = ReadCsv(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->columns[0], (std::vector<double>{1, 2, 3}));

  // Invalid tables: an error, the old file untouched, no temporary file left.
  Table ragged;
  ragged.names = {"a", "b"};
  ragged.columns = {{1, 2}, {1}};
  const Status s = WriteCsvAtomic(path, ragged);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().kind, ErrorKind::kInvalidArgument);
  Table comma;
  comma.Add("a,b", {1});
  EXPECT_FALSE(WriteCsvAtomic(dir_ + "/comma.csv", comma).ok());
  EXPECT_EQ(Files(), std::vector<std::string>{"out.csv"});
  EXPECT_TRUE(ReadCsv(path).ok());

  // A directory that does not exist: kIo, nothing created.
  const Status missing = WriteCsvAtomic(dir_ + "/no/such/dir/x.csv", t);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().kind, ErrorKind::kIo);
  EXPECT_NE(missing.error().message.find("no/such/dir"), std::string::npos) << missing.error().message;
  EXPECT_EQ(Files(), std::vector<std::string>{"out.csv"});
}

TEST_F(IoTest, WriteTextAtomicPlainAndGzip) {
  ASSERT_TRUE(WriteTextAtomic(dir_ + "/j.json", "{\"a\": 1}\n").ok());
  std::ifstream in(dir_ + "/j.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "{\"a\": 1}\n");
  ASSERT_TRUE(WriteTextAtomic(dir_ + "/t.csv.gz", "a,b\n1,2\n").ok());
  const auto t = ReadCsv(dir_ + "/t.csv.gz");
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_EQ(t->columns[1][0], 2.0);
}

TEST_F(IoTest, InvalidDelimiterIsAnArgumentError) {
  CsvReadOptions o;
  o.delimiter = '.';
  const auto t = ReadCsv(Put("d.csv", "a\n1\n"), o);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.error().kind, ErrorKind::kInvalidArgument);
  EXPECT_NE(t.error().message.find("CsvReadOptions::delimiter"), std::string::npos);
  o.delimiter = ';';
  const auto u = ReadCsv(Put("semi_ok.csv", "a;b\n1;2\n"), o);
  ASSERT_TRUE(u.ok()) << u.error().message;
  EXPECT_EQ(u->columns[1][0], 2.0);
}

}  // namespace
}  // namespace gyrocomp
