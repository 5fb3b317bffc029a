#!/usr/bin/env python3
"""Is the gap between any single-run cubic and the true static curve estimation noise?
(docs/explanation/accuracy-calibration.md "The bound of one run, and several calibration runs")

    /usr/bin/python3 bench/imu_calibration_two_runs.py --pyulog DIR [--build build] [--seeds 5]

On the bias(T)-only structure (calibration data = cubic(T) + noise), fits a least-squares cubic
to one calibration run and to two (independent seeds), and scores both on held-out heating and
cooling runs as bench/imu_calibration_side_by_side.py does (gyro, RMS of 10 s means, mean
removed, deg/s). If the excess over the true curve, sqrt(RMS^2 - RMS_true^2), falls by about
1/sqrt(2) with two runs, it is the calibration run's own slow noise. Figures: docs/explanation/flight-controller-export.md.
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import imu_calibration_side_by_side as b  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--pyulog", required=True)
    args = ap.parse_args()
    sys.path.insert(0, args.pyulog)
    gc = os.path.join(args.build, "gyrocomp")
    res = {1: [], 2: [], "true": []}
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, args.seeds + 1):
            cal = []
            for k in range(2):
                f = os.path.join(tmp, "cal%d.ulg" % k)
                b.simulate(gc, f, 100 * seed + 1000 * k, 10, "static")
                cal.append(b.read_imu(f)[0])
            held = {}
            for k, name in enumerate(("heating", "cooling")):
                f = os.path.join(tmp, "held.ulg")
                b.simulate(gc, f, 100 * seed + 50 + 10 * k, 10, "static", name)
                held[name] = b.read_imu(f)[0]
            for nruns in (1, 2):
                temp = np.concatenate([c[0] for c in cal[:nruns]])
                rate = np.hstack([c[1] for c in cal[:nruns]])
                coefs = [np.polyfit(temp - 35.0, rate[a], 3) for a in range(3)]
                for name, (t, g) in held.items():
                    corr = np.array([np.polyval(coefs[a], t - 35.0) for a in range(3)])
                    res[nruns].append((name, b.score(g, corr, 10).mean()))
            for name, (t, g) in held.items():
                res["true"].append((name, b.score(g, b.truth_offsets(t, "gyro"), 10).mean()))
    for name in ("heating", "cooling"):
        m = {k: np.mean([v for n, v in res[k] if n == name]) for k in res}
        ex = {k: np.sqrt(max(m[k] ** 2 - m["true"] ** 2, 0.0)) for k in (1, 2)}
        print("%s: LS cubic on 1 run %.4f (excess %.4f), on 2 runs %.4f (excess %.4f), true curve %.4f deg/s" %
              (name, m[1], ex[1], m[2], ex[2], m["true"]))


if __name__ == "__main__":
    main()
