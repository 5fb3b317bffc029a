#include "gyrocomp/export/axis_cubics.h"

#include <algorithm>

#include "gyrocomp/export/static_cubic.h"

namespace gyrocomp {
namespace {

// The static curve of axis `k` (options.static_weight): the model's own curve (time, `c->cubic_dps`
// as projected), the calibration run's static curve with each temperature alike (temperature), or
// the one with the lower expected next-run error (auto; time without a calibration run).
Status ChooseWeight(StaticWeight weight, const AxisDriftModel& x, std::size_t k, std::size_t n, const GyroLog* cal,
                    const CubicProjectionOptions& po, AxisCubic* c) {
  if (weight == StaticWeight::kTime) return Status::Ok();
  if (!cal) {
    if (weight == StaticWeight::kTemperature)
      return InvalidArgument("--static-weight temperature needs the calibration run (-i CAL, the model's columns)");
    c->weight_reason = "auto without a calibration run (-i): the model's own curve";
    return Status::Ok();
  }
  const std::vector<double>* y = AxisValues(*cal, x.model, k, n);
  if (!y) {
    const std::string why = "-i has no column " + x.model.rate_col + " (and not one rate column per model)";
    if (weight == StaticWeight::kTemperature) return InvalidInput(why);
    c->weight_reason = "auto: " + why + "; the model's own curve";
    return Status::Ok();
  }
  const DriftInputs in{cal->temp_c, cal->fs_hz};
  StaticCubicOptions so;
  so.temp_min_c = c->cubic_dps.temp_min_c, so.temp_max_c = c->cubic_dps.temp_max_c, so.ref_temp_c = c->cubic_dps.ref_temp_c;
  Result<TemperatureCubic> by_temp = FitStaticCubicByTemperature(x.model, in, *y, so);
  if (!by_temp.ok()) return by_temp.error();
  if (weight == StaticWeight::kTemperature) {
    c->cubic_dps = *by_temp, c->weight = "temperature";
    return Status::Ok();
  }
  Result<StaticWeightChoice> ch = ChooseStaticWeight(x.model, in, *po.temp_min_c, *po.temp_max_c, CubicCondition::kSteady);
  if (!ch.ok()) {
    c->weight_reason = "auto fell back to the model's own curve: " + ch.error().message;
    return Status::Ok();
  }
  c->weight_choice = *ch;
  c->weight = StaticWeightName(ch->chosen);
  if (ch->chosen == StaticWeight::kTemperature) c->cubic_dps = *by_temp;
  return Status::Ok();
}

}  // namespace

const std::vector<double>* AxisValues(const GyroLog& run, const DriftModel& model, std::size_t k, std::size_t n) {
  for (std::size_t i = 0; i < run.axis_names.size(); ++i)
    if (run.axis_names[i] == model.rate_col) return &run.rate_dps[i];
  return run.rate_dps.size() == n ? &run.rate_dps[k] : nullptr;
}

Result<std::vector<AxisCubic>> ExportAxisCubics(const std::vector<AxisDriftModel>& axes, const GyroLog* calibration,
                                                const GyroLog* validation, const AxisCubicsOptions& options) {
  if (axes.empty()) return InvalidArgument("ExportAxisCubics: no axis model");
  CubicProjectionOptions po;
  po.temp_min_c = axes[0].model.summary.temp_min_c;
  po.temp_max_c = axes[0].model.summary.temp_max_c;
  for (const auto& x : axes) {
    po.temp_min_c = std::max(*po.temp_min_c, x.model.summary.temp_min_c);
    po.temp_max_c = std::min(*po.temp_max_c, x.model.summary.temp_max_c);
  }
  std::vector<AxisCubic> out;
  for (const auto& x : axes) {
    AxisCubic c;
    auto cubic = ProjectOntoCubic(x.model, po);
    if (!cubic.ok()) return cubic.error();
    c.cubic_dps = *cubic;
    if (Status st = ChooseWeight(options.static_weight, x, out.size(), axes.size(), calibration, po, &c); !st.ok())
      return st.error();
    std::optional<DriftInputs> run;
    if (calibration) run = DriftInputs{calibration->temp_c, calibration->fs_hz};
    auto expected = ExpectedCubicError(x.model, c.cubic_dps, run);
    if (expected.ok()) c.expected = *expected;
    else c.expected_reason = expected.error().message;
    for (auto [log, cost] : {std::pair{calibration, &c.calibration}, std::pair{validation, &c.validation}}) {
      if (!log) continue;
      auto m = MeasureCubicProjectionCost(x.model, c.cubic_dps, DriftInputs{log->temp_c, log->fs_hz});
      if (!m.ok()) return m.error();
      *cost = *m;
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace gyrocomp
