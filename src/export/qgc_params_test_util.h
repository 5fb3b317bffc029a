// Test-only reader of QGroundControl parameter files (what `export --format px4` and `calibrate
// --format px4` write), shared by the export tests: '#' comment lines, then one parameter per line
// "sys<TAB>comp<TAB>NAME<TAB>VALUE<TAB>TYPE" (QGroundControl's ParameterManager file format).
#pragma once

#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace gyrocomp::testing {

struct QgcParam {
  std::string sys, comp, value, type;
};

struct QgcFile {
  bool has_column_header = false;  // the "# Vehicle-Id Component-Id Name Value Type" comment
  std::map<std::string, QgcParam> params;
  float Value(const std::string& name) const { return std::stof(params.at(name).value); }
};

// Every data line must have five tab-separated fields (a failed expectation names the line).
inline QgcFile ReadQgcFile(const std::string& text) {
  QgcFile out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line == "# Vehicle-Id Component-Id Name Value Type") out.has_column_header = true;
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::istringstream ls(line);
    std::string x;
    while (std::getline(ls, x, '\t')) f.push_back(x);
    EXPECT_EQ(f.size(), 5u) << line;
    if (f.size() != 5) continue;
    out.params[f[2]] = QgcParam{f[0], f[1], f[3], f[4]};
  }
  return out;
}

}  // namespace gyrocomp::testing
