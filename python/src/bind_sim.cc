// gyrocomp.simulate: SimulatorOptions as keywords; nested structs as dicts
// (profile={...}, bias={...}, noise={...}, true_rate={...}).
#include "bindings.h"

#include "gyrocomp/sim/simulator.h"

namespace gyrocomp::python {

void ReadProfile(py::dict d, ThermalProfileOptions* p, const std::string& function) {
  Kwargs kw(d, function + "(profile=...)");
  py::object kind = kw.Take("kind");
  if (!kind.is_none()) {
    const std::string name = py::str(kind);
    const auto k = ParseThermalProfileKind(name);
    if (!k) throw py::value_error("profile kind=" + name + ": must be paper, soak, ramp or cycle");
    p->kind = *k;
  }
  kw.Get("room_temp_c", &p->room_temp_c);
  kw.Get("room_hold_s", &p->room_hold_s);
  kw.Get("hot_temp_c", &p->hot_temp_c);
  kw.Get("cold_temp_c", &p->cold_temp_c);
  kw.Get("step_c", &p->step_c);
  kw.Get("hold_s", &p->hold_s);
  kw.Get("ramp_rate_c_per_min", &p->ramp_rate_c_per_min);
  kw.Get("soak_temp_c", &p->soak_temp_c);
  kw.Get("soak_duration_s", &p->soak_duration_s);
  kw.Get("ramp_end_c", &p->ramp_end_c);
  kw.Get("num_cycles", &p->num_cycles);
  kw.Done();
}

void ReadBias(py::dict d, BiasModelOptions* b, const std::string& function) {
  Kwargs kw(d, function + "(bias=...)");
  kw.Get("reference_temp_c", &b->reference_temp_c);
  kw.Get("poly_dps", &b->poly_dps);
  kw.Get("dtemp_coeff_dps_per_c_per_s", &b->dtemp_coeff_dps_per_c_per_s);
  kw.Get("hysteresis_width_c", &b->hysteresis_width_c);
  kw.Get("hysteresis_coeff_dps_per_c", &b->hysteresis_coeff_dps_per_c);
  kw.Done();
}

void ReadNoise(py::dict d, NoiseOptions* n, const std::string& function) {
  Kwargs kw(d, function + "(noise=...)");
  kw.Get("arw_deg_per_sqrt_h", &n->arw_deg_per_sqrt_h);
  kw.Get("bias_instability_deg_per_h", &n->bias_instability_deg_per_h);
  kw.Get("flicker_min_corr_s", &n->flicker_min_corr_s);
  kw.Get("flicker_max_corr_s", &n->flicker_max_corr_s);
  kw.Get("flicker_per_decade", &n->flicker_per_decade);
  kw.Get("rrw_deg_per_h_per_sqrt_h", &n->rrw_deg_per_h_per_sqrt_h);
  kw.Get("quantization_deg", &n->quantization_deg);
  kw.Get("resolution_dps", &n->resolution_dps);
  kw.Done();
}

namespace {

void ReadTrueRate(py::dict d, TrueRateOptions* t) {
  Kwargs kw(d, "simulate(true_rate=...)");
  kw.Get("constant_dps", &t->constant_dps);
  kw.Get("step_amplitude_dps", &t->step_amplitude_dps);
  kw.Get("step_period_s", &t->step_period_s);
  kw.Get("sine_amplitude_dps", &t->sine_amplitude_dps);
  kw.Get("sine_frequency_hz", &t->sine_frequency_hz);
  kw.Done();
}

// SimulatorOptions from keywords (nested structs as dicts); `function` names the caller in errors.
SimulatorOptions ReadSimulatorOptions(Kwargs& kw, const std::string& function) {
  SimulatorOptions o;
  kw.Get("fs_hz", &o.fs_hz);
  kw.Get("seed", &o.seed);
  kw.Get("duration_s", &o.duration_s);
  kw.Get("thermal_lag_s", &o.thermal_lag_s);
  kw.Get("temp_noise_c", &o.temp_noise_c);
  ReadProfile(kw.Nested("profile"), &o.profile, function);
  ReadBias(kw.Nested("bias"), &o.bias, function);
  ReadNoise(kw.Nested("noise"), &o.noise, function);
  ReadTrueRate(kw.Nested("true_rate"), &o.true_rate);
  return o;
}

py::list Axes(std::array<std::vector<double>, 3>&& v) {
  py::list l;
  for (std::vector<double>& a : v) l.append(ToNumpy(std::move(a)));
  return l;
}

}  // namespace

void BindSimulator(py::module_& m) {
  m.def(
      "simulate_board",
      [](int num_imus, std::optional<std::string> log_format, std::optional<double> log_rate_hz, int ahrs_orientation,
         const py::kwargs& kwargs) {
        Kwargs kw(kwargs, "simulate_board");
        BoardSimOptions b;
        b.chamber = ReadSimulatorOptions(kw, "simulate_board");
        b.num_imus = num_imus;
        kw.Get("with_baro", &b.with_baro);
        kw.Done();
        if (log_format && *log_format != "ulog" && *log_format != "dataflash")
          throw py::value_error("simulate_board(): log_format=" + *log_format + ": must be ulog or dataflash");
        BoardRun r = Unwrap(WithoutGil([&] { return SimulateBoard(b); }));
        py::dict d;
        if (log_format) {  // the file `gyrocomp simulate -o run.ulg / run.bin` writes, as bytes
          const double rate = log_rate_hz.value_or(r.fs_hz);
          const std::string bytes = Unwrap(WithoutGil([&] {
            return *log_format == "ulog" ? EncodeBoardULog(r, rate) : EncodeBoardDataFlash(r, rate, ahrs_orientation);
          }));
          d["log_bytes"] = py::bytes(bytes);
        } else {
          d["log_bytes"] = py::none();
        }
        d["fs_hz"] = r.fs_hz;
        d["time_s"] = ToNumpy(std::move(r.time_s));
        py::list imus;
        for (BoardImuRun& i : r.imus) {
          py::dict x;
          x["temp_c"] = ToNumpy(std::move(i.temp_c));
          x["gyro_rad_s"] = Axes(std::move(i.gyro_rad_s));
          x["accel_m_s2"] = Axes(std::move(i.accel_m_s2));
          x["true_gyro_drift_rad_s"] = Axes(std::move(i.true_gyro_drift_rad_s));
          x["true_accel_bias_m_s2"] = Axes(std::move(i.true_accel_bias_m_s2));
          imus.append(x);
        }
        d["imus"] = imus;
        d["baro_pressure_pa"] = ToNumpy(std::move(r.baro_pressure_pa));
        d["baro_temp_c"] = ToNumpy(std::move(r.baro_temp_c));
        return d;
      },
      py::kw_only(), py::arg("num_imus") = BoardSimOptions{}.num_imus, py::arg("log_format") = py::none(),
      py::arg("log_rate_hz") = py::none(), py::arg("ahrs_orientation") = 0,
      "A simulated board (SimulateBoard: num_imus IMUs, gyro and accel x / y / z, a barometer) with the "
      "chamber's SimulatorOptions as simulate's keywords; log_format 'ulog' | 'dataflash' adds log_bytes, the "
      "file `gyrocomp simulate -o run.ulg / run.bin` writes (log_rate_hz, ahrs_orientation as --log-rate, "
      "--ahrs-orientation).");

  m.def(
      "simulate",
      [](const py::kwargs& kwargs) {
        Kwargs kw(kwargs, "simulate");
        const SimulatorOptions o = ReadSimulatorOptions(kw, "simulate");
        kw.Done();
        SimulatedRun r = Unwrap(WithoutGil([&] { return Simulate(o); }));
        py::dict d;
        d["fs_hz"] = r.fs_hz;
        d["time_s"] = ToNumpy(std::move(r.time_s));
        d["rate_dps"] = ToNumpy(std::move(r.rate_dps));
        d["temp_c"] = ToNumpy(std::move(r.temp_c));
        d["chamber_temp_c"] = ToNumpy(std::move(r.chamber_temp_c));
        d["sensor_temp_c"] = ToNumpy(std::move(r.sensor_temp_c));
        d["true_rate_dps"] = ToNumpy(std::move(r.true_rate_dps));
        d["true_drift_dps"] = ToNumpy(std::move(r.true_drift_dps));
        d["true_noise_dps"] = ToNumpy(std::move(r.true_noise_dps));
        const SimulationSummary& s = r.summary;
        d["summary"] = py::dict(py::arg("num_samples") = s.num_samples, py::arg("duration_s") = s.duration_s,
                                py::arg("seconds") = s.seconds, py::arg("min_temp_c") = s.min_temp_c,
                                py::arg("max_temp_c") = s.max_temp_c, py::arg("min_drift_dps") = s.min_drift_dps,
                                py::arg("max_drift_dps") = s.max_drift_dps,
                                py::arg("flicker_process_sigma_dps") = s.flicker_process_sigma_dps,
                                py::arg("num_flicker_processes") = s.num_flicker_processes,
                                py::arg("brief_report") = s.BriefReport());
        return d;
      },
      "Simulated gyro in a temperature chamber, with ground truth (SimulatorOptions as keywords; "
      "profile=, bias=, noise=, true_rate= as dicts of their fields).");
}

}  // namespace gyrocomp::python
