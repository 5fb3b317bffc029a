// The self-contained HTML report: the last stage of the pipeline (io -> ... -> analysis ->
// report). It holds no numerics of its own: callers (process, demo) fill a ReportData from the
// results the stages returned, and RenderReportHtml turns it into one HTML file that opens
// offline, with the charting library (uPlot, MIT licence, from npm at build time) inlined.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gyrocomp {

// A series reduced for display: for each of at most `max_buckets` equal-width buckets of x, the
// minimum and the maximum of y in time order (two points per bucket), so spikes and the noise
// envelope of millions of samples stay visible while the page stays responsive.
struct DisplaySeries {
  std::vector<double> x;  // x of each kept point (x of the bucket's min or max)
  std::vector<double> y;  // y of each kept point
};
// The envelope of y(x) over at most `max_buckets` buckets; a series no longer than 2 x max_buckets
// is returned whole.
DisplaySeries MinMaxEnvelope(std::span<const double> x, std::span<const double> y,
                             std::size_t max_buckets = 2000);
// The same bucket boundaries applied to several y series sharing x (each keeps its own min/max).
std::vector<DisplaySeries> MinMaxEnvelopes(std::span<const double> x,
                                           const std::vector<std::span<const double>>& ys,
                                           std::size_t max_buckets = 2000);

// Report content. Every field is optional; absent sections are not drawn. Schema (JSON):
//   title, subtitle: strings
//   summary: {title, columns: [str], rows: [[str|num]], note}  headline table (title optional,
//            default "Before and after")
//   timeseries: {title, note, x_label, x: [..], series: [{name, y: [..], axis: "rate"|"temp"}]}
//            (title, note optional: default "Rate and temperature" and the envelope note)
//   modes: [{index, sample_entropy, center_frequency_hz, class, x: [..], y: [..]}]
//   allan: [{name, tau_s: [..], adev_dps: [..], lo_dps: [..], hi_dps: [..],
//            lines: [{name, tau_s: [..], adev_dps: [..]}]}]    fitted noise-term lines
//   drift: {temp_c: [..], drift_dps: [..], model_temp_c: [..], model_dps: [..]}
//   sections: [{title, note, table: {columns, rows, note}, charts: [xy]}]  groups of charts with
//            their table (drawn after drift, before tables; e.g. one per calibrated sensor), table
//            and charts optional; an xy chart is a scatter with line overlays and bands:
//            {title, x_label, y_label, points: [{name, x: [..], y: [..]}] (one colour each),
//             lines: [{name, x: [..], y: [..]}], bands: [{name, x: [..], lo: [..], hi: [..]}]}
//            (x need not be sorted; every entry has its own x; other fields of an entry, e.g.
//            calibrate's rows / every of a thinned points entry, are not drawn)
//   tables: [{title, columns: [str], rows: [[..]], note}]
//   parameters: any JSON (printed verbatim); versions: {name: version}
struct ReportData {
  nlohmann::json content = nlohmann::json::object();  // the sections above; empty by default
};

// The complete HTML document.
std::string RenderReportHtml(const ReportData& data);

}  // namespace gyrocomp
