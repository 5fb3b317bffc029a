// Damage reports of the binary log readers (include/gyrocomp/io/log_damage.h).
#include "gyrocomp/io/log_damage.h"

#include <nlohmann/json.hpp>

namespace gyrocomp {

std::string DamageWarning(const std::string& source, const std::vector<LogDamage>& damage) {
  if (damage.empty()) return "";
  std::size_t bytes = 0;
  std::map<std::string, std::size_t> lost;
  std::size_t unidentified = 0;
  std::string ranges;
  for (std::size_t i = 0; i < damage.size(); ++i) {
    const LogDamage& d = damage[i];
    bytes += d.end - d.begin;
    for (const auto& [topic, rows] : d.rows_lost) lost[topic] += rows;
    unidentified += d.records_unidentified;
    if (i < 8) {
      ranges += (i ? ", " : "") + std::to_string(d.begin) + "-" + std::to_string(d.end) + " (" + d.what + ")";
    } else if (i == 8) {
      ranges += ", ... (" + std::to_string(damage.size() - 8) + " more in --json)";
    }
  }
  std::string s = source + ": damaged: skipped " + std::to_string(damage.size()) + " byte range" +
                  (damage.size() == 1 ? "" : "s") + " (" + std::to_string(bytes) + " bytes) and read on from the next " +
                  "valid record: bytes " + ranges + "; rows lost: ";
  if (lost.empty() && unidentified == 0) s += "none";
  bool first = true;
  for (const auto& [topic, rows] : lost) {
    s += (first ? "" : ", ") + topic + " " + std::to_string(rows);
    first = false;
  }
  if (unidentified > 0) {
    s += (first ? "" : ", ") + std::to_string(unidentified) + " record" + (unidentified == 1 ? "" : "s") +
         " of unknown topic";
  }
  s += " (--strict refuses damaged logs)";
  return s;
}

nlohmann::json DamageJson(const std::vector<LogDamage>& damage) {
  nlohmann::json a = nlohmann::json::array();
  for (const LogDamage& d : damage) {
    a.push_back({{"begin_byte", d.begin},
                 {"end_byte", d.end},
                 {"bytes", d.end - d.begin},
                 {"what", d.what},
                 {"rows_lost", d.rows_lost},
                 {"records_unidentified", d.records_unidentified}});
  }
  return a;
}

}  // namespace gyrocomp
