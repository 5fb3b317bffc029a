#!/usr/bin/env python3
"""The default (`fit`, auto) against poly(T, dT/dt) on held-out runs of two simulator families.

For each family, drift structure, calibration profile and seed: simulate the calibration run, fit
the default and poly(T, dT/dt) on it, and poly(T, dT/dt) on the one-direction (paper) profile of
the same structure and seed (the reference); apply the three to a held-out heating run and a
held-out cooling run (other seeds: independent noise) and read the RMS error against the true drift,
the default's band coverage of the true drift and the model auto chose.

Families:
  own   gyrocomp's simulator (`gyrocomp simulate`): structures A-D of bench/drift_heldout.sh;
        calibrations paper (one direction: a cooling staircase), heat-cool (two directions) and
        rate-cycles (two directions at two rates each, with holds: CALS=cycles); held out: ramp
        -40 -> 60 C (heating) and the paper staircase (cooling).
  sim2  bench/sim2/sim2.py, written apart from gyrocomp's model code: structures lag2, preisach,
        memory, rate-temp (smooth-nonpoly with STRUCTS); calibrations paper (one direction: a heating
        staircase), two-direction (25 -> 60 -> -40 -> 60 C at 0.6 C/min) and rate-cycles (60 / -40 C
        at 2 and 1 C/min, 20 min holds: CALS=cycles); held out: heating and cooling.

The oracle: the true form of the structure (own: a cubic in the true sensor temperature, its true
rate and the play operator of the true width, bench/drift_design_bound.py; sim2: the structure's own
basis of the die state, bench/sim2/sim2.py oracle_basis) fitted by ordinary least squares on the
same calibration run, applied to the held-out runs: what an estimator given the form reaches there
(it is told the latent states no real estimator sees; its only error is the run's noise projected
on the coefficients).

Usage: G=build/gyrocomp D=admission SEEDS="1 2 3 4 5 6" FAMILIES="own sim2" JOBS=2 \
           /usr/bin/python3 bench/drift_admission.py [-v]
Options (environment): STRUCTS="A B lag2 memory" keeps those structures; CALS="one two cycles" keeps
those calibrations (default "one two"). Prints per-run rows (-v) and the summary tables of
docs/explanation/accuracy.md ("The default against poly(T, dT/dt) on two simulator families").
"""
import concurrent.futures
import json
import os
import statistics as st
import subprocess
import sys

import numpy as np

G = os.environ.get("G", "gyrocomp")
# GP: the binary for everything but the default's fit (simulate, poly fits, apply); the same as G
# unless given. SKIP_AUTO=1: only the simulations and the poly(T, dT/dt) fits and their errors.
GP = os.environ.get("GP", G)
SKIP_AUTO = os.environ.get("SKIP_AUTO") == "1"
D = os.environ.get("D", "admission")
SEEDS = [int(s) for s in os.environ.get("SEEDS", "1 2 3 4 5 6").split()]
FAMILIES = os.environ.get("FAMILIES", "own sim2").split()
JOBS = int(os.environ.get("JOBS", "2"))
VERBOSE = "-v" in sys.argv
SIM2 = os.path.join(os.path.dirname(os.path.abspath(__file__)), "sim2", "sim2.py")

OWN = {
    "A": "",
    "B": "--hysteresis-width 10 --hysteresis-coeff 4e-3 --dtemp-coeff 0.5",
    "C": "--thermal-lag 1500 --dtemp-coeff 4",
    "D": "--hysteresis-coeff 0 --thermal-lag 300 --dtemp-coeff 2.5 --drift-poly 0.01,-1e-3,3e-5,1e-7",
}
OWN_PROFILES = {"one": "--profile paper", "two": "--profile heat-cool", "cycles": "--profile rate-cycles",
                "heat": "--profile ramp --room-temp -40 --ramp-end 60", "cool": "--profile paper"}
SIM2_STRUCTS = ["lag2", "preisach", "memory", "rate-temp"]
SIM2_PROFILES = {"one": "paper", "two": "two-direction", "cycles": "rate-cycles", "heat": "heating", "cool": "cooling"}
CALS = os.environ.get("CALS", "one two").split()
SEED_OFFSET = {"one": 0, "two": 0, "cycles": 0, "heat": 10, "cool": 20}
CAL_LABEL = {"one": "one-direction", "two": "two-direction", "cycles": "rate-cycles"}


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sim2"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def own_design(csv, struct):
    """The own simulator's exact drift form at a run (bench/drift_design_bound.py oracle_design):
    1, d, d^2, d^3 (d = (T - 25) / 25), the true rate and, when the structure has one, the
    hysteresis (T - play_w(T))."""
    import drift_design_bound as bound
    d = np.genfromtxt(csv, delimiter=",", names=True)
    run = {"T": d["sensor_temp_c"], "u": d["chamber_temp_c"]}
    lag, w = bound.struct_params(OWN[struct])
    x = bound.oracle_design(run, lag, w)
    if "--hysteresis-coeff 0" in OWN[struct]:
        x = x[:, :5]
    return x, d["rate_dps"], d["true_drift_dps"]


def sim2_design(struct, profile, seed):
    import sim2
    r = sim2.simulate(struct, SIM2_PROFILES[profile], seed + SEED_OFFSET[profile])
    x = np.column_stack([np.ones(len(r["rate_dps"])), sim2.oracle_basis(struct, r)])
    return x, r["rate_dps"], r["true_drift_dps"]


def oracle(family, struct, cal, seed):
    """RMS error (deg/s) against the true drift on the held-out heating and cooling runs of the
    true form fitted by OLS on calibration `cal`; cached in D."""
    p = f"{D}/{family}.{struct}.{seed}"
    out = f"{p}.{cal}.oracle.json"
    if os.path.exists(out):
        return json.load(open(out))
    design = (lambda prof: own_design(f"{p}.{prof}.csv", struct)) if family == "own" else \
        (lambda prof: sim2_design(struct, prof, seed))
    x, y, _ = design(cal)
    beta = np.linalg.lstsq(x, y, rcond=None)[0]
    res = {}
    for held in ("heat", "cool"):
        xh, _, truth = design(held)
        res[held] = float(np.sqrt(np.mean((xh @ beta - truth) ** 2)))
    json.dump(res, open(out, "w"))
    return res


def run(cmd):
    r = subprocess.run(cmd, shell=True, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{cmd}: {r.stderr.strip()}")
    return r.stdout


def simulate(family, struct, profile, seed, path):
    if os.path.exists(path):
        return
    s = seed + SEED_OFFSET[profile]
    if family == "own":
        run(f"{GP} simulate {OWN_PROFILES[profile]} --fs 1 --seed {s} {OWN[struct]} -o {path}")
    else:
        run(f"/usr/bin/python3 {SIM2} --structure {struct} --profile {SIM2_PROFILES[profile]} --seed {s} -o {path}")


def apply(model, data, out, g=None):
    if not (os.path.exists(out + ".json") and os.path.getmtime(out + ".json") > os.path.getmtime(model)):
        run(f"{g or GP} apply -m {model} -i {data} -o {out}.csv --json {out}.json")
        os.remove(out + ".csv")
    j = json.load(open(out + ".json"))
    return j["rmse_vs_true_drift_dps"], j.get("band_coverage_of_true_drift_dps"), j.get("band_half_width_rms")


def one(job):
    family, struct, cal, seed = job
    p = f"{D}/{family}.{struct}.{seed}"
    c = f"{p}.{cal}"
    if not os.path.exists(c + ".poly.json"):
        run(f"{GP} fit -i {c}.csv --model poly --inputs temp,dtemp -o {c}.poly.json")
    ref = f"{p}.one.poly.json"  # poly(T, dT/dt) on the paper profile
    if cal != "one":
        ref = f"{c}.ref.json"
        if not os.path.exists(ref):
            run(f"{GP} fit -i {p}.one.csv --model poly --inputs temp,dtemp -o {ref}")
    orc = oracle(family, struct, cal, seed)
    if SKIP_AUTO:
        for held in ("heat", "cool"):
            apply(c + ".poly.json", f"{p}.{held}.csv", f"{c}.poly.{held}")
            apply(ref, f"{p}.{held}.csv", f"{c}.ref.{held}")
        return []
    fit_json = c + ".auto.fit.json"  # kept when newer than the binary G (a rerun reuses it)
    g_path = G if os.path.exists(G) else None
    if not (os.path.exists(fit_json) and g_path and os.path.getmtime(fit_json) > os.path.getmtime(g_path)):
        run(f"{G} fit -i {c}.csv -o {c}.auto.json --json {c}.auto.fit.json")
    fit = json.load(open(c + ".auto.fit.json"))
    admitted = [t["term"] for t in fit.get("term_admissions", []) if t["admitted"]]
    rows = []
    for held in ("heat", "cool"):
        rmse, cov, half = apply(c + ".auto.json", f"{p}.{held}.csv", f"{c}.auto.{held}", G)
        prmse, _, _ = apply(c + ".poly.json", f"{p}.{held}.csv", f"{c}.poly.{held}")
        rrmse, _, _ = apply(ref, f"{p}.{held}.csv", f"{c}.ref.{held}")
        rows.append(dict(f=family, s=struct, cal=cal, seed=seed, held=held, model=f"{fit['model']}({fit['inputs']})",
                         terms="+".join(admitted) or "-", auto=rmse, poly=prmse, ref=rrmse, oracle=orc[held], cov=cov,
                         half=half))
    return rows


def criterion(g, a, rf, orc):
    """Criterion 1 on a two-direction row: the default <= 0.8x poly(T, dT/dt) on the paper profile
    where the oracle reaches 0.8x, else the default within the oracle's mean + SD."""
    if g[0]["cal"] == "one":
        return "-"
    sd = st.stdev(orc) if len(orc) > 1 else 0.0
    if st.mean(orc) <= 0.8 * st.mean(rf):
        return "met (<= 0.8x)" if st.mean(a) <= 0.8 * st.mean(rf) else "NOT met (oracle reaches 0.8x)"
    return "met (within oracle + SD)" if st.mean(a) <= st.mean(orc) + sd else "NOT met (> oracle + SD)"


def summary(rows):
    print("| family | structure | calibration | held out | default chose (runs) | default (mdps) | "
          "poly(T,dT/dt) same run (mdps) | default - poly, paired (mdps) | default / poly per seed | "
          "poly(T,dT/dt) on paper (mdps) | default / paper-poly | oracle same run (mdps) | oracle / paper-poly | "
          "criterion 1 | coverage | band half-width / RMSE |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    keys = sorted({(r["f"], r["s"], r["cal"], r["held"]) for r in rows})
    sd = lambda v: st.stdev(v) if len(v) > 1 else 0.0
    for k in keys:
        g = [r for r in rows if (r["f"], r["s"], r["cal"], r["held"]) == k]
        a, p, rf, orc = ([1e3 * r[x] for r in g] for x in ("auto", "poly", "ref", "oracle"))
        diff = [x - y for x, y in zip(a, p)]
        chose = {}
        for r in g:
            chose[r["model"]] = chose.get(r["model"], 0) + 1
        cov = [r["cov"] for r in g if r["cov"] is not None]
        cov_text = f"{100 * st.mean(cov):.0f}%" if cov else "-"
        hw = [r["half"] / r["auto"] for r in g if r.get("half") is not None and r["auto"] > 0]
        hw_text = f"{st.mean(hw):.2f}" if hw else "-"
        print(f"| {k[0]} | {k[1]} | {CAL_LABEL[k[2]]} | {'heating' if k[3] == 'heat' else 'cooling'} | "
              f"{', '.join(f'{m} x{n}' for m, n in sorted(chose.items()))} | {st.mean(a):.2f} +- {sd(a):.2f} | "
              f"{st.mean(p):.2f} +- {sd(p):.2f} | {st.mean(diff):+.2f} +- {sd(diff):.2f} | "
              f"{', '.join(f'{x / y:.2f}' for x, y in zip(a, p))} | {st.mean(rf):.2f} +- {sd(rf):.2f} | "
              f"{st.mean(a) / st.mean(rf):.2f} | {st.mean(orc):.2f} +- {sd(orc):.2f} | {st.mean(orc) / st.mean(rf):.2f} | "
              f"{criterion(g, a, rf, orc)} | {cov_text} | {hw_text} |")
    print()
    print("| family | coverage (all runs) | lowest run | runs | band half-width / RMSE (median over runs) |")
    print("|---|---|---|---|---|")
    for f in sorted({r["f"] for r in rows}):
        cov = [r["cov"] for r in rows if r["f"] == f and r["cov"] is not None]
        hw = [r["half"] / r["auto"] for r in rows if r["f"] == f and r.get("half") is not None and r["auto"] > 0]
        print(f"| {f} | {100 * st.mean(cov):.1f}% | {100 * min(cov):.1f}% | {len(cov)} | "
              f"{f'{st.median(hw):.2f}' if hw else '-'} |")


def main():
    os.makedirs(D, exist_ok=True)
    keep = os.environ.get("STRUCTS", "").split()
    jobs = []
    for family in FAMILIES:
        structs = list(OWN) if family == "own" else SIM2_STRUCTS + (["smooth-nonpoly"] if "smooth-nonpoly" in keep else [])
        for s in structs:
            if keep and s not in keep:
                continue
            for cal in CALS:
                for seed in SEEDS:
                    jobs.append((family, s, cal, seed))
    runs = sorted({(f, s, seed, prof) for f, s, cal, seed in jobs for prof in ("one", cal, "heat", "cool")})
    with concurrent.futures.ThreadPoolExecutor(JOBS) as ex:
        list(ex.map(lambda r: simulate(r[0], r[1], r[3], r[2], f"{D}/{r[0]}.{r[1]}.{r[2]}.{r[3]}.csv"), runs))
    rows = []
    with concurrent.futures.ThreadPoolExecutor(JOBS) as ex:
        for rs in ex.map(one, jobs):
            rows += rs
            if VERBOSE:
                for r in rs:
                    print(f"| {r['f']} | {r['s']} | {r['cal']} | {r['seed']} | {r['held']} | {r['model']} | {r['terms']} | "
                          f"{1e3 * r['auto']:.2f} | {1e3 * r['poly']:.2f} | {1e3 * r['ref']:.2f} | {1e3 * r['oracle']:.2f} | "
                          f"{100 * (r['cov'] or 0):.0f}% |", flush=True)
    if rows:
        json.dump(rows, open(f"{D}/rows.json", "w"))
        summary(rows)


if __name__ == "__main__":
    main()
