#!/usr/bin/env python3
"""One calibration run against two, and gyrocomp's pooled fit checked against its own definition
(docs/explanation/accuracy-calibration.md "The bound of one run, and several calibration runs").

    /usr/bin/python3 bench/imu_calibration_two_runs.py --pyulog DIR [--build build] [--seeds 5]
        [--second-profile heating|fast-heating|slow-heating|cooling] [--structure static|dtemp]
        [--optimise-for steady|warm-up|both] [--front [--estimation-excess E] [--steady-excess E]]

Per seed: run 1 is the bench's calibration run (heating 10 -> 60 C at 1 C/min, seed 100 s), run 2
another seed (100 s + 1000) of the same profile (`heating`, the default) or of the bench's second
profile (bench/imu_calibration_side_by_side.py --second-profile, seed 100 s + 5000). Gyro only.
1. The least-squares cubic with a constant per run (pooled_fit.h's definition) computed here from
   the runs' 1 s means (the rows gyrocomp's pooled fit takes from a chamber run still throughout),
   without and with a shared dT/dt column (dT/dt over +-30 s, as calibrate_runs.cc's HeatingRate),
   against the file `gyrocomp calibrate -i RUN1 -i RUN2 --json` writes: the largest difference of
   the centred curves over the range, in % of the curve's own change, says which of the two the
   pooled fit returned (the JSON does not say whether the dT/dt term was admitted).
2. The pooled curve's error against the true static curve (the simulator's bias cubic), centred,
   RMS over 101 temperatures, over the seeds, against the JSON's `curve_sd` (the fit's 1 sigma of
   the same quantity: pooled_fit.h Eqs. P-1..P-3, HAC and the delete-one-log jackknife).
3. Held-out heating and cooling (RMS of 10 s means, mean removed, deg/s, as the side-by-side bench
   scores): run 1's cubic, run 2's, the pooled file's, the two LS cubics of 1., the true curve; on
   the bias(T)-only structure
   the excess over the true curve, sqrt(RMS^2 - RMS_true^2), is estimation noise and falls by about
   1/sqrt(2) with two runs of one profile.
4. With --optimise-for warm-up|both: the file `calibrate ... --optimise-for C` writes against its
   definition computed here: the heating state s(T) (per 1 C bin from the lowest temperature, the
   median dT/dt of the two runs' rows heating at >= 1/300 C/s, 0 in bins without any; the binning
   of the single run's StateWhileHeating) and the least-squares cubic over 401 temperatures of the
   steady file's curve + w g s(T), g the JSON's rate_gain, w = 1 (warm-up) or 1/2 (both): the
   largest difference of the centred curves, in % of the term's own change (w g s over the range),
   on the axes that kept the term; the others must equal the steady file.
5. With --front: whether any cubic at all could be never worse than the better single run in both
   held-out directions. Each held-out run is simulated a second time without the gyro's noise
   (--arw 0 --bias-instability 0 --rrw 0, same seed: the same drift; the thermometer keeps its own
   noise), so that every file is scored by its expected residual over the held-out noise,
   sqrt(R_nf^2 + N^2) (R_nf: on the noise-free run; N: the RMS of the noise's own centred 10 s
   means, the difference of the two runs). Each single run's own file (`gyrocomp calibrate -i RUN`)
   scored so: a = the lower heating residual of the two, b = the lower cooling one (means over seeds
   and axes). Against them the best any cubic can do, knowing the true drift: per seed and axis, the
   cubic fitted to the noise-free held-out runs, weighted (1 - w) heating / w cooling, traces the
   reachable (heating, cooling) pairs; their set averaged over seeds and axes is convex and meets
   {heating <= a, cooling <= b} only if no line (1 - u) h + u c separates them, so the largest over u
   of [min over the set of (1 - u) h + u c] - [(1 - u) a + u b] > 0 proves that no cubic, however it
   was fitted, is never worse than the better single run in both directions; <= 0: not proven.
   --estimation-excess E (deg/s) repeats the test with E added in quadrature to every point: the
   least estimation error of a cubic estimated from the two runs (any linear unbiased estimator of
   any target cubic: with the dT/dt and hysteresis terms known it is the static design's GLS-exact
   excess, sqrt(ratio^2 - 1) RMS_true from `bench/imu_calibration_bound.py --second-profile P`, and
   not knowing them cannot lower it).
   --steady-excess E (deg/s): the same for the steady export (the default), whose target is the true
   static curve (dT/dt = 0): that curve scored so, and with E in quadrature, the least excess of a
   steady export, which must estimate the dT/dt gain to remove it (`bench/imu_calibration_bound.py
   --second-profile P --rate-term`, steady GLS-exact): above a or b, no estimator of the steady curve
   linear in the two runs' data is never worse than the better single run in that direction.
"""
import argparse
import json
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import imu_calibration_side_by_side as b  # noqa: E402


def one_hz(gyro, fs):
    """1 s means of temperature and the three axes (rad/s), and dT/dt over +-30 s (C/s)."""
    temp, v = gyro
    n = int(round(fs))
    m = len(temp) // n
    t = temp[: m * n].reshape(m, n).mean(axis=1)
    y = v[:, : m * n].reshape(3, m, n).mean(axis=2)
    idx = np.arange(m)
    lo, hi = np.maximum(idx - 30, 0), np.minimum(idx + 30, m - 1)
    rate = (t[hi] - t[lo]) / np.maximum(hi - lo, 1)
    return t, y, rate


def pooled_fit(runs, ref, with_rate):
    """Least squares: y = b_run + c1 dT + c2 dT^2 + c3 dT^3 [+ g dT/dt]; returns (c1, c2, c3) per axis."""
    t = np.concatenate([r[0] for r in runs])
    groups = np.concatenate([np.full(len(r[0]), k) for k, r in enumerate(runs)])
    d = t - ref
    cols = [(groups == k).astype(float) for k in range(len(runs))] + [d, d * d, d ** 3]
    if with_rate:
        cols.append(np.concatenate([r[2] for r in runs]))
    x = np.vstack(cols).T
    out = []
    for a in range(3):
        y = np.concatenate([r[1][a] for r in runs])
        c = np.linalg.lstsq(x, y, rcond=None)[0]
        out.append(c[len(runs): len(runs) + 3])
    return out


def heating_state(runs, min_rate=1.0 / 300.0):
    """(t0, per 1 C bin the median dT/dt of the runs' rows heating at >= min_rate, 0 without any)."""
    t = np.concatenate([r[0] for r in runs])
    rate = np.concatenate([r[2] for r in runs])
    t0 = t.min()
    bins = [[] for _ in range(int((t.max() - t0) // 1.0) + 1)]
    for ti, ri in zip(t, rate):
        if ri >= min_rate:
            bins[int((ti - t0) // 1.0)].append(ri)
    return t0, np.array([sorted(v)[len(v) // 2] if v else 0.0 for v in bins])


def condition_cubic(cubic, gain, w, t0, state, tmin, tmax, ref):
    """The LS cubic over 401 temperatures of cubic(T) + w gain s(T): (c0, c1, c2, c3)."""
    grid = np.linspace(tmin, tmax, 401)
    d = grid - ref
    s = state[np.clip(np.floor((grid - t0) / 1.0).astype(int), 0, len(state) - 1)]
    y = cubic[0] + cubic[1] * d + cubic[2] * d ** 2 + cubic[3] * d ** 3 + w * gain * s
    h = 0.5 * (tmax - tmin)
    u = d / h
    c = np.linalg.lstsq(np.vstack([np.ones_like(u), u, u * u, u ** 3]).T, y, rcond=None)[0]
    return c / h ** np.arange(4), w * gain * s


def score_blocks(t, v, fs, ref):
    """The score's 10 s block means (b.score), centred: the cubic's columns (T - ref)^1..3 (n x 3) and
    the three axes (3 x n, deg/s)."""
    n = int(round(10 * fs))
    m = len(t) // n
    d = t[: m * n] - ref
    x = np.vstack([d, d * d, d ** 3]).reshape(3, m, n).mean(axis=2).T
    y = (v[:, : m * n] / b.RAD).reshape(3, m, n).mean(axis=2)
    return x - x.mean(axis=0), y - y.mean(axis=1, keepdims=True)


def front(held, weights):
    """Per axis, the expected (heating, cooling) residual RMS, sqrt(R_nf^2 + N^2), of the cubic minimising
    (1 - w) R_h^2 + w R_c^2 on the noise-free held-out runs, for each w: axes x len(weights) x 2 (deg/s)."""
    (xh, yh, nh), (xc, yc, nc) = held
    scale = np.abs(np.vstack([xh, xc])).max(axis=0)
    xh, xc = xh / scale, xc / scale
    out = np.zeros((3, len(weights), 2))
    for a in range(3):
        for i, w in enumerate(weights):
            rows = np.vstack([np.sqrt((1 - w) / len(yh[a])) * xh, np.sqrt(w / len(yc[a])) * xc])
            rhs = np.concatenate([np.sqrt((1 - w) / len(yh[a])) * yh[a], np.sqrt(w / len(yc[a])) * yc[a]])
            c = np.linalg.lstsq(rows, rhs, rcond=None)[0]
            out[a, i] = [np.sqrt(np.mean((yh[a] - xh @ c) ** 2) + nh[a]), np.sqrt(np.mean((yc[a] - xc @ c) ** 2) + nc[a])]
    return out


def separation(points, a, b_, us):
    """max over u of mean over (seed, axis) of min over the traced points of (1 - u) h + u c, minus
    (1 - u) a + u b: > 0 proves the averaged reachable set misses {h <= a, c <= b} (5.); with the u."""
    best = (-np.inf, None)
    for u in us:
        lower = np.mean([np.min((1 - u) * p[:, 0] + u * p[:, 1]) for p in points])
        gap = lower - ((1 - u) * a + u * b_)
        if gap > best[0]:
            best = (gap, u)
    return best


def cubic_correction(t, ref, slopes):
    """Per axis a, the cubic sum_j slopes[a][j] (t - ref_a)^(j + 1), j = 0..2 (unclamped, as the
    bound scores it); ref: one temperature for every axis or one per axis."""
    refs = ref if np.ndim(ref) else [ref] * len(slopes)
    return np.array([sum(s[j] * (t - r) ** (j + 1) for j in range(3)) for s, r in zip(slopes, refs)])


def centred(slopes, ref, grid):
    d = grid - ref
    c = slopes[0] * d + slopes[1] * d * d + slopes[2] * d ** 3
    return c - c.mean()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--pyulog", required=True)
    ap.add_argument("--second-profile", default="heating", choices=["heating"] + sorted(b.SECOND_PROFILES))
    ap.add_argument("--structure", default="static", choices=["static", "dtemp"])
    ap.add_argument("--optimise-for", default="steady", choices=["steady", "warm-up", "both"],
                    help="also check the pooled file calibrate --optimise-for writes against its definition (4.)")
    ap.add_argument("--front", action="store_true",
                    help="score each run's own file and test whether any cubic is never worse than both (5.)")
    ap.add_argument("--estimation-excess", type=float, default=0.0,
                    help="with --front: also the test with this least estimation excess, deg/s (5.)")
    ap.add_argument("--steady-excess", type=float, default=0.0,
                    help="with --front: the least estimation excess of the steady export, deg/s (5.)")
    args = ap.parse_args()
    sys.path.insert(0, args.pyulog)
    gc = os.path.join(args.build, "gyrocomp")
    fs = 10
    diffs = {False: [], True: []}
    err, sd = [], []
    held_rms = {}
    cond_diffs, cond_same, cond_terms, cond_lagged = [], [], 0, 0
    weights = np.linspace(0.0, 1.0, 401)
    front_points = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, args.seeds + 1):
            cal, raw = [], []
            for k, (prof, s) in enumerate((("heating", 100 * seed),
                                           (args.second_profile, 100 * seed + (1000 if args.second_profile == "heating"
                                                                               else b.SECOND_SEED)))):
                f = os.path.join(tmp, "cal%d.ulg" % k)
                b.simulate(gc, f, s, fs, args.structure, prof)
                cal.append(f)
                raw.append(one_hz(b.read_imu(f)[0], fs))
            j = os.path.join(tmp, "pooled.json")
            rc, out = b.run([gc, "calibrate", "-i", cal[0], "-i", cal[1], "--format", "px4",
                             "-o", os.path.join(tmp, "p.params"), "--json", j])
            if rc != 0:
                sys.exit("calibrate failed: " + out)
            gyro = [s for s in json.load(open(j))["sensors"] if s["type"] == "gyro"][0]
            tmin, tmax = gyro["temp_min_c"], gyro["temp_max_c"]
            grid = np.linspace(tmin, tmax, 101)
            ref = gyro["axes"][0]["cubic"]["ref_temp_c"]
            mine = {w: pooled_fit(raw, ref, w) for w in (False, True)}
            truth = b.truth_offsets(grid, "gyro")
            singles = []
            for r in raw:
                singles.append([np.polyfit(r[0] - ref, r[1][a], 3)[::-1][1:] for a in range(3)])
            for a in range(3):
                cub = gyro["axes"][a]["cubic"]["coeff"]
                g = centred(cub[1:], ref, grid)
                span = np.ptp(g)
                for w in (False, True):
                    diffs[w].append(np.max(np.abs(g - centred(mine[w][a], ref, grid))) / span)
                e = g - (truth[a] - truth[a].mean())
                err.append(np.sqrt(np.mean(e ** 2)))
                sd.append(gyro["curve_sd"][a])
            if args.optimise_for != "steady":
                jc = os.path.join(tmp, "cond.json")
                rc, out = b.run([gc, "calibrate", "-i", cal[0], "-i", cal[1], "--format", "px4", "--optimise-for",
                                 args.optimise_for, "-o", os.path.join(tmp, "c.params"), "--json", jc])
                if rc != 0:
                    sys.exit("calibrate failed: " + out)
                cg = [s for s in json.load(open(jc))["sensors"] if s["type"] == "gyro"][0]
                t0, state = heating_state(raw)
                w = 1.0 if args.optimise_for == "warm-up" else 0.5
                cond_lagged += gyro["temp_lag_s"] > 0
                for a in range(3 if gyro["temp_lag_s"] == 0 else 0):  # a lag kept: not this definition
                    gain = gyro["rate_gain"][a]
                    got = cg["axes"][a]["cubic"]["coeff"]
                    if gain == 0.0:
                        cond_same.append(got == gyro["axes"][a]["cubic"]["coeff"])
                        continue
                    cond_terms += 1
                    want, term = condition_cubic(gyro["axes"][a]["cubic"]["coeff"], gain, w, t0, state, tmin, tmax, ref)
                    cond_diffs.append(np.max(np.abs(centred(got[1:], ref, grid) - centred(want[1:], ref, grid))) /
                                      max(np.ptp(term), 1e-300))
            own = []
            if args.front:
                for k in range(2):
                    jk = os.path.join(tmp, "own%d.json" % k)
                    rc, out = b.run([gc, "calibrate", "-i", cal[k], "--format", "px4", "-o",
                                     os.path.join(tmp, "own.params"), "--json", jk])
                    if rc != 0:
                        sys.exit("calibrate failed: " + out)
                    gk = [s for s in json.load(open(jk))["sensors"] if s["type"] == "gyro"][0]
                    own.append([(gk["axes"][a]["cubic"]["ref_temp_c"], gk["axes"][a]["cubic"]["coeff"][1:])
                                for a in range(3)])
            held = []
            # held-out scoring of the cubics (unclamped polynomial over the held-out run, as the bound)
            for k, name in enumerate(("heating", "cooling")):
                f = os.path.join(tmp, "held.ulg")
                b.simulate(gc, f, 100 * seed + 50 + 10 * k, fs, args.structure, name)
                t, v = b.read_imu(f)[0]
                sets = {"run 1": singles[0], "run 2": singles[1], "gyrocomp pooled":
                        [gyro["axes"][a]["cubic"]["coeff"][1:] for a in range(3)],
                        "pooled LS without dT/dt": mine[False], "pooled LS with dT/dt": mine[True]}
                for sname, sl in sets.items():
                    held_rms.setdefault((name, sname), []).append(b.score(v, cubic_correction(t, ref, sl), fs).mean())
                held_rms.setdefault((name, "true curve"), []).append(b.score(v, b.truth_offsets(t, "gyro"), fs).mean())
                if args.front:
                    fnf = os.path.join(tmp, "held_nf.ulg")
                    b.simulate(gc, fnf, 100 * seed + 50 + 10 * k, fs, args.structure, name,
                               ["--arw", "0", "--bias-instability", "0", "--rrw", "0"])
                    tn, vn = b.read_imu(fnf)[0]
                    noise2 = b.score(v - vn, np.zeros_like(v), fs) ** 2
                    held.append(score_blocks(tn, vn, fs, ref) + (noise2,))

                    def expected(key, corr):  # the residual expected over the held-out noise
                        held_rms.setdefault((name, key), []).append(np.sqrt(b.score(vn, corr, fs) ** 2 + noise2).mean())
                    expected("true curve, expected", b.truth_offsets(tn, "gyro"))
                    for r, sl in enumerate(own):
                        expected("run %d alone, expected" % (r + 1),
                                 cubic_correction(tn, [x[0] for x in sl], [x[1] for x in sl]))
                    files = {"pooled, expected": gyro}
                    if args.optimise_for != "steady":
                        files["pooled --optimise-for, expected"] = cg
                    for key, g in files.items():
                        expected(key, cubic_correction(tn, ref, [g["axes"][a]["cubic"]["coeff"][1:] for a in range(3)]))
            if args.front:
                front_points.extend(front(held, weights))
            print("done: seed %d" % seed, file=sys.stderr)
    print("%s structure, run 2 = %s, %d seeds x 3 gyro axes" % (args.structure, args.second_profile, args.seeds))
    for w in (False, True):
        print("gyrocomp's pooled curve vs the pooled LS cubic %s the dT/dt column: largest difference %.2g %% of "
              "the curve's change (median %.2g %%)" % ("with" if w else "without", 100 * max(diffs[w]),
                                                       100 * np.median(diffs[w])))
    match = [(d0 < 0.01, d1 < 0.01) for d0, d1 in zip(diffs[False], diffs[True])]
    print("axes whose pooled curve is the LS cubic within 1 %%: without dT/dt %d, with dT/dt %d, both (gain ~0) %d, "
          "neither %d, of %d" % (sum(a and not b for a, b in match), sum(b and not a for a, b in match),
                                 sum(a and b for a, b in match), sum(not a and not b for a, b in match), len(match)))
    print("pooled curve - true curve (centred, RMS over the range): %.3g rad/s RMS over axes and seeds; the JSON's "
          "curve_sd %.3g rad/s: actual / reported %.1f" % (np.sqrt(np.mean(np.square(err))), np.sqrt(np.mean(np.square(sd))),
                                                          np.sqrt(np.mean(np.square(err))) / np.sqrt(np.mean(np.square(sd)))))
    if args.optimise_for != "steady":
        print("--optimise-for %s file vs the steady curve + w g s(T) (numpy): %d axes with the dT/dt term, largest "
              "difference %s of the term's change; %d of %d axes without it equal to the steady file; %d seeds with a lag "
              "kept (not checked here)" % (args.optimise_for, cond_terms,
                                           "%.2g %%" % (100 * max(cond_diffs)) if cond_diffs else "-",
                                           sum(cond_same), len(cond_same), cond_lagged))
    for name in ("heating", "cooling"):
        true = np.mean(held_rms[(name, "true curve")])
        parts = []
        for sname in ("run 1", "run 2", "gyrocomp pooled", "pooled LS without dT/dt", "pooled LS with dT/dt"):
            m = np.mean(held_rms[(name, sname)])
            parts.append("%s %.4f (x%.3f, excess %.4f)" % (sname, m, m / true, np.sqrt(max(m * m - true * true, 0.0))))
        print("held-out %s, deg/s: %s; true curve %.4f" % (name, "; ".join(parts), true))
    if args.front:
        single = {name: [np.mean(held_rms[(name, "run %d alone, expected" % r)]) for r in (1, 2)]
                  for name in ("heating", "cooling")}
        a, b_ = min(single["heating"]), min(single["cooling"])
        pooled = [np.mean(held_rms[(name, "pooled, expected")]) for name in ("heating", "cooling")]
        for key in ["pooled, expected"] + (["pooled --optimise-for, expected"] if args.optimise_for != "steady" else []):
            parts = []
            for name in ("heating", "cooling"):
                best = np.argmin(single[name]) + 1
                d = np.array(held_rms[(name, key)]) - np.array(held_rms[(name, "run %d alone, expected" % best)])
                parts.append("%s %+.5f +- %.5f" % (name, d.mean(), d.std(ddof=1) / np.sqrt(len(d))))
            print("paired over seeds, %s - the better single run (deg/s, mean +- SE): %s" % (key, "; ".join(parts)))
        if args.optimise_for != "steady":
            cond = [np.mean(held_rms[(name, "pooled --optimise-for, expected")]) for name in ("heating", "cooling")]
            print("expected residuals (5.), pooled --optimise-for %s: %.4f / %.4f (x%.3f / x%.3f the better single run)"
                  % (args.optimise_for, cond[0], cond[1], cond[0] / a, cond[1] / b_))
        mean_front = np.mean(front_points, axis=0)
        print("expected residuals (5.), each run alone (gyrocomp calibrate -i RUN), held-out heating / cooling, deg/s: run 1 %.4f / %.4f, "
              "run 2 %.4f / %.4f; better single a = %.4f, b = %.4f; pooled %.4f / %.4f (x%.3f / x%.3f)"
              % (single["heating"][0], single["cooling"][0], single["heating"][1], single["cooling"][1], a, b_,
                 pooled[0], pooled[1], pooled[0] / a, pooled[1] / b_))
        for e in sorted({0.0, args.steady_excess}):
            h, c = (np.sqrt(np.mean(held_rms[(name, "true curve, expected")]) ** 2 + e * e) for name in ("heating", "cooling"))
            print("the steady export's target, the true static curve, with estimation excess %.5f deg/s: %.4f / %.4f "
                  "(x%.3f / x%.3f the better single run)" % (e, h, c, h / a, c / b_))
        print("best cubic knowing the true drift, w = weight on cooling: heating / cooling (x a / x b)")
        for w in (0.0, 0.25, 0.4, 0.45, 0.5, 0.75, 1.0):
            i = int(round(w * (len(weights) - 1)))
            h, c = mean_front[i]
            print("  w %.2f: %.4f / %.4f (x%.3f / x%.3f)" % (w, h, c, h / a, c / b_))
        for e in sorted({0.0, args.estimation_excess}):
            pts = [np.sqrt(p ** 2 + e * e) for p in front_points]
            gap, u = separation(pts, a, b_, np.linspace(0.0, 1.0, 201))
            print("separation (5.), estimation excess %.5f deg/s: %+.5f deg/s at u = %.3f: %s" % (
                e, gap, u, "no such cubic is never worse than the better single run in both directions" if gap > 0
                else "not proven: some cubic may be never worse in both directions"))


if __name__ == "__main__":
    main()
