// Damage reports of the binary log readers (include/gyrocomp/io/log_damage.h).
#include "gyrocomp/io/log_damage.h"

#include <nlohmann/json.hpp>

namespace gyrocomp {

namespace {

// "1-5": a byte or message id range; "from 7 on" for a message id range nothing after could be read.
std::string Range(const LogDamage& d) {
  if (d.message_ids && d.end <= d.begin) return "from " + std::to_string(d.begin) + " on";
  return std::to_string(d.begin) + "-" + std::to_string(d.end);
}

// "3 byte ranges (120 bytes)", "1 message id range (12 ids)": the ranges of one kind, or "".
std::string Ranges(const std::vector<LogDamage>& damage, bool message_ids) {
  std::size_t n = 0, units = 0;
  for (const LogDamage& d : damage) {
    if (d.message_ids != message_ids) continue;
    ++n;
    units += d.end > d.begin ? d.end - d.begin : 0;
  }
  if (n == 0) return "";
  return std::to_string(n) + (message_ids ? " message id range" : " byte range") + (n == 1 ? "" : "s") + " (" +
         std::to_string(units) + (message_ids ? " ids)" : " bytes)");
}

}  // namespace

std::string DamageWarning(const std::string& source, const std::vector<LogDamage>& damage) {
  if (damage.empty()) return "";
  std::map<std::string, std::size_t> lost;
  std::size_t unidentified = 0;
  std::string ranges;
  for (std::size_t i = 0; i < damage.size(); ++i) {
    const LogDamage& d = damage[i];
    for (const auto& [topic, rows] : d.rows_lost) lost[topic] += rows;
    unidentified += d.records_unidentified;
    // Each run of ranges of one kind is named once: "bytes 1-5 (...), 9-12 (...)".
    const bool named = i == 0 || damage[i - 1].message_ids != d.message_ids;
    const std::string kind = named ? (d.message_ids ? "message ids " : "bytes ") : "";
    if (i < 8) {
      ranges += (i ? ", " : "") + kind + Range(d) + " (" + d.what + ")";
    } else if (i == 8) {
      ranges += ", ... (" + std::to_string(damage.size() - 8) + " more in --json)";
    }
  }
  const std::string bytes = Ranges(damage, false), ids = Ranges(damage, true);
  std::string s = source + ": damaged: skipped " + bytes + (bytes.empty() || ids.empty() ? "" : " and ") + ids +
                  " and read on from the next valid record: " + ranges + "; rows lost: ";
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
    nlohmann::json j;
    if (d.message_ids) {
      j = {{"begin_message_id", d.begin},
           {"end_message_id", d.end > d.begin ? nlohmann::json(d.end) : nlohmann::json(nullptr)},
           {"messages", d.end > d.begin ? d.end - d.begin : 0}};
    } else {
      j = {{"begin_byte", d.begin}, {"end_byte", d.end}, {"bytes", d.end - d.begin}};
    }
    j["what"] = d.what;
    j["rows_lost"] = d.rows_lost;
    j["records_unidentified"] = d.records_unidentified;
    a.push_back(std::move(j));
  }
  return a;
}

}  // namespace gyrocomp
