// gyrocomp.compute_allan, compute_deviation, kalibr_imu_yaml.
#include "bindings.h"

#include "gyrocomp/allan/allan.h"
#include "gyrocomp/allan/deviations.h"
#include "gyrocomp/allan/kalibr.h"
#include "gyrocomp/allan/vio_noise.h"

namespace gyrocomp::python {
namespace {

py::dict TermsDict(const AllanNoiseTerms& t) {
  py::dict d;
  d["arw_deg_per_sqrt_h"] = t.arw_deg_per_sqrt_h;
  d["arw_method"] = t.arw_method;
  d["arw_fit_deg_per_sqrt_h"] = t.arw_fit_deg_per_sqrt_h;
  d["adev_min_deg_per_h"] = t.adev_min_deg_per_h;
  d["tau_at_min_s"] = t.tau_at_min_s;
  d["min_at_longest_tau"] = t.min_at_longest_tau;
  d["adev_min_usable_deg_per_h"] = t.adev_min_usable_deg_per_h;
  d["tau_at_min_usable_s"] = t.tau_at_min_usable_s;
  d["min_usable_at_longest_usable_tau"] = t.min_usable_at_longest_usable_tau;
  d["min_edf"] = t.min_edf;
  d["num_taus_used"] = t.num_taus_used;
  d["bias_instability_deg_per_h"] = t.bias_instability_deg_per_h;
  d["rrw_deg_per_h_per_sqrt_h"] = t.rrw_deg_per_h_per_sqrt_h;
  d["rrw_fit_tau_min_s"] = t.rrw_fit_tau_min_s;
  d["rrw_fit_tau_max_s"] = t.rrw_fit_tau_max_s;
  return d;
}

}  // namespace

AllanOptions ReadAllanOptions(Kwargs& kw) {
  AllanOptions o;
  kw.GetParsed("taus", &o.grid, [&o](const std::string& text) { return ParseTauGrid(text, &o.points_per_decade); },
               "must be octave, decade, all or a number of taus per decade (1-1000)");
  kw.Get("confidence", &o.confidence);
  kw.Get("arw_tau_s", &o.arw_tau_s);
  kw.Get("rrw_tau_s", &o.rrw_tau_s);
  kw.Get("slope_tolerance", &o.slope_tolerance);
  kw.Get("min_edf_for_terms", &o.min_edf_for_terms);
  return o;
}

py::dict AllanDict(AllanResult&& r) {
  py::dict d;
  d["brief_report"] = r.BriefReport();  // before the curve is moved out
  AllanCurve& c = r.curve;
  d["axis"] = r.axis;
  d["fs_hz"] = r.fs_hz;
  d["bandwidth_max_hz"] = r.BandwidthMaxHz();
  d["n_samples"] = r.n_samples;
  d["m"] = ToNumpy(std::move(c.m));
  d["tau_s"] = ToNumpy(std::move(c.tau_s));
  d["adev_dps"] = ToNumpy(std::move(c.adev_dps));
  d["adev_error_dps"] = ToNumpy(std::move(c.adev_error_dps));
  d["n_clusters"] = ToNumpy(std::move(c.n_clusters));
  d["slope"] = ToNumpy(std::move(c.slope));
  d["edf"] = ToNumpy(std::move(c.edf));
  d["adev_lo_dps"] = ToNumpy(std::move(c.adev_lo_dps));
  d["adev_hi_dps"] = ToNumpy(std::move(c.adev_hi_dps));
  py::list noise;
  for (PowerLawNoise n : c.noise) noise.append(PowerLawNoiseName(n));
  d["noise"] = noise;
  d["terms"] = TermsDict(r.terms);
  d["confidence"] = r.confidence;
  d["deviation_method"] = r.deviation_method;
  d["edf_method"] = r.edf_method;
  d["seconds"] = r.seconds;
  return d;
}

namespace {

py::dict ComputeAllanCall(const DoubleArray& rate_dps, double fs_hz, const CancellationToken* cancel,
                          const py::kwargs& kwargs) {
  AllanOptions o = ReadAll(kwargs, "compute_allan", ReadAllanOptions);
  const std::span<const double> y = AsSpan(rate_dps, "rate_dps");
  LongCall call(cancel);
  o.cancel = call.token();
  Result<AllanResult> r = call.Run([&] { return ComputeAllan(y, fs_hz, o); });
  return AllanDict(Unwrap(std::move(r)));
}

py::dict DeviationDict(DeviationCurve&& c) {
  py::dict d;
  d["kind"] = DeviationKindName(c.kind);
  d["m"] = ToNumpy(std::move(c.m));
  d["tau_s"] = ToNumpy(std::move(c.tau_s));
  d["dev_dps"] = ToNumpy(std::move(c.dev_dps));
  d["error_dps"] = ToNumpy(std::move(c.error_dps));
  d["n"] = ToNumpy(std::move(c.n));
  d["edf"] = ToNumpy(std::move(c.edf));
  d["lo_dps"] = ToNumpy(std::move(c.lo_dps));
  d["hi_dps"] = ToNumpy(std::move(c.hi_dps));
  d["confidence"] = c.confidence;
  d["method"] = c.method;
  d["edf_method"] = c.edf_method;
  d["seconds"] = c.seconds;
  return d;
}

py::dict ComputeDeviationCall(const DoubleArray& rate_dps, double fs_hz, const std::string& kind,
                              const py::kwargs& kwargs) {
  const AllanOptions o = ReadAll(kwargs, "compute_deviation", ReadAllanOptions);
  const std::optional<DeviationKind> k = ParseDeviationKind(kind);
  if (!k) throw py::value_error("kind=" + kind + ": must be adev, mdev, hdev, ohdev or totdev");
  const std::span<const double> y = AsSpan(rate_dps, "rate_dps");
  return DeviationDict(Unwrap(WithoutGil([&] { return ComputeDeviation(y, fs_hz, *k, o); })));
}

std::string KalibrImuYamlCall(const DoubleArray& rate_dps, double fs_hz, const std::string& rostopic,
                              const py::kwargs& kwargs) {
  const AllanOptions o = ReadAll(kwargs, "kalibr_imu_yaml", ReadAllanOptions);
  const std::span<const double> y = AsSpan(rate_dps, "rate_dps");
  AllanResult r = Unwrap(WithoutGil([&] { return ComputeAllan(y, fs_hz, o); }));
  KalibrAxisNoise g = Unwrap(KalibrNoiseFromAllan(r, KalibrSensor::kGyroscope, o.min_edf_for_terms));
  KalibrYamlOptions yo;
  yo.rostopic = rostopic;
  return KalibrImuYaml({g}, {}, fs_hz, yo);
}

// Every axis of imu_noise_files (gyro axes, then accelerometer axes) as the library's input; the
// arrays the spans look into are kept in `keep`.
std::vector<AllanAxisInput> NoiseAxes(const py::dict& gyro_dps, const py::dict* accel_m_s2, double fs_hz,
                                      std::vector<DoubleArray>* keep) {
  std::vector<AllanAxisInput> axes;
  for (const py::dict* d : {&gyro_dps, accel_m_s2}) {
    if (!d) continue;
    for (auto item : *d) {
      keep->push_back(item.second.cast<DoubleArray>());
      axes.push_back({py::str(item.first), AsSpan(keep->back(), "axis"), fs_hz});
    }
  }
  return axes;
}

py::list KalibrAxisList(const std::vector<KalibrAxisNoise>& v) {
  py::list l;
  for (const KalibrAxisNoise& n : v)
    l.append(py::dict(py::arg("axis") = n.axis, py::arg("noise_density") = n.noise_density,
                      py::arg("random_walk") = n.random_walk,
                      py::arg("random_walk_is_upper_bound") = n.random_walk_is_upper_bound));
  return l;
}

// The three files' text from the Kalibr figures (OpenVINS and VINS-Fusion need the accelerometer's
// figures too: None without them).
void AddNoiseFiles(const std::vector<KalibrAxisNoise>& gyro, const std::vector<KalibrAxisNoise>& accel, double fs_hz,
                   const std::string& rostopic, const std::string& source, py::dict* d) {
  KalibrYamlOptions ko;
  ko.rostopic = rostopic;
  ko.source = source;
  VioNoiseFileOptions vo;
  vo.rostopic = rostopic;
  vo.source = source;
  (*d)["kalibr_imu_yaml"] = KalibrImuYaml(gyro, accel, fs_hz, ko);
  (*d)["openvins_imu_chain_yaml"] =
      accel.empty() ? py::object(py::none()) : py::object(py::str(OpenVinsImuChainYaml(gyro, accel, fs_hz, vo)));
  (*d)["vins_fusion_imu_yaml"] =
      accel.empty() ? py::object(py::none()) : py::object(py::str(VinsFusionImuYaml(gyro, accel, fs_hz, vo)));
}

// As `gyrocomp allan --kalibr-yaml / --openvins-yaml / --vins-yaml`: every axis's ADEV (gyro axes,
// then accelerometer axes), Kalibr's figures per axis, the three files' text.
py::dict ImuNoiseFilesCall(const py::dict& gyro_dps, double fs_hz, std::optional<py::dict> accel_m_s2,
                           const std::string& rostopic, const std::string& source, const py::kwargs& kwargs) {
  const AllanOptions o = ReadAll(kwargs, "imu_noise_files", ReadAllanOptions);
  std::vector<DoubleArray> keep;
  const std::vector<AllanAxisInput> axes = NoiseAxes(gyro_dps, accel_m_s2 ? &*accel_m_s2 : nullptr, fs_hz, &keep);
  if (gyro_dps.empty()) throw py::value_error("imu_noise_files(): gyro_dps: no axis");
  std::vector<AllanResult> results = Unwrap(WithoutGil([&] { return ComputeAllan(axes, source, o); }));
  std::vector<KalibrAxisNoise> gyro, accel;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const bool is_gyro = k < gyro_dps.size();
    KalibrAxisNoise n = Unwrap(KalibrNoiseFromAllan(
        results[k], is_gyro ? KalibrSensor::kGyroscope : KalibrSensor::kAccelerometer, o.min_edf_for_terms));
    (is_gyro ? gyro : accel).push_back(std::move(n));
  }
  py::dict d;
  d["gyro"] = KalibrAxisList(gyro);
  d["accel"] = KalibrAxisList(accel);
  AddNoiseFiles(gyro, accel, fs_hz, rostopic, source, &d);
  return d;
}

}  // namespace

void BindAllan(py::module_& m) {
  m.def("compute_allan", &ComputeAllanCall, py::arg("rate_dps"), py::arg("fs_hz"), py::kw_only(),
        py::arg("cancel") = nullptr,
        "Overlapping Allan deviation and noise terms (AllanOptions as keywords: taus, confidence, "
        "arw_tau_s, rrw_tau_s, slope_tolerance, min_edf_for_terms); cancel: a CancellationToken. "
        "Ctrl-C stops it (KeyboardInterrupt).");
  m.def("compute_deviation", &ComputeDeviationCall, py::arg("rate_dps"), py::arg("fs_hz"), py::arg("kind") = "adev",
        "One deviation curve (adev, mdev, hdev, ohdev, totdev) as allantools computes it.");
  m.def("kalibr_imu_yaml", &KalibrImuYamlCall, py::arg("rate_dps"), py::arg("fs_hz"),
        py::arg("rostopic") = KalibrYamlOptions{}.rostopic,
        "Kalibr imu.yaml text for one gyro axis (docs/guides/imu-noise.md).");
  m.def("imu_noise_files", &ImuNoiseFilesCall, py::arg("gyro_dps"), py::arg("fs_hz"), py::kw_only(),
        py::arg("accel_m_s2") = py::none(), py::arg("rostopic") = KalibrYamlOptions{}.rostopic,
        py::arg("source") = "",
        "The robotics noise files of `gyrocomp allan` (docs/guides/imu-noise.md) from every axis: gyro_dps "
        "{axis name: rate, deg/s}, accel_m_s2 {axis name: m/s^2} (OpenVINS and VINS-Fusion need it); "
        "AllanOptions as keywords. Returns gyro / accel (Kalibr figures per axis), kalibr_imu_yaml, "
        "openvins_imu_chain_yaml, vins_fusion_imu_yaml (None without accelerometer axes).");
}

}  // namespace gyrocomp::python
