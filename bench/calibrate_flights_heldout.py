#!/usr/bin/env python3
"""Calibration from ordinary flight logs, scored on held-out chamber runs of the same board.

What it measures (docs/explanation/accuracy-flights.md): for each generator x board x seed,
bench/flights_heldout_gen.cc writes ten flight logs, a dedicated chamber calibration run (cold
start, the chamber heating at 1 C/min) and three held-out chamber runs (heating, cooling,
warm-up) of one 3-IMU board as PX4 ULogs, with the ground truth. Then:
  (a) `gyrocomp calibrate` on the ten flights and on the chamber run, each scored on every
      held-out run by `calibrate --validation` (PX4 formula in float, T clamped; RMS of 10 s block
      means, their mean removed); beside them no correction and the least-squares cubic of the
      true static curve over the flights' still temperatures (scored the same way by the
      generator, on the same rows);
  (b) still detection: the still segments of calibrate --json per log against the generator's
      truly still intervals: motion rows inside a segment, fraction of the true still time used;
  (c) three logs (the first three flights; three quick hops and three restarts that barely warm,
      which the generator writes besides):
      per sensor, an entry exactly when the true still rows identify the curve (>= 300 s still,
      >= 10 C of change inside a log, accelerometer: inside a still segment), the still time and
      temperature range it states against the truth, and an entry never worse than no
      correction on the held-out heating run (judge()).
Generator 1 is gyrocomp's own flight simulator (SimulateFlight); generator 2 is written apart
from it (bench/flights_heldout_gen.cc: die lag of second order, non-cubic curves, IMU instance
order shuffled per power-on, other vibration, disarmed handling).

How to run (after building the CLI and the library: cmake --build build --target gyrocomp_cli):
  nice bench/calibrate_flights_heldout.py [--build build] [--work /tmp/gyrocomp_flights_heldout]
      [--boards 3] [--seeds 2] [--rate 50] [--jobs 2] [--optimise-for steady|warm-up|both]
Prints markdown tables (the defaults: 2 generators x 3 boards x 2 seeds, about 11 min on 2 shared
cores); --json FILE keeps every number, --tables-from FILE prints them again. The logs (about
0.45 GB per board and seed) are deleted after each is scored unless --keep.
"""
import argparse
import concurrent.futures
import json
import math
import os
import re
import shutil
import subprocess
import sys

HELDOUT = ["heating", "cooling", "warm-up"]  # over the flights' ambients: criterion (a)
BEYOND = ["wide-heating"]  # to 55 C ambient, beyond the flights' temperatures: reported beside
G = 9.80665
MIN_SPAN_C = 10.0
MIN_STILL_S = 300.0
MIN_SEGMENT_S = 30.0


def run(cmd, check=True):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if check and p.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stderr}")
    return p


def calibrate(gyrocomp, logs, out_dir, tag, validation, extra=()):
    js = os.path.join(out_dir, f"{tag}.json")
    cmd = [gyrocomp, "calibrate"] + list(extra)
    for log in logs:
        cmd += ["-i", log]
    cmd += ["--format", "px4", "-o", os.path.join(out_dir, f"{tag}.params"), "--json", js]
    if validation:
        cmd += ["--validation", validation]
    if os.path.exists(js):
        os.remove(js)
    p = run(cmd, check=False)
    if p.returncode != 0 or not os.path.exists(js):
        # No sensor calibratable: exit 2 and no JSON; the console names each sensor's reason.
        sensors = []
        for line in p.stderr.splitlines():
            m = re.match(r"\s+(gyro|accel|baro) (\d+) \(id (\d+)\): skipped, (.*)$", line)
            if m:
                still = re.search(r"still time ([0-9.e+]+) s", m.group(4))
                sensors.append({"type": m.group(1), "instance": int(m.group(2)), "device_id": int(m.group(3)), "status": "skipped",
                                "reason": m.group(4), "identification": {"still_s": float(still.group(1))} if still else {}})
        return {"exit": p.returncode, "stderr": p.stderr, "sensors": sensors, "logs": []}
    with open(js) as f:
        return json.load(f)


def rms(values):
    values = [v for v in values if v is not None and math.isfinite(v)]
    return math.sqrt(sum(v * v for v in values) / len(values)) if values else float("nan")


def overlap(a, b):
    """Length of the intersection of two lists of [start, end) intervals."""
    total = 0.0
    for s0, e0 in a:
        for s1, e1 in b:
            total += max(0.0, min(e0, e1) - max(s0, s1))
    return total


def still_scores(truth, cal, fs):
    """Motion rows inside detected still segments, and the fraction of the true still time used."""
    motion_rows, used_s, true_s, min_fraction = 0, 0.0, 0.0, 1.0
    for flight, log in zip(truth["flights"], cal["logs"]):
        still = [(iv[0], iv[1]) for iv in flight["still"]]
        segs = [(s["start_s"], s["start_s"] + s["length_s"]) for s in log["still_segments"]]
        seg_s = sum(e - s for s, e in segs)
        in_still = overlap(segs, still)
        motion_rows += int(round((seg_s - in_still) * fs))
        log_true = sum(e - s for s, e in still)
        used_s += in_still
        true_s += log_true
        min_fraction = min(min_fraction, in_still / log_true if log_true else 1.0)
    return {"motion_rows": motion_rows, "still_fraction": used_s / true_s, "min_log_fraction": min_fraction}


def true_identification(entries, imu, kind):
    """What the truly still rows of `flights` identify for IMU `imu`: still time, temperature
    range, change inside a log (gyro) or a still segment of at least 30 s (accel)."""
    still_s, lo, hi, ranges = 0.0, math.inf, -math.inf, []
    for entry in entries:
        log_lo, log_hi = math.inf, -math.inf
        for iv in entry["still"]:
            if iv[1] - iv[0] < MIN_SEGMENT_S:
                continue
            t_lo, t_hi = iv[2 + 2 * imu], iv[3 + 2 * imu]
            still_s += iv[1] - iv[0]
            lo, hi = min(lo, t_lo), max(hi, t_hi)
            if kind == "accel":
                ranges.append((t_lo, t_hi))
            log_lo, log_hi = min(log_lo, t_lo), max(log_hi, t_hi)
        if kind == "gyro" and log_hi > log_lo:
            ranges.append((log_lo, log_hi))
    span, covered = 0.0, -math.inf
    for a, b in sorted(ranges):
        span += max(0.0, b - max(a, covered))
        covered = max(covered, b)
    return {"still_s": still_s, "temp_min_c": lo, "temp_max_c": hi, "span_c": span}


def imu_of(truth_sensors, kind, device_id):
    for s in truth_sensors:
        if s["type"] == kind and s["device_id"] == device_id:
            return s["imu"]
    return None


def judge(row):
    """A sensor's three-log statement is correct when: an entry exactly when the true still rows
    identify the curve (either way within 1 C or 10 % of a limit: not judged); the still time it
    reports (where it reports one) is at most the true still time (it counts what it used, never
    more); the temperature range within 1.5 C of the truth's; no entry: the reason names the limit the true rows miss;
    an entry: not worse than no correction on the held-out heating run."""
    # (A run with no entry at all has only its console lines: a still time only in that reason.)
    still_ok = row["reported_still_s"] is None or row["reported_still_s"] <= row["true_still_s"] + 1.0
    if not row["entry"] and not row["truly_identified"] and not row["borderline"]:
        limit = "still time" if row["true_still_s"] < MIN_STILL_S else "temperature change"
        still_ok = still_ok and limit in row["reason"]
    row["still_ok"] = still_ok
    row["correct"] = (row["entry"] == row["truly_identified"] or row["borderline"]) and row["range_ok"] and still_ok and row["harm_ok"]
    return row


def three_log_check(gyrocomp, truth, d, name, entries):
    logs = [os.path.join(d, e["path"]) for e in entries]
    cal = calibrate(gyrocomp, logs, d, "three_" + name, os.path.join(d, "heldout_heating.ulg"))
    heat = next(h for h in truth["heldout"] if h["name"] == "heating")
    rows = []
    for s in cal["sensors"]:
        if s["type"] not in ("gyro", "accel"):
            continue
        imu = imu_of(heat["sensors"], s["type"], s.get("device_id"))
        t = true_identification(entries, imu, s["type"])
        entry = s["status"] == "calibrated"
        should = t["still_s"] >= MIN_STILL_S and t["span_c"] >= MIN_SPAN_C
        border = abs(t["span_c"] - MIN_SPAN_C) < 1.0 or abs(t["still_s"] - MIN_STILL_S) < 0.1 * MIN_STILL_S
        ident = s.get("identification", {})
        # The range is in the JSON only (a run with no entry at all has none: not checked).
        range_ok = "temp_min_c" not in ident or (abs(ident["temp_min_c"] - t["temp_min_c"]) < 1.5 and abs(ident["temp_max_c"] - t["temp_max_c"]) < 1.5)
        harm_ok = True
        if entry and s.get("validation", {}).get("status") == "scored":
            v = s["validation"]
            harm_ok = rms(v["cubic_rms"]) <= rms(v["raw_rms"])
        rows.append(judge({"sensor": f"{s['type']} {s['instance']}", "entry": entry, "truly_identified": should, "borderline": border,
                           "true_span_c": t["span_c"], "reported_span_c": ident.get("identified_span_c"), "true_still_s": t["still_s"],
                           "reported_still_s": ident.get("still_s"), "range_ok": range_ok, "harm_ok": harm_ok,
                           "reason": s.get("reason", ""), "statement": ident.get("statement", "")}))
    return {"subset": name, "logs": [e["path"] for e in entries], "sensors": rows, "exit": cal.get("exit", 0)}


def one_case(args, gen, board, seed):
    d = os.path.join(args.work, f"g{gen}_b{board}_s{seed}")
    os.makedirs(d, exist_ok=True)
    if not os.path.exists(os.path.join(d, "truth.json")):
        run([args.gen, d, str(gen), str(board), str(seed), str(args.rate)])
    with open(os.path.join(d, "truth.json")) as f:
        truth = json.load(f)
    flights = [os.path.join(d, fl["path"]) for fl in truth["flights"]]
    out = {"generator": gen, "board": board, "seed": seed, "heldout": {}}
    for h in truth["heldout"]:
        path = os.path.join(d, h["path"])
        fl = calibrate(args.gyrocomp, flights, d, "flights_" + h["name"], path, ["--optimise-for", args.optimise_for])
        ch = calibrate(args.gyrocomp, [os.path.join(d, "chamber_cal.ulg")], d, "chamber_" + h["name"], path)
        if h["name"] == HELDOUT[0]:
            out["still"] = still_scores(truth, fl, truth["rate_hz"])
            out["lags"] = [{"sensor": f"{x['type']} {x.get('device_id')}", "lag_s": x.get("temp_lag_s", 0.0),
                            "gain": x.get("lag_term", {}).get("gain"), "se": x.get("lag_term", {}).get("gain_se")}
                           for x in fl["sensors"] if x["type"] in ("gyro", "accel")]
        per = {}
        for kind in ("gyro", "accel"):
            scores = {"raw": [], "chamber": [], "flights": [], "lsq": [], "missing": []}
            for ts in h["sensors"]:
                if ts["type"] != kind:
                    continue
                scores["raw"] += ts["raw"]
                scores["lsq"] += ts["lsq"]
                for tag, cal in (("flights", fl), ("chamber", ch)):
                    s = next((x for x in cal["sensors"] if x["type"] == kind and x.get("device_id") == ts["device_id"]), None)
                    if s and s.get("validation", {}).get("status") == "scored":
                        scores[tag] += s["validation"]["cubic_rms"]
                    else:
                        scores[tag] += [ts["raw"][a] for a in range(3)]  # no entry: no correction
                        scores["missing"].append(f"{tag} {kind} {ts['imu']}")
            per[kind] = scores
        out["heldout"][h["name"]] = per
    out["three"] = [three_log_check(args.gyrocomp, truth, d, "first three flights", truth["flights"][:3]),
                    three_log_check(args.gyrocomp, truth, d, "three quick hops", truth["quick"]),
                    three_log_check(args.gyrocomp, truth, d, "three warm restarts", truth["warm"])]
    out["flight_still_range_c"] = truth["flight_still_range_c"]
    if not args.keep:
        shutil.rmtree(d)
    return out


def summarise(case, kind):
    agg = {tag: rms([v for h in HELDOUT for v in case["heldout"][h][kind][tag]]) for tag in ("raw", "chamber", "flights", "lsq")}
    agg["missing"] = sorted({m for h in HELDOUT for m in case["heldout"][h][kind]["missing"]})
    f = agg["flights"]
    agg["vs_chamber"] = f / agg["chamber"]
    agg["vs_lsq"] = f / agg["lsq"]
    agg["vs_raw"] = f / agg["raw"]
    agg["pass"] = (agg["vs_chamber"] <= 1.3 or agg["vs_lsq"] <= 1.15) and agg["vs_raw"] <= 0.5
    return agg


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(here, "..", "build"))
    ap.add_argument("--work", default="/tmp/gyrocomp_flights_heldout")
    ap.add_argument("--boards", type=int, default=3)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--generators", default="1,2")
    ap.add_argument("--rate", type=float, default=50.0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--keep", action="store_true")
    ap.add_argument("--optimise-for", default="steady", choices=["steady", "warm-up", "both"],
                    help="calibrate --optimise-for of the ten flights' pooled file (the chamber run's: the default)")
    ap.add_argument("--json")
    ap.add_argument("--tables-from", help="print the tables of a --json FILE of an earlier run (nothing is run)")
    args = ap.parse_args()
    if args.tables_from:
        with open(args.tables_from) as f:
            results = json.load(f)
        for c in results:
            for t in c["three"]:
                t["sensors"] = [judge(row) for row in t["sensors"]]
        print_tables(results, args.rate)
        return
    build = os.path.abspath(args.build)
    args.gyrocomp = os.path.join(build, "gyrocomp")
    os.makedirs(args.work, exist_ok=True)
    args.gen = os.path.join(args.work, "flights_heldout_gen")
    srcs = [os.path.join(here, f) for f in ("flights_heldout_gen.cc", "flights_heldout_gen2.cc", "flights_heldout_gen.h")]
    newest = max(os.path.getmtime(p) for p in srcs + [os.path.join(build, "libgyrocomp.a")])
    if not os.path.exists(args.gen) or os.path.getmtime(args.gen) < newest:
        run(["c++", "-std=c++20", "-O2", "-I" + os.path.join(here, "..", "include"), *srcs[:2], os.path.join(build, "libgyrocomp.a"),
             "-lfftw3", "-lz", "-lsvm", "-lzstd", "-llz4", "-lsqlite3", "-lbz2", "-o", args.gen])
    cases = [(g, b, s) for g in map(int, args.generators.split(",")) for b in range(args.boards) for s in range(1, args.seeds + 1)]
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, min(2, args.jobs))) as pool:
        results = list(pool.map(lambda c: one_case(args, *c), cases))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    print_tables(results, args.rate)


def print_tables(results, rate):
    unit = {"gyro": ("mdps", 1000.0 * 180.0 / math.pi), "accel": ("mg", 1000.0 / G)}
    print(f"IMU rate {rate:g} Hz. (a): RMS over the held-out runs {', '.join(HELDOUT)} (chamber ambient within the flights' 0..35 C),")
    print("3 IMUs and 3 axes of each axis's calibrate --validation score (10 s block means, mean removed); the run to 55 C")
    print(f"({', '.join(BEYOND)}) in the per-run table only.\n")
    for kind in ("gyro", "accel"):
        name, k = unit[kind]
        print(f"### (a) {kind}, held-out RMS in {name}\n")
        print("| gen | board | seed | none | chamber | flights | LS cubic of truth | flights / chamber | flights / LS | flights / none | (a) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for c in results:
            a = summarise(c, kind)
            miss = f" (no entry: {', '.join(a['missing'])})" if a["missing"] else ""
            print(f"| {c['generator']} | {c['board']} | {c['seed']} | {a['raw'] * k:.3g} | {a['chamber'] * k:.3g} | {a['flights'] * k:.3g} | "
                  f"{a['lsq'] * k:.3g} | {a['vs_chamber']:.2f} | {a['vs_lsq']:.2f} | {a['vs_raw']:.2f} | {'holds' if a['pass'] else 'fails'}{miss} |")
        print()
        print(f"Per held-out run, RMS over every case ({name}):\n")
        print("| gen | held-out | none | chamber | flights | LS cubic of truth |")
        print("|---|---|---|---|---|---|")
        for gen in sorted({c["generator"] for c in results}):
            for h in HELDOUT + BEYOND:
                cs = [c for c in results if c["generator"] == gen]
                r = {tag: rms([v for c in cs for v in c["heldout"][h][kind][tag]]) * k for tag in ("raw", "chamber", "flights", "lsq")}
                print(f"| {gen} | {h} | {r['raw']:.3g} | {r['chamber']:.3g} | {r['flights']:.3g} | {r['lsq']:.3g} |")
        print()
    if all("lags" in c for c in results):
        print("### The lag of the temperature the ten flights' pooled cubic is fitted on (gyro; accel)\n")
        print("| gen | board | seed | gyro lags kept (s) | accel lags kept (s) | gyro paired gain +- SE (%) |")
        print("|---|---|---|---|---|---|")
        for c in results:
            cell = {k: ", ".join(f"{x['lag_s']:g}" for x in c["lags"] if x["sensor"].startswith(k)) for k in ("gyro", "accel")}
            gains = ", ".join("-" if x["gain"] is None else f"{100 * x['gain']:+.1f} +- {100 * x['se']:.1f}"
                              for x in c["lags"] if x["sensor"].startswith("gyro"))
            print(f"| {c['generator']} | {c['board']} | {c['seed']} | {cell['gyro']} | {cell['accel']} | {gains} |")
        print()
    print("### (b) still detection over the ten flights\n")
    print("| gen | board | seed | motion rows used | true still time used | lowest log | (b) |")
    print("|---|---|---|---|---|---|---|")
    for c in results:
        s = c["still"]
        ok = s["motion_rows"] == 0 and s["still_fraction"] >= 0.9
        print(f"| {c['generator']} | {c['board']} | {c['seed']} | {s['motion_rows']} | {100 * s['still_fraction']:.1f} % | "
              f"{100 * s['min_log_fraction']:.1f} % | {'holds' if ok else 'fails'} |")
    print()
    print("### (c) three logs: entries against what the true still rows identify\n")
    print("| gen | board | seed | logs | entries (gyro, accel) | truly identified | wrong | (c) |")
    print("|---|---|---|---|---|---|---|---|")
    for c in results:
        for t in c["three"]:
            ss = t["sensors"]
            ent = f"{sum(s['entry'] for s in ss if s['sensor'].startswith('gyro'))}, {sum(s['entry'] for s in ss if s['sensor'].startswith('accel'))}"
            tru = f"{sum(s['truly_identified'] for s in ss if s['sensor'].startswith('gyro'))}, {sum(s['truly_identified'] for s in ss if s['sensor'].startswith('accel'))}"
            wrong = [s for s in ss if not s["correct"]]
            why = "; ".join(f"{s['sensor']}: entry {s['entry']}, true span {s['true_span_c']:.1f} C / {s['true_still_s']:.0f} s, "
                            f"range {'ok' if s['range_ok'] else 'off'}, still {'ok' if s['still_ok'] else 'off'}, harm {'none' if s['harm_ok'] else 'worse'}"
                            for s in wrong)
            print(f"| {c['generator']} | {c['board']} | {c['seed']} | {t['subset']} | {ent} | {tru} | {why or '-'} | "
                  f"{'holds' if not wrong and ss else 'fails'} |")


if __name__ == "__main__":
    main()
