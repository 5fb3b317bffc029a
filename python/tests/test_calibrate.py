"""gyrocomp.calibrate: the calibrate stage from Python gives the file the CLI writes."""
import json
import subprocess

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
