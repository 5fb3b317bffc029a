#!/usr/bin/env python3
"""Calibrate many gyros on a Dask cluster: fit, validate and export one drift model per unit.

    examples/batch_dask.py --manifest units.csv --out DIR [--scheduler tcp://host:8786]
                           [--local-workers 2] [--model poly|svr|cs-svr] [--time-col time_s]
                           [--rate-col rate_dps] [--temp-col temp_c]

units.csv has the columns unit_id,calibration,validation: each unit's calibration run (the model
is fitted on it) and a separate validation run (held out: the model is only applied to it). Runs
are CSV files (.csv or .csv.gz) with a time, a rate (deg/s) and a temperature (deg C) column, as
`gyrocomp simulate` writes them. Without --scheduler a LocalCluster of --local-workers processes
runs on this machine; with it, the same code runs on a real cluster (workers must see the run
files and DIR at the same paths, e.g. a shared filesystem, and have the gyrocomp module).

Per unit, on a worker: read both runs, Allan analysis of the calibration run (ARW, ADEV minimum,
bias instability), fit the drift model of rate against temperature, predict on the validation
run, write DIR/units/<unit_id>/model.json (the model file `gyrocomp apply -m` reads) and
imu.yaml (Kalibr noise densities). Only the paths go to the workers and only a row of figures
comes back: the records never cross the network.

DIR/summary.csv has one row per unit; DIR/summary.html shows the table with outliers flagged: a
figure whose robust z-score |x - median| / (1.4826 MAD) exceeds --outlier-z (default 3.5) across
the batch and which is at least --outlier-rel (default 25%) away from the median. Units that fail keep a row with the error and empty figures. docs/guides/many-units.md explains the
figures and how the work scales.
"""

import argparse
import csv
import html
import math
import os
import sys
import time

import numpy as np

FIGURES = ["arw_deg_per_sqrt_h", "adev_min_deg_per_h", "bias_instability_deg_per_h",
           "drift_span_dps", "heldout_residual_rms_dps"]


def read_run(path, time_col, rate_col, temp_col):
    """(rate_dps, temp_c, fs_hz) of one run; ValueError naming the file on a missing column."""
    import gzip
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        header = f.readline().strip().split(",")
    for col in (time_col, rate_col, temp_col):
        if col not in header:
            raise ValueError(f"{path}: no column '{col}' (columns: {', '.join(header)})")
    data = np.loadtxt(path, delimiter=",", skiprows=1,
                      usecols=[header.index(time_col), header.index(rate_col), header.index(temp_col)], ndmin=2)
    if data.shape[0] < 10:
        raise ValueError(f"{path}: {data.shape[0]} rows: too short")
    fs_hz = 1.0 / float(np.median(np.diff(data[:, 0])))
    return np.ascontiguousarray(data[:, 1]), np.ascontiguousarray(data[:, 2]), fs_hz


def block_means(x, n):
    k = len(x) // n
    return x[:k * n].reshape(k, n).mean(axis=1) if k > 0 else np.array([np.mean(x)])


def process_unit(unit_id, calibration, validation, out_dir, options):
    """Runs on a worker: fit, validate, export one unit. Returns one summary row (small)."""
    import gyrocomp
    row = {"unit_id": unit_id, "error": ""}
    t0 = time.time()
    try:
        rate, temp, fs = read_run(calibration, options["time_col"], options["rate_col"], options["temp_col"])
        allan = gyrocomp.compute_allan(rate, fs)
        model = gyrocomp.fit_drift_model(temp, rate, fs, model=options["model"])
        v_rate, v_temp, v_fs = read_run(validation, options["time_col"], options["rate_col"], options["temp_col"])
        predicted = model.predict(v_temp, v_fs)
        compensated = v_rate - predicted
        # Held-out residual: RMS about zero of 60 s means of the compensated validation run, i.e.
        # the drift (and bias) left after the model, with the white noise averaged down.
        means = block_means(compensated, max(1, int(round(60.0 * v_fs))))
        fitted = model.predict(temp, fs)
        unit_dir = os.path.join(out_dir, "units", unit_id)
        os.makedirs(unit_dir, exist_ok=True)
        model.save(os.path.join(unit_dir, "model.json"))
        with open(os.path.join(unit_dir, "imu.yaml"), "w") as f:
            f.write(gyrocomp.kalibr_imu_yaml(rate, fs, rostopic=f"/{unit_id}/imu"))
        row.update({
            "arw_deg_per_sqrt_h": allan.terms.arw_deg_per_sqrt_h,
            "adev_min_deg_per_h": allan.terms.adev_min_deg_per_h,
            "bias_instability_deg_per_h": allan.terms.bias_instability_deg_per_h,
            "drift_span_dps": float(np.max(fitted) - np.min(fitted)),
            "heldout_residual_rms_dps": float(np.sqrt(np.mean(means ** 2))),
            "model": model.kind,
            "calibration_samples": len(rate),
            "validation_samples": len(v_rate),
        })
    except Exception as e:  # one bad unit must not stop the batch: its row carries the reason
        row["error"] = f"{type(e).__name__}: {e}"
    row["seconds"] = round(time.time() - t0, 3)
    row["worker"] = os.uname().nodename + ":" + str(os.getpid())
    return row


def flag_outliers(rows, z_max, min_rel_dev):
    """Adds '<figure>_outlier' booleans and 'outlier' (any): robust z-score above z_max across the
    batch AND at least min_rel_dev (relative) from the median, so that a tight batch (ARW within
    1-2%) does not flag a unit 3% off."""
    for fig in FIGURES:
        values = np.array([r[fig] for r in rows if r.get(fig) is not None and math.isfinite(r[fig])])
        med = float(np.median(values)) if len(values) else 0.0
        mad = 1.4826 * float(np.median(np.abs(values - med))) if len(values) else 0.0
        for r in rows:
            v = r.get(fig)
            z = abs(v - med) / mad if v is not None and mad > 0 else 0.0
            far = v is not None and abs(v - med) > min_rel_dev * abs(med)
            r[fig + "_outlier"] = bool(v is not None and mad > 0 and z > z_max and far)
    for r in rows:
        r["outlier"] = any(r[f + "_outlier"] for f in FIGURES) or bool(r["error"])
    return rows


def write_summary(rows, out_dir):
    columns = ["unit_id"] + FIGURES + ["outlier"] + [f + "_outlier" for f in FIGURES] + \
        ["model", "calibration_samples", "validation_samples", "seconds", "worker", "error"]
    with open(os.path.join(out_dir, "summary.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in columns})
    cells = []
    for r in rows:
        tds = [f"<td>{html.escape(r['unit_id'])}</td>"]
        for fig in FIGURES:
            v = r.get(fig)
            text = "" if v is None else f"{v:.4g}"
            cls = ' class="out"' if r.get(fig + "_outlier") else ""
            tds.append(f"<td{cls}>{text}</td>")
        tds.append(f"<td>{'OUTLIER' if r['outlier'] else ''}</td><td>{html.escape(r['error'])}</td>")
        cells.append("<tr>" + "".join(tds) + "</tr>")
    head = "".join(f"<th>{h}</th>" for h in ["unit_id"] + FIGURES + ["flag", "error"])
    n_out = sum(r["outlier"] for r in rows)
    with open(os.path.join(out_dir, "summary.html"), "w") as f:
        f.write("<!doctype html><meta charset='utf-8'><title>gyrocomp batch summary</title>"
                "<style>body{font-family:sans-serif}td,th{padding:2px 8px;text-align:right}"
                ".out{background:#f8c0c0;font-weight:bold}</style>"
                f"<h1>gyrocomp batch: {len(rows)} units, {n_out} flagged</h1>"
                "<p>Flagged cells: robust z-score above the threshold across the batch "
                "(|x - median| / (1.4826 MAD)) and far from the median (relative threshold). Held-out residual: RMS of 60 s means of the "
                "validation run after the model.</p>"
                f"<table><tr>{head}</tr>{''.join(cells)}</table>")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--manifest", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://host:8786)")
    p.add_argument("--local-workers", type=int, default=2, help="LocalCluster size without --scheduler")
    p.add_argument("--model", default="poly", help="drift model: poly | svr | cs-svr (default poly)")
    p.add_argument("--time-col", default="time_s")
    p.add_argument("--rate-col", default="rate_dps")
    p.add_argument("--temp-col", default="temp_c")
    p.add_argument("--outlier-z", type=float, default=3.5, help="robust z-score above which a figure is flagged")
    p.add_argument("--outlier-rel", type=float, default=0.25,
                   help="... and only when also this far from the median, relative (default 0.25)")
    a = p.parse_args(argv)

    with open(a.manifest, newline="") as f:
        reader = csv.DictReader(f)
        missing = {"unit_id", "calibration", "validation"} - set(reader.fieldnames or [])
        if missing:
            print(f"batch_dask: {a.manifest}:1: missing column(s) {', '.join(sorted(missing))}", file=sys.stderr)
            return 2
        units = list(reader)
    ids = [u["unit_id"] for u in units]
    if len(set(ids)) != len(ids):
        print(f"batch_dask: {a.manifest}: duplicate unit_id", file=sys.stderr)
        return 2
    base = os.path.dirname(os.path.abspath(a.manifest))
    resolve = lambda path: path if os.path.isabs(path) else os.path.join(base, path)  # noqa: E731
    os.makedirs(a.out, exist_ok=True)
    out_dir = os.path.abspath(a.out)
    options = {"model": a.model, "time_col": a.time_col, "rate_col": a.rate_col, "temp_col": a.temp_col}

    from dask.distributed import Client, LocalCluster
    cluster = None
    if a.scheduler:
        client = Client(a.scheduler)
    else:
        cluster = LocalCluster(n_workers=a.local_workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    try:
        t0 = time.time()
        futures = [client.submit(process_unit, u["unit_id"], resolve(u["calibration"]), resolve(u["validation"]),
                                 out_dir, options, key=f"unit-{u['unit_id']}", pure=False) for u in units]
        rows = client.gather(futures)
        elapsed = time.time() - t0
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    rows = flag_outliers(rows, a.outlier_z, a.outlier_rel)
    write_summary(rows, out_dir)
    failed = sum(bool(r["error"]) for r in rows)
    print(f"batch_dask: {len(rows)} units in {elapsed:.1f} s on {len({r['worker'] for r in rows})} workers, "
          f"{sum(r['outlier'] for r in rows)} flagged, {failed} failed -> {out_dir}/summary.csv, summary.html")
    return 1 if failed == len(rows) and rows else 0


if __name__ == "__main__":
    sys.exit(main())
