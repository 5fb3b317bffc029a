#!/usr/bin/env python3
"""Coverage of the drift model's 90% prediction band on held-out simulated runs
(docs/explanation/prediction-bands.md "Coverage on held-out runs").

For each drift structure, seed and calibration profile: simulate the calibration run, fit the
default model (`gyrocomp fit`, auto) and poly(T), apply both to a held-out run in the opposite
direction and one in the same direction (other seeds: independent noise), and read the band's
coverage of the true drift, its half-width and the realised RMSE from `apply --json`.

Usage: G=build/gyrocomp D=bandcov SEEDS="1 2 3 4 5 6" FS=1 /usr/bin/python3 bench/drift_band_coverage.py [-v]
Options (environment): TWO_DIRECTION=1 adds the heat-cool, stairs and rate-cycles calibrations, ONLY=<profile>
keeps one calibration profile, STRUCTS="A B C E" keeps those structures.
Prints per-run rows (with -v) and the summary tables of docs/explanation/prediction-bands.md.
"""
import json
import os
import subprocess
import sys

G = os.environ.get("G", "gyrocomp")
D = os.environ.get("D", "bandcov")
FS = os.environ.get("FS", "1")
SEEDS = [int(s) for s in os.environ.get("SEEDS", "1 2 3 4 5 6").split()]
VERBOSE = "-v" in sys.argv

# name -> simulator flags (bench/drift_heldout.sh's A-D, and E: a plain cubic).
STRUCTS = {
    "A default (gain 1.5, lag 600 s, hysteresis 2e-3)": "",
    "B strong memory (hysteresis 10 C x 4e-3)": "--hysteresis-width 10 --hysteresis-coeff 4e-3 --dtemp-coeff 0.5",
    "C long lag (1500 s, gain 4)": "--thermal-lag 1500 --dtemp-coeff 4",
    "D nonlinear-free, strong dT/dt (2.5)": "--hysteresis-coeff 0 --thermal-lag 300 --dtemp-coeff 2.5 --drift-poly 0.01,-1e-3,3e-5,1e-7",
    "E plain cubic": "--hysteresis-coeff 0 --dtemp-coeff 0",
}
HEAT = "--profile ramp --room-temp -40 --ramp-end 60"
COOL = "--profile paper"
# calibration profile -> (its flags, opposite-direction held-out flags, same-direction flags); a
# two-direction calibration: "opposite" = the heating ramp, "same" = the cooling staircase.
PROFILES = {
    "cooling (paper)": (COOL, HEAT, COOL),
    "heating only": (HEAT, COOL, HEAT),
}
if os.environ.get("TWO_DIRECTION"):
    PROFILES["heat-cool"] = ("--profile heat-cool", HEAT, COOL)
    PROFILES["stairs"] = ("--profile stairs", HEAT, COOL)
    PROFILES["rate-cycles"] = ("--profile rate-cycles", HEAT, COOL)
if os.environ.get("ONLY"):  # e.g. ONLY=heat-cool or ONLY=stairs (with TWO_DIRECTION=1)
    PROFILES = {k: v for k, v in PROFILES.items() if k == os.environ["ONLY"]}
if os.environ.get("STRUCTS"):  # e.g. STRUCTS="A B C E": the structures whose names start so
    STRUCTS = {k: v for k, v in STRUCTS.items() if k[0] in os.environ["STRUCTS"].split()}


def run(cmd):
    r = subprocess.run(cmd, shell=True, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{cmd}: {r.stderr.strip()}")
    return r.stdout


def sim(flags, extra, seed, path):
    run(f"{G} simulate {flags} --fs {FS} --seed {seed} {extra} -o {path}")


def apply(model, data, tag):
    out = f"{D}/{tag}.json"
    run(f"{G} apply -m {model} -i {data} -o {D}/tmp.csv --json {out}")
    j = json.load(open(out))
    return j["rmse_vs_true_drift_dps"], j.get("band_coverage_of_true_drift_dps"), j.get("band_half_width_rms")


def main():
    os.makedirs(D, exist_ok=True)
    rows = []
    for sname, sflags in STRUCTS.items():
        for pname, (cal, opp, same) in PROFILES.items():
            for seed in SEEDS:
                p = f"{D}/{sname[0]}{pname[0]}{seed}"
                sim(cal, sflags, seed, p + ".cal.csv")
                sim(opp, sflags, seed + 10, p + ".opp.csv")
                sim(same, sflags, seed + 20, p + ".same.csv")
                run(f"{G} fit -i {p}.cal.csv -o {p}.auto.json --json {p}.auto.fit.json")
                run(f"{G} fit -i {p}.cal.csv --model poly --inputs temp -o {p}.poly.json")
                # The reference: poly(T, dT/dt) fitted on the paper's cooling run.
                ref = f"{D}/{sname[0]}ref{seed}"
                if not os.path.exists(ref + ".json"):
                    sim(COOL, sflags, seed, ref + ".cal.csv")
                    run(f"{G} fit -i {ref}.cal.csv --model poly --inputs temp,dtemp -o {ref}.json")
                fit = json.load(open(p + ".auto.fit.json"))
                for direction in ("opp", "same"):
                    rmse, cov, half = apply(p + ".auto.json", f"{p}.{direction}.csv", f"a{direction}")
                    prmse, _, _ = apply(p + ".poly.json", f"{p}.{direction}.csv", f"p{direction}")
                    rrmse, _, _ = apply(ref + ".json", f"{p}.{direction}.csv", f"r{direction}")
                    rows.append(dict(s=sname, p=pname, seed=seed, d=direction, model=f"{fit['model']}({fit['inputs']})",
                                     rmse=rmse, cov=cov, half=half, poly=prmse, ref=rrmse, fit_s=fit["fit_time_s"],
                                     expected=fit.get("band", {}).get("expected_rms")))
                    if VERBOSE:
                        r = rows[-1]
                        print(f"| {sname[0]} | {pname} | {seed} | {direction} | {r['model']} | {1e3*rmse:.2f} | "
                              f"{1e3*prmse:.2f} | {100*cov:.1f} | {1e3*half:.2f} | {1e3*r['expected']:.2f} |")
    print("| structure | calibration | held-out | model(s) | RMSE default (mdps) | RMSE poly(T) (mdps) | "
          "poly(T,dT/dt) on paper (mdps) | coverage | half-width / RMSE (pooled) | mean of per-run ratios | "
          "expected RMS (mdps) | fit (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    # Pooled: RMS half-width / RMS error over the group's runs (the band states an expected squared
    # error, so it is compared in mean squares); the mean of per-run ratios is dominated by the
    # runs whose error happened to be small.
    pooled = lambda g: (sum(r['half']**2 for r in g) / sum(r['rmse']**2 for r in g)) ** 0.5
    import statistics as st
    for sname in STRUCTS:
        for pname in PROFILES:
            for d in ("opp", "same"):
                g = [r for r in rows if r["s"] == sname and r["p"] == pname and r["d"] == d]
                models = sorted(set(r["model"] for r in g))
                sd = lambda k: st.stdev([r[k] for r in g]) if len(g) > 1 else 0.0
                print(f"| {sname} | {pname} | {'opposite' if d == 'opp' else 'same'} | {', '.join(models)} | "
                      f"{1e3*st.mean(r['rmse'] for r in g):.2f} +- {1e3*sd('rmse'):.2f} | "
                      f"{1e3*st.mean(r['poly'] for r in g):.2f} +- {1e3*sd('poly'):.2f} | "
                      f"{1e3*st.mean(r['ref'] for r in g):.2f} | "
                      f"{100*st.mean(r['cov'] for r in g):.1f}% | {pooled(g):.2f} | {st.mean(r['half']/r['rmse'] for r in g):.2f} | "
                      f"{1e3*st.mean(r['expected'] for r in g):.2f} | {max(r['fit_s'] for r in g):.2f} |")
    print()
    print("| structure | coverage (all runs) | lowest run | RMS half-width / RMS error (pooled) |")
    print("|---|---|---|---|")
    for sname in STRUCTS:
        g = [r for r in rows if r["s"] == sname]
        print(f"| {sname} | {100*st.mean(r['cov'] for r in g):.1f}% | {100*min(r['cov'] for r in g):.1f}% | {pooled(g):.2f} |")
    print(f"| all | {100*st.mean(r['cov'] for r in rows):.1f}% | {100*min(r['cov'] for r in rows):.1f}% | {pooled(rows):.2f} |")
    groups = {}
    for r in rows:
        groups.setdefault((r["s"], r["p"], r["d"]), []).append(r)
    worst = max(groups.items(), key=lambda kv: pooled(kv[1]))
    print(f"\nruns: {len(rows)}; max single-run half-width / RMSE: {max(r['half']/r['rmse'] for r in rows):.2f}; "
          f"widest group (pooled): {pooled(worst[1]):.2f} ({worst[0][0][0]}, {worst[0][1]}, {worst[0][2]})")


if __name__ == "__main__":
    main()
