// ROS bags as log tables (include/gyrocomp/io/bag_log.h).
#include "gyrocomp/io/bag_log.h"

#include <utility>

namespace gyrocomp {

BagReadOptions BagOptionsFromSpec(const LogSpec& spec) {
  BagReadOptions o;
  o.topic = spec.topic;
  o.time = spec.bag_time;
  return o;
}

FlightLogTable BagFlightLog(BagImuTable bag) {
  FlightLogTable f;
  f.table = std::move(bag.table);
  f.format = LogFormat::kRosBag;
  f.origin = std::move(bag.origin);
  f.warnings = std::move(bag.warnings);
  f.damage = std::move(bag.damage);
  return f;
}

Result<LogTableRead> ReadBagLogTable(const std::string& path, const LogSpec& spec, bool strict) {
  BagReadOptions options = BagOptionsFromSpec(spec);
  options.strict = strict;
  Result<BagImuTable> bag = ReadBagImu(path, options);
  if (!bag) return bag.error();
  LogTableRead out;
  out.format = LogFormat::kRosBag;
  out.spec = spec;
  out.spec.time_col = kBagTimeCol;
  out.spec.temp_col = kBagTempCol;
  out.spec.rate_unit = RateUnit::kRadPerSec;
  if (spec.rate_cols == LogSpec{}.rate_cols) out.spec.rate_cols.assign(std::begin(kBagGyroCols), std::end(kBagGyroCols));
  FlightLogTable flight = BagFlightLog(std::move(*bag));
  if (spec.on_warning) {
    for (const std::string& w : flight.warnings) spec.on_warning(w);
  }
  if (spec.temp_required && flight.table.Find(kBagTempCol) < 0) {
    return InvalidInput(path + ": " + flight.origin + ": this command needs a temperature, and the bag has no "
                        "sensor_msgs/Temperature topic to join");
  }
  out.table = std::move(flight.table);
  flight.table = Table{};
  out.flight = std::move(flight);
  return out;
}

}  // namespace gyrocomp
