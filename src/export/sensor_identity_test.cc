// The model file's top-level "sensor" key (docs/reference/model-file.md): written, read
// back, optional for older files, refused when malformed.
#include <gtest/gtest.h>

#include "gyrocomp/drift/drift_model.h"

namespace gyrocomp {
namespace {

DriftModelSet OneAxis() {
  std::vector<double> temp, y;
  for (int i = 0; i < 200; ++i) {
    temp.push_back(10.0 + 0.2 * i);
    y.push_back(0.01 * (temp.back() - 25.0));
  }
  DriftFitOptions o;
  o.model = DriftModelKind::kPolynomial;
  o.inputs = DriftInputSet::kTemp;
  auto m = FitDriftModel(DriftInputs{temp, 1.0}, y, o);
  EXPECT_TRUE(m.ok());
  DriftModelSet set;
  set.axes.push_back(*m);
  return set;
}

TEST(SensorIdentity, RoundTripsAndStaysOptional) {
  DriftModelSet set = OneAxis();
  const std::string plain = DriftModelSetToJson(set);
  EXPECT_EQ(plain.find("\"sensor\""), std::string::npos);
  auto back = DriftModelSetFromJson(plain, "plain.json");
  ASSERT_TRUE(back.ok());
  EXPECT_FALSE(back->sensor);
  set.device_id = 2293768;
  set.sensor = SensorIdentity{"accel", 2, 2293768u, "sensor"};
  auto read = DriftModelSetFromJson(DriftModelSetToJson(set), "s.json");
  ASSERT_TRUE(read.ok()) << read.error().message;
  ASSERT_TRUE(read->sensor);
  EXPECT_EQ(read->sensor->type, "accel");
  EXPECT_EQ(read->sensor->instance, 2);
  EXPECT_EQ(read->sensor->device_id, std::optional<std::uint32_t>(2293768u));
  EXPECT_EQ(read->sensor->frame, "sensor");
  EXPECT_EQ(read->device_id, std::optional<std::uint32_t>(2293768u));
}

TEST(SensorIdentity, MalformedIsRefusedWithTheField) {
  DriftModelSet set = OneAxis();
  set.sensor = SensorIdentity{};
  std::string text = DriftModelSetToJson(set);
  const auto at = text.find("\"gyro\"");
  ASSERT_NE(at, std::string::npos);
  std::string bad = text;
  bad.replace(at, 6, "\"magnet\"");
  auto r = DriftModelSetFromJson(bad, "bad.json");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("bad.json: sensor: field 'type'"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace gyrocomp
