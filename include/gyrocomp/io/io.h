// Reading and writing numeric CSV tables: the first stage of the pipeline.
//
// A log is a CSV file with one header row and numeric cells only. Plain text, gzip (".gz",
// detected by content, not by name) and stdin ("-") are read the same way. Every malformed input
// is a returned Error of kind kInvalidInput whose message is one line:
//     "<file>:<line>:<column>: <what is wrong>"
// (line and column are 1-based; column is the field index, named in the message when known).
// Writing is atomic: a temporary file in the target's directory, renamed over the target only
// when complete, so a failure never leaves a partial output file.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "gyrocomp/core/status.h"

namespace gyrocomp {

// A column-major table of doubles with named columns.
struct Table {
  std::string source;                       // file name for messages ("<stdin>" for "-")
  std::vector<std::string> names;           // header, in file order
  std::vector<std::vector<double>> columns; // columns[j][i] = row i of column j
  // The file's whole header, in file order, when only some of its columns were kept (ReadCsv
  // with CsvReadOptions::columns); empty when `names` is the whole header. For messages: the
  // columns a file has, and the column number of a kept column (FileColumn).
  std::vector<std::string> header;
  // Number of rows (of the first column; 0 without columns).
  std::size_t num_rows() const { return columns.empty() ? 0 : columns.front().size(); }
  // Index of the named column, or -1.
  int Find(const std::string& name) const;
  // 1-based number of column j in the file (j + 1 unless columns were dropped on reading).
  std::size_t FileColumn(std::size_t j) const;
  // Every column name of the file: `header`, or `names` when it is empty.
  const std::vector<std::string>& FileNames() const { return header.empty() ? names : header; }
  // Drops column j (name and values); `header` is kept, so messages still see the file's columns.
  void Remove(std::size_t j);
  // Appends a column (must have num_rows() entries unless the table is empty).
  void Add(std::string name, std::vector<double> values);
  // Add, or, when a column of that name exists (a command run on its own output), replaces it in
  // place: returns true then. Keeps the names unique, as ReadCsv requires.
  bool Set(std::string name, std::vector<double> values);
};

// How ReadCsv parses and checks a file.
struct CsvReadOptions {
  // Field separator. Comma by default; a header that only parses with ';' or a tab is an error
  // that says so.
  char delimiter = ',';
  // Reject NaN / Inf cells (the gyro pipeline cannot use them). A cell reading "nan" is reported
  // as "NaN in column 'x'" rather than as non-numeric.
  bool reject_non_finite = true;
  // Longest line accepted, bytes. A longer one (/dev/zero, a binary file without line breaks) is
  // an error at that line instead of a buffer growing until memory runs out.
  std::size_t max_line_bytes = std::size_t{16} << 20;
  // Memory the table may take, bytes (8 per cell). Past it the read stops with an error saying
  // how much the file needs ("needs N GB ...; at most M GB allowed (--max-memory)").
  std::size_t max_memory_bytes = std::size_t{8} << 30;
  // The columns to keep, by name; nullopt (default): every column. With a list, the cells of
  // the other columns are still parsed and checked (a bad cell anywhere is the same error, at
  // the same line and column, as without it) but not stored, so the table takes 8 bytes per
  // kept cell only. Names the header lacks are ignored (the caller reports what it misses). The
  // kept columns stay in file order; Table::header holds the whole header. When no name matches,
  // the first column is kept, so that num_rows() still counts the file's rows.
  std::optional<std::vector<std::string>> columns;
};

// Reads `path` ("-" = stdin, plain or gzip). Errors: cannot open (kIo); empty file, header only,
// duplicate or empty header names, ragged row, non-numeric cell, NaN/Inf, binary garbage
// (NUL bytes or invalid UTF-8 in the header) (kInvalidInput).
Result<Table> ReadCsv(const std::string& path, const CsvReadOptions& options = {});

// The whole of a regular file, as bytes (the binary log readers parse it in memory). Errors
// (kIo): cannot open, size unknown (not a regular file), read error.
Result<std::string> ReadFileBytes(const std::string& path);

// Writes `table` as CSV with shortest round-trip formatting of every double (std::to_chars), so
// reading it back gives bit-identical values. ".gz" suffix -> gzip. Atomic (temp + rename).
Status WriteCsvAtomic(const std::string& path, const Table& table);

// Writes `text` to `path` atomically ("-" = stdout, not atomic by nature).
Status WriteTextAtomic(const std::string& path, const std::string& text);

}  // namespace gyrocomp
