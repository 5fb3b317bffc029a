// Plain-text tables for the console (compare, demo).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace gyrocomp::cli {

// "n/a" for nullopt / non-finite, otherwise `digits` significant digits.
std::string FormatNumber(std::optional<double> v, int digits = 4);

// Left-aligned first column, right-aligned others; header underlined.
std::string FormatTable(const std::vector<std::string>& header,
                        const std::vector<std::vector<std::string>>& rows);

}  // namespace gyrocomp::cli
