"""Each subcommand's work called from Python equals what the CLI writes (same inputs, same files)."""
import json
import math
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
