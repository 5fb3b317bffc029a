#!/usr/bin/python3
"""Probe (issue 11, second session): how much of poly(T, dT/dt)'s held-out error is flicker the
ordinary least-squares fit absorbs, and would a generalised least-squares fit recover it?

For each run TAG (files TAG.cool.csv = calibration, TAG.heat.csv and TAG.cool2.csv = held-out, as
bench/drift_heldout.sh writes them) it fits cubic-in-T + linear dT/dt on BLOCK-s block means by
  ols     ordinary least squares (what `fit --model poly --inputs temp,dtemp` computes, on block means)
  oracle  GLS with the noise autocovariance measured on the simulator's true_noise_dps of every
          paper-profile run given (not available on real data: the bound of what GLS could give)
  fgls    feasible GLS: autocovariance of the calibration run's own OLS residual, Tukey-tapered to
          lag n/TAPER, two iterations (what a fit could do on real data)
and prints each held-out RMSE against true_drift_dps (mdps) and the ratio to ols.
Only numpy. Not a test; a measurement (docs/notes/issue-11-s2.md).
Usage: /usr/bin/python3 bench/drift_gls_probe.py DIR TAG[,TAG...] [BLOCK=60] [TAPER=4]
"""
import glob
import sys

import numpy as np


def load(path):
    d = np.genfromtxt(path, delimiter=",", names=True)
    return d["temp_c"], d["rate_dps"], d["true_drift_dps"], d["true_noise_dps"]


def slope(temp, window=300):
    """Centred least-squares slope over `window` samples (1 Hz), one-sided at the ends."""
    h = window // 2
    k = np.arange(-h, h + 1, dtype=float)
    s = np.convolve(temp, (k / (k @ k))[::-1], mode="same")
    for i in range(h):
        s[i] = np.polyfit(np.arange(i + h + 1), temp[: i + h + 1], 1)[0]
        s[-1 - i] = np.polyfit(np.arange(i + h + 1), temp[-(i + h + 1):], 1)[0]
    return s


def design(temp, rate, sc):
    t = (temp - sc[0]) / sc[1]
    r = (rate - sc[2]) / sc[3]
    return np.column_stack([t**0, t, t**2, t**3, r])


def block_means(a, blk):
    n = len(a) // blk
    return a[: n * blk].reshape((n, blk) + a.shape[1:]).mean(1)


def autocov(z, n_out):
    z = z - z.mean()
    n = len(z)
    f = np.fft.rfft(z, 2 * n)
    return (np.fft.irfft(np.abs(f) ** 2)[:n] / n)[:n_out]


def toeplitz(a):
    n = len(a)
    i = np.arange(n)
    return a[np.abs(i[:, None] - i[None, :])]


def gls(x, y, acov):
    c = toeplitz(acov)
    c += 1e-6 * c[0, 0] * np.eye(len(y))
    l = np.linalg.cholesky(c)
    xw = np.linalg.solve(l, x)
    yw = np.linalg.solve(l, y)
    return np.linalg.lstsq(xw, yw, rcond=None)[0]


def main():
    d, tags = sys.argv[1], sys.argv[2].split(",")
    blk = int(sys.argv[3]) if len(sys.argv) > 3 else 60
    taper = int(sys.argv[4]) if len(sys.argv) > 4 else 4
    noise = [block_means(load(f)[3], blk) for f in sorted(glob.glob(f"{d}/*.cool*.csv"))]
    n0 = min(len(z) for z in noise)
    oracle_acov = np.mean([autocov(z[:n0], n0) for z in noise], 0)
    print(f"block {blk} s, taper n/{taper}, oracle autocovariance from {len(noise)} paper-profile runs")
    for tag in tags:
        temp, y, _, _ = load(f"{d}/{tag}.cool.csv")
        rate = slope(temp)
        sc = (temp.mean(), temp.std(), rate.mean(), rate.std())
        x, yb = block_means(design(temp, rate, sc), blk), block_means(y, blk)
        n = len(yb)
        fits = {"ols": np.linalg.lstsq(x, yb, rcond=None)[0], "oracle": gls(x, yb, oracle_acov[:n])}
        b = fits["ols"]
        window = np.zeros(n)
        k = np.arange(n // taper)
        window[: n // taper] = 0.5 * (1 + np.cos(np.pi * k / (n // taper)))
        for _ in range(2):
            b = gls(x, yb, autocov(yb - x @ b, n) * window)
        fits["fgls"] = b
        row = []
        for run in ("heat", "cool2"):
            th, _, truth, _ = load(f"{d}/{tag}.{run}.csv")
            xh = design(th, slope(th), sc)
            e = {k: 1000 * np.sqrt(np.mean((xh @ v - truth) ** 2)) for k, v in fits.items()}
            row.append(" ".join(f"{k} {e[k]:.2f} ({e[k] / e['ols']:.2f}x)" for k in fits))
        print(f"{tag}: heating {row[0]} | cooling-2 {row[1]}")


if __name__ == "__main__":
    main()
