#include "progress.h"

#include <unistd.h>

#include <cstdio>

namespace gyrocomp::cli {
namespace {
bool g_drawn = false;
}

ProgressCallback TerminalProgress(const std::string& command, bool quiet) {
  if (quiet || !isatty(STDERR_FILENO)) return {};
  return [command](const std::string& stage, double fraction) {
    std::fprintf(stderr, "\r\033[K%s: %s %3.0f%%", command.c_str(), stage.c_str(), 100.0 * fraction);
    std::fflush(stderr);
    g_drawn = true;
  };
}

void EndProgress() {
  if (g_drawn) std::fprintf(stderr, "\r\033[K");
  g_drawn = false;
}

}  // namespace gyrocomp::cli
