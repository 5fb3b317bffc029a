#include "gyrocomp/core/format.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace gyrocomp {
namespace {

std::string Stream(double v, int precision) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

TEST(FormatNumber, SixSignificantDigitsByDefault) {
  EXPECT_EQ(FormatNumber(0.1), "0.1");
  EXPECT_EQ(FormatNumber(1.0 / 3.0), "0.333333");
  EXPECT_EQ(FormatNumber(123456789.0), "1.23457e+08");
  EXPECT_EQ(FormatNumber(-2.5e-7), "-2.5e-07");
  EXPECT_EQ(FormatNumber(0.0), "0");
}

TEST(FormatNumber, GivenDigits) {
  EXPECT_EQ(FormatNumber(3.14159265, 4), "3.142");
  EXPECT_EQ(FormatNumber(3.14159265, 1), "3");
  EXPECT_EQ(FormatNumber(0.1, 17), "0.10000000000000001");
  EXPECT_EQ(FormatNumber(0.1, 40), "0.10000000000000001");  // clamped to 17
  EXPECT_EQ(FormatNumber(2.0, 0), "2");                      // clamped to 1
}

// The text the ostream formatters it replaced printed (messages must not change).
TEST(FormatNumber, SameTextAsAnOstreamWithThatPrecision) {
  const double values[] = {0.0,    -0.0,    1.0,     -1.5,   1e-300, 4.9e-324, 1.7976931348623157e308,
                           123.456, 1e6,    1e-5,    0.1234567, 98765.4321,
                           std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                           std::nan("")};
  for (double v : values) {
    for (int p : {4, 6}) EXPECT_EQ(FormatNumber(v, p), Stream(v, p)) << v << " precision " << p;
  }
}

}  // namespace
}  // namespace gyrocomp
