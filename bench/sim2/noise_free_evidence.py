#!/usr/bin/python3
"""What a calibration profile shows of the drift's form, with and without the gyro's noise.

For each structure and calibration profile: the calibration run with its noise and the same run
noise-free (`sim2.py --noise-free`: rate = the true drift, the thermometer keeps its noise and
LSB). On each, `gyrocomp fit --auto-lagged-curve 2` with the lagged curve's paired test on
segment pieces (Eq. A-4; 1, 3 and 6 pieces per segment on the noise-free run), then the default
(`fit`), poly(T, dT/dt) and the lagged curve forced (`fit --model poly --inputs temp,lag
--gain-temp-degree 2`) applied to the held-out heating and cooling runs of the seed (the runs
bench/drift_admission.py uses: sim2 seeds + 10 and + 20). RMS error against the true drift, mdps.

On the noise-free run the paired gain is the model-form difference alone: when it does not beat
its SE there, no treatment of the noise can make the run's own cross-validation admit the term.

Usage: G=build/gyrocomp D=/tmp/nfe /usr/bin/python3 bench/sim2/noise_free_evidence.py \
           [--structures lag2 memory preisach] [--profiles two-direction rate-cycles] [--seed 1]
"""
import argparse
import concurrent.futures
import json
import os
import re
import subprocess

G = os.environ.get("G", "gyrocomp")
D = os.environ.get("D", "noise_free_evidence")
SIM2 = os.path.join(os.path.dirname(os.path.abspath(__file__)), "sim2.py")
GAIN = re.compile(r"\+lagged curve \([^;]*?\): gain ([-+0-9.e]+) \+- ([0-9.e+-]+) mdps "
                  r"\((\d+) segment pieces\), (admitted|rejected)")
HELD_OUT = (("heat", "heating", 10), ("cool", "cooling", 20))  # name, sim2 profile, seed offset


def run(cmd):
    r = subprocess.run(cmd, shell=True, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{cmd}: {r.stderr.strip()}")
    return r.stdout + r.stderr


def simulate(struct, profile, seed, path, noise_free=False):
    if not os.path.exists(path):
        run(f"/usr/bin/python3 {SIM2} --structure {struct} --profile {profile} --seed {seed} -o {path}"
            + (" --noise-free" if noise_free else ""))


def lagged_curve_test(csv, pieces):
    """The lagged curve's Eq. A-4 line of `fit -v` as a dict (gain, se in mdps; pairs; admitted), or None."""
    out = run(f"{G} fit -i {csv} --auto-lagged-curve 2 --auto-lagged-curve-pieces {pieces} -o /dev/null -v")
    m = GAIN.search(out)
    if not m:
        return None
    return dict(gain=float(m.group(1)), se=float(m.group(2)), pairs=int(m.group(3)), admitted=m.group(4) == "admitted")


def heldout_csv(struct, profile, seed):
    return f"{D}/{struct}.{seed}.{profile}.csv"


def heldout(model, struct, seed):
    """RMS error (mdps) of `model` on the seed's held-out runs (simulated by main, before the jobs)."""
    res = {}
    for held, profile, offset in HELD_OUT:
        data = heldout_csv(struct, profile, seed + offset)
        out = f"{model}.{held}"
        run(f"{G} apply -m {model} -i {data} -o {out}.csv --json {out}.json")
        os.remove(out + ".csv")
        res[held] = 1e3 * json.load(open(out + ".json"))["rmse_vs_true_drift_dps"]
    return res


def one(job):
    struct, profile, seed, noise_free = job
    tag = f"{D}/{struct}.{profile}.{seed}.{'nf' if noise_free else 'noisy'}"
    csv = tag + ".csv"
    simulate(struct, profile, seed, csv, noise_free)
    tests = {p: lagged_curve_test(csv, p) for p in ((1, 3, 6) if noise_free else (3,))}
    errors = {}
    for name, args in (("default", ""), ("poly(T,dT/dt)", "--model poly --inputs temp,dtemp"),
                       ("lagged curve forced", "--model poly --inputs temp,lag --gain-temp-degree 2")):
        model = f"{tag}.{re.sub(r'[^a-z]', '', name)}.json"
        run(f"{G} fit -i {csv} {args} -o {model}")
        errors[name] = heldout(model, struct, seed)
    return dict(struct=struct, profile=profile, seed=seed, noise="noise-free" if noise_free else "with noise",
                tests=tests, errors=errors)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--structures", nargs="+", default=["lag2", "memory", "preisach"])
    ap.add_argument("--profiles", nargs="+", default=["two-direction", "rate-cycles"])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    os.makedirs(D, exist_ok=True)
    for s in a.structures:  # shared by a structure's jobs: written once, before they run
        for _, profile, offset in HELD_OUT:
            simulate(s, profile, a.seed + offset, heldout_csv(s, profile, a.seed + offset))
    jobs = [(s, p, a.seed, nf) for s in a.structures for p in a.profiles for nf in (True, False)]
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as ex:
        rows = list(ex.map(one, jobs))
    print("| structure | calibration | gyro noise | lagged curve, Eq. A-4 gain +- SE (mdps): 1 / 3 / 6 pieces (with noise: 3) | "
          "default: heating / cooling | poly(T,dT/dt) | lagged curve forced |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        t = " / ".join(f"{v['gain']:+.2f} +- {v['se']:.2f}{' (admitted)' if v['admitted'] else ''}" if v else "-"
                       for v in r["tests"].values())
        e = " | ".join(f"{r['errors'][k]['heat']:.2f} / {r['errors'][k]['cool']:.2f}"
                       for k in ("default", "poly(T,dT/dt)", "lagged curve forced"))
        print(f"| {r['struct']} | {r['profile']} | {r['noise']} | {t} | {e} |")
    json.dump(rows, open(f"{D}/rows.json", "w"), indent=1)


if __name__ == "__main__":
    main()
