#!/usr/bin/python3
"""Oracle bound (docs/explanation/calibration-design.md "What any estimator can reach"): can ANY
estimator of the simulator's own drift form, fitted on one calibration run of <= 14.25 h, reach 0.8x
the held-out drift RMSE of poly(T, dT/dt) fitted on the paper's cooling run? And on which profile?

The simulator's drift (docs/explanation/simulator.md, src/sim/simulator.cc BiasDriftDps) is
    drift = c0 + c1 d + c2 d^2 + c3 d^3 + k_dot r + k_h (T - P_w(T)),   d = T - 25 C,
with T the true sensor temperature, r = (u - T) / lag its true rate and P_w the play operator of
the true width w. Given T, r and w (which no real estimator has), that is LINEAR in its six
coefficients: the "oracle" fits them by ordinary least squares on the calibration run's 1 Hz
output (true rate 0), so its only error on another run is the calibration run's noise projected on
the coefficients. Nothing that has to estimate T, r or w, or choose the form, does better except
by weighting (GLS with the exact noise covariance, the best linear unbiased estimator, is printed
too) or by dropping terms (biased: every subset, cubic / + gain / + memory / full, is printed).
The constant's floor, sqrt(1 / 1'S^-1 1), is the error of the best estimate of the bias offset
alone when every other coefficient is known: no estimator of any form gets under it. The reference: poly(T, dT/dt) (cubic in the MEASURED temperature + a gain on its centred
300 s least-squares slope, gyrocomp's batch rate, src/drift/temperature_rate.cc) fitted on the
paper's cooling run of the same structure and seed, the issue's yardstick.
Held-out runs (bench/drift_band_coverage.py's two-direction mode): a heating ramp (-40 -> 60 C,
seed + 10) and the paper's cooling staircase (seed + 20); score: RMSE against the true drift.

Analytic (seed-free; the sensor temperature path does not depend on the seed): with 30 s block
means, the coefficients' covariance under the simulator's exact noise (white + 9 Gauss-Markov
flicker processes, discrete autocovariance, + the rate random walk started at 0: cov = s^2 min(i, j))
    OLS: C = P S P',  P = (X'X)^-1 X';   GLS: C = (X' S^-1 X)^-1
gives E[RMSE^2] = trace(Xh C Xh') / n_h (the oracle is unbiased); for the reference
E[RMSE^2] = bias^2 + trace(Xh Cr Xh') / n_h, bias = its noise-free fit's held-out error.

Usage: /usr/bin/python3 bench/drift_design_bound.py [--build build] [--seeds 1,2,3,4,5,6]
       [--structs A,B,C,E] [--profiles paper,stairs,...] [--no-analytic]
       /usr/bin/python3 bench/drift_design_bound.py --plan-check [--structs ...]
           (the expected value and 3-seed scatter of `gyrocomp plan`'s simulated figure)
Prints the table of docs/explanation/drift-models.md "What any estimator can reach: the design bound".
Only numpy and `gyrocomp simulate`.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

# bench/drift_band_coverage.py's structures (D left out: the brief's four) -> simulate flags.
STRUCTS = {
    "A": ("default (gain 1.5, lag 600 s, hysteresis 4 C x 2e-3)", ""),
    "B": ("strong memory (hysteresis 10 C x 4e-3, gain 0.5)",
          "--hysteresis-width 10 --hysteresis-coeff 4e-3 --dtemp-coeff 0.5"),
    "C": ("long lag (1500 s, gain 4)", "--thermal-lag 1500 --dtemp-coeff 4"),
    "E": ("plain cubic", "--hysteresis-coeff 0 --dtemp-coeff 0"),
}
HEAT = "--profile ramp --room-temp -40 --ramp-end 60"
COOL = "--profile paper"


def staircase_csv(path, cold=-40.0, hot=60.0, soak_s=3600.0, up=(20.0, 40.0), down=(20.0, 40.0),
                  rates_up=(2.0, 0.5), rates_down=(0.5, 2.0), plateau_s=1800.0, end_hold_s=3600.0):
    """A two-direction staircase with two ramp rates each way: cold soak, up in steps alternating
    `up` sizes at alternating `rates_up` (C/min), plateaus of plateau_s, a hot hold, then down
    likewise (defaults: up -40, -20, 20, 40, 60 C at 2 / 0.5 / 2 / 0.5 C/min; down 40, 0, -20,
    -40 C at 0.5 / 2 / 0.5 / 2 C/min; 10.2 h)."""
    t, u = [0.0, soak_s], [cold, cold]

    def ramp(to, rate):
        t.append(t[-1] + abs(to - u[-1]) / (rate / 60.0))
        u.append(to)

    def hold(s):
        t.append(t[-1] + s)
        u.append(u[-1])

    k = 0
    while u[-1] < hot - 1e-9:
        ramp(min(hot, u[-1] + up[k % 2]), rates_up[k % 2])
        hold(plateau_s if u[-1] < hot - 1e-9 else end_hold_s)
        k += 1
    k = 0
    while u[-1] > cold + 1e-9:
        ramp(max(cold, u[-1] - down[k % 2]), rates_down[k % 2])
        hold(plateau_s if u[-1] > cold + 1e-9 else end_hold_s)
        k += 1
    with open(path, "w") as f:
        f.write("time_s,chamber_temp_c\n")
        for a, b in zip(t, u):
            f.write(f"{a:.6f},{b:.6f}\n")
    return t[-1] / 3600.0


def profiles(tmp):
    """name -> simulate flags of the calibration run (every one <= 14.25 h)."""
    p = {
        "paper": "--profile paper",
        "stairs": "--profile stairs",
        "heat-cool": "--profile heat-cool",
        "cycle x1": "--profile cycle --cycles 1",
        "cycle x2": "--profile cycle --cycles 2",
    }
    s1 = os.path.join(tmp, "stairs2r.csv")
    staircase_csv(s1)  # 20 / 40 C steps, up 2 & 0.5 C/min, down 0.5 & 2 C/min, 30 min plateaus
    p["2-rate staircase (csv)"] = f"--profile user --profile-csv {s1}"
    # 4 x (-40 -> 60 -> -40 C), up 2 / 1 / 2 / 1 C/min, down 1 / 2 / 1 / 2, 20 min holds: 13.2 h
    p["rate-cycles"] = "--profile rate-cycles"
    return p


class Runner:
    def __init__(self, gc, tmp):
        self.gc, self.tmp, self.n = gc, tmp, 0

    def sim(self, flags, sflags, seed):
        path = os.path.join(self.tmp, f"run{self.n}.csv")
        self.n += 1
        cmd = [self.gc, "simulate"] + flags.split() + sflags.split() + ["--fs", "1", "--seed", str(seed), "-o", path]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit("simulate failed: " + " ".join(cmd) + "\n" + r.stderr)
        d = np.loadtxt(path, delimiter=",", skiprows=1)
        os.remove(path)
        return {"rate": d[:, 1], "temp": d[:, 2], "u": d[:, 3], "T": d[:, 4], "drift": d[:, 6], "noise": d[:, 7]}


def struct_params(sflags):
    """lag (s), hysteresis width (C) of a structure's flags (simulate defaults otherwise)."""
    f = sflags.split()
    get = lambda k, dflt: float(f[f.index(k) + 1]) if k in f else dflt
    return get("--thermal-lag", 600.0), get("--hysteresis-width", 4.0)


def play(T, w):
    """The simulator's play operator: P <- clamp(P, T - w/2, T + w/2), started at T[0]."""
    p = np.empty_like(T)
    q, h = T[0], 0.5 * w
    for i, x in enumerate(T.tolist()):
        q = min(max(q, x - h), x + h)
        p[i] = q
    return p


def oracle_design(run, lag, w):
    T = run["T"]
    d = (T - 25.0) / 25.0
    r = (run["u"] - T) / lag if lag > 0 else np.gradient(run["u"])
    return np.column_stack([np.ones_like(d), d, d * d, d ** 3, r * 60.0, (T - play(T, w)) / 4.0])


def slope300(temp, window_s=300.0):
    """gyrocomp's batch dT/dt at 1 Hz: least-squares slope over a centred window of 2h + 1 samples
    (h = floor(window / 2)), truncated at the ends (src/drift/temperature_rate.cc)."""
    n, h = len(temp), int(window_s // 2)
    x = temp - temp[0]
    s_t = np.concatenate([[0.0], np.cumsum(x)])
    s_it = np.concatenate([[0.0], np.cumsum(np.arange(n) * x)])
    i = np.arange(n)
    a, b = np.maximum(i - h, 0), np.minimum(n - 1, i + h)
    m = (b - a + 1).astype(float)
    ibar = (a + b) / 2.0
    sxx = m * (m * m - 1.0) / 12.0
    sxy = (s_it[b + 1] - s_it[a]) - ibar * (s_t[b + 1] - s_t[a])
    return sxy / sxx


def ref_design(temp):
    d = (temp - 25.0) / 25.0
    return np.column_stack([np.ones_like(d), d, d * d, d ** 3, slope300(temp) * 60.0])


def ols(x, y):
    return np.linalg.lstsq(x, y, rcond=None)[0]


def rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


# ---- analytic: exact noise covariance of block means --------------------------------------------

def noise_cov(n_blocks, blk, arw=1.667, b_dph=44.0, rrw=3.0):
    """Covariance of n_blocks means of blk 1 Hz samples of the simulator's noise (simulator.cc
    SensorNoise): white sigma N (deg/s at 1 Hz), 9 Gauss-Markov processes (10 .. 1e5 s, 2 per
    decade, equal sigma q: the ADEV of the sum = 0.664 B at 1000 s), and the rate random walk
    x_i = s (e_0 + .. + e_{i-1}) (cov s^2 min(i, j))."""
    white = arw / 60.0
    corr = 10.0 * 10.0 ** (np.arange(9) / 2.0)
    tau = 1000.0
    unit = 0.0
    for t in corr:
        x = tau / t
        unit += (2.0 / x) * (1.0 - (3.0 - 4.0 * math.exp(-x) + math.exp(-2.0 * x)) / (2.0 * x))
    q2 = (0.664 * b_dph / 3600.0) ** 2 / unit
    lagk = np.arange(n_blocks)
    r = np.zeros(n_blocks)
    k = np.arange(blk)
    for t in corr:
        phi = math.exp(-1.0 / t)
        s_plus, s_minus = np.sum(phi ** k), np.sum(phi ** (-k.astype(float)))
        r0 = (blk + 2.0 * np.sum((blk - k[1:]) * phi ** k[1:])) / blk ** 2
        rj = phi ** (lagk * blk) * s_plus * s_minus / blk ** 2
        rj[0] = r0
        r += q2 * rj
    r[0] += white ** 2 / blk
    i = np.arange(n_blocks)
    S = r[np.abs(i[:, None] - i[None, :])]
    s2 = (rrw / 3600.0 / 60.0) ** 2
    if s2 > 0:
        mean_idx = i * blk + (blk - 1) / 2.0
        summin = sum(min(x, y) for x in range(blk) for y in range(blk)) / blk ** 2
        lo = np.minimum(i[:, None], i[None, :])
        S += s2 * np.where(i[:, None] == i[None, :], i[:, None] * blk + summin, mean_idx[lo])
    return S


def blocks(x, blk):
    n = len(x) // blk
    return x[: n * blk].reshape(n, blk, *x.shape[1:]).mean(axis=1)


def excess2(xh, c):
    return float(np.einsum("ij,jk,ik->", xh, c, xh) / len(xh))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--seeds", default="1,2,3,4,5,6")
    ap.add_argument("--structs", default="A,B,C,E")
    ap.add_argument("--profiles", default="", help="comma-separated names (default: all)")
    ap.add_argument("--no-analytic", action="store_true")
    ap.add_argument("--block", type=int, default=30, help="analytic: block-mean length, s")
    ap.add_argument("--plan-check", action="store_true",
                    help="instead: the sampling scatter of `gyrocomp plan`'s 3-seed simulated RMS")
    a = ap.parse_args()
    seeds = [int(s) for s in a.seeds.split(",")]
    gc = os.path.join(a.build, "gyrocomp")
    with tempfile.TemporaryDirectory() as tmp:
        run = Runner(gc, tmp)
        if a.plan_check:
            plan_check(run, a.structs.split(","), a.block)
            return
        profs = profiles(tmp)
        if a.profiles:
            profs = {k: v for k, v in profs.items() if k in a.profiles.split(",")}
        rows = []
        for sk in a.structs.split(","):
            sname, sflags = STRUCTS[sk]
            lag, w = struct_params(sflags)
            held = {}
            for seed in seeds:
                held[seed] = {"heat": run.sim(HEAT, sflags, seed + 10), "cool": run.sim(COOL, sflags, seed + 20)}
                for h in held[seed].values():
                    x = oracle_design(h, lag, w)
                    h["xo"], h["xr"] = x, ref_design(h["temp"])
            # Self-check: the oracle's family reproduces the simulator's true drift exactly.
            h0 = held[seeds[0]]["heat"]
            resid = np.max(np.abs(h0["xo"] @ ols(h0["xo"], h0["drift"]) - h0["drift"]))
            assert resid < 1e-9, f"oracle family does not reproduce the true drift ({resid})"
            ref = {}
            for seed in seeds:  # the reference: poly(T, dT/dt) on the paper run (seed = the calibration's)
                c = run.sim(COOL, sflags, seed)
                beta = ols(ref_design(c["temp"]), c["rate"])
                ref[seed] = {d: rmse(held[seed][d]["xr"] @ beta, held[seed][d]["drift"]) for d in ("heat", "cool")}
            ana_ref = None
            if not a.no_analytic:
                ana_ref = analytic(run, COOL, sflags, lag, w, held[seeds[0]], a.block, reference=True)
            for pname, pflags in profs.items():
                res = {(k, d): [] for k in SUBSETS for d in ("heat", "cool")}
                hours = None
                for seed in seeds:
                    c = run.sim(pflags, sflags, seed)
                    hours = len(c["T"]) / 3600.0
                    xc = oracle_design(c, lag, w)
                    for name, k in SUBSETS.items():
                        beta = ols(xc[:, k], c["rate"])
                        for d in ("heat", "cool"):
                            h = held[seed][d]
                            res[(name, d)].append(rmse(h["xo"][:, k] @ beta, h["drift"]))
                ana = analytic(run, pflags, sflags, lag, w, held[seeds[0]], a.block) if not a.no_analytic else None
                rows.append(dict(s=sk, sname=sname, p=pname, hours=hours, res=res, ref=ref, ana=ana, ana_ref=ana_ref))
                print_row(rows[-1], seeds)
                sys.stdout.flush()
    print_summary(rows, seeds)


SUBSETS = {"full form": [0, 1, 2, 3, 4, 5], "cubic + gain": [0, 1, 2, 3, 4], "cubic + memory": [0, 1, 2, 3, 5],
           "cubic": [0, 1, 2, 3]}


def analytic(run, pflags, sflags, lag, w, held, blk, reference=False):
    """Expected held-out RMSE, sqrt(bias^2 + trace(Xh C Xh') / n_h), per term subset (oracle
    regressors; bias: the subset's noise-free fit's held-out error, 0 for the full form) with C
    of OLS and of GLS under the exact noise; the reference's (OLS); and the constant's floor:
    sqrt(1 / 1'S^-1 1), the error of the best estimate of the bias offset alone when every other
    coefficient is known."""
    c = run.sim(pflags, sflags, 1)
    x = ref_design(c["T"]) if reference else oracle_design(c, lag, w)
    key = "xr" if reference else "xo"
    xb = blocks(x, blk)
    S = noise_cov(len(xb), blk)
    one = np.ones(len(xb))
    out = {"c0_floor": math.sqrt(1.0 / (one @ np.linalg.solve(S, one)))}
    subsets = {"reference": list(range(x.shape[1]))} if reference else SUBSETS
    for name, k in subsets.items():
        beta_nf = ols(x[:, k], c["drift"])
        xk = xb[:, k]
        P = np.linalg.pinv(xk)
        c_ols = P @ S @ P.T
        c_gls = np.linalg.inv(xk.T @ np.linalg.solve(S, xk))
        for d in ("heat", "cool"):
            xh = held[d][key][:, k]
            b2 = rmse(xh @ beta_nf, held[d]["drift"]) ** 2
            out[(name, d, "ols")] = math.sqrt(b2 + excess2(xh, c_ols))
            out[(name, d, "gls")] = math.sqrt(b2 + excess2(xh, c_gls))
            out[(name, d, "bias")] = math.sqrt(b2)
    return out


PLAN_PROFILES = {"paper": "--profile paper", "heat-cool": "--profile heat-cool", "cycle": "--profile cycle --cycles 1",
                 "ramp": HEAT, "stairs": "--profile stairs"}


def plan_check(run, structs, block, seeds_plan=(1, 2, 3), many=30):
    """`gyrocomp plan`'s "simulated" figure is sqrt(mean over seeds and the two held-out runs of
    MSE): how far does it scatter with 3 seeds? For a model of fixed form fitted by OLS (oracle
    regressors: `cubic` = poly(T), `cubic + gain` ~ poly(T, dT/dt)), per seed
    MS = B + 2 g'db + db' M db (B, g: the form's bias on the held-out runs; M = mean of Xh'Xh / n_h
    over the two runs; db ~ N(0, C)): E MS = B + tr(MC), Var MS = 4 g'Cg + 2 tr((MC)^2), so a
    k-seed RMS has relative SD ~ 0.5 sqrt(Var MS / k) / E MS. Also the measured k-seed RMS on
    seeds 1-3 (plan's) and on seeds 1..many."""
    print("| structure | profile | form | expected RMS (mdps) | of which model-form bias | 1-sigma of a 3-seed RMS | seeds for +-10%% "
          "| measured RMS, seeds 1-3 | measured RMS, seeds 1-%d |" % many)
    print("|---|---|---|---|---|---|---|---|---|")
    for sk in structs:
        sname, sflags = STRUCTS[sk]
        lag, w = struct_params(sflags)
        held = {"heat": run.sim(HEAT, sflags, 101), "cool": run.sim(COOL, sflags, 201)}
        for h in held.values():
            h["xo"] = oracle_design(h, lag, w)
        for pname, pflags in PLAN_PROFILES.items():
            c = run.sim(pflags, sflags, 1)
            x = oracle_design(c, lag, w)
            xb = blocks(x, block)
            S = noise_cov(len(xb), block)
            cals = [run.sim(pflags, sflags, k) for k in range(1, many + 1)]
            for form in ("cubic", "cubic + gain"):
                k = SUBSETS[form]
                P = np.linalg.pinv(xb[:, k])
                C = P @ S @ P.T
                beta_nf = ols(x[:, k], c["drift"])
                M = np.zeros((len(k), len(k)))
                g = np.zeros(len(k))
                B = 0.0
                for d in ("heat", "cool"):
                    xh = held[d]["xo"][:, k]
                    bias = xh @ beta_nf - held[d]["drift"]
                    M += 0.5 * xh.T @ xh / len(xh)
                    g += 0.5 * xh.T @ bias / len(xh)
                    B += 0.5 * np.mean(bias ** 2)
                mean = B + np.trace(M @ C)
                var = 4.0 * g @ C @ g + 2.0 * np.trace(M @ C @ M @ C)
                rel1 = 0.5 * math.sqrt(var) / mean
                ms = []
                for cal in cals:
                    beta = ols(oracle_design(cal, lag, w)[:, k], cal["rate"])
                    ms.append(np.mean([np.mean((held[d]["xo"][:, k] @ beta - held[d]["drift"]) ** 2)
                                       for d in ("heat", "cool")]))
                print(f"| {sk} | {pname} | {form} | {1e3 * math.sqrt(mean):.2f} | {1e3 * math.sqrt(B):.2f} | {100 * rel1 / math.sqrt(3):.0f}% | "
                      f"{math.ceil((rel1 / 0.1) ** 2)} | {1e3 * math.sqrt(np.mean(ms[:3])):.2f} | "
                      f"{1e3 * math.sqrt(np.mean(ms)):.2f} |")
                sys.stdout.flush()


HDR = ("| structure | calibration | hours | oracle, full form: heat (mdps) | cool (mdps) | reference heat / cool (mdps) "
       "| ratio heat / cool / mean | best term subset (measured): ratio heat / cool / mean "
       "| analytic ratio heat / cool: full form OLS | full form GLS | best subset GLS | constant's floor / reference |")


def stat(v):
    return f"{1e3 * np.mean(v):.2f} +- {1e3 * np.std(v, ddof=1):.2f}" if len(v) > 1 else f"{1e3 * v[0]:.2f}"


def measured_ratios(r, seeds, name):
    rh = np.mean([r["ref"][s]["heat"] for s in seeds])
    rc = np.mean([r["ref"][s]["cool"] for s in seeds])
    oh, oc = np.mean(r["res"][(name, "heat")]), np.mean(r["res"][(name, "cool")])
    return oh / rh, oc / rc, (oh + oc) / (rh + rc)


def analytic_ratio(r, name, kind, d=None):
    """sqrt(E RMSE^2) over the reference's: one held-out run d, or both (root mean square)."""
    a, ar = r["ana"], r["ana_ref"]
    if d:
        return a[(name, d, kind)] / ar[("reference", d, "ols")]
    num = math.hypot(a[(name, "heat", kind)], a[(name, "cool", kind)])
    return num / math.hypot(ar[("reference", "heat", "ols")], ar[("reference", "cool", "ols")])


def print_row(r, seeds):
    if not hasattr(print_row, "done"):
        print(HDR)
        print("|---" * (HDR.count("|") - 1) + "|")
        print_row.done = True
    res, ref = r["res"], r["ref"]
    rh = np.mean([ref[s]["heat"] for s in seeds])
    rc = np.mean([ref[s]["cool"] for s in seeds])
    full = measured_ratios(r, seeds, "full form")
    best = min(SUBSETS, key=lambda k: measured_ratios(r, seeds, k)[2])
    bq = measured_ratios(r, seeds, best)
    cells = [f"{r['s']} {r['sname']}", r["p"], f"{r['hours']:.2f}", stat(res[("full form", "heat")]),
             stat(res[("full form", "cool")]), f"{1e3 * rh:.2f} / {1e3 * rc:.2f}",
             f"{full[0]:.2f} / {full[1]:.2f} / {full[2]:.2f}", f"{best}: {bq[0]:.2f} / {bq[1]:.2f} / {bq[2]:.2f}"]
    if r["ana"]:
        ab = min(SUBSETS, key=lambda k: analytic_ratio(r, k, "gls"))
        hc = lambda name, kind: f"{analytic_ratio(r, name, kind, 'heat'):.2f} / {analytic_ratio(r, name, kind, 'cool'):.2f}"
        floor = lambda d: r["ana"]["c0_floor"] / r["ana_ref"][("reference", d, "ols")]
        cells += [hc("full form", "ols"), hc("full form", "gls"), f"{ab}: {hc(ab, 'gls')}",
                  f"{floor('heat'):.2f} / {floor('cool'):.2f}"]
    else:
        cells += ["-"] * 4
    print("| " + " | ".join(cells) + " |")


def print_summary(rows, seeds):
    print()
    print("Lowest measured ratio (mean of heating and cooling RMSE over the reference's; the target is <= 0.8):")
    for s in dict.fromkeys(r["s"] for r in rows):
        g = [(measured_ratios(r, seeds, k), k, r) for r in rows if r["s"] == s for k in SUBSETS]
        (h, c, m), k, r = min(g, key=lambda t: t[0][2])
        print(f"  {s}: {r['p']} ({r['hours']:.2f} h), {k}: {m:.2f} (heating {h:.2f}, cooling {c:.2f})")
    if rows and rows[0]["ana"]:
        print("Analytic reference (sqrt E RMSE^2, heat / cool; its model-form bias in brackets), mdps:")
        for s in dict.fromkeys(r["s"] for r in rows):
            ar = next(r for r in rows if r["s"] == s)["ana_ref"]
            print(f"  {s}: {1e3 * ar[('reference', 'heat', 'ols')]:.2f} / {1e3 * ar[('reference', 'cool', 'ols')]:.2f} "
                  f"({1e3 * ar[('reference', 'heat', 'bias')]:.2f} / {1e3 * ar[('reference', 'cool', 'bias')]:.2f})")
        print("Constant's floor (the bias offset's GLS error with every other coefficient known), mdps:")
        for r in rows:
            if r["s"] == rows[0]["s"]:
                print(f"  {r['p']} ({r['hours']:.2f} h): {1e3 * r['ana']['c0_floor']:.2f}")


if __name__ == "__main__":
    main()
