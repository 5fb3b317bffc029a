// Numbers in messages and reports: the one formatter of the library's error and summary texts.
#pragma once

#include <string>

namespace gyrocomp {

// v with `significant_digits` significant digits, printf "%.*g" (the same text as an ostream with
// that precision and default float format): 0.000123456, 1.5e+07, inf, nan. Default 6 digits.
std::string FormatNumber(double v, int significant_digits = 6);

}  // namespace gyrocomp
