#include "demo_table.h"

#include <cmath>

#include "gyrocomp/report/applicability.h"
#include "report_builder.h"
#include "result_json.h"
#include "table_printer.h"

namespace gyrocomp::cli {
namespace {

TableCell Value(std::optional<double> v) { return {v, "", ""}; }
TableCell Text(const std::string& text) { return {std::nullopt, text, ""}; }
TableCell NotApplicable(const std::string& reason) { return {std::nullopt, "", reason}; }

TableCell Term(const AllanResult& a, std::optional<double> bandwidth_hz, bool arw) {
  const TermApplicability t = arw ? ArwApplicability(a, bandwidth_hz) : RrwApplicability(a, bandwidth_hz);
  if (!t.applicable) return NotApplicable(t.reason);
  return Value(arw ? a.terms.arw_deg_per_sqrt_h : a.terms.rrw_deg_per_h_per_sqrt_h);
}

std::string CellText(const TableCell& c, int note_number) {
  if (!c.not_applicable.empty()) return "n/a [" + std::to_string(note_number) + "]";
  if (!c.text.empty()) return c.text;
  return FormatNumber(c.value);
}

}  // namespace

SideBySideTable DemoTable(const std::vector<DemoVariant>& ours, const std::string& held_out_label,
                          const PaperFigures& paper) {
  SideBySideTable t;
  for (const DemoVariant& v : ours) {
    t.columns.push_back(v.name);
    t.keys.push_back(v.key);
  }
  t.columns.insert(t.columns.end(), {"paper: raw", "paper: processed"});
  t.keys.insert(t.keys.end(), {"paper_raw", "paper_processed"});
  const TableCell not_reported = Text("not reported");
  auto row = [&](std::string metric, std::string unit, std::string key, auto ours_cell, TableCell paper_raw,
                 TableCell paper_processed) {
    SideBySideRow r{std::move(metric), std::move(unit), std::move(key), {}};
    for (const DemoVariant& v : ours) r.cells.push_back(ours_cell(v));
    r.cells.push_back(std::move(paper_raw));
    r.cells.push_back(std::move(paper_processed));
    t.rows.push_back(std::move(r));
  };
  row("ARW", "deg/sqrt(h)", "arw_deg_per_sqrt_h", [](const DemoVariant& v) { return Term(*v.allan, v.bandwidth_hz, true); },
      Value(paper.arw_raw),
      NotApplicable("ARW without the record's bandwidth is not comparable: the paper publishes " +
                    FormatNumber(paper.arw_processed) + " (Figure 13, abstract) and reports no bandwidth"));
  row("bandwidth (-3 dB)", "Hz", "bandwidth_hz", [](const DemoVariant& v) { return Value(v.bandwidth_hz); },
      not_reported, not_reported);
  row("ADEV minimum (bias stability)", "deg/h", "adev_min_deg_per_h",
      [](const DemoVariant& v) { return Value(v.allan->terms.adev_min_deg_per_h); }, Value(paper.bs_raw),
      Value(paper.bs_processed));
  row("ADEV minimum over tau >= 10 s", "deg/h", "adev_min_tau_ge_10s_deg_per_h",
      [](const DemoVariant& v) { return Value(AdevMinAbove(v.allan->curve, 10.0)); }, not_reported, not_reported);
  row("RRW", "deg/h/sqrt(h)", "rrw_deg_per_h_per_sqrt_h",
      [](const DemoVariant& v) { return Term(*v.allan, v.bandwidth_hz, false); }, not_reported, not_reported);
  row("drift RMSE vs truth, this run", "deg/s", "drift_rmse_dps",
      [](const DemoVariant& v) { return Value(v.drift_rmse_dps); }, not_reported, not_reported);
  row("drift RMSE vs truth, held-out run", "deg/s", "held_out_drift_rmse_dps",
      [](const DemoVariant& v) { return Value(v.held_out_drift_rmse_dps); }, not_reported, not_reported);
  row("RMSE vs true rate, this run", "deg/s", "rate_rmse_dps", [](const DemoVariant& v) { return Value(v.rate_rmse_dps); },
      not_reported, not_reported);
  t.note = "Raw: the simulated record (its bandwidth is the Nyquist frequency; drift error = the true drift left in "
           "it). Drift RMSE: the model's prediction against the simulator's true drift; held-out: the models "
           "fitted on this run applied to " + held_out_label + ". Paper: Chang, Cao & Shen 2020, Section 4.3.1, "
           "Figure 13 and the abstract (its drift errors and bandwidth are not published). Not applicable: the "
           "rule of docs/explanation/pipeline.md (bandwidth known, taus >= 1/(2 bandwidth), ADEV slope within 0.2 of -1/2 for "
           "ARW, +1/2 for RRW).";
  return t;
}

std::string FormatSideBySide(const SideBySideTable& t) {
  std::vector<std::string> header = {""};
  header.insert(header.end(), t.columns.begin(), t.columns.end());
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> notes;
  for (const SideBySideRow& r : t.rows) {
    std::vector<std::string> cells = {r.metric + " (" + r.unit + ")"};
    for (std::size_t k = 0; k < r.cells.size(); ++k) {
      const TableCell& c = r.cells[k];
      if (!c.not_applicable.empty()) notes.push_back(r.metric + ", " + t.columns[k] + ": not applicable: " + c.not_applicable);
      cells.push_back(CellText(c, static_cast<int>(notes.size())));
    }
    rows.push_back(std::move(cells));
  }
  std::string out = FormatTable(header, rows);
  for (std::size_t i = 0; i < notes.size(); ++i) out += "  [" + std::to_string(i + 1) + "] " + notes[i] + "\n";
  return out;
}

nlohmann::json SideBySideJson(const SideBySideTable& t) {
  nlohmann::json rows = nlohmann::json::array();
  for (const SideBySideRow& r : t.rows) {
    nlohmann::json values = nlohmann::json::object(), text = nlohmann::json::object(), na = nlohmann::json::object();
    for (std::size_t k = 0; k < r.cells.size() && k < t.keys.size(); ++k) {
      values[t.keys[k]] = Num(r.cells[k].value);
      if (!r.cells[k].text.empty()) text[t.keys[k]] = r.cells[k].text;
      if (!r.cells[k].not_applicable.empty()) na[t.keys[k]] = r.cells[k].not_applicable;
    }
    rows.push_back({{"metric", r.metric}, {"unit", r.unit}, {"key", r.key}, {"values", values}, {"text", text},
                    {"not_applicable", na}});
  }
  return {{"columns", t.keys}, {"column_names", t.columns}, {"rows", rows}, {"note", t.note}};
}

nlohmann::json SideBySideReportTable(const SideBySideTable& t, const std::string& title) {
  nlohmann::json columns = {"metric"};
  for (const std::string& c : t.columns) columns.push_back(c);
  nlohmann::json rows = nlohmann::json::array();
  std::string note = t.note;
  for (const SideBySideRow& r : t.rows) {
    nlohmann::json cells = {r.metric + " (" + r.unit + ")"};
    for (std::size_t k = 0; k < r.cells.size(); ++k) {
      const TableCell& c = r.cells[k];
      if (!c.not_applicable.empty()) {
        cells.push_back("not applicable");
        note += " " + r.metric + ", " + t.columns[k] + ": " + c.not_applicable + ".";
      } else if (!c.text.empty()) {
        cells.push_back(c.text);
      } else {
        cells.push_back(Num(c.value));
      }
    }
    rows.push_back(cells);
  }
  return {{"title", title}, {"columns", columns}, {"rows", rows}, {"note", note}};
}

}  // namespace gyrocomp::cli
