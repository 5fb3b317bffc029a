#!/usr/bin/python3
"""Bound (docs/explanation/drift-noise-model.md "The bound of any weighting"): how much better than
ordinary least squares can ANY fit of poly(T, dT/dt) do on the next run, when the noise is the
simulator's and the form is right?

Gauss-Markov: generalised least squares with the exact noise covariance (GLS-exact) is the best
linear unbiased estimator of the coefficients. This draws R independent realisations of the noise
block means from the exact covariance of the simulator's default noise model (white ARW 1.667
deg/sqrt(h), flicker B = 44 deg/h as a sum of Gauss-Markov processes 10 .. 1e5 s at 2 per decade,
RRW 3 deg/h/sqrt(h): include/gyrocomp/sim/simulator.h), adds them to the true drift of one
calibration run (TAG.cool.csv's true_drift_dps on BLOCK-s block means; its temperature and dT/dt
are the design), fits cubic-in-T + linear dT/dt by OLS and by GLS-exact (and OLS of degree 2, a
biased alternative), and scores each on the true drift of the held-out runs TAG.heat.csv and
TAG.cool2.csv. Reports per estimator: RMS over draws of the held-out RMSE as a ratio to OLS's
(the expected-MSE ratio), mean / median / 10th / 90th percentile of the per-draw ratio, and the
share of draws at or below 0.8x.
A bound for the form-right structures (D; A and C up to their hysteresis); on B the residual is
misspecification, and GLS re-weights it (the draws add only noise: B's rows say what GLS does to
the misfit in expectation).
With FEASIBLE > 0 it also draws FEASIBLE realisations at 1 Hz (the same noise model, generated
sample by sample) and adds pgls: GLS with the noise model of bench/drift_gls_param_probe.py
(h0, h_-1, h_-2 fitted to the Allan variance of the draw's own 1 Hz OLS residual): how close the
feasible estimator comes to the bound (slow: about 0.5 s per draw).
Only numpy. Not a test; a measurement (docs/explanation/drift-noise-model.md).
Usage: /usr/bin/python3 bench/drift_gls_bound.py DIR TAG[,TAG...] [DRAWS=200] [BLOCK=60] [SEED=1] [FEASIBLE=0]
"""
import math
import sys

import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from drift_gls_probe import block_means, design, load, slope, toeplitz  # noqa: E402


def simulator_block_cov(n, blk):
    """Autocovariance of n block means (blk s each) of the simulator's default noise, (dps)^2."""
    sig_w = 1.667 / 60.0                                   # white, dps at 1 Hz
    corr = 10.0 * 10.0 ** (np.arange(9) / 2.0)             # 10 .. 1e5 s, 2 per decade
    x = 1000.0 / corr                                      # tau_mid = sqrt(10 * 1e5) s
    unit = np.sum((2.0 / x) * (1.0 - (3.0 - 4.0 * np.exp(-x) + np.exp(-2.0 * x)) / (2.0 * x)))
    q2 = (0.664 * 44.0 / 3600.0) ** 2 / unit               # variance of each Gauss-Markov process
    k_rrw = 3.0 / 3600.0 / 60.0                            # dps / sqrt(s)
    m = 8 * n                                              # circulant grid, 1 / (8 record)
    f = np.arange(m // 2 + 1) / (m * blk)
    s = np.zeros_like(f)                                   # one-sided PSD, (dps)^2 / Hz
    for t in corr:
        s += 4.0 * q2 * t / (1.0 + (2.0 * math.pi * f * t) ** 2)
    s[1:] += k_rrw**2 / (2.0 * math.pi**2) / f[1:] ** 2
    s *= np.sinc(f * blk) ** 2                             # block mean
    r = np.fft.irfft(s / 2.0, m) / blk
    r = r[:n].copy()
    r[0] += sig_w**2 / blk                                 # white: variance / samples per block
    return r


NOISE = dict(sig_w=1.667 / 60.0, corr=10.0 * 10.0 ** (np.arange(9) / 2.0), k_rrw=3.0 / 3600.0 / 60.0)


def draw_1hz(n, rng):
    """One 1 Hz realisation of the simulator's default noise (white + Gauss-Markov sum + RRW)."""
    corr = NOISE["corr"]
    x = 1000.0 / corr
    unit = np.sum((2.0 / x) * (1.0 - (3.0 - 4.0 * np.exp(-x) + np.exp(-2.0 * x)) / (2.0 * x)))
    q = math.sqrt((0.664 * 44.0 / 3600.0) ** 2 / unit)
    phi = np.exp(-1.0 / corr)
    drive = q * np.sqrt(1.0 - phi * phi) * rng.standard_normal((n, len(corr)))
    state = q * rng.standard_normal(len(corr))
    out = np.empty(n)
    for i in range(n):
        state = phi * state + drive[i]
        out[i] = state.sum()
    return out + NOISE["sig_w"] * rng.standard_normal(n) + np.cumsum(NOISE["k_rrw"] * rng.standard_normal(n))


def feasible(d, tag, draws, blk, rng):
    from drift_gls_param_probe import block_cov, fit_noise
    from drift_gls_probe import gls
    temp, _, drift, _ = load(f"{d}/{tag}.cool.csv")
    rate = slope(temp)
    sc = (temp.mean(), temp.std(), rate.mean(), rate.std())
    x1 = design(temp, rate, sc)
    x = block_means(x1, blk)
    n = len(x)
    c = simulator_block_cov(n, blk)
    th, _, truth = None, None, None
    held = {}
    for run in ("heat", "cool2"):
        th, _, truth, _ = load(f"{d}/{tag}.{run}.csv")
        held[run] = (design(th, slope(th), sc), truth)
    e = {run: {"ols": [], "gls-exact": [], "pgls": []} for run in held}
    for _ in range(draws):
        y = drift + draw_1hz(len(drift), rng)
        yb = block_means(y, blk)
        bo = np.linalg.lstsq(x, yb, rcond=None)[0]
        h = fit_noise(y - x1 @ bo, 10, blk)
        b = {"ols": bo, "gls-exact": gls(x, yb, c), "pgls": gls(x, yb, block_cov(h, n, blk))}
        for run, (xh, truth) in held.items():
            for k, v in b.items():
                e[run][k].append(1000 * math.sqrt(np.mean((xh @ v - truth) ** 2)))
    for run in held:
        o = np.array(e[run]["ols"])
        parts = []
        for k, v in e[run].items():
            v = np.array(v)
            q = v / o
            parts.append(f"{k} RMS {math.sqrt(np.mean(v**2)):.2f} mdps ({math.sqrt(np.mean(v**2) / np.mean(o**2)):.3f}x), "
                         f"per draw mean {q.mean():.3f} median {np.median(q):.3f} <=0.8: {np.mean(q <= 0.8):.2f}")
        print(f"{tag} {run}, 1 Hz draws ({draws}):\n  " + "\n  ".join(parts))


def main():
    d, tags = sys.argv[1], sys.argv[2].split(",")
    draws = int(sys.argv[3]) if len(sys.argv) > 3 else 200
    blk = int(sys.argv[4]) if len(sys.argv) > 4 else 60
    seed = int(sys.argv[5]) if len(sys.argv) > 5 else 1
    print(f"{draws} noise draws per run, block {blk} s; ratio = held-out RMSE / OLS's")
    for i, tag in enumerate(tags):
        rng = np.random.default_rng([seed, i])     # per run: a run's draws do not depend on the others
        temp, _, drift, _ = load(f"{d}/{tag}.cool.csv")
        rate = slope(temp)
        sc = (temp.mean(), temp.std(), rate.mean(), rate.std())
        x, mu = block_means(design(temp, rate, sc), blk), block_means(drift, blk)
        n = len(mu)
        c = toeplitz(simulator_block_cov(n, blk))
        lc = np.linalg.cholesky(c + 1e-9 * c[0, 0] * np.eye(n))
        xw = np.linalg.solve(lc, x)
        est = {
            "ols": np.linalg.pinv(x),
            "gls-exact": np.linalg.pinv(xw) @ np.linalg.inv(lc),
            "ols-deg2": np.vstack([np.linalg.pinv(x[:, [0, 1, 2, 4]])[:3], np.zeros(n),
                                   np.linalg.pinv(x[:, [0, 1, 2, 4]])[3:]]),
        }
        held = {}
        for run in ("heat", "cool2"):
            th, _, truth, _ = load(f"{d}/{tag}.{run}.csv")
            held[run] = (design(th, slope(th), sc), truth)
        y = mu[:, None] + lc @ rng.standard_normal((n, draws))
        for run, (xh, truth) in held.items():
            e = {k: 1000 * np.sqrt(np.mean((xh @ (p @ y) - truth[:, None]) ** 2, 0)) for k, p in est.items()}
            parts = []
            for k, v in e.items():
                q = v / e["ols"]
                parts.append(f"{k} RMS {math.sqrt(np.mean(v**2)):.2f} mdps ({math.sqrt(np.mean(v**2) / np.mean(e['ols']**2)):.3f}x), "
                             f"per draw mean {q.mean():.3f} median {np.median(q):.3f} p10 {np.percentile(q, 10):.3f} "
                             f"p90 {np.percentile(q, 90):.3f} <=0.8: {np.mean(q <= 0.8):.2f}")
            print(f"{tag} {run}:\n  " + "\n  ".join(parts))
        if len(sys.argv) > 6 and int(sys.argv[6]) > 0:
            feasible(d, tag, int(sys.argv[6]), blk, np.random.default_rng([seed, i, 1]))


if __name__ == "__main__":
    main()
