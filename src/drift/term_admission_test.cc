// Eqs. A-1..A-5 (term_admission.h) in closed form.
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

// A setting that wins on one fold only: lowest overall (mean 2.575 < 3), yet on each fold the
// choice made on the other three is the one that fold then scores (Eq. A-5): fold 0 gets
// setting 0 (others' means 3 < 3.1), folds 1-3 get setting 1 (others' means 2.4 < 3).
TEST(TermAdmission, NestedChoiceScoresEachFoldWithTheOthersChoice) {
  const std::vector<std::vector<double>> scores{{3.0, 3.0, 3.0, 3.0}, {1.0, 3.1, 3.1, 3.1}};
  EXPECT_EQ(LowestMeanSetting(scores, scores[0].size()), 1u);
  EXPECT_EQ(LowestMeanSetting(scores, 0), 0u);
  EXPECT_EQ(LowestMeanSetting(scores, 2), 1u);
  EXPECT_EQ(NestedChoiceRmse(scores), (std::vector<double>{3.0, 3.1, 3.1, 3.1}));
  // Read on its own scores the fluke gains 0.425 over the simpler model; nested it loses 0.075.
  EXPECT_NEAR(PairedTermGain(kSimpler, scores[1]).gain, 0.425, 1e-15);
  EXPECT_NEAR(PairedTermGain(kSimpler, NestedChoiceRmse(scores)).gain, -0.075, 1e-15);
}

// A setting better on every fold is chosen on every fold: nesting leaves its scores as they are.
TEST(TermAdmission, NestedChoiceKeepsAConsistentWinner) {
  const std::vector<std::vector<double>> scores{{3.0, 3.0, 3.0}, {2.9, 2.8, 2.95}, {3.2, 2.6, 3.3}};
  EXPECT_EQ(NestedChoiceRmse(scores), scores[1]);
}

// Ties go to the lower setting; non-finite RMSEs are left out of a mean; a row of another size
// is never chosen; nothing in, nothing out.
TEST(TermAdmission, NestedChoiceEdges) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(LowestMeanSetting({{1.0, 2.0}, {2.0, 1.0}}, 5), 0u);
  EXPECT_EQ(LowestMeanSetting({{2.0, 2.0, 2.0}, {nan, 1.0, 1.0}}, 3), 1u);
  EXPECT_EQ(LowestMeanSetting({{nan, nan}, {5.0, 5.0}}, 2), 1u);
  EXPECT_EQ(LowestMeanSetting({{2.0, 2.0}, {1.0}}, 2), 0u);
  EXPECT_EQ(LowestMeanSetting({}, 0), 0u);
  EXPECT_TRUE(NestedChoiceRmse({}).empty());
}

}  // namespace
}  // namespace gyrocomp
