// Progress on stderr for the long stages, only when stderr is a terminal and not --quiet.
#pragma once

#include <string>

#include "gyrocomp/pipeline/pipeline.h"

namespace gyrocomp::cli {

// A ProgressCallback that redraws one status line ("process: vmd 100% | entropy 50%") on a
// terminal, or an empty callback when stderr is not a terminal or `quiet`.
ProgressCallback TerminalProgress(const std::string& command, bool quiet);

// Ends the status line (newline) if one was drawn.
void EndProgress();

}  // namespace gyrocomp::cli
