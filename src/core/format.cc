// Numbers in messages: see format.h.
#include "gyrocomp/core/format.h"

#include <cstdio>

namespace gyrocomp {

std::string FormatNumber(double v, int significant_digits) {
  char buf[48];  // "%.17g" of any double fits in 25 characters; more digits are not meaningful
  const int digits = significant_digits < 1 ? 1 : significant_digits > 17 ? 17 : significant_digits;
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace gyrocomp
