"""Allan deviations from Python: golden values, the same numbers as the CLI, options, errors."""
import json
import subprocess

import numpy as np
import pytest

import gyrocomp


def read_golden(golden_dir):
    data = np.loadtxt(golden_dir / "allan_kinds" / "rate.csv", delimiter=",", skiprows=1)
    golden = json.loads((golden_dir / "allan_kinds" / "deviations.json").read_text())
    return data[:, 1], golden


@pytest.mark.parametrize("kind,key", [("adev", "oadev"), ("mdev", "mdev"), ("hdev", "hdev"),
                                      ("ohdev", "ohdev"), ("totdev", "totdev")])
def test_deviations_match_allantools(golden_dir, kind, key):
    rate, golden = read_golden(golden_dir)
    d = gyrocomp.compute_deviation(rate, golden["fs_hz"], kind)
    g = golden[key]
    # Same bar as the C++ test: 1e-9 relative (summation order only).
    np.testing.assert_allclose(d.tau_s, g["tau_s"], rtol=1e-12)
    np.testing.assert_allclose(d.dev_dps, g["dev_dps"], rtol=1e-9)
    np.testing.assert_array_equal(d.n, g["n"])
    assert np.all(d.lo_dps < d.dev_dps) and np.all(d.hi_dps > d.dev_dps)


def test_python_and_cli_give_identical_numbers(golden_dir, cli, tmp_path):
    rate, golden = read_golden(golden_dir)
    out = subprocess.run([cli, "allan", "-i", str(golden_dir / "allan_kinds" / "rate.csv"), "--deviation", "totdev",
                          "--min-edf", "5", "--json", "-"], check=True, capture_output=True, text=True)
    j = json.loads(out.stdout)
    a = gyrocomp.compute_allan(rate, golden["fs_hz"], min_edf_for_terms=5)
    t = gyrocomp.compute_deviation(rate, golden["fs_hz"], "totdev", min_edf_for_terms=5)
    # Identical, not close: the same library on the same doubles (the CLI reads the CSV with the
    # same shortest round-trip parsing as numpy, and its JSON keeps every digit).
    assert j["tau_s"] == a.tau_s.tolist()
    assert j["adev_dps"] == a.adev_dps.tolist()
    assert j["adev_lo_dps"] == a.adev_lo_dps.tolist()
    assert j["totdev_dps"] == t.dev_dps.tolist()
    assert j["totdev_hi_dps"] == t.hi_dps.tolist()
    for key in ("arw_deg_per_sqrt_h", "adev_min_deg_per_h", "adev_min_usable_deg_per_h", "tau_at_min_s",
                "bias_instability_deg_per_h", "min_edf"):
        assert j[key] == getattr(a.terms, key), key
    assert j["adev_min_at_longest_tau"] == a.terms.min_at_longest_tau
    assert j["bandwidth_max_hz"] == a.bandwidth_max_hz == golden["fs_hz"] / 2


def test_white_noise_arw_and_result_object():
    fs = 100.0
    rng = np.random.default_rng(3)
    # ARW 0.5 deg/sqrt(h): sigma(1 s) = 0.5 / 60 deg/s, per-sample sigma = that * sqrt(fs).
    y = rng.standard_normal(200_000) * 0.5 / 60.0 * np.sqrt(fs)
    a = gyrocomp.compute_allan(y, fs)
    # EDF at 1 s is ~3e3 (1.3% standard error): 5%.
    assert a.terms.arw_deg_per_sqrt_h == pytest.approx(0.5, rel=0.05)
    d = a.to_dict()
    assert d["terms"]["arw_deg_per_sqrt_h"] == a.terms.arw_deg_per_sqrt_h
    assert isinstance(d["adev_dps"], np.ndarray) and d["adev_dps"].dtype == np.float64
    assert "taus" not in repr(a) or "0 taus" not in repr(a)


def test_options_defaults_and_errors():
    y = np.random.default_rng(1).standard_normal(5000)
    default = gyrocomp.compute_allan(y, 10.0)
    assert default.confidence == 0.683 and default.terms.min_edf == 10.0  # the C++ defaults
    decade = gyrocomp.compute_allan(y, 10.0, taus="decade", confidence=0.95)
    assert decade.confidence == 0.95 and decade.m.tolist()[:4] == [1, 2, 4, 10]
    with pytest.raises(ValueError, match="AllanOptions::confidence"):
        gyrocomp.compute_allan(y, 10.0, confidence=1.5)
    with pytest.raises(ValueError, match="sample 3 is not finite"):
        gyrocomp.compute_allan(np.array([1.0, 2.0, 3.0, np.nan, 5.0]), 1.0)
    with pytest.raises(TypeError, match="unexpected keyword argument 'confidance'"):
        gyrocomp.compute_allan(y, 10.0, confidance=0.9)
    with pytest.raises(ValueError, match="kind=oadev"):
        gyrocomp.compute_deviation(y, 10.0, "oadev")
    with pytest.raises(ValueError, match="1-D"):
        gyrocomp.compute_allan(y.reshape(50, 100), 10.0)
    # Other dtypes are converted (once): int input gives the same numbers as float.
    ints = np.arange(100, dtype=np.int32) % 7
    assert gyrocomp.compute_allan(ints, 1.0).adev_dps.tolist() == \
        gyrocomp.compute_allan(ints.astype(float), 1.0).adev_dps.tolist()


def test_kalibr_yaml():
    fs = 100.0
    y = np.random.default_rng(2).standard_normal(100_000) * 1.0 / 60.0 * np.sqrt(fs)
    text = gyrocomp.kalibr_imu_yaml(y, fs, rostopic="/imu/data")
    a = gyrocomp.compute_allan(y, fs)
    line = next(l for l in text.splitlines() if l.startswith("gyroscope_noise_density:"))
    value = float(line.split(":")[1].split("#")[0])
    assert value == pytest.approx(a.terms.arw_deg_per_sqrt_h / 60.0 * np.pi / 180.0, rel=1e-12)
    assert "rostopic: /imu/data" in text and "update_rate: 100" in text
