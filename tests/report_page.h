// The HTML report (gyrocomp/report/report.h) as its tests read it: the data block parsed back,
// and the page as headless Chromium leaves it after its script ran.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace gyrocomp::testing {

// The report's data block (report.h schema), parsed back; null when the page has none.
inline nlohmann::json ReportDataOf(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"report-data\">";
  const auto start = html.find(open);
  if (start == std::string::npos) return nullptr;
  const auto end = html.find("</script>", start);
  std::string text = html.substr(start + open.size(), end - start - open.size());
  for (std::size_t p = 0; (p = text.find("<\\/", p)) != std::string::npos;) text.replace(p, 3, "</");
  return nlohmann::json::parse(text);
}

// The DOM of the page at `path` after Debian's headless Chromium ran its script (--dump-dom),
// with Chromium's log after it, into *output; `dir` holds the browser profile. False without
// /usr/bin/chromium (scripts/install-deps.sh --browser installs it); else Chromium's exit status is 0.
// The skip message of a test whose rendering part needs Chromium (its other checks have run).
inline constexpr char kNoChromium[] =
    "rendering not checked: no /usr/bin/chromium (scripts/install-deps.sh --browser); the checks before it ran";

inline bool DumpDomInChromium(const std::string& path, const std::string& dir, std::string* output, int* status) {
  const char* chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium)) return false;
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
      " --disable-background-networking --disable-component-update --disable-sync"
      " --user-data-dir=" + dir + "/profile --enable-logging=stderr --v=0"
      " --virtual-time-budget=5000 --dump-dom file://" + path;
  *status = RunCommand(std::string(chromium) + flags, output);
  return true;
}

}  // namespace gyrocomp::testing
