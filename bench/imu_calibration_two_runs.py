#!/usr/bin/env python3
"""One calibration run against two, and gyrocomp's pooled fit checked against its own definition
(docs/explanation/accuracy-calibration.md "The bound of one run, and several calibration runs").

    /usr/bin/python3 bench/imu_calibration_two_runs.py --pyulog DIR [--build build] [--seeds 5]
        [--second-profile heating|fast-heating|slow-heating|cooling] [--structure static|dtemp]
        [--optimise-for steady|warm-up|both]

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
    args = ap.parse_args()
    sys.path.insert(0, args.pyulog)
    gc = os.path.join(args.build, "gyrocomp")
    fs = 10
    diffs = {False: [], True: []}
    err, sd = [], []
    held_rms = {}
    cond_diffs, cond_same, cond_terms, cond_lagged = [], [], 0, 0
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
            # held-out scoring of the cubics (unclamped polynomial over the held-out run, as the bound)
            for k, name in enumerate(("heating", "cooling")):
                f = os.path.join(tmp, "held.ulg")
                b.simulate(gc, f, 100 * seed + 50 + 10 * k, fs, args.structure, name)
                t, v = b.read_imu(f)[0]
                sets = {"run 1": singles[0], "run 2": singles[1], "gyrocomp pooled":
                        [gyro["axes"][a]["cubic"]["coeff"][1:] for a in range(3)],
                        "pooled LS without dT/dt": mine[False], "pooled LS with dT/dt": mine[True]}
                for sname, sl in sets.items():
                    corr = np.array([sl[a][0] * (t - ref) + sl[a][1] * (t - ref) ** 2 + sl[a][2] * (t - ref) ** 3
                                     for a in range(3)])
                    held_rms.setdefault((name, sname), []).append(b.score(v, corr, fs).mean())
                held_rms.setdefault((name, "true curve"), []).append(b.score(v, b.truth_offsets(t, "gyro"), fs).mean())
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


if __name__ == "__main__":
    main()
