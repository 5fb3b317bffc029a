#!/usr/bin/python3
"""Summary of bench/drift_heldout.sh tables (docs/explanation/drift-models.md): per structure and model the
mean and seed-to-seed SD of the heating and cooling-2 RMSE, and each run's ratio to
poly(T, dT/dt). Later tables override earlier rows of the same (structure, seed, model).
Usage: /usr/bin/python3 bench/drift_heldout_summary.py table.md [more.md ...]
"""
import statistics
import sys

rows = {}
for path in sys.argv[1:]:
    for line in open(path):
        f = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(f) != 8 or not f[1].isdigit():
            continue
        rows[(f[0], int(f[1]), f[2])] = (float(f[4]), float(f[5]))
print("| structure | model | heating mean (SD) | heating ratio per seed | cooling-2 mean (SD) | cooling-2 ratio per seed |")
print("|---|---|---|---|---|---|")
for s in sorted({k[0] for k in rows}):
    seeds = sorted({k[1] for k in rows if k[0] == s})
    for m in ("poly", "poly-allan", "cs-svr", "hybrid", "auto"):
        if not all((s, seed, m) in rows for seed in seeds):
            continue
        cells = []
        for j in (0, 1):
            v = [rows[(s, seed, m)][j] for seed in seeds]
            r = [rows[(s, seed, m)][j] / rows[(s, seed, "poly")][j] for seed in seeds]
            sd = statistics.stdev(v) if len(v) > 1 else 0.0
            cells += [f"{statistics.mean(v):.1f} ({sd:.1f})", ", ".join(f"{x:.2f}" for x in r)]
        name = "poly(T, dT/dt)" if m == "poly" else m
        print(f"| {s} | {name} | {cells[0]} | {cells[1]} | {cells[2]} | {cells[3]} |")
