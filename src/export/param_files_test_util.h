// Test-only readers of the parameter files `export` and `calibrate` write, shared by the export
// tests:
// - QGroundControl (--format px4): '#' comment lines, then one parameter per line
//   "sys<TAB>comp<TAB>NAME<TAB>VALUE<TAB>TYPE" (QGroundControl's ParameterManager file format);
// - Mission Planner (--format ardupilot): '#' comment lines, then "NAME,VALUE", names of at most
//   16 characters (ArduPilot's AP_MAX_NAME_SIZE).
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

inline std::map<std::string, float> ReadMissionPlannerFile(const std::string& text) {
  std::map<std::string, float> p;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto comma = line.find(',');
    EXPECT_NE(comma, std::string::npos) << line;
    EXPECT_LE(comma, 16u) << line;
    if (comma == std::string::npos) continue;
    p[line.substr(0, comma)] = std::stof(line.substr(comma + 1));
  }
  return p;
}

}  // namespace gyrocomp::testing
