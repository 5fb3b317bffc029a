"""Simulator, VMD, entropy, denoising, drift model and the parallel model from Python."""
import threading

import numpy as np
import pytest

import gyrocomp


def soak(seconds, fs_hz=20.0, **noise):
    return gyrocomp.simulate(fs_hz=fs_hz, seed=4, duration_s=seconds,
                             profile=dict(kind="soak", soak_duration_s=seconds), noise=noise)


def test_simulator_round_trip_arw():
    run = soak(7200.0, arw_deg_per_sqrt_h=1.0, bias_instability_deg_per_h=0.0, rrw_deg_per_h_per_sqrt_h=0.0)
    assert run.rate_dps.shape == (144000,) and run.summary.num_samples == 144000
    # Ground truth: rate = true rate + drift + noise, to rounding.
    np.testing.assert_allclose(run.rate_dps, run.true_rate_dps + run.true_drift_dps + run.true_noise_dps,
                               rtol=0, atol=1e-12)
    a = gyrocomp.compute_allan(run.rate_dps, run.fs_hz)
    # 1.44e5 samples: EDF ~ 3N/2m = 1e4 at 1 s (1% standard error): 4%.
    assert a.terms.arw_deg_per_sqrt_h == pytest.approx(1.0, rel=0.04)
    with pytest.raises(ValueError, match="profile kind=sauna"):
        gyrocomp.simulate(profile=dict(kind="sauna"))
    with pytest.raises(TypeError, match="'arw'"):
        gyrocomp.simulate(noise=dict(arw=1.0))


def test_vmd_separates_two_tones_progress_and_cancel():
    n, fs = 2048, 100.0
    t = np.arange(n) / fs
    x = np.sin(2 * np.pi * 2.0 * t) + 0.5 * np.sin(2 * np.pi * 20.0 * t)
    calls = []
    v = gyrocomp.vmd(x, num_modes=2, fs_hz=fs, progress=lambda stage, f: calls.append((stage, f)))
    assert v.modes.shape == (2, n)
    assert sorted(v.center_frequency_hz) == pytest.approx([2.0, 20.0], rel=0.02)
    assert calls and calls[0][0] == "vmd" and len(calls) == v.iterations
    # Cancellation from another thread while the call runs without the GIL.
    token = gyrocomp.CancellationToken()
    started = threading.Event()

    def progress(stage, fraction):
        started.set()
    timer = threading.Timer(0.0, lambda: (started.wait(5), token.cancel()))
    timer.start()
    with pytest.raises(gyrocomp.Cancelled):
        gyrocomp.vmd(np.random.default_rng(0).standard_normal(1 << 15), num_modes=6, tol=1e-300,
                     max_iterations=100000, progress=progress, cancel=token)
    timer.join()
    # A Python exception raised by the progress callback propagates as itself.
    def boom(stage, fraction):
        raise KeyError("from progress")
    with pytest.raises(KeyError, match="from progress"):
        gyrocomp.vmd(x, num_modes=2, progress=boom)


def test_sample_entropy_and_denoisers():
    rng = np.random.default_rng(5)
    white = rng.standard_normal(3000)
    se = gyrocomp.sample_entropy(white)
    # White Gaussian noise, m = 2, r = 0.2 SD: SampEn ~ 2.2 (Richman & Moorman 2000, Fig. 2).
    assert se.defined and se.sample_entropy == pytest.approx(2.2, abs=0.15)
    with pytest.raises(ValueError, match="SampleEntropyOptions::m"):
        gyrocomp.sample_entropy(white, m=0)
    x = np.sin(np.arange(4096) * 2 * np.pi / 512) + 0.1 * rng.standard_normal(4096)
    clean = np.sin(np.arange(4096) * 2 * np.pi / 512)
    w = gyrocomp.wavelet_denoise(x)
    # Universal soft threshold on a slow sine plus 0.1 white noise: most of the noise goes.
    assert np.std(w.denoised - clean) < 0.5 * np.std(x - clean)
    wf = gyrocomp.wflp_denoise(x, flp=dict(order=4))
    assert wf.denoised.shape == x.shape and np.all(np.isfinite(wf.denoised))
    assert wf.summary.flp.order == 4 and wf.summary.level == 4  # the keyword and the default
    assert gyrocomp.flp_denoise(x, order=4).summary.order == 4
    with pytest.raises(ValueError, match="extension=mirror"):
        gyrocomp.wavelet_denoise(x, extension="mirror")


def test_drift_model_fit_predict_save_load(tmp_path):
    fs = 1.0
    temp = np.linspace(-20.0, 50.0, 3000)
    drift = 0.02 + 1e-3 * (temp - 25.0) + 2e-5 * (temp - 25.0) ** 2
    target = drift + 1e-3 * np.random.default_rng(6).standard_normal(temp.size)
    model = gyrocomp.fit_drift_model(temp, target, fs, model="poly", degree=2)
    assert model.kind == "poly"
    predicted = model.predict(temp, fs)
    # A quadratic fitted to a quadratic plus 1e-3 noise: residual near the noise level.
    assert np.sqrt(np.mean((predicted - drift) ** 2)) < 3e-4
    path = tmp_path / "model.json"
    model.save(str(path))
    again = gyrocomp.load_drift_model(str(path))
    assert again.predict(temp, fs).tolist() == predicted.tolist()
    # The prediction band, kept through the file.
    band = again.predict_band(temp, fs)
    assert band["level"] == 0.9
    assert np.all(band["lo"] <= band["center"]) and np.all(band["hi"] >= band["center"])
    assert band["center"].tolist() == predicted.tolist()
    # The band's parts and what the run supports, beside the band itself.
    parts = again.band
    assert parts["level"] == 0.9 and parts["expected_rms"] > 0.0
    assert set(parts["noise"]) == {"white", "flicker", "random_walk"}
    summary = gyrocomp.fit_drift_model(temp, target, fs).summary  # the default, auto
    assert summary["drift_span"] > 0.0 and "Eq. I-0" in summary["data_support"]
    # A single ramp identifies no dT/dt gain: left out, with the run that would identify it.
    assert any(t["term"] == "dT/dt gain" and t["would_identify"] for t in summary["excluded_terms"])
    # fit --auto-lagged-curve's option is read (out of its range 0..2: refused).
    with pytest.raises((RuntimeError, ValueError), match="lagged_curve_gain_degree"):
        gyrocomp.fit_drift_model(temp, target, fs, lagged_curve_gain_degree=3)
    with pytest.raises((RuntimeError, ValueError), match="lagged_curve_pieces"):
        gyrocomp.fit_drift_model(temp, target, fs, lagged_curve_pieces=0)
    with pytest.raises(ValueError):
        gyrocomp.drift_model_from_json("{}")
    with pytest.raises((RuntimeError, ValueError)):
        gyrocomp.load_drift_model(str(tmp_path / "missing.json"))


def test_parallel_model_on_a_short_simulated_chamber_run():
    run = gyrocomp.simulate(fs_hz=2.0, seed=2, profile=dict(kind="ramp", room_hold_s=600.0, ramp_end_c=45.0))
    stages = set()
    r = gyrocomp.run_parallel_model(run.rate_dps, run.temp_c, run.fs_hz, measure_bandwidth=False,
                                    drift=dict(max_generations=2, num_nests=5),
                                    progress=lambda stage, f: stages.add(stage))
    assert r.compensated_dps.shape == run.rate_dps.shape
    assert len(r.mode_reports) == 6 and {m.to_dict()["class"] for m in r.mode_reports} <= {"drift", "mixed", "noise"}
    assert "vmd" in stages
    # The drift branch tracks the simulated drift better than no model at all: SD of (predicted -
    # true drift) was 0.62 (seed 2) and 0.20 (seed 3) of the true drift's SD on this 1.5 h, 2 Hz
    # run with a 2-generation search; 0.75 fails if the branch predicts nothing useful.
    truth = run.true_drift_dps
    assert np.std(r.predicted_drift_dps - truth) < 0.75 * np.std(truth)
    assert isinstance(r.drift_model, gyrocomp.DriftModel)
    assert r.allan_before.terms.arw_deg_per_sqrt_h > 0


def test_export_cubic_projection_and_autopilot_files():
    fs = 1.0
    temp = np.linspace(-10.0, 60.0, 2000)
    # A cubic drift (deg/s): a degree-3 polynomial model reproduces it, and its projection onto a
    # cubic about the range's middle (25 C) is that same cubic.
    c = [0.02, 1.5e-3, 1.2e-5, -2e-7]
    x = temp - 25.0
    drift = c[0] + c[1] * x + c[2] * x ** 2 + c[3] * x ** 3
    models = [gyrocomp.fit_drift_model(temp, s * drift, fs, model="poly", degree=3) for s in (1.0, -0.5, 2.0)]
    cubic = gyrocomp.project_onto_cubic(models[0])
    assert cubic.ref_temp_c == pytest.approx(25.0)
    # Exact data, exact model: coefficients to rounding of the fits (1e-9 of the largest term).
    np.testing.assert_allclose(cubic.coeff_dps, c, rtol=0, atol=1e-9 * 0.1)
    px4 = gyrocomp.export_params(models, "px4", device_id=1234)
    assert "TC_G0_ID\t1234" in px4 and "TC_G0_TMIN" in px4
    # TC_G0_X0_0 is c0 of the x axis in rad/s, written as float32.
    line = next(l for l in px4.splitlines() if "\tTC_G0_X0_0\t" in l)
    assert float(line.split("\t")[3]) == pytest.approx(0.02 * np.pi / 180.0, rel=1e-6)
    ardu = gyrocomp.export_params(models, "ardupilot", imu=2)
    assert "INS_TCAL2_" in ardu
    with pytest.raises(ValueError):
        gyrocomp.export_params(models[:2], "px4")
    with pytest.raises(ValueError, match="device_id|TC_G|ID"):
        gyrocomp.export_params(models, "px4")  # PX4 needs the sensor's device id


def test_read_log_csv_and_ulog(golden_dir):
    log = gyrocomp.read_log(str(golden_dir / "allan_kinds" / "rate.csv"))
    assert log.axis_names == ["rate_dps"] and log.fs_hz == pytest.approx(10.0, rel=1e-9)
    data = np.loadtxt(golden_dir / "allan_kinds" / "rate.csv", delimiter=",", skiprows=1)
    assert log.rate_dps["rate_dps"].tolist() == data[:, 1].tolist()
    assert log.temp_c is None
    with pytest.raises(ValueError, match="rate_unit=furlongs"):
        gyrocomp.read_log(str(golden_dir / "allan_kinds" / "rate.csv"), rate_unit="furlongs")
    with pytest.raises(ValueError, match="no_such_column|not found|column"):
        gyrocomp.read_log(str(golden_dir / "allan_kinds" / "rate.csv"), rate_cols="no_such_column")


def test_read_log_px4_ulog_matches_pyulog_extraction(golden_dir):
    fieldlogs = golden_dir.parent / "fieldlogs"
    ulg = fieldlogs / "sample_log_small.ulg"
    if not ulg.exists():
        pytest.skip("tests/fieldlogs/ absent")
    ref = np.loadtxt(fieldlogs / "sample_log_small.ulg.sensor_gyro_0.csv", delimiter=",", skiprows=1, ndmin=2)
    log = gyrocomp.read_log(str(ulg), instance=0)
    assert log.device_id == 2424842 and log.axis_names == ["x_rad_s", "y_rad_s", "z_rad_s"]
    x = log.rate_dps[log.axis_names[0]]
    # pyulog's float32 values widened to double, in rad/s; ours in deg/s (x 180/pi, one rounding).
    np.testing.assert_allclose(x, ref[: len(x), 1] * 180.0 / np.pi, rtol=1e-15)
