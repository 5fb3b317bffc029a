// The demo's side-by-side table: the raw record, the paper's pipeline
// (CS-SVR drift branch), gyrocomp's default (auto drift branch) and the paper's published figures,
// with the drift error against the simulator's truth on the run and on a held-out run. Figures the
// processing makes meaningless are cells with a not-applicable reason (gyrocomp/report/
// applicability.h), the same in the console, the JSON and the report.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gyrocomp/allan/allan.h"

namespace gyrocomp::cli {

struct TableCell {
  std::optional<double> value;
  std::string text;            // shown instead of a number (e.g. "not reported"); "" = the number
  std::string not_applicable;  // why the figure is meaningless here; "" = applicable
};

struct SideBySideRow {
  std::string metric;
  std::string unit;
  std::string key;                // JSON key of the row
  std::vector<TableCell> cells;   // one per column
};

struct SideBySideTable {
  std::vector<std::string> columns;  // headers of the value columns
  std::vector<std::string> keys;     // JSON keys of the value columns
  std::vector<SideBySideRow> rows;
  std::string note;
};

// One output of the demo run measured against the truth (ours: raw, paper pipeline, default).
struct DemoVariant {
  std::string key, name;
  const AllanResult* allan = nullptr;
  std::optional<double> bandwidth_hz;          // raw: fs/2; processed: measured
  std::optional<double> drift_rmse_dps;        // model - true drift on this run (raw: the true drift)
  std::optional<double> held_out_drift_rmse_dps;  // the same on the held-out run
  std::optional<double> rate_rmse_dps;         // output - true rate
};

// The published figures of Chang, Cao & Shen 2020 (Section 4.3.1, Figure 13 and the abstract).
struct PaperFigures {
  double arw_raw = 1.667, arw_processed = 0.0667;  // deg/sqrt(h)
  double bs_raw = 30.0, bs_processed = 4.0;       // "bias stability" = ADEV minimum, deg/h
};

// Rows: ARW, bandwidth, ADEV minimum, ADEV minimum over tau >= 10 s, RRW, drift RMSE vs truth
// (this run), drift RMSE vs truth (held-out run, described by held_out_label), RMSE vs true rate.
// Columns: each variant, then "paper: raw" and "paper: processed".
SideBySideTable DemoTable(const std::vector<DemoVariant>& ours, const std::string& held_out_label,
                          const PaperFigures& paper = {});

// Console text: numbers, "n/a [k]" for not-applicable cells and the reasons as numbered notes.
std::string FormatSideBySide(const SideBySideTable& t);
// JSON: {columns, rows: [{metric, unit, key, values: {column key: number | null},
//        text: {column key: string}, not_applicable: {column key: reason}}], note}.
nlohmann::json SideBySideJson(const SideBySideTable& t);
// A report table ({title, columns, rows, note}): "not applicable" in the cell, reasons in the note.
nlohmann::json SideBySideReportTable(const SideBySideTable& t, const std::string& title);

}  // namespace gyrocomp::cli
