// Console output for people: each command's default summary is a few lines a person reads in
// ten seconds (what was read, what came out, the headline figure beside what it is compared
// with, each warning once, the next step); --verbose and --json keep the full detail.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace gyrocomp::cli {

// True when stderr is a terminal and NO_COLOR is unset or empty (https://no-color.org).
bool UseColour();

// `text` in bold / in the warning colour when UseColour(), else unchanged.
std::string Bold(const std::string& text);
std::string WarnColour(const std::string& text);

// `v` with `digits` significant digits; a magnitude below 1e-7 of its unit (below a float's
// resolution at one unit, e.g. 2e-19 rad/s) prints as 0, a missing or non-finite value as "n/a".
std::string Figure(double v, int digits = 3);
std::string Figure(const std::optional<double>& v, int digits = 3);

// A gyro rate or rate error in the unit a person reads, labelled: "18.1 mdps" below 1 deg/s,
// "1.23 deg/s" from 1 deg/s up. `rad_s` variant converts first.
std::string RateDps(double dps, int digits = 3);
std::string RateRadS(double rad_s, int digits = 3);

// "before -> after unit (ratio x)": the headline figure beside what it is compared with.
std::string BeforeAfter(double before, double after, const std::string& unit, int digits = 3);

// Prints "gyrocomp COMMAND: text" on stderr (the summary's first line, the command name bold).
void Headline(const std::string& command, const std::string& text);
// Prints "  text" on stderr (a summary line under the headline).
void Line(const std::string& text);

// Prints "  wrote A, B" on stderr for the paths given (empty ones and "-", stdout, left out).
void Wrote(const std::vector<std::string>& paths);

}  // namespace gyrocomp::cli
