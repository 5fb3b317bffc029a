#!/usr/bin/python3
"""Probe (issue 11, third session): generalised least squares with a *parametric* noise model.

For each run TAG (TAG.cool.csv = calibration, TAG.heat.csv and TAG.cool2.csv = held-out, as
bench/drift_heldout.sh writes them) it fits cubic-in-T + linear dT/dt on BLOCK-s block means by
  ols     ordinary least squares
  oracle  GLS with the noise autocovariance measured on the simulator's true_noise_dps of every
          paper-profile run given (the bound; not available on real data)
  pgls    GLS with the IEEE-952 noise model S(f) = h0 + h_-1/f + h_-2/f^2 (one-sided, (dps)^2/Hz)
          fitted to the Allan variance of the calibration run's own 1 Hz OLS residual
          (AVAR = h0/(2 tau) + 2 ln2 h_-1 + (2 pi^2/3) h_-2 tau, non-negative weighted least squares,
          tau = BLOCK .. record/TAUDIV), covariance of the block means from that PSD (white:
          h0/(2 block); flicker + RRW: S(f) sinc^2(f block) folded over the aliases, inverse DFT on
          a 2n grid, nothing below 1/(2 record)), ITER iterations (residual of the previous fit):
          the same estimator as `fit --model poly --noise-model allan` (Eq. G-0 .. G-3)
and prints each held-out RMSE against true_drift_dps (mdps), the ratio to ols, the fitted h's, and
the decision statistics of two calibration-only tests of whether to use GLS:
  H1  Eq. H-1 on contiguous blocks: g_k = RMSE_k(ols) - RMSE_k(pgls), GLS iff mean(g) > SD(g)
  HS  Hausman: d = b_ols - b_gls, V = Var(b_ols) - Var(b_gls) under the fitted noise model,
      H = d' V^+ d against chi^2(p); reject the model (keep OLS) iff p-value < 0.05
Only numpy. Not a test; a measurement (docs/notes/issue-11-s3-i11gls.md).
Usage: /usr/bin/python3 bench/drift_gls_param_probe.py DIR TAG[,TAG...] [BLOCK=60] [TAUDIV=10] [ITER=1]
"""
import glob
import math
import sys

import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from drift_gls_probe import autocov, block_means, design, gls, load, slope, toeplitz  # noqa: E402


def avar(y, taus):
    """Overlapping Allan variance of a 1 Hz series at integer taus (s)."""
    c = np.concatenate([[0.0], np.cumsum(y)])
    out = []
    for m in taus:
        a = (c[m:] - c[:-m]) / m            # means over m samples, every start
        d = a[m:] - a[:-m]
        out.append(0.5 * np.mean(d * d))
    return np.array(out)


def nnls3(a, b):
    """Non-negative least squares of 3 columns by enumeration of the 7 active sets."""
    best, h = np.inf, None
    for mask in range(1, 8):
        cols = [j for j in range(3) if mask >> j & 1]
        c = np.linalg.lstsq(a[:, cols], b, rcond=None)[0]
        if np.any(c < 0):
            continue
        r = np.sum((a[:, cols] @ c - b) ** 2)
        if r < best:
            best, h = r, np.zeros(3)
            h[cols] = c
    return h


def fit_noise(resid, taudiv, min_tau=1.0):
    """Eq. G-1 as src/drift/noise_model.cc: h0, h_-1, h_-2 >= 0 by weighted least squares on the
    AVAR at 30 log-spaced taus min_tau .. n/taudiv, weights EDF / AVAR_model^2 (EDF = n / m),
    4 passes starting from the measured AVAR."""
    n = len(resid)
    m_max = max(1.0, min(n / taudiv, n / 2))
    m_min = min(max(min_tau, 1.0), m_max)
    ms = []
    for k in range(30):
        m = int(round(m_min * (m_max / m_min) ** (k / 29)))
        if not ms or m != ms[-1]:
            ms.append(m)
    taus = np.array(ms, dtype=float)
    av = avar(resid, ms)
    t = np.column_stack([0.5 / taus, 2 * math.log(2) * np.ones(len(taus)), (2 * math.pi**2 / 3) * taus])
    edf = n / taus
    scale = av
    for _ in range(4):
        w = np.sqrt(edf) / scale
        h = nnls3(t * w[:, None], av * w)
        scale = t @ h
    return h


def block_cov(h, n, blk, aliases=200):
    """Eq. G-2 as src/drift/noise_model.cc: autocovariance of n block means (block blk s) of noise
    with one-sided PSD h0 + h1/f + h2/f^2; red part folded over +-aliases, nothing below 1/(2n blk)."""
    m = 2 * n
    df = 1.0 / (m * blk)
    f0 = np.arange(1, n + 1) * df
    sin2 = np.sin(np.pi * f0 * blk) ** 2
    s = np.zeros(n)
    for a in range(-aliases, aliases + 1):
        f = np.abs(f0 + a / blk)
        s += (h[1] / f + h[2] / f**2) * sin2 / (np.pi * f * blk) ** 2
    s *= df
    s[-1] *= 0.5
    k = np.arange(n)
    r = np.cos(2 * np.pi * np.outer(k, np.arange(1, n + 1)) / m) @ s
    r[0] += h[0] / (2 * blk)
    return r


def var_ols_gls(x, acov):
    c = toeplitz(acov)
    xtx_inv = np.linalg.inv(x.T @ x)
    v_ols = xtx_inv @ x.T @ c @ x @ xtx_inv
    v_gls = np.linalg.inv(x.T @ np.linalg.solve(c, x))
    return v_ols, v_gls


def hausman(x, b_ols, b_gls, acov):
    v_ols, v_gls = var_ols_gls(x, acov)
    d = b_ols - b_gls
    w, u = np.linalg.eigh(v_ols - v_gls)
    keep = w > 1e-9 * w.max()
    z = u[:, keep].T @ d
    stat = float(np.sum(z * z / w[keep]))
    dof = int(keep.sum())
    return stat, dof, chi2_sf(stat, dof)


def chi2_sf(x, k):
    """Upper tail of chi^2(k) via the regularised incomplete gamma (series / continued fraction)."""
    a, x = k / 2.0, x / 2.0
    if x <= 0:
        return 1.0
    if x < a + 1:
        s, t, n = 1.0 / a, 1.0 / a, a
        while abs(t) > 1e-14 * abs(s):
            n += 1
            t *= x / n
            s += t
        return 1.0 - s * math.exp(-x + a * math.log(x) - math.lgamma(a))
    b, c, d = x + 1 - a, 1e300, 1.0 / (x + 1 - a)
    hh = d
    for i in range(1, 500):
        an = -i * (i - a)
        b += 2
        d = an * d + b
        d = 1.0 / d
        c = b + an / c
        hh *= d * c
    return math.exp(-x + a * math.log(x) - math.lgamma(a)) * hh


def memory(rate, thr=1e-3):
    """+1 after heating, -1 after cooling (last ramp beyond thr deg C / s), 0 before any ramp."""
    m, out = 0.0, np.zeros(len(rate))
    for i, r in enumerate(rate):
        m = 1.0 if r > thr else -1.0 if r < -thr else m
        out[i] = m
    return out


def misspec(x, z, yb, acov):
    """Wald test of extra thermal-state terms z under the fitted noise covariance (GLS): chi^2(q)."""
    xa = np.column_stack([x, z])
    xa = xa / np.sqrt(np.mean(xa**2, 0))
    c = toeplitz(acov)
    c += 1e-6 * c[0, 0] * np.eye(len(yb))
    l = np.linalg.cholesky(c)
    xw, yw = np.linalg.solve(l, xa), np.linalg.solve(l, yb)
    q, r = np.linalg.qr(xw)
    b = np.linalg.solve(r, q.T @ yw)
    v = np.linalg.inv(r.T @ r)
    k = z.shape[1]
    bz, vz = b[-k:], v[-k:, -k:]
    stat = float(bz @ np.linalg.solve(vz, bz))
    return stat, k, chi2_sf(stat, k)


def blocked_gain(x, yb, fitter, folds=5):
    n = len(yb)
    edges = [n * k // folds for k in range(folds + 1)]
    g = []
    for k in range(folds):
        test = np.zeros(n, bool)
        test[edges[k]:edges[k + 1]] = True
        tr = ~test
        # in-range scoring on the first column's (standardised T) range
        lo, hi = x[tr, 1].min(), x[tr, 1].max()
        sc = test & (x[:, 1] >= lo) & (x[:, 1] <= hi)
        if sc.sum() == 0:
            continue
        bo = np.linalg.lstsq(x[tr], yb[tr], rcond=None)[0]
        bg = fitter(x[tr], yb[tr])
        eo = np.sqrt(np.mean((x[sc] @ bo - yb[sc]) ** 2))
        eg = np.sqrt(np.mean((x[sc] @ bg - yb[sc]) ** 2))
        g.append(eo - eg)
    g = np.array(g)
    return g.mean(), g.std(ddof=1)


def main():
    d, tags = sys.argv[1], sys.argv[2].split(",")
    blk = int(sys.argv[3]) if len(sys.argv) > 3 else 60
    taudiv = float(sys.argv[4]) if len(sys.argv) > 4 else 10
    iters = int(sys.argv[5]) if len(sys.argv) > 5 else 1
    noise = [block_means(load(f)[3], blk) for f in sorted(glob.glob(f"{d}/*.cool*.csv"))]
    n0 = min(len(z) for z in noise)
    oracle_acov = np.mean([autocov(z[:n0], n0) for z in noise], 0)
    print(f"block {blk} s, AVAR taus {blk} s .. record/{taudiv:g}, {iters} iteration(s)")
    for tag in tags:
        temp, y, _, _ = load(f"{d}/{tag}.cool.csv")
        rate = slope(temp)
        sc = (temp.mean(), temp.std(), rate.mean(), rate.std())
        x1 = design(temp, rate, sc)
        x, yb = block_means(x1, blk), block_means(y, blk)
        n = len(yb)
        b_ols = np.linalg.lstsq(x, yb, rcond=None)[0]
        b = b_ols
        for _ in range(iters):
            h = fit_noise(y - x1 @ b, taudiv, blk)
            acov = block_cov(h, n, blk)
            b = gls(x, yb, acov)
        fits = {"ols": b_ols, "oracle": gls(x, yb, oracle_acov[:n]), "pgls": b}
        stat, dof, p = hausman(x, b_ols, b, acov)
        tb = x[:, 1]
        rb = x[:, 4]
        z = np.column_stack([tb**4, tb * rb, rb**2, block_means(memory(rate), blk)])
        ms, mk, mp = misspec(x, z, yb, acov)
        gm, gs = blocked_gain(x, yb, lambda xx, yy: gls(xx, yy, block_cov(h, len(yy), blk)))
        row = []
        for run in ("heat", "cool2"):
            th, _, truth, _ = load(f"{d}/{tag}.{run}.csv")
            xh = design(th, slope(th), sc)
            e = {k: 1000 * np.sqrt(np.mean((xh @ v - truth) ** 2)) for k, v in fits.items()}
            row.append(" ".join(f"{k} {e[k]:.2f} ({e[k] / e['ols']:.2f}x)" for k in fits))
        print(f"{tag}: heating {row[0]} | cooling-2 {row[1]}")
        print(f"    h0 {h[0]:.3g} h-1 {h[1]:.3g} h-2 {h[2]:.3g} | H1 gain {1000*gm:.3f} +- {1000*gs:.3f} mdps "
              f"-> {'GLS' if gm > gs else 'OLS'} | Hausman {stat:.1f} (dof {dof}) p {p:.3g} "
              f"-> {'OLS' if p < 0.05 else 'GLS'} | misspec {ms:.1f} (dof {mk}) p {mp:.3g} -> {'OLS' if mp < 0.05 else 'GLS'}")


if __name__ == "__main__":
    main()
