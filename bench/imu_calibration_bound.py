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
With --second-profile P (a profile of the bench's --second-profile), also the pooled fit of
`calibrate -i RUN1 -i RUN2` (the cubic shared by both runs, a constant per run, least squares on
every row, no dT/dt term) on the calibration run and a second run of profile P, and P alone:
excess from the slope block of Cov over the stacked design [run indicators, cubic columns] with
the two runs' noise independent (OLS: (D'D)^-1 D' S D (D'D)^-1; GLS-exact: (D' S^-1 D)^-1).
With --second-profile P --rate-term, also the pooled design with a shared dT/dt column (what
`calibrate` fits when the two runs' rates identify a dT/dt gain; dT/dt over +-30 s as
calibrate_runs.cc's HeatingRate): the excess of each `--optimise-for` export on each held-out run,
the cubic's slopes plus w g times the held-out run's own dT/dt (steady w = 0, both 1/2, warm-up 1;
the export takes the state the calibration runs had while heating, which for held-out heating at
the calibration run's rate is the same), OLS and GLS-exact. The steady export is the curve at
dT/dt = 0, so it has to estimate g to remove it: its least excess is that of this design, not of
the static one.
Only numpy and `gyrocomp simulate` (for the temperature profiles: the bench's arguments).
Usage: /usr/bin/python3 bench/imu_calibration_bound.py [--build build] [--second-profile P [--rate-term]]
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import imu_calibration_side_by_side as bench  # noqa: E402  (its profiles; numpy only)

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


def temperature(gc, args, tmp, full=None):
    path = os.path.join(tmp, "run.csv")
    r = subprocess.run([gc, "simulate"] + (full if full else BASE + args) + ["--seed", "1", "-o", path],
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("simulate failed: " + r.stdout + r.stderr)
    d = np.genfromtxt(path, delimiter=",", names=True)
    t = d["temp_c"]
    n = len(t) // BLOCK_S
    return t[: n * BLOCK_S].reshape(n, BLOCK_S).mean(axis=1)


def second_args(profile):
    """simulate arguments of the bench's second calibration run of `profile` (bench.simulate's merge)."""
    base = {"--room-hold": "600", "--hold": "1200", "--ramp-rate": "1"}
    prof = bench.SECOND_PROFILES[profile]
    for k in list(base):
        if k in prof:
            del base[k]
    return ["--profile", "ramp", "--thermal-lag", "120", "--fs", "1", "--dtemp-coeff", "0", "--hysteresis-coeff", "0"] + \
        [x for kv in base.items() for x in kv] + prof


def pooled_excess(cal, xh, p, nh, rates=None, rate_h=None, w=0.0):
    """Excess of the pooled fit (a constant per run, the cubic's slopes shared) on held-out design
    xh, for OLS and GLS-exact: {"ols": e, "gls": e}. cal: list of calibration-run designs (cubic
    columns with the constant first, as design() gives). With rates (each calibration run's dT/dt
    per block, C/min) a shared dT/dt column too, and the export scored is the cubic plus w g
    rate_h (the held-out run's dT/dt per block, C/min)."""
    n = [len(x) for x in cal]
    rows = sum(n)
    k = len(cal) + 3 + (1 if rates is not None else 0)
    d = np.zeros((rows, k))
    s = np.zeros((rows, rows))
    at = 0
    for r, x in enumerate(cal):
        d[at:at + n[r], r] = 1.0
        d[at:at + n[r], len(cal):len(cal) + 3] = x[:, 1:]
        if rates is not None:
            d[at:at + n[r], -1] = rates[r]
        s[at:at + n[r], at:at + n[r]] = toeplitz(block_cov(n[r], BLOCK_S, **p))
        at += n[r]
    pinv = np.linalg.pinv(d)
    cov = {"ols": pinv @ s @ pinv.T, "gls": np.linalg.inv(d.T @ np.linalg.solve(s, d))}
    xc = xh[:, 1:] - xh[:, 1:].mean(axis=0)
    if rates is not None:
        xc = np.hstack([xc, (w * (rate_h - rate_h.mean()))[:, None]])
    return {k: math.sqrt(np.trace(xc @ v[len(cal):, len(cal):] @ xc.T) / nh) for k, v in cov.items()}


def block_rate(t):
    """dT/dt per block over +-30 s (calibrate_runs.cc's HeatingRate, shortened at the ends), C/min."""
    h = 30 // BLOCK_S
    i = np.arange(len(t))
    lo, hi = np.maximum(i - h, 0), np.minimum(i + h, len(t) - 1)
    return (t[hi] - t[lo]) / ((hi - lo) * BLOCK_S) * 60.0


def design(t, ref):
    d = (t - ref) / 25.0
    return np.vstack([np.ones_like(d), d, d * d, d * d * d]).T


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--second-profile", choices=sorted(bench.SECOND_PROFILES))
    ap.add_argument("--rate-term", action="store_true", help="with --second-profile: also the pooled design with a "
                    "shared dT/dt column, the excess of each --optimise-for export")
    a = ap.parse_args()
    if a.rate_term and not a.second_profile:
        ap.error("--rate-term needs --second-profile")
    gc = os.path.join(a.build, "gyrocomp")
    with tempfile.TemporaryDirectory() as tmp:
        temps = {k: temperature(gc, v, tmp) for k, v in RUNS.items()}
        if a.second_profile:
            temps["second"] = temperature(gc, [], tmp, second_args(a.second_profile))
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
    if not a.second_profile:
        return
    x2 = design(temps["second"], ref)
    print()
    print("Second calibration run: %s, %d blocks; pooled: -i calibration -i %s (a constant per run)" % (
        a.second_profile, len(x2), a.second_profile))
    print("| sensor | held-out run | RMS_true | ratio OLS run 1 | ratio OLS run 2 | ratio OLS pooled "
          "| ratio GLS-exact pooled |")
    print("|---|---|---|---|---|---|---|")
    for sensor, p in NOISE.items():
        for run in ("heating", "cooling"):
            xh = design(temps[run], ref)
            nh = len(xh)
            sh = toeplitz(block_cov(nh, BLOCK_S, **p))
            c = np.eye(nh) - 1.0 / nh
            true = math.sqrt(np.trace(c @ sh @ c) / nh)
            e1, e2, e12 = (pooled_excess(cal, xh, p, nh) for cal in ([x], [x2], [x, x2]))
            print("| %s | %s | %.4g | %.3f | %.3f | %.3f | %.3f |" % (
                sensor, run, true, math.hypot(true, e1["ols"]) / true, math.hypot(true, e2["ols"]) / true,
                math.hypot(true, e12["ols"]) / true, math.hypot(true, e12["gls"]) / true))
    if not a.rate_term:
        return
    rates = [block_rate(temps["calibration"]), block_rate(temps["second"])]
    print()
    print("Pooled with a shared dT/dt column: excess of each --optimise-for export (deg/s or m/s^2), OLS / GLS-exact; "
          "without the column (the static design) for comparison")
    print("| sensor | held-out run | static design | steady | both | warm-up |")
    print("|---|---|---|---|---|---|")
    for sensor, p in NOISE.items():
        for run in ("heating", "cooling"):
            xh = design(temps[run], ref)
            cells = [pooled_excess([x, x2], xh, p, len(xh))]
            cells += [pooled_excess([x, x2], xh, p, len(xh), rates, block_rate(temps[run]), w) for w in (0.0, 0.5, 1.0)]
            print("| %s | %s | %s |" % (sensor, run, " | ".join("%.5f / %.5f" % (e["ols"], e["gls"]) for e in cells)))


if __name__ == "__main__":
    main()
