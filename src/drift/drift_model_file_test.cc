// Model file compatibility and reproducibility: version 1 files still load and predict
// bit-identically; version 2 holds several axes; the same fit gives byte-identical files.
#include <cmath>

#include <gtest/gtest.h>

#include "gyrocomp/drift/drift_model.h"
#include "test_support.h"

namespace gyrocomp {
namespace {

// tests/golden/drift_v1: model files of format version 1 (written by earlier gyrocomp) and their predictions.
// Equality is exact: the model arithmetic is unchanged for one-part models, and the CSVs hold
// shortest round-trip doubles.
TEST(DriftModelFileV1, LoadsAndPredictsBitIdentically) {
  auto input = testing::ReadGoldenCsv(testing::GoldenPath("drift_v1/input.csv"));
  auto expected = testing::ReadGoldenCsv(testing::GoldenPath("drift_v1/predictions.csv"));
  const std::vector<std::pair<std::string, std::string>> files = {
      {"poly.json", "poly"}, {"svr.json", "svr"}, {"cs-svr.json", "cs_svr"}};
  for (const auto& [file, column] : files) {
    auto m = LoadDriftModel(testing::GoldenPath("drift_v1/" + file));
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->out_of_range, OutOfRangePolicy::kExtrapolate);
    EXPECT_EQ(m->rate_col, "rate_dps");
    auto p = m->Predict({input["temp_c"], 0.5});
    ASSERT_TRUE(p.ok()) << p.error().message;
    ASSERT_EQ(p->size(), expected[column].size());
    for (std::size_t i = 0; i < p->size(); ++i) ASSERT_EQ((*p)[i], expected[column][i]) << file << " sample " << i;
    // Written back as version 2 and read again: still the same predictions.
    auto again = DriftModelFromJson(DriftModelToJson(*m), "v2");
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_EQ(*again->Predict({input["temp_c"], 0.5}), *p) << file;
  }
}

std::vector<double> Chamber(double fs_hz, double hours) {
  const std::size_t n = static_cast<std::size_t>(hours * 3600.0 * fs_hz);
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = static_cast<double>(i) / static_cast<double>(n);
    t[i] = u < 0.5 ? 25.0 - 120.0 * u : -35.0 + 190.0 * (u - 0.5);
  }
  return t;
}

// Several axes in one file, each naming its rate column; reading one axis of a set is refused.
TEST(DriftModelFileV2, SeveralAxesRoundTrip) {
  const std::vector<double> temp = Chamber(1.0, 2.0);
  DriftModelSet set;
  for (const char* axis : {"gx", "gy", "gz"}) {
    std::vector<double> y(temp.size());
    for (std::size_t i = 0; i < y.size(); ++i) y[i] = (axis[1] - 'x' + 1) * 1e-3 * temp[i];
    DriftFitOptions o;
    o.model = DriftModelKind::kPolynomial;
    auto m = FitDriftModel({temp, 1.0}, y, o);
    ASSERT_TRUE(m.ok()) << m.error().message;
    m->rate_col = axis;
    set.axes.push_back(std::move(*m));
  }
  auto loaded = DriftModelSetFromJson(DriftModelSetToJson(set), "m.json");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  ASSERT_EQ(loaded->axes.size(), 3u);
  ASSERT_NE(loaded->Find("gz"), nullptr);
  EXPECT_EQ(*loaded->Find("gz")->Predict({temp, 1.0}), *set.axes[2].Predict({temp, 1.0}));
  EXPECT_EQ(loaded->Find("gq"), nullptr);
  auto one = DriftModelFromJson(DriftModelSetToJson(set), "m.json");
  ASSERT_FALSE(one.ok());
  EXPECT_EQ(one.error().message, "m.json: holds models for 3 axes (gx, gy, gz); read it as a model set");
}

// A file that is not JSON is refused with the line and column the parser stopped at, and why.
TEST(DriftModelFileV2, NotJsonSaysWhereAndWhy) {
  const auto nan = DriftModelSetFromJson("{\n \"axes\": [\n  NaN\n ]\n}\n", "m.json");
  ASSERT_FALSE(nan.ok());
  EXPECT_EQ(nan.error().kind, ErrorKind::kInvalidInput);
  EXPECT_EQ(nan.error().message.rfind("m.json:3:3: not valid JSON (", 0), 0u) << nan.error().message;
  EXPECT_NE(nan.error().message.find("invalid literal"), std::string::npos) << nan.error().message;
  const auto cut = DriftModelSetFromJson("{\n \"axes\": [", "m.json");
  ASSERT_FALSE(cut.ok());
  EXPECT_EQ(cut.error().message.rfind("m.json:2:", 0), 0u) << cut.error().message;
  EXPECT_NE(cut.error().message.find("end of input"), std::string::npos) << cut.error().message;
  EXPECT_EQ(cut.error().message.find('\n'), std::string::npos) << "one line";
  // A number beyond the double range stops the parser too (nlohmann's out_of_range, not a throw),
  // at the last byte of the number it read (column 15 of 1e400's 11-15).
  const auto big = DriftModelSetFromJson("{\"axes\": [1e400]}", "m.json");
  ASSERT_FALSE(big.ok());
  EXPECT_EQ(big.error().message, "m.json:1:15: not valid JSON (number overflow parsing '1e400')");
}

// Two fits of the same data with the same seed give byte-identical files, whatever the thread
// count (no timings in the file; the cuckoo search depends on the seed only).
TEST(DriftModelFileV2, ReproducibleBytes) {
  const double fs_hz = 0.5;
  const std::vector<double> temp = Chamber(fs_hz, 3.0);
  std::vector<double> y(temp.size());
  for (std::size_t i = 0; i < temp.size(); ++i) y[i] = 1e-3 * temp[i] + 2e-3 * std::sin(temp[i] / 7.0);
  DriftFitOptions o;
  o.model = DriftModelKind::kHybrid;
  o.inputs = DriftInputSet::kTempAndRate;
  o.max_train_samples = 150;
  o.search.cuckoo.num_nests = 5;
  o.search.cuckoo.max_generations = 2;
  o.search.cuckoo.num_threads = 1;
  auto a = FitDriftModel({temp, fs_hz}, y, o);
  o.search.cuckoo.num_threads = 2;
  auto b = FitDriftModel({temp, fs_hz}, y, o);
  ASSERT_TRUE(a.ok() && b.ok());
  const std::string ja = DriftModelToJson(*a);
  EXPECT_EQ(ja, DriftModelToJson(*b));
  EXPECT_EQ(ja.find("fit_time"), std::string::npos);
}

}  // namespace
}  // namespace gyrocomp
