#include "gyrocomp/report/report.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string_view>

namespace gyrocomp {
namespace report_assets {
extern const unsigned char kUplotJs[];
extern const std::size_t kUplotJs_size;
extern const unsigned char kUplotCss[];
extern const std::size_t kUplotCss_size;
extern const unsigned char kUplotLicense[];
extern const std::size_t kUplotLicense_size;
extern const unsigned char kReportJs[];
extern const std::size_t kReportJs_size;
extern const unsigned char kReportCss[];
extern const std::size_t kReportCss_size;
}  // namespace report_assets

namespace {

std::string_view Asset(const unsigned char* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Text placed inside <script> must not contain "</" (it would end the element early).
std::string ScriptSafe(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') {
      out += "<\\/";
      ++i;
    } else {
      out += text[i];
    }
  }
  return out;
}

std::string HtmlEscape(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::vector<DisplaySeries> MinMaxEnvelopes(std::span<const double> x,
                                           const std::vector<std::span<const double>>& ys,
                                           std::size_t max_buckets) {
  std::vector<DisplaySeries> out(ys.size());
  const std::size_t n = x.size();
  for ([[maybe_unused]] const auto& y : ys) assert(y.size() == n);
  if (n == 0) return out;
  max_buckets = std::max<std::size_t>(max_buckets, 1);
  if (n <= 2 * max_buckets) {  // small enough to draw every point
    for (std::size_t s = 0; s < ys.size(); ++s) {
      out[s].x.assign(x.begin(), x.end());
      out[s].y.assign(ys[s].begin(), ys[s].end());
    }
    return out;
  }
  for (std::size_t s = 0; s < ys.size(); ++s) {
    out[s].x.reserve(2 * max_buckets);
    out[s].y.reserve(2 * max_buckets);
  }
  for (std::size_t b = 0; b < max_buckets; ++b) {
    const std::size_t lo = b * n / max_buckets;
    const std::size_t hi = (b + 1) * n / max_buckets;
    if (lo >= hi) continue;
    for (std::size_t s = 0; s < ys.size(); ++s) {
      const auto& y = ys[s];
      std::size_t imin = lo, imax = lo;
      for (std::size_t i = lo; i < hi; ++i) {
        if (y[i] < y[imin]) imin = i;
        if (y[i] > y[imax]) imax = i;
      }
      // Two points per bucket, placed at the bucket's first and last x so every series shares
      // the same x grid (uPlot needs one x array per chart), min/max in time order.
      const bool min_first = imin <= imax;
      out[s].x.push_back(x[lo]);
      out[s].y.push_back(min_first ? y[imin] : y[imax]);
      out[s].x.push_back(x[hi - 1]);
      out[s].y.push_back(min_first ? y[imax] : y[imin]);
    }
  }
  return out;
}

DisplaySeries MinMaxEnvelope(std::span<const double> x, std::span<const double> y,
                             std::size_t max_buckets) {
  return MinMaxEnvelopes(x, {y}, max_buckets).front();
}

std::string RenderReportHtml(const ReportData& data) {
  using namespace report_assets;
  const nlohmann::json& c = data.content;
  const std::string title = c.contains("title") && c["title"].is_string()
                                ? c["title"].get<std::string>()
                                : std::string("gyrocomp report");
  std::string html;
  html.reserve(kUplotJs_size + kReportJs_size + (std::size_t{1} << 16));
  html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  html += "<meta name=\"generator\" content=\"gyrocomp " GYROCOMP_VERSION "\">\n";
  html += "<title>" + HtmlEscape(title) + "</title>\n<style>\n";
  html += Asset(kUplotCss, kUplotCss_size);
  html += "\n";
  html += Asset(kReportCss, kReportCss_size);
  html += "\n</style>\n</head>\n<body data-render-status=\"pending\">\n";
  html += "<main id=\"report\"><h1>" + HtmlEscape(title) + "</h1></main>\n";
  // NaN / Inf are not JSON: nlohmann writes them as null, which uPlot draws as a gap.
  html += "<script type=\"application/json\" id=\"report-data\">";
  html += ScriptSafe(c.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  html += "</script>\n<script>\n/* uPlot ";
  html += ScriptSafe(Asset(kUplotLicense, kUplotLicense_size));
  html += " */\n";
  html += ScriptSafe(Asset(kUplotJs, kUplotJs_size));
  html += "\n</script>\n<script>\n";
  html += ScriptSafe(Asset(kReportJs, kReportJs_size));
  html += "\n</script>\n</body>\n</html>\n";
  return html;
}

}  // namespace gyrocomp
