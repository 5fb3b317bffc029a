// Helpers for tests: where the golden vectors and the (licensed, optional) real recordings are,
// and small readers for them that do not depend on gyrocomp's own CSV reader.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gyrocomp::testing {

// tests/golden/<relative> (copied from ../shared/golden; see tests/golden/README.md).
std::string GoldenPath(const std::string& relative);

// ../shared/realdata/<relative>, or "" when that folder is absent (a user's fresh clone): tests
// that need it call GTEST_SKIP() with the reason then.
std::string RealdataPath(const std::string& relative);

// Path of the built gyrocomp CLI (for end-to-end tests), or "" when the CLI is not built.
std::string CliPath();

nlohmann::json ReadJsonFile(const std::string& path);

// Reads a plain numeric CSV with a header into name -> column. Aborts the test on error.
std::map<std::string, std::vector<double>> ReadGoldenCsv(const std::string& path);

// A fresh empty directory under the system temp dir for a test's files.
std::string MakeTempDir(const std::string& prefix);

// Runs `command` with /bin/sh, returns its exit status; stdout+stderr captured into *output.
int RunCommand(const std::string& command, std::string* output);

}  // namespace gyrocomp::testing
