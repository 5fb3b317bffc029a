#include "table_printer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gyrocomp::cli {

std::string FormatNumber(std::optional<double> v, int digits) {
  if (!v || !std::isfinite(*v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, *v);
  return buf;
}

std::string FormatTable(const std::vector<std::string>& header,
                        const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width(header.size(), 0);
  for (std::size_t j = 0; j < header.size(); ++j) width[j] = header[j].size();
  for (const auto& row : rows) {
    for (std::size_t j = 0; j < row.size() && j < width.size(); ++j) width[j] = std::max(width[j], row[j].size());
  }
  auto line = [&](const std::vector<std::string>& cells) {
    std::string s;
    for (std::size_t j = 0; j < width.size(); ++j) {
      const std::string cell = j < cells.size() ? cells[j] : "";
      const std::string pad(width[j] - std::min(width[j], cell.size()), ' ');
      s += (j == 0 ? cell + pad : pad + cell);
      if (j + 1 < width.size()) s += "  ";
    }
    return s + "\n";
  };
  std::string out = line(header);
  std::size_t total = 0;
  for (std::size_t w : width) total += w + 2;
  out += std::string(total > 2 ? total - 2 : total, '-') + "\n";
  for (const auto& row : rows) out += line(row);
  return out;
}

}  // namespace gyrocomp::cli
