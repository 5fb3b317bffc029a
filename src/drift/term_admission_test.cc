// Eqs. A-1..A-4 (term_admission.h) in closed form.
#include "gyrocomp/drift/term_admission.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

namespace gyrocomp {
namespace {

const std::vector<double> kSimpler = {3.0, 3.0, 3.0, 3.0};

// A steady gain of 0.1 on every fold: SE 0, admitted.
TEST(TermAdmission, SteadyGainIsAdmitted) {
  const TermGain g = PairedTermGain(kSimpler, std::vector<double>{2.9, 2.9, 2.9, 2.9});
  EXPECT_NEAR(g.gain, 0.1, 1e-15);  // Eq. A-1; 1e-15: four subtractions of O(1) numbers
  EXPECT_NEAR(g.se, 0.0, 1e-15);
  EXPECT_EQ(g.pairs, 4u);
  EXPECT_TRUE(g.Admitted());
}

// Gains {1, -0.5, 1, -0.5}: mean 0.25, SD sqrt(4 * 0.75^2 / 3) = 0.866, SE 0.433 > 0.25: the gain
// lies within its SE, the term is rejected and the simpler model stands.
TEST(TermAdmission, GainWithinItsStandardErrorIsRejected) {
  const TermGain g = PairedTermGain(kSimpler, std::vector<double>{2.0, 3.5, 2.0, 3.5});
  EXPECT_NEAR(g.gain, 0.25, 1e-15);
  EXPECT_NEAR(g.se, std::sqrt(4 * 0.5625 / 3.0) / 2.0, 1e-15);  // Eqs.
  EXPECT_FALSE(g.Admitted());
}

// Gains {0.5, -0.1, 0.5, -0.1}: mean 0.2, SD sqrt(4 * 0.09 / 3) = 0.346, SE 0.173 < 0.2: admitted
// by Eq. A-4, while the kernel's stricter mean > SD (Eq. H-1) would not take it.
TEST(TermAdmission, StandardErrorNotSpreadDecides) {
  const TermGain g = PairedTermGain(kSimpler, std::vector<double>{2.5, 3.1, 2.5, 3.1});
  EXPECT_NEAR(g.gain, 0.2, 1e-15);
  EXPECT_NEAR(g.Sd(), std::sqrt(4 * 0.09 / 3.0), 1e-14);
  EXPECT_NEAR(g.se, std::sqrt(4 * 0.09 / 3.0) / 2.0, 1e-14);
  EXPECT_TRUE(g.Admitted());
  EXPECT_LT(g.gain, g.Sd());
}

// A richer model that is worse on every fold: negative gain, rejected.
TEST(TermAdmission, NegativeGainIsRejected) {
  const TermGain g = PairedTermGain(kSimpler, std::vector<double>{3.1, 3.2, 3.1, 3.2});
  EXPECT_LT(g.gain, 0.0);
  EXPECT_FALSE(g.Admitted());
}

// One pair gives no spread to judge by: SE +inf, never admitted; non-finite pairs are skipped.
TEST(TermAdmission, NeedsTwoFinitePairs) {
  TermGain g = PairedTermGain(std::vector<double>{3.0}, std::vector<double>{1.0});
  EXPECT_EQ(g.pairs, 1u);
  EXPECT_TRUE(std::isinf(g.se));
  EXPECT_FALSE(g.Admitted());
  const double inf = std::numeric_limits<double>::infinity();
  g = PairedTermGain(std::vector<double>{3.0, 3.0, 3.0}, std::vector<double>{2.0, inf, 2.0});
  EXPECT_EQ(g.pairs, 2u);
  EXPECT_NEAR(g.gain, 1.0, 1e-15);
  EXPECT_TRUE(g.Admitted());
}

TEST(TermAdmission, BriefReport) {
  const TermGain g{0.00012, 0.00005, 7};
  EXPECT_EQ(g.BriefReport(1000.0, "mdps", "segments"), "gain 0.12 +- 0.05 mdps (7 segments)");
}

}  // namespace
}  // namespace gyrocomp
