#!/usr/bin/python3
"""Bound (docs/explanation/accuracy-calibration.md "The bound of one run, and several calibration
runs"): how close to the true static curve can ANY cubic fitted on the side-by-side bench's
calibration run come on its held-out heating and cooling runs?

The bench (bench/imu_calibration_side_by_side.py) scores the residual a parameter set leaves on a
held-out run as the RMS of 10 s block means with their mean removed. For a cubic b_hat fitted on
one calibration run whose drift is exactly a cubic (the `static` structure: bias(T) only; the
accelerometers in every structure), that residual is the held-out run's own noise plus the
estimation error X_h (b_hat - b), independent of each other, so in expectation
    RMS^2 = RMS_true^2 + excess^2,   excess^2 = trace(Xc_h Cov(b_hat) Xc_h') / n_h
(Xc_h: the held-out run's cubic design, columns centred: the mean is removed). Cov(b_hat) under
the simulator's noise (white + flicker as a sum of Gauss-Markov processes + rate random walk,
include/gyrocomp/sim/simulator.h, exact autocovariance of 10 s block means):
    OLS (what gyrocomp, the PX4 script and tempcal_IMU compute, up to weighting):
        (X'X)^-1 X' S X (X'X)^-1
    GLS-exact (the best linear unbiased estimator, Gauss-Markov; needs the true noise covariance):
        (X' S^-1 X)^-1
No estimator that is linear in the calibration run's data does better than GLS-exact. The
target "within 5 % of the true cubic" needs excess <= sqrt(1.05^2 - 1) RMS_true = 0.32 RMS_true.
Printed per sensor and held-out run: RMS_true, excess (OLS, GLS-exact), the ratios
sqrt(RMS_true^2 + excess^2) / RMS_true, and how many independent calibration runs of the same
profile (excess / sqrt(k)) each estimator needs to reach 1.05.
Only numpy and `gyrocomp simulate` (for the temperature profiles: the bench's arguments).
Usage: /usr/bin/python3 bench/imu_calibration_bound.py [--build build]
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

# bench/imu_calibration_side_by_side.py: simulate arguments of the calibration and held-out runs.
BASE = ["--profile", "ramp", "--thermal-lag", "120", "--room-hold", "600", "--hold", "1200", "--ramp-rate", "1",
        "--fs", "1", "--dtemp-coeff", "0", "--hysteresis-coeff", "0"]
RUNS = {"calibration": ["--room-temp", "10", "--ramp-end", "60"],
        "heating": ["--room-temp", "10", "--ramp-end", "60"],
        "cooling": ["--room-temp", "60", "--ramp-end", "10"]}
BLOCK_S = 10
# Noise of include/gyrocomp/sim/simulator.h: white sigma at 1 Hz, flicker floor 0.664 B, RRW.
NOISE = {"gyro deg/s": dict(white=1.667 / 60.0, b=44.0 / 3600.0, rrw=3.0 / 3600.0 / 60.0),
         "accel m/s^2": dict(white=0.06 / 60.0, b=4.0e-4, rrw=0.0)}


def block_cov(n, blk, white, b, rrw):
    """Autocovariance of n block means (blk s) of white + Gauss-Markov flicker (10 .. 1e5 s, 2 per
    decade, equal variances scaled to the ADEV floor 0.664 B at tau_mid) + RRW (bench/drift_gls_bound.py's
    construction with the sensor's numbers)."""
    corr = 10.0 * 10.0 ** (np.arange(9) / 2.0)
    x = 1000.0 / corr
    unit = np.sum((2.0 / x) * (1.0 - (3.0 - 4.0 * np.exp(-x) + np.exp(-2.0 * x)) / (2.0 * x)))
    q2 = (0.664 * b) ** 2 / unit
    m = 8 * n
    f = np.arange(m // 2 + 1) / (m * blk)
    s = np.zeros_like(f)
    for t in corr:
        s += 4.0 * q2 * t / (1.0 + (2.0 * math.pi * f * t) ** 2)
    s[1:] += rrw ** 2 / (2.0 * math.pi ** 2) / f[1:] ** 2
    s *= np.sinc(f * blk) ** 2
    r = np.fft.irfft(s / 2.0, m) / blk
    r = r[:n].copy()
    r[0] += white ** 2 / blk
    return r


def toeplitz(a):
    n = len(a)
    i = np.arange(n)
    return a[np.abs(i[:, None] - i[None, :])]


def temperature(gc, args, tmp):
    path = os.path.join(tmp, "run.csv")
    r = subprocess.run([gc, "simulate"] + BASE + args + ["--seed", "1", "-o", path], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("simulate failed: " + r.stdout + r.stderr)
    d = np.genfromtxt(path, delimiter=",", names=True)
    t = d["temp_c"]
    n = len(t) // BLOCK_S
    return t[: n * BLOCK_S].reshape(n, BLOCK_S).mean(axis=1)


def design(t, ref):
    d = (t - ref) / 25.0
    return np.vstack([np.ones_like(d), d, d * d, d * d * d]).T


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    a = ap.parse_args()
    gc = os.path.join(a.build, "gyrocomp")
    with tempfile.TemporaryDirectory() as tmp:
        temps = {k: temperature(gc, v, tmp) for k, v in RUNS.items()}
    ref = 35.0
    x = design(temps["calibration"], ref)
    n = len(x)
    print("Calibration run: %d blocks of %d s; target: excess <= 0.32 x RMS_true (ratio <= 1.05)" % (n, BLOCK_S))
    print("| sensor | held-out run | RMS_true | excess OLS | excess GLS-exact | ratio OLS | ratio GLS-exact "
          "| runs for 1.05, OLS | runs for 1.05, GLS |")
    print("|---|---|---|---|---|---|---|---|---|")
    for sensor, p in NOISE.items():
        s = toeplitz(block_cov(n, BLOCK_S, **p))
        pinv = np.linalg.pinv(x)
        cov_ols = pinv @ s @ pinv.T
        cov_gls = np.linalg.inv(x.T @ np.linalg.solve(s, x))
        for run in ("heating", "cooling"):
            xh = design(temps[run], ref)
            nh = len(xh)
            xc = xh - xh.mean(axis=0)
            sh = toeplitz(block_cov(nh, BLOCK_S, **p))
            c = np.eye(nh) - 1.0 / nh
            true = math.sqrt(np.trace(c @ sh @ c) / nh)
            ex = {k: math.sqrt(np.trace(xc @ v @ xc.T) / nh) for k, v in (("ols", cov_ols), ("gls", cov_gls))}
            allowed = math.sqrt(1.05 ** 2 - 1.0) * true
            runs = {k: math.ceil((v / allowed) ** 2) for k, v in ex.items()}
            print("| %s | %s | %.4g | %.4g | %.4g | %.3f | %.3f | %d | %d |" % (
                sensor, run, true, ex["ols"], ex["gls"], math.hypot(true, ex["ols"]) / true,
                math.hypot(true, ex["gls"]) / true, runs["ols"], runs["gls"]))


if __name__ == "__main__":
    main()
