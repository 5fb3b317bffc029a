"""Each subcommand's work called from Python equals what the CLI writes (same inputs, same files)."""
import json
import math
import re
import subprocess

import numpy as np
import pytest

import gyrocomp


def _run(cli, *args):
    p = subprocess.run([cli, *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert p.returncode == 0, p.stdout
    return p.stdout


def _table(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
        data = np.loadtxt(f, delimiter=",", ndmin=2)
    return {name: data[:, k] for k, name in enumerate(header)}


@pytest.fixture
def chamber(cli, tmp_path):
    """A short chamber run (2 Hz, about 3 h), a second seed as the held-out run, a poly model."""
    sim = ["simulate", "--fs", "2", "--room-hold", "1200", "--hold", "1200", "--step", "25", "--ramp-rate", "2",
           "--thermal-lag", "300"]
    _run(cli, *sim, "--seed", "5", "-o", str(tmp_path / "run.csv"))
    _run(cli, *sim, "--seed", "6", "-o", str(tmp_path / "run2.csv"))
    _run(cli, "fit", "-i", str(tmp_path / "run.csv"), "--model", "poly", "--inputs", "temp,dtemp",
         "-o", str(tmp_path / "m.json"))
    return tmp_path


def _same(a, b):
    if a is None or b is None:
        return a is None and b is None
    if isinstance(a, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-15)


def test_validate_drift_model_equals_validate_json(cli, chamber):
    _run(cli, "validate", "-m", str(chamber / "m.json"), "-i", str(chamber / "run2.csv"),
         "--json", str(chamber / "v.json"))
    want = json.loads((chamber / "v.json").read_text())
    run = _table(chamber / "run2.csv")
    model = gyrocomp.load_drift_model(str(chamber / "m.json"))
    got = gyrocomp.validate_drift_model(model, run["rate_dps"], run["temp_c"], 2.0,
                                       true_drift=run["true_drift_dps"]).to_dict()
    for key, value in got.items():
        assert _same(value, want[key]), (key, value, want[key])


def test_generate_c_equals_export_format_c(cli, chamber):
    out = chamber / "gen" / "drift"
    out.parent.mkdir()
    model_path = str(chamber / "m.json")
    _run(cli, "export", "-m", model_path, "--format", "c", "-o", str(out))
    model = gyrocomp.load_drift_model(model_path)
    got = gyrocomp.generate_c([model], ["rate_dps"], prefix="drift", comments=["model: " + model_path]).to_dict()
    assert got["header_name"] == "drift.h" and got["source_name"] == "drift.c"
    assert got["header"] == (out.parent / "drift.h").read_text()
    assert got["source"] == (out.parent / "drift.c").read_text()


# gyrocomp.plan (PlanChamberRun) equals `gyrocomp plan --json`: the library's names on the Python
# side, the CLI's JSON keys on the other.
_PLAN_PROFILE_KEYS = {
    "profile": "profile", "hours": "hours", "models": "models", "excluded": "left_out",
    "predicted_heat_dps": "predicted_rms_heating", "predicted_cool_dps": "predicted_rms_cooling",
    "simulated_heat_dps": "simulated_rms_heating", "simulated_cool_dps": "simulated_rms_cooling",
    "predicted_dps": "predicted_rms", "simulated_dps": "simulated_rms", "simulated_rel_se": "simulated_rms_rel_se",
}


def _same_value(a, b):
    if isinstance(a, str) or isinstance(b, str):
        return a == b
    if isinstance(a, list) and a and isinstance(a[0], str):
        return a == b
    return _same(a, b)


def _assert_plan_equals_json(got, want):
    unit, wu = got.unit, want["unit"]
    for key in ("arw_deg_per_sqrt_h", "bias_instability_deg_per_h", "rrw_deg_per_h_per_sqrt_h"):
        assert _same(getattr(unit.noise, key), wu["noise"][key]), key
    assert unit.noise_source == wu["noise"]["source"]
    for key in ("reference_temp_c", "poly_dps", "dtemp_coeff_dps_per_c_per_s", "hysteresis_width_c",
                "hysteresis_coeff_dps_per_c"):
        assert _same(getattr(unit.bias, key), wu["drift"][key]), key
    assert _same(unit.thermal_lag_s, wu["drift"]["thermal_lag_s"])
    assert unit.family_source == wu["drift"]["source"]
    assert _same(unit.cold_temp_c, wu["cold_c"]) and _same(unit.hot_temp_c, wu["hot_c"])
    assert unit.notes == wu["notes"]
    assert len(got.profiles) == len(want["profiles"])
    for o, w in zip(got.profiles, want["profiles"]):
        for key, json_key in _PLAN_PROFILE_KEYS.items():
            assert _same_value(o[key], w[json_key]), (o.profile, key, o[key], w[json_key])
        assert len(o.simulated_ms_per_seed) == want["seeds"]
    assert got.recommended_profile == want["recommended"]
    assert got.profiles[got.recommended].profile == want["recommended"]
    assert got.seeds == want["seeds"]
    assert got.brief_report.startswith("recommended: " + want["recommended"])


def test_plan_equals_plan_json(cli, tmp_path):
    _run(cli, "plan", "--profiles", "ramp,paper", "--seeds", "2", "--fs", "0.2", "--arw", "0.5",
         "--bias-instability", "10", "--cold", "-20", "--hot", "70", "--drift-poly", "0.01,0.001",
         "--json", str(tmp_path / "p.json"))
    want = json.loads((tmp_path / "p.json").read_text())
    got = gyrocomp.plan(profiles=["ramp", "paper"], seeds=2, fs_hz=0.2,
                        noise={"arw_deg_per_sqrt_h": 0.5, "bias_instability_deg_per_h": 10.0},
                        profile={"cold_temp_c": -20.0, "hot_temp_c": 70.0}, bias={"poly_dps": [0.01, 0.001]})
    _assert_plan_equals_json(got, want)


def test_plan_with_a_pilot_and_an_allan_run_equals_plan_json(cli, tmp_path):
    pilot, static = str(tmp_path / "pilot.csv"), str(tmp_path / "static.csv")
    _run(cli, "simulate", "--profile", "cycle", "--fs", "0.5", "--seed", "37", "-o", pilot)
    _run(cli, "simulate", "--profile", "soak", "--soak-duration", "3600", "--fs", "10", "--seed", "31", "-o", static)
    _run(cli, "plan", "--pilot", pilot, "--noise-from", static, "--profiles", "paper,ramp", "--seeds", "1",
         "--fs", "0.2", "--rrw", "2", "--json", str(tmp_path / "p.json"))
    want = json.loads((tmp_path / "p.json").read_text())
    got = gyrocomp.plan(pilot, static, profiles="paper,ramp", seeds=1, fs_hz=0.2,
                        noise={"rrw_deg_per_h_per_sqrt_h": 2.0})
    _assert_plan_equals_json(got, want)
    assert got.profiles[0].simulated_rel_se is None  # one seed: no scatter to read


def test_plan_errors_are_the_libraries(tmp_path):
    with pytest.raises(ValueError, match="--profiles: 'nosuch'"):
        gyrocomp.plan(profiles=["nosuch"], seeds=1)
    with pytest.raises(ValueError, match="seeds"):
        gyrocomp.plan(seeds=0)
    with pytest.raises(TypeError, match="plan"):
        gyrocomp.plan(nosuch=1)


# gyrocomp.inspect (InspectLog) equals `gyrocomp inspect --json` (which adds only "input") on a
# ULog, an appended ULog, a DataFlash log and a ROS 2 bag.
@pytest.mark.parametrize("relative", [
    "tests/fieldlogs/sample_log_small.ulg",
    "tests/fieldlogs/sample_appended_multiple.ulg",
    "../shared/fieldlogs/ardupilot/test.BIN",
    "tests/bags/rosbag2/talker_mcap",
])
def test_inspect_equals_inspect_json(cli, golden_dir, tmp_path, relative):
    path = (golden_dir.parents[1] / relative).resolve()
    if not path.exists():
        pytest.skip(f"{relative} is not here (the shared field logs are licensed data)")
    _run(cli, "inspect", "-i", str(path), "--json", str(tmp_path / "i.json"))
    want = json.loads((tmp_path / "i.json").read_text())
    assert want.pop("input") == str(path)
    got = gyrocomp.inspect(str(path)).to_dict()
    brief = got.pop("brief_report")
    assert got == want
    assert brief.startswith(want["format"] + ": ")


def test_inspect_refuses_a_csv(tmp_path):
    (tmp_path / "x.csv").write_text("time_s,rate_dps\n0,1\n")
    with pytest.raises(ValueError, match="not a PX4 ULog"):
        gyrocomp.inspect(str(tmp_path / "x.csv"))


# gyrocomp.decompose (DecomposeVmd + ClassifyVmdModes) equals `gyrocomp decompose --json` on one
# axis: iterations, each mode's centre frequency, sample entropy and class, the rule; the modes
# equal the CSV the CLI writes (written with 17 significant digits: 1e-12 relative).
@pytest.mark.parametrize("rule", ["standard", "paper"])
def test_decompose_equals_decompose_json(cli, tmp_path, rule):
    log = str(tmp_path / "run.csv")
    _run(cli, "simulate", "--profile", "ramp", "--fs", "2", "--seed", "4", "--duration", "3000", "-o", log)
    _run(cli, "decompose", "-i", log, "--modes", "4", "--rule", rule, "--entropy-max-samples", "2000",
         "--json", str(tmp_path / "d.json"), "-o", str(tmp_path / "modes.csv"))
    want = json.loads((tmp_path / "d.json").read_text())
    run = _table(log)
    got = gyrocomp.decompose(run["rate_dps"], num_modes=4, fs_hz=2.0, rule=rule, entropy_max_samples=2000)
    assert got.iterations == want["iterations"] and got.converged == want["converged"]
    assert _same(got.final_update, want["final_update"])
    assert len(got.classes) == len(want["modes"])
    for c, w in zip(got.classes, want["modes"]):
        assert c.index == w["index"] and c.feature == w["class"]
        for key in ("center_frequency_hz", "center_frequency_cycles_per_sample", "sample_entropy"):
            assert _same(c[key], w[key]), (c.index, key)
    for key in ("drift_max_se", "noise_min_se", "drift_max_frequency_hz", "keep_lowest_mode"):
        assert got.rule[key] == want["classification"][key], key
    assert got.rule.rule_name == want["classification"]["rule"]
    assert got.rule_text == want["classification"]["description"]
    modes = _table(tmp_path / "modes.csv")
    for k in range(4):
        np.testing.assert_allclose(got.modes[k], modes[f"mode_{k + 1}"], rtol=1e-12, atol=1e-15)


# `gyrocomp apply` is DriftModel.predict / predict_band / check_temperature_range: the columns it
# writes and the keys of apply --json equal them (plain and causal).
@pytest.mark.parametrize("causal", [False, True])
def test_drift_model_predict_equals_apply(cli, chamber, causal):
    args = ["apply", "-m", str(chamber / "m.json"), "-i", str(chamber / "run2.csv"), "-o", str(chamber / "o.csv"),
            "--json", str(chamber / "a.json")] + (["--causal"] if causal else [])
    _run(cli, *args)
    out = _table(chamber / "o.csv")
    want = json.loads((chamber / "a.json").read_text())
    run = _table(chamber / "run2.csv")
    model = gyrocomp.load_drift_model(str(chamber / "m.json"))
    predicted = model.predict(run["temp_c"], want["fs_hz"], causal=causal)
    np.testing.assert_allclose(predicted, out["predicted_drift_dps"], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(run["rate_dps"] - predicted, out["compensated_dps"], rtol=1e-12, atol=1e-15)
    band = model.predict_band(run["temp_c"], want["fs_hz"], causal=causal)
    np.testing.assert_allclose(band["lo"], out["predicted_drift_lo_dps"], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(band["hi"], out["predicted_drift_hi_dps"], rtol=1e-12, atol=1e-15)
    assert band["level"] == want["band_level"]
    rng = model.check_temperature_range(run["temp_c"])
    assert rng["outside"] == want["temp_outside_fitted_range"]
    for key, json_key in (("below_c", "temp_below_fitted_c"), ("above_c", "temp_above_fitted_c"),
                          ("fraction_outside", "fraction_outside_fitted_range")):
        assert _same(rng[key], want[json_key]), key
    rmse = float(np.sqrt(np.mean((predicted - run["true_drift_dps"]) ** 2)))
    assert math.isclose(rmse, want["rmse_vs_true_drift_dps"], rel_tol=1e-9)  # summation order differs


# gyrocomp.compare_methods (RunParallelModel + CompareMethods) equals `gyrocomp compare --json`:
# every row's figures but its wall time. Without the grid search (as long as CS-SVR).
def test_compare_methods_equals_compare_json(cli, chamber):
    _run(cli, "compare", "-i", str(chamber / "run.csv"), "--no-grid", "--quiet", "--json", str(chamber / "c.json"))
    want = json.loads((chamber / "c.json").read_text())
    run = _table(chamber / "run.csv")
    got = gyrocomp.compare_methods(run["rate_dps"], run["temp_c"], 2.0, true_rate_dps=run["true_rate_dps"],
                                   true_drift_dps=run["true_drift_dps"], grid_search=False, measure_bandwidth=True)
    assert [(r.group, r.method) for r in got.rows] == [(r["group"], r["method"]) for r in want["rows"]]
    for r, w in zip(got.rows, want["rows"]):
        for key, value in w.items():
            if key == "seconds":  # wall time
                continue
            if key in ("group", "method", "note"):
                assert r[key] == value, key
                continue
            g = r[key]
            if g is not None and not math.isfinite(g):
                g = None  # compare --json writes a non-finite figure as null
            assert _same(g, value), (r.method, key, g, value)


# gyrocomp.read_log_rows equals `gyrocomp convert`: the CSV's columns (round-trip digits: exact)
# and the keys of convert --json.
@pytest.mark.parametrize("relative,instance", [
    ("tests/fieldlogs/sample_log_small.ulg", 1),
    ("tests/fieldlogs/sample_appended_multiple.ulg", None),
    ("../shared/fieldlogs/ardupilot/test.BIN", 0),
])
def test_read_log_rows_equals_convert(cli, golden_dir, tmp_path, relative, instance):
    path = (golden_dir.parents[1] / relative).resolve()
    if not path.exists():
        pytest.skip(f"{relative} is not here (the shared field logs are licensed data)")
    extra = [] if instance is None else ["--instance", str(instance)]
    _run(cli, "convert", "-i", str(path), *extra, "-o", str(tmp_path / "c.csv"), "--json", str(tmp_path / "c.json"))
    want = json.loads((tmp_path / "c.json").read_text())
    got = gyrocomp.read_log_rows(str(path), instance=instance)
    for key in ("format", "origin", "instance", "device_id", "rows", "warnings", "damage"):
        assert got[key] == want[key], key
    assert got.names == want["columns"]
    table = _table(tmp_path / "c.csv")
    assert list(table) == got.names
    for name in got.names:
        np.testing.assert_array_equal(got.columns[name], table[name])


def test_read_log_rows_refuses_a_csv(tmp_path):
    (tmp_path / "x.csv").write_text("time_s,rate_dps\n0,1\n")
    with pytest.raises(ValueError, match="read_log reads a CSV"):
        gyrocomp.read_log_rows(str(tmp_path / "x.csv"))


# `gyrocomp entropy` is gyrocomp.sample_entropy: the same counts and value on the same column.
@pytest.mark.parametrize("extra,options", [([], {}), (["--m", "3", "--r", "0.15"], {"m": 3, "r_factor": 0.15}),
                                           (["--r-abs", "0.05"], {"r_absolute": 0.05})])
def test_sample_entropy_equals_entropy_json(cli, chamber, extra, options):
    _run(cli, "entropy", "-i", str(chamber / "run2.csv"), "--col", "rate_dps", *extra,
         "--json", str(chamber / "e.json"))
    want = json.loads((chamber / "e.json").read_text())
    got = gyrocomp.sample_entropy(_table(chamber / "run2.csv")["rate_dps"], **options)
    for key in ("m", "n", "a_matches", "b_matches", "defined"):
        assert got[key] == want[key], key
    assert _same(got.r, want["r"]) and _same(got.sample_entropy, want["sample_entropy"])


# gyrocomp.imu_noise_files equals the noise files `gyrocomp allan` writes (Kalibr imu.yaml,
# OpenVINS kalibr_imu_chain.yaml, VINS-Fusion's keys) for three gyro and three accelerometer axes.
def test_imu_noise_files_equal_allan_files(cli, tmp_path):
    fs = 50.0
    rng = np.random.default_rng(7)
    n = 30000  # 10 min: tau = 1 s and a few decades above
    cols = {"gx": 0.01, "gy": 0.02, "gz": 0.015, "ax": 0.002, "ay": 0.003, "az": 0.004}
    data = {name: sd * rng.standard_normal(n) + np.cumsum(sd * 1e-3 * rng.standard_normal(n))
            for name, sd in cols.items()}
    path = tmp_path / "imu.csv"
    with open(path, "w") as f:
        f.write(",".join(cols) + "\n")  # no time column: --fs
        for i in range(n):
            f.write(",".join(repr(float(data[c][i])) for c in cols) + "\n")
    files = {k: tmp_path / f"{k}.yaml" for k in ("kalibr", "openvins", "vins")}
    _run(cli, "allan", "-i", str(path), "--time-col", "none", "--fs", "50", "--rate-col", "gx,gy,gz",
         "--accel-col", "ax,ay,az", "--rostopic", "/imu1", "--kalibr-yaml", str(files["kalibr"]), "--openvins-yaml", str(files["openvins"]),
         "--vins-yaml", str(files["vins"]))
    got = gyrocomp.imu_noise_files({c: data[c] for c in ("gx", "gy", "gz")}, fs,
                                   accel_m_s2={c: data[c] for c in ("ax", "ay", "az")}, rostopic="/imu1",
                                   source=str(path))
    assert [a.axis for a in got.gyro] == ["gx", "gy", "gz"] and [a.axis for a in got.accel] == ["ax", "ay", "az"]
    assert got.kalibr_imu_yaml == files["kalibr"].read_text()
    assert got.openvins_imu_chain_yaml == files["openvins"].read_text()
    assert got.vins_fusion_imu_yaml == files["vins"].read_text()
    assert gyrocomp.imu_noise_files({"gx": data["gx"]}, fs).openvins_imu_chain_yaml is None


# `gyrocomp denoise --method wavelet | flp | wflp` is wavelet_denoise / flp_denoise / wflp_denoise
# with the defaults: the denoised column equals the CSV it writes (round-trip digits: 1e-12).
@pytest.mark.parametrize("method", ["wavelet", "flp", "wflp"])
def test_denoisers_equal_denoise(cli, chamber, method):
    _run(cli, "denoise", "-i", str(chamber / "run2.csv"), "--method", method, "-o", str(chamber / "d.csv"))
    want = _table(chamber / "d.csv")["denoised_dps"]
    x = _table(chamber / "run2.csv")["rate_dps"]
    got = {"wavelet": gyrocomp.wavelet_denoise, "flp": gyrocomp.flp_denoise, "wflp": gyrocomp.wflp_denoise}[method](x)
    np.testing.assert_allclose(got.denoised, want, rtol=1e-12, atol=1e-15)


# gyrocomp.measure_bandwidth equals `gyrocomp denoise --bandwidth`: the -3 dB bandwidth, delay and
# test amplitude of each denoiser on the record's first segment, 24 frequencies as the CLI.
@pytest.mark.parametrize("method", ["wavelet", "flp", "wflp"])
def test_measure_bandwidth_equals_denoise_bandwidth(cli, chamber, method):
    _run(cli, "denoise", "-i", str(chamber / "run2.csv"), "--method", method, "--bandwidth",
         "--bandwidth-segment", "4096", "--json", str(chamber / "b.json"))
    want = json.loads((chamber / "b.json").read_text())
    x = _table(chamber / "run2.csv")["rate_dps"]
    got = gyrocomp.measure_bandwidth(method, x[:4096], 2.0, num_frequencies=24)
    assert _same(got.bandwidth_hz, want["bandwidth_hz"])
    assert got.bandwidth_below_range == want["bandwidth_below_range"]
    for key, json_key in (("max_frequency_hz", "bandwidth_max_tested_hz"), ("delay_s", "delay_s"),
                          ("amplitude", "bandwidth_test_amplitude_dps")):
        assert _same(got[key], want[json_key]), key
    assert got.brief_report == want["bandwidth_report"]


# gyrocomp.simulate_board's log_bytes are the file `gyrocomp simulate -o run.ulg / run.bin` writes
# (two IMUs, 10 min at 10 Hz logged at 5 Hz; the DataFlash board rotated by AHRS_ORIENTATION 2).
@pytest.mark.parametrize("suffix,log_format,extra", [(".ulg", "ulog", {}),
                                                     (".bin", "dataflash", {"ahrs_orientation": 2})])
def test_simulate_board_equals_simulate_log(cli, tmp_path, suffix, log_format, extra):
    out = tmp_path / ("run" + suffix)
    args = ["simulate", "--fs", "10", "--duration", "600", "--seed", "9", "--imus", "2", "--log-rate", "5"]
    if "ahrs_orientation" in extra:
        args += ["--ahrs-orientation", str(extra["ahrs_orientation"])]
    _run(cli, *args, "-o", str(out))
    got = gyrocomp.simulate_board(num_imus=2, log_format=log_format, log_rate_hz=5.0, fs_hz=10.0, duration_s=600.0,
                                  seed=9, **extra)
    assert got.log_bytes == out.read_bytes()
    assert len(got.imus) == 2 and len(got.imus[0].gyro_rad_s) == 3
    listing = gyrocomp.inspect(str(out))  # and the log reads back with two gyro instances
    assert sum(1 for s in listing.sensors if s.type == "gyro") == 2


def _report_data(path):
    """The data block of an HTML report (report.h schema), parsed back."""
    html = path.read_text()
    start = html.index('<script type="application/json" id="report-data">')
    start = html.index(">", start) + 1
    return json.loads(html[start:html.index("</script>", start)])  # "<\/" is JSON's escaped "/"


def _without_timings(data):
    """The report's data without wall times: the Timings table's seconds, the drift model's fit time,
    the seconds a warning quotes (VMD's "did not converge in 499 iterations ... in 0.8 s")."""
    for table in data["tables"]:
        if table["title"] == "Warnings":
            table["rows"] = [[re.sub(r"in [0-9.e+-]+ s\b", "in _ s", row[0])] for row in table["rows"]]
        if table["title"] == "Timings":
            table["rows"] = [row[0] for row in table["rows"]]
        if table["title"] == "Drift model":
            k = table["columns"].index("fit time (s)")
            for row in table["rows"]:
                row[k] = None
    return data


def _same_json(a, b, where=""):
    if isinstance(a, dict):
        assert isinstance(b, dict) and sorted(a) == sorted(b), (where, sorted(a), sorted(b))
        for key in a:
            _same_json(a[key], b[key], f"{where}/{key}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), (where, len(a), len(b))
        for k, (x, y) in enumerate(zip(a, b)):
            _same_json(x, y, f"{where}[{k}]")
    elif isinstance(a, float) or isinstance(b, float):
        assert _same(a, b), (where, a, b)
    else:
        assert a == b, (where, a, b)


# run_parallel_model(report=...) writes the report `gyrocomp process --report` writes: the same
# data (every figure, chart, table, the parameters) but the wall times.
def test_run_parallel_model_report_equals_process_report(cli, chamber):
    path = str(chamber / "run.csv")
    _run(cli, "process", "-i", path, "--quiet", "--report", str(chamber / "cli.html"))
    run = _table(chamber / "run.csv")
    result = gyrocomp.run_parallel_model(
        run["rate_dps"], run["temp_c"], 2.0, measure_bandwidth=True,
        report=dict(path=str(chamber / "py.html"), source=path, axis="rate_dps", time_s=run["time_s"]))
    want = _without_timings(_report_data(chamber / "cli.html"))
    got = _without_timings(_report_data(chamber / "py.html"))
    _same_json(got, want)
    assert result.drift_model is not None
    gyrocomp.run_parallel_model(run["rate_dps"], run["temp_c"], 2.0, report=chamber / "short.html",
                                drift=dict(max_generations=1))
    short = _report_data(chamber / "short.html")
    assert short["title"] == "gyrocomp: Python arrays" and short["subtitle"].startswith("Python arrays, axis rate_dps:")
    with pytest.raises(ValueError, match="time_s"):
        gyrocomp.run_parallel_model(run["rate_dps"], run["temp_c"], 2.0, report=dict(path=str(chamber / "x.html"),
                                                                                  time_s=run["time_s"][:10]))
    assert not (chamber / "x.html").exists()


def _without_comparison_times(data):
    """The comparison tables without their wall-time column ("time (s)")."""
    for table in data["tables"]:
        if table["title"].startswith("Comparison:"):
            k = table["columns"].index("time (s)")
            for row in table["rows"]:
                row[k] = None
    return data


# compare_methods(report=...) writes the report of `gyrocomp process --compare --report`: the
# run's report with the comparison tables, the same but for the wall times. On a run shorter than
# the chamber fixture (1 Hz, 10-min holds): process --compare always runs the SVR grid search.
def test_compare_methods_report_equals_process_compare_report(cli, tmp_path):
    path = str(tmp_path / "short.csv")
    _run(cli, "simulate", "--fs", "1", "--room-hold", "600", "--hold", "600", "--step", "25", "--ramp-rate", "2",
         "--thermal-lag", "300", "--seed", "5", "-o", path)
    _run(cli, "process", "-i", path, "--quiet", "--compare", "--report", str(tmp_path / "cli.html"))
    run = _table(path)
    gyrocomp.compare_methods(run["rate_dps"], run["temp_c"], 1.0, measure_bandwidth=True,
                             report=dict(path=str(tmp_path / "py.html"), source=path, time_s=run["time_s"]))
    want = _without_comparison_times(_without_timings(_report_data(tmp_path / "cli.html")))
    got = _without_comparison_times(_without_timings(_report_data(tmp_path / "py.html")))
    assert any(t["title"].startswith("Comparison:") for t in want["tables"])
    _same_json(got, want)


def _demo_lines():
    """The Python lines of docs/guides/python.md that do what `gyrocomp demo` does."""
    from conftest import SOURCE_DIR
    page = (SOURCE_DIR / "docs" / "guides" / "python.md").read_text()
    start = page.index("```python\n", page.index("## The demo in Python")) + len("```python\n")
    return page[start:page.index("```", start)]


# The demo's lines of the Python guide give the figures of `gyrocomp demo`'s summary.json (at 1 Hz
# and without the comparisons, to keep the test short: the lines' first assignment sets the rate).
def test_demo_lines_equal_demo_summary(cli, tmp_path):
    _run(cli, "demo", "--out", str(tmp_path / "demo"), "--fs", "1", "--no-compare", "--quiet")
    want = json.loads((tmp_path / "demo" / "summary.json").read_text())
    lines = _demo_lines()
    assert lines.startswith("fs_hz, seed = 5.0, 1\n")
    scope = {}
    exec(lines.replace("fs_hz, seed = 5.0, 1\n", "fs_hz, seed = 1.0, 1\n", 1), scope)
    ours, paper, paper_after, held_out = scope["ours"], scope["paper"], scope["paper_after"], scope["held_out"]
    for key in ("adev_min_deg_per_h", "bias_instability_deg_per_h", "tau_at_min_s"):
        assert _same(ours.allan_before.terms[key], want["before"][key]), key
        assert _same(ours.allan_after.terms[key], want["after"][key]), key
        assert _same(paper_after.terms[key], want["paper_pipeline"]["after"][key]), key
    for got, summary in ((ours.drift_model.summary, want["drift_model"]),
                         (paper.summary, want["paper_pipeline"]["drift_model"])):
        assert got.model == summary["model"] and got.inputs == summary["inputs"]
        assert _same(got.cv_rmse, summary["cv_rmse_dps"]) and _same(got.C, summary["C"])
    for name in ("default", "paper_pipeline"):
        got = held_out[name].to_dict()
        for key, value in want["held_out"][name].items():
            assert _same(got[key], value), (name, key, got[key], value)
    rows = {row["key"]: row["values"] for row in want["side_by_side"]["rows"]}
    for column, drift in (("default", ours.predicted_drift_dps), ("paper_pipeline", scope["paper_drift"])):
        rms = scope["rms"](drift, scope["run"].true_drift_dps)
        assert math.isclose(rms, rows["drift_rmse_dps"][column], rel_tol=1e-9)  # summation order differs


def _values(text):
    """A parameter file's lines without its comments."""
    return [line for line in text.splitlines() if line and not line.startswith("#")]


# export_cubics / export_params with a calibration run equal `gyrocomp export -i CAL --validation RUN
# --static-weight W`: each axis's cubic, static curve, costs and expected error, and the file's values.
@pytest.mark.parametrize("weight", ["auto", "temperature", "time"])
def test_export_with_a_calibration_run_equals_export(cli, chamber, weight):
    m = str(chamber / "m.json")
    out, js = chamber / f"tc_{weight}.params", chamber / f"e_{weight}.json"
    _run(cli, "export", "-m", m, "-m", m, "-m", m, "--format", "px4", "--device-id", "1", "-i", str(chamber / "run.csv"),
         "--validation", str(chamber / "run2.csv"), "--static-weight", weight, "-o", str(out), "--json", str(js))
    want = json.loads(js.read_text())["axes"]
    models = [gyrocomp.load_drift_model(m)] * 3
    got = gyrocomp.export_cubics(models, calibration=str(chamber / "run.csv"), validation=chamber / "run2.csv",
                                 static_weight=weight)
    assert len(got) == len(want) == 3
    for g, w in zip(got, want):
        assert g.static_weight == w["static_weight"]["static_weight"]
        assert _same(list(g.cubic_dps.coeff_dps), w["cubic_dps"]["coeff"])
        assert _same(g.cubic_dps.ref_temp_c, w["cubic_dps"]["ref_temp_c"])
        for cost in ("cost_calibration", "cost_validation"):
            assert _same(g[cost].rms_dps, w[cost]["rms_dps"]) and g[cost].n_samples == w[cost]["n_samples"]
        if weight == "auto":
            assert g.weight_choice.reason == w["static_weight"]["reason"]
            assert _same(g.weight_choice.time.total_rms_dps, w["static_weight"]["time"]["total_rms_dps"])
        assert _same(g.expected_error.steady.total_rms_dps, w["expected_error"]["steady"]["total_rms_dps"])
    text = gyrocomp.export_params(models, "px4", calibration=str(chamber / "run.csv"), static_weight=weight, device_id=1)
    assert _values(text) == _values(out.read_text())


# `gyrocomp export` takes one calibration run (-i), and so does Python: several are refused.
def test_export_takes_one_calibration_run(cli, chamber):
    m = str(chamber / "m.json")
    p = subprocess.run([cli, "export", "-m", m, "-m", m, "-m", m, "--format", "px4", "--device-id", "1",
                        "-i", str(chamber / "run.csv"), "-i", str(chamber / "run2.csv")],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert p.returncode != 0 and "--input" in p.stdout
    models = [gyrocomp.load_drift_model(m)] * 3
    with pytest.raises(ValueError, match="one run"):
        gyrocomp.export_cubics(models, calibration=[str(chamber / "run.csv"), str(chamber / "run2.csv")])
    with pytest.raises(ValueError, match="static_weight=mean"):
        gyrocomp.export_cubics(models, static_weight="mean")
