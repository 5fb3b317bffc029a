"""gyrocomp.calibrate: the calibrate stage from Python gives the file the CLI writes."""
import json
import subprocess

import numpy as np
import pytest

import gyrocomp


def simulate_board(cli, path):
    subprocess.run([cli, "simulate", "--profile", "ramp", "--ramp-end", "60", "--room-hold", "600", "--hold", "600",
                    "--fs", "10", "--imus", "3", "-o", str(path)], check=True, capture_output=True)
    return str(path)


@pytest.mark.parametrize("fmt,name", [("px4", "board.ulg"), ("ardupilot", "board.bin")])
def test_python_parameter_text_equals_the_cli_file(cli, tmp_path, fmt, name):
    log = simulate_board(cli, tmp_path / name)
    out = tmp_path / "tc.params"
    subprocess.run([cli, "calibrate", "-i", log, "--format", fmt, "-o", str(out), "--json", str(tmp_path / "cal.json")],
                   check=True, capture_output=True)
    r = gyrocomp.calibrate([log], format=fmt)
    assert r.parameter_text == out.read_text()
    cal = json.loads((tmp_path / "cal.json").read_text())
    assert len(r.sensors) == len(cal["sensors"])
    for s, j in zip(r.sensors, cal["sensors"]):
        assert (s.type, s.instance, s.status) == (j["type"], j["instance"], j["status"])
        for cubic, axis in zip(s.cubics, j["axes"]):
            assert cubic.coeff == pytest.approx(axis["cubic"]["coeff"], rel=1e-12, abs=0)
    assert "gyro    2" in r.brief_report


def test_options_are_checked(cli, tmp_path):
    log = simulate_board(cli, tmp_path / "board.ulg")
    with pytest.raises(ValueError, match="fit_rate_hz"):
        gyrocomp.calibrate([log], fit_rate_hz=0.0)
    with pytest.raises(TypeError, match="'fit_rate'"):
        gyrocomp.calibrate([log], fit_rate=1.0)
    r = gyrocomp.calibrate([log], min_span_c=100.0)
    assert r.parameter_text == "" and all("temperature span" in s.reason for s in r.sensors)


def test_still_segments_identification_and_the_pooled_fit(cli, tmp_path):
    # A chamber run is still throughout: one still segment, nothing rejected, the single-run fit.
    log = simulate_board(cli, tmp_path / "a.ulg")
    r = gyrocomp.calibrate([log])
    assert len(r.logs) == 1 and len(r.logs[0].still_segments) == 1 and r.logs[0].rejected == []
    assert r.logs[0].still_s == pytest.approx(r.logs[0].total_s, rel=1e-3)
    assert all(s.fit == "single run" and s.identification.logs_with_still == 1 for s in r.sensors)
    # Two runs of the board: one pooled cubic over both, each sensor's identification filled.
    other = tmp_path / "b.ulg"
    subprocess.run([cli, "simulate", "--profile", "paper", "--hot", "60", "--cold", "0", "--step", "20", "--room-hold", "600",
                    "--hold", "600", "--fs", "10", "--imus", "3", "--seed", "2", "-o", str(other)], check=True,
                   capture_output=True)
    r = gyrocomp.calibrate([log, str(other)])
    assert len(r.logs) == 2 and r.parameter_text
    # The lag search and the dT/dt gains as calibrate --json has them.
    subprocess.run([cli, "calibrate", "-i", log, "-i", str(other), "--format", "px4", "-o", str(tmp_path / "tc.params"),
                    "--json", str(tmp_path / "cal.json")], check=True, capture_output=True)
    cal = json.loads((tmp_path / "cal.json").read_text())
    for s, j in zip(r.sensors, cal["sensors"]):
        if s.status != "calibrated":
            continue
        assert s.temp_lag_s == j["temp_lag_s"] and s.rate_gain == pytest.approx(j["rate_gain"], rel=1e-12, abs=0)
        lag = s.lag_term.to_dict()
        assert sorted(lag) == sorted(j["lag_term"]) == ["admitted", "gain", "gain_se", "groups"]
        for k, v in j["lag_term"].items():
            assert (lag[k] is None and v is None) or lag[k] == pytest.approx(v, rel=1e-12, abs=0), k
        # The heating state --optimise-for warm-up / both take the kept term at (None: no term).
        if j["heating_state"] is None:
            assert s.heating_state is None
        else:
            h = s.heating_state.to_dict()
            assert h["kind"] == j["heating_state"]["kind"] and h["t0_c"] == pytest.approx(j["heating_state"]["t0_c"], rel=1e-12)
            assert h["state"] == pytest.approx(j["heating_state"]["state"], rel=1e-12, abs=0)
    for s in r.sensors:
        if s.type == "baro":
            continue
        assert s.fit == "pooled" and s.status == "calibrated", s.reason
        assert s.identification.logs_with_still == 2 and s.identification.overlap_c > 10
        assert len(s.curve_sd) == 3 and all(v > 0 for v in s.curve_sd)
    # Too little still time asked for: no entry, the reason and what would help.
    r = gyrocomp.calibrate([log, str(other)], min_still_s=1e9)
    assert r.parameter_text == ""
    assert all("still time" in s.reason and "still" in s.identification.would_help for s in r.sensors)


def _report_data(path):
    """The data block of an HTML report (report.h schema), parsed back."""
    html = path.read_text()
    start = html.index('<script type="application/json" id="report-data">')
    start = html.index(">", start) + 1
    return json.loads(html[start:html.index("</script>", start)])  # "<\/" is JSON's escaped "/"


@pytest.mark.parametrize("pooled", [False, True])
def test_fit_rows_and_curve_bands_are_what_the_report_draws(cli, tmp_path, pooled):
    # The rows the fit saw and each axis's band, as `gyrocomp calibrate --report` draws them: the
    # band's temperatures, its half-width z sd (model unit), the rows per log.
    logs = [simulate_board(cli, tmp_path / "a.ulg")]
    if pooled:
        other = tmp_path / "b.ulg"
        subprocess.run([cli, "simulate", "--profile", "paper", "--hot", "60", "--cold", "0", "--step", "20",
                        "--room-hold", "600", "--hold", "600", "--fs", "10", "--imus", "3", "--seed", "2", "-o",
                        str(other)], check=True, capture_output=True)
        logs.append(str(other))
    args = [cli, "calibrate", "--format", "px4", "-o", str(tmp_path / "tc.params"), "--report", str(tmp_path / "r.html")]
    for log in logs:
        args += ["-i", log]
    subprocess.run(args, check=True, capture_output=True)
    sections = _report_data(tmp_path / "r.html")["sections"]
    r = gyrocomp.calibrate(logs, format="px4")
    assert len(sections) == len(r.sensors)
    checked = 0
    for s, section in zip(r.sensors, sections):
        if s.status != "calibrated":
            continue
        rows = s.fit_rows
        n = len(rows.temp_c)
        assert rows.values.shape == (len(s.cols), n) and len(rows.log) == n and len(rows.group) == n and len(rows.time_s) == n
        assert set(rows.log.tolist()) <= set(range(len(logs)))
        assert len(s.curve_bands) == len(s.cols)
        for k, band in enumerate(s.curve_bands):
            residual = section["charts"][2 * k + 1]
            assert residual["title"] == s.cols[k] + ": residual after the cubic"
            assert sum(p["rows"] for p in residual["points"]) == n
            first = residual["points"][0]
            assert first["x"][0] == rows.temp_c[rows.log == rows.log.min()][0]
            assert band.level == pytest.approx(0.9) and band.z == pytest.approx(1.6448536, rel=1e-6)
            drawn = residual["bands"][0]
            np.testing.assert_array_equal(band.temp_c, drawn["x"])
            np.testing.assert_allclose(band.z * band.sd * s.to_model, drawn["hi"], rtol=1e-15, atol=0)
            assert band.temp_c[0] == pytest.approx(s.temp_min_c) and band.temp_c[-1] == pytest.approx(s.temp_max_c)
            if pooled:  # the pooled fit's band: curve_sd at every temperature
                np.testing.assert_allclose(band.sd, s.curve_sd[k], rtol=1e-12)
            checked += 1
    assert checked >= 6
