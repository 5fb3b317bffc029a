// gyrocomp.inspect: InspectLog (gyrocomp/io/inspect.h), the work of `gyrocomp inspect`: what a PX4
// ULog, ArduPilot DataFlash log or ROS bag holds, as the dict `gyrocomp inspect --json` writes
// (without "input"), plus brief_report.
#include "bindings.h"

#include "gyrocomp/io/inspect.h"

namespace gyrocomp::python {

void BindInspect(py::module_& m) {
  m.def(
      "inspect",
      [](const std::string& path, bool strict) {
        InspectOptions options;
        options.strict = strict;
        LogInventory inv = Unwrap(WithoutGil([&] { return InspectLog(path, options); }));
        // The listing through Python's json module: numbers, strings, lists and dicts as the CLI's
        // JSON holds them (doubles round-trip: nlohmann writes 17 significant digits).
        const std::string text = inv.listing.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
        py::dict d = py::module_::import("json").attr("loads")(text);
        d["brief_report"] = inv.BriefReport();
        return d;
      },
      py::arg("path"), py::arg("strict") = false,
      "What a PX4 ULog, ArduPilot DataFlash log or ROS bag holds (gyrocomp inspect): format, sensors (type, "
      "source, instance, rows, device_id, time_span_s, sample_rate_hz, temp_range_c), gyro_instances, damage, "
      "compensation_parameters, warnings; topics for a bag. strict: a damaged record is an error.");
}

}  // namespace gyrocomp::python
