#!/usr/bin/env python3
"""Side by side: gyrocomp calibrate vs PX4's process_sensor_caldata.py and ArduPilot's
tempcal_IMU.py on simulated boards, scored on held-out runs with each firmware's own formula
(docs/explanation/accuracy-calibration.md "Side by side with the autopilots' scripts").

    bench/imu_calibration_side_by_side.py [--build build] [--seeds 5] [--fs 10]
        [--px4-script PX4/Tools/process_sensor_caldata.py] [--pyulog DIR]
        [--tempcal ARDUPILOT/Tools/scripts/tempcal_IMU.py] [--pymavlink DIR] [--runs K]
        [--second-profile fast-heating|slow-heating|cooling] [--no-variants]

The scripts are optional and are not dependencies of gyrocomp: give the path of each (from a
checkout you fetched; never committed here) and the folder holding the `pyulog` / `pymavlink`
package. A script that is not given or does not run (it needs numpy, scipy, matplotlib; Debian:
python3-scipy python3-matplotlib) is skipped with its reason.

For each seed and drift structure (`dtemp`: bias(T) + 1.5 deg/s per C/s x dT/dt + hysteresis, the
simulator's default; `static`: bias(T) only; the accelerometers have neither term in both), one IMU
is simulated:
  calibration   cold start at 10 C, 10 min hold, heating at 1 C/min to 60 C, 20 min hold
  heating       the same profile, another seed            (held out)
  cooling       60 C -> 10 C at 1 C/min, holds, another seed  (held out)
  warm-up       power-on self-heating 20 -> 50 C at 3 C/min, 20 min steady, another seed (held out)
The held-out runs are read with pyulog (--pyulog, required). Each parameter set is scored per gyro
and accel axis on the held-out runs: the residual the firmware leaves, value - offset(T) (PX4
calc_thermal_offsets_3D, float32, T clamped to [TMIN, TMAX]; ArduPilot correct_sensor relative to
INS_GYRn_CALTEMP / INS_ACCn_CALTEMP = the run's boot temperature, float32, clamped), as 10 s block
means with their mean removed (the constant is the boot offset calibration's), RMS in deg/s and
m/s^2. Rows: no correction, each script, gyrocomp (its default, --static-weight auto; the PX4
file also with --optimise-for warm-up / both, with --static-weight time: the model's own
time-weighted curve, and temperature: each temperature alike; --no-variants leaves these out;
and with --runs K on 2..K calibration runs of the board of the same profile, other seeds,
`calibrate -i` repeated: the pooled fit, which has no weighting to choose), and the true static
curve (the simulator's bias cubic, the best a static cubic can do against its own static part).
Printed: mean over seeds and axes, the seed spread (SD of the per-seed means), per-axis win counts
of gyrocomp against each script and the RMS ratios.
--second-profile P adds a second calibration run of the board with another profile (seed 100 s +
5000; fast-heating: 10 -> 60 C at 3 C/min; slow-heating: at 0.5 C/min with a 40 min hold;
cooling: 60 -> 10 C at 1 C/min): gyrocomp on it alone and pooled with the first
(`calibrate -i RUN1 -i RUN2`, PX4 and ArduPilot files), each script on each run, and a last
table per structure and sensor on the held-out heating and cooling runs: each single run, the
pooled file, each script on each run, the scripts' best per column, the true curve; then the
pooled file against the better single run, the true curve and each script (and the true curve
against each script: where it is above a target ratio, no static cubic reaches it).
--pooled-conditions steady,warm-up,both (with --second-profile) adds the pooled PX4 file with
`--optimise-for C` for each condition C other than steady (the default): its rows in the last
table and its ratio against the better single run.
Figures and the scripts' commits: docs/explanation/accuracy-calibration.md, "Side by side with the autopilots' scripts".
"""
import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

DEFAULT_POLY = [0.02, 1.5e-3, 1.2e-5, -2.0e-7]  # simulator.h BiasModelOptions::poly_dps (deg/s)
ACCEL_POLY = [0.02, 1.5e-3, 1.0e-5, -1.0e-7]    # simulator.h AccelAxisOptions::bias_poly_m_s2
AXIS_SCALE = [1.0, -0.7, 0.5]                     # BoardAxisDriftScale(imu 0, axis)
RAD = math.pi / 180.0
# Held-out runs (name -> simulate arguments). warm-up: power-on self-heating from room temperature,
# 20 -> 50 C at 3 C/min behind the same 120 s lag, then steady (the condition a vehicle meets each boot).
PROFILES = {
    "heating": ["--room-temp", "10", "--ramp-end", "60"],
    "cooling": ["--room-temp", "60", "--ramp-end", "10"],
    "warm-up": ["--room-temp", "20", "--ramp-end", "50", "--ramp-rate", "3", "--room-hold", "60"],
}
# Profiles of the second calibration run of the board (--second-profile; the first is `heating`).
# fast-heating: the same chamber run at 3 C/min; slow-heating: a slow soak at 0.5 C/min with a 40 min
# hold; cooling: 60 -> 10 C at 1 C/min (the held-out cooling run's profile, another seed).
SECOND_PROFILES = {
    "fast-heating": ["--room-temp", "10", "--ramp-end", "60", "--ramp-rate", "3"],
    "slow-heating": ["--room-temp", "10", "--ramp-end", "60", "--ramp-rate", "0.5", "--hold", "2400"],
    "cooling": PROFILES["cooling"],
}
SECOND_SEED = 5000  # the second calibration run's seed: 100 s + 5000 (the --runs runs: 100 s + 1000 k)


def run(cmd, env=None, cwd=None):
    r = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=cwd)
    return r.returncode, r.stdout + r.stderr


def simulate(gc, path, seed, fs, structure, profile="heating", extra=()):
    base = {"--room-hold": "600", "--hold": "1200", "--ramp-rate": "1"}
    prof = PROFILES[profile] if profile in PROFILES else SECOND_PROFILES[profile]
    for k in list(base):
        if k in prof:
            del base[k]
    drift = [] if structure == "dtemp" else ["--dtemp-coeff", "0", "--hysteresis-coeff", "0"]
    rc, out = run([gc, "simulate", "--profile", "ramp", "--thermal-lag", "120", "--fs", str(fs), "--seed", str(seed),
                   "--imus", "1"] + [x for kv in base.items() for x in kv] + prof + drift + list(extra) + ["-o", path])
    if rc != 0:
        sys.exit("simulate failed: " + out)


def read_imu(log):
    """(temperature C, 3 x n rad/s, temperature C, 3 x n m/s^2) of instance 0 of a ULog (pyulog)."""
    try:
        from pyulog import ULog
    except ImportError:
        sys.exit("the held-out runs are read with pyulog: give --pyulog DIR (the folder holding the package)")
    u = ULog(log, ["sensor_gyro", "sensor_accel"])
    out = {}
    for d in u.data_list:
        if d.multi_id == 0:
            out[d.name] = (d.data["temperature"].astype(np.float64),
                           np.vstack([d.data[a].astype(np.float64) for a in "xyz"]))
    return out["sensor_gyro"], out["sensor_accel"]


def read_params(path):
    p = {}
    for line in open(path):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        f = line.replace(",", " ").split()
        if len(f) == 5:      # QGroundControl: sys comp name value type
            p[f[2]] = float(f[3])
        elif len(f) == 2:    # Mission Planner / tempcal_IMU
            p[f[0]] = float(f[1])
    return p


def px4_offsets(p, slot, temp, sensor="G"):
    """PX4 TemperatureCompensation::calc_thermal_offsets_3D: offset = sum X_k (T - TREF)^k, T clamped
    to [TMIN, TMAX], float32; the sensor's Correct() subtracts it (gyro TC_G, accel TC_A)."""
    f32 = np.float32
    s = "TC_%s%d_" % (sensor, slot)
    t = np.clip(temp.astype(f32), f32(p[s + "TMIN"]), f32(p[s + "TMAX"]))
    dt = (t - f32(p[s + "TREF"])).astype(f32)
    out = []
    for a in range(3):
        c = [f32(p[s + "X%d_%d" % (k, a)]) for k in range(4)]
        out.append(c[0] + c[1] * dt + c[2] * dt * dt + c[3] * dt * dt * dt)
    return np.array(out, dtype=np.float64)


def ardupilot_correction(p, imu, temp, sensor="GYR"):
    """AP_InertialSensor_TCal::correct_sensor: v -= poly(T - 35) - poly(CALTEMP - 35), poly with no
    constant term, coefficients 1e-6 scaled, T clamped to [TMIN, TMAX], float32. CALTEMP
    (INS_GYRn_CALTEMP / INS_ACCn_CALTEMP) is the temperature of the offset calibration: for the gyro
    ArduPilot calibrates its offsets at every boot, so it is the held-out run's first temperature."""
    f32 = np.float32
    s = "INS_TCAL%d_" % imu
    tmin, tmax = f32(p.get(s + "TMIN", 0.0)), f32(p.get(s + "TMAX", 70.0))
    t = np.clip(temp.astype(f32), tmin, tmax)
    tcal = t[0]  # INS_GYRn_CALTEMP / INS_ACCn_CALTEMP: the boot temperature of the held-out run
    out = []
    for a, ax in enumerate("XYZ"):
        c = [f32(p.get("%s%s%d_%s" % (s, sensor, k, ax), 0.0)) for k in (1, 2, 3)]
        poly = lambda x: (c[0] + (c[1] + c[2] * x) * x) * x * f32(1e-6)
        out.append(poly(t - f32(35.0)) - poly(tcal - f32(35.0)))
    return np.array(out, dtype=np.float64)


def truth_offsets(temp, sensor):
    """The simulator's static curve (its bias cubic; its own least-squares cubic), rad/s or m/s^2."""
    d = temp - 25.0
    if sensor == "gyro":
        return np.array([sum(DEFAULT_POLY[k] * AXIS_SCALE[a] * d ** k for k in range(4)) * RAD for a in range(3)])
    # accel axis a carries BoardAxisDriftScale(0, (a + 1) % 3) (simulator.cc SimulateBoard)
    return np.array([sum(ACCEL_POLY[k] * AXIS_SCALE[(a + 1) % 3] * d ** k for k in range(4)) for a in range(3)])


def score(rate, correction, fs, unit=1.0 / RAD):
    """RMS of the 10 s block means of rate - correction, their mean removed, per axis (deg/s for the
    gyro, m/s^2 for the accel)."""
    n = int(round(10 * fs))
    r = (rate - correction) * unit
    m = r[:, : (r.shape[1] // n) * n].reshape(3, -1, n).mean(axis=2)
    m -= m.mean(axis=1, keepdims=True)
    return np.sqrt((m ** 2).mean(axis=1))


def try_px4_script(args, ulg, tmp):
    if not args.px4_script:
        return None, "not given (--px4-script)"
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=args.pyulog or "")
    env.pop("PYTHONHOME", None)
    local = os.path.join(tmp, "px4_" + os.path.basename(ulg))
    shutil.copy(ulg, local)
    rc, out = run([sys.executable, args.px4_script, local], env=env)
    if rc != 0 or not os.path.exists(local + ".params"):
        return None, ("failed: " + out.strip().splitlines()[-1]) if out.strip() else "failed"
    return read_params(local + ".params"), ""


def try_tempcal(args, binlog, tmp):
    if not args.tempcal:
        return None, "not given (--tempcal)"
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=args.pymavlink or "")
    outfile = os.path.join(tmp, "tempcal_" + os.path.basename(binlog) + ".parm")
    rc, out = run([sys.executable, args.tempcal, "--no-graph", "--outfile", outfile, binlog], env=env)
    if rc != 0 or not os.path.exists(outfile):
        return None, ("failed: " + out.strip().splitlines()[-1]) if out.strip() else "failed"
    return read_params(outfile), ""


def calibrate(gc, logs, fmt, out, extra=()):
    """gyrocomp calibrate -i LOG [-i LOG ...] --format FMT: its parameters (several logs: the pooled fit)."""
    cmd = [gc, "calibrate", "--format", fmt, "-o", out] + list(extra)
    for f in logs:
        cmd += ["-i", f]
    rc, msg = run(cmd)
    if rc != 0:
        sys.exit("calibrate failed: " + msg)
    return read_params(out)


def mean_of(rows, key):
    """Mean over seeds and axes of one row's cell (None when missing)."""
    v = rows.get(key)
    return None if not v else float(np.mean([x.mean() for x in v]))


def print_second_profile(rows, structures, profile, conditions=("steady",)):
    """The two-profile comparison (--second-profile): each single run, the pooled file, each script on
    each run and the scripts' best, the true curve; then the ratios the acceptance reads."""
    held = ("heating", "cooling")
    single = [("gyrocomp, run 1 (heating 1 C/min)", "gyrocomp -> px4"),
              ("gyrocomp, run 2 (%s)" % profile, "gyrocomp -> px4, run 2")]
    pooled = ("gyrocomp, pooled (-i run 1 -i run 2)", "gyrocomp -> px4, pooled")
    pooled_by = [pooled] + [("gyrocomp, pooled --optimise-for %s" % c, "gyrocomp -> px4, pooled (--optimise-for %s)" % c)
                            for c in conditions if c != "steady"]
    scripts = [("PX4 script, run 1", "PX4 script"), ("PX4 script, run 2", "PX4 script, run 2"),
               ("tempcal_IMU, run 1", "tempcal_IMU"), ("tempcal_IMU, run 2", "tempcal_IMU, run 2")]
    truth = ("true static curve (its own LS cubic)", "true static curve")
    print()
    print("Two calibration runs of different profiles: run 1 heating 10 -> 60 C at 1 C/min, run 2 %s"
          " (seed 100 s + %d); held out: heating, cooling; mean = mean(heating, cooling)" % (profile, SECOND_SEED))
    for sensor in ("gyro", "accel"):
        print()
        print("| structure | %s parameter set | heating | cooling | mean |" % sensor)
        print("|---|---|---|---|---|")
        for structure in structures:
            def cell(name, r):
                return mean_of(rows, (structure, sensor, r, name))

            def sd(name, r):
                v = rows.get((structure, sensor, r, name))
                return float(np.std([x.mean() for x in v])) if v else float("nan")

            def line(label, name):
                c = [cell(name, r) for r in held]
                if any(x is None for x in c):
                    return
                print("| %s | %s | %s | %.3g |" % (structure, label, " | ".join(
                    "%.3g +- %.2g" % (x, sd(name, r)) for x, r in zip(c, held)), np.mean(c)))

            for label, name in single + pooled_by:
                line(label, name)
            present = [(label, name) for label, name in scripts if cell(name, "heating") is not None]
            for label, name in present:
                line(label, name)
            best = {}
            if present:
                for r in held:
                    best[r] = min((cell(name, r), label) for label, name in present)
                print("| %s | scripts' best (per column) | %s | %.3g |" % (structure, " | ".join(
                    "%.3g (%s)" % best[r] for r in held), np.mean([best[r][0] for r in held])))
            line(*truth)
            # Ratios (means over seeds and axes; mean: of the two directions' means).
            def ratios(num, den):
                a = [cell(num, r) for r in held]
                b = [den[r] if isinstance(den, dict) else cell(den, r) for r in held]
                if any(x is None for x in a + b):
                    return None
                return [a[0] / b[0], a[1] / b[1], np.mean(a) / np.mean(b)]

            def fmt(v):
                return "heating %.3f, cooling %.3f, mean %.3f" % tuple(v)

            better = {r: min(cell(n, r) for _, n in single) for r in held}
            for label, name in pooled_by:
                rp = ratios(name, better)
                if rp is None:
                    continue
                worse = [r for r, x in zip(held, rp) if x > 1.0]
                print("  %s %s: %s / better single run: %s -> %s" % (
                    structure, sensor, label, fmt(rp), "never worse" if not worse else "WORSE on " + ", ".join(worse)))
            rt = ratios(pooled[1], truth[1])
            print("  %s %s: pooled / true curve's cubic: %s" % (structure, sensor, fmt(rt)))
            for k, (label, name) in enumerate(single):
                print("  %s %s: %s / true curve's cubic: %s" % (structure, sensor, label, fmt(ratios(name, truth[1]))))
            for label, name in present:
                run_name = single[0][1] if name in ("PX4 script", "tempcal_IMU") else single[1][1]
                print("  %s %s: vs %s: pooled %s; gyrocomp on that run %s; true curve %s" % (
                    structure, sensor, label, fmt(ratios(pooled[1], name)), fmt(ratios(run_name, name)),
                    fmt(ratios(truth[1], name))))
            if best:
                bd = {r: best[r][0] for r in held}
                print("  %s %s: vs scripts' best: pooled %s; true curve %s" % (
                    structure, sensor, fmt(ratios(pooled[1], bd)), fmt(ratios(truth[1], bd))))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--fs", type=float, default=10.0)
    ap.add_argument("--px4-script")
    ap.add_argument("--pyulog", help="folder holding the pyulog package (needed: the held-out runs are read with it)")
    ap.add_argument("--tempcal")
    ap.add_argument("--pymavlink")
    ap.add_argument("--structures", default="dtemp,static")
    ap.add_argument("--runs", type=int, default=1,
                    help="also calibrate gyrocomp on 2..RUNS calibration runs of the board (other seeds, same "
                         "profile, -i repeated: the pooled fit)")
    ap.add_argument("--second-profile", choices=sorted(SECOND_PROFILES),
                    help="a second calibration run of the board with this profile: gyrocomp on it alone and "
                         "pooled with the first (-i run1 -i run2), each script on each run")
    ap.add_argument("--no-variants", action="store_true",
                    help="leave out the single-run --optimise-for / --static-weight rows (faster)")
    ap.add_argument("--pooled-conditions", default="steady",
                    help="with --second-profile: the pooled PX4 file also with --optimise-for C for each C of this "
                         "comma-separated list other than steady (steady, warm-up, both)")
    args = ap.parse_args()
    if args.pyulog:
        sys.path.insert(0, args.pyulog)
    gc = os.path.join(args.build, "gyrocomp")
    rows = {}   # (structure, sensor, run, set) -> list of per-seed arrays of 3 axes
    skipped = {}
    structures = args.structures.split(",")
    runs = list(PROFILES)
    variants = [[]] if args.no_variants else [[], ["--optimise-for", "warm-up"], ["--optimise-for", "both"],
                                              ["--static-weight", "time"], ["--static-weight", "temperature"]]
    with tempfile.TemporaryDirectory() as tmp:
        for structure in structures:
            for seed in range(1, args.seeds + 1):
                cal_ulg, cal_bin = os.path.join(tmp, "cal.ulg"), os.path.join(tmp, "cal.bin")
                simulate(gc, cal_ulg, 100 * seed, args.fs, structure)
                simulate(gc, cal_bin, 100 * seed, args.fs, structure)
                held = {}
                for k, name in enumerate(runs):
                    held[name] = os.path.join(tmp, "held_%s.ulg" % name)
                    simulate(gc, held[name], 100 * seed + 50 + 10 * k, args.fs, structure, name)
                sets = {}
                for fmt, log in (("px4", cal_ulg), ("ardupilot", cal_bin)):
                    for extra in variants:
                        if fmt == "ardupilot" and extra:
                            continue
                        sets["gyrocomp -> " + fmt + (" (%s)" % " ".join(extra) if extra else "")] = \
                            (fmt, calibrate(gc, [log], fmt, os.path.join(tmp, "gc_" + fmt), extra))
                # More calibration runs of the same board and profile (other seeds): calibrate -i ... -i ...,
                # one pooled fit (no --static-weight: the pooled fit has no weighting to choose).
                extra_cal = []
                for k in range(1, args.runs):
                    extra_cal.append(os.path.join(tmp, "cal%d.ulg" % k))
                    simulate(gc, extra_cal[-1], 100 * seed + 1000 * k, args.fs, structure)
                    sets["gyrocomp -> px4 (%d runs, pooled)" % (k + 1)] = (
                        "px4", calibrate(gc, [cal_ulg] + extra_cal, "px4", os.path.join(tmp, "gc_runs")))
                cal2 = None
                if args.second_profile:
                    cal2 = (os.path.join(tmp, "cal2.ulg"), os.path.join(tmp, "cal2.bin"))
                    for f in cal2:
                        simulate(gc, f, 100 * seed + SECOND_SEED, args.fs, structure, args.second_profile)
                    for fmt, k in (("px4", 0), ("ardupilot", 1)):
                        logs = ([cal_ulg, cal_bin][k], cal2[k])
                        sets["gyrocomp -> %s, run 2" % fmt] = (fmt, calibrate(gc, [logs[1]], fmt, os.path.join(tmp, "gc2")))
                        sets["gyrocomp -> %s, pooled" % fmt] = (fmt, calibrate(gc, list(logs), fmt, os.path.join(tmp, "gc12")))
                    for c in args.pooled_conditions.split(","):
                        if c != "steady":
                            sets["gyrocomp -> px4, pooled (--optimise-for %s)" % c] = (
                                "px4", calibrate(gc, [cal_ulg, cal2[0]], "px4", os.path.join(tmp, "gc12c"),
                                                 ["--optimise-for", c]))
                for suffix, ulg, binlog in [("", cal_ulg, cal_bin)] + ([(", run 2",) + cal2] if cal2 else []):
                    p, why = try_px4_script(args, ulg, tmp)
                    if p is None:
                        skipped["PX4 script" + suffix] = why
                    else:
                        sets["PX4 script" + suffix] = ("px4", p)
                    p, why = try_tempcal(args, binlog, tmp)
                    if p is None:
                        skipped["tempcal_IMU" + suffix] = why
                    else:
                        sets["tempcal_IMU" + suffix] = ("ardupilot", p)
                for name, path in held.items():
                    gyro, accel = read_imu(path)
                    for sensor, (temp, v), unit in (("gyro", gyro, 1.0 / RAD), ("accel", accel, 1.0)):
                        key = lambda s: (structure, sensor, name, s)
                        rows.setdefault(key("no correction"), []).append(score(v, 0 * v, args.fs, unit))
                        rows.setdefault(key("true static curve"), []).append(
                            score(v, truth_offsets(temp, sensor), args.fs, unit))
                        for sname, (fmt, p) in sets.items():
                            if fmt == "px4":
                                corr = px4_offsets(p, 0, temp, "G" if sensor == "gyro" else "A")
                            else:
                                corr = ardupilot_correction(p, 1, temp, "GYR" if sensor == "gyro" else "ACC")
                            rows.setdefault(key(sname), []).append(score(v, corr, args.fs, unit))
                print("done: %s seed %d" % (structure, seed), file=sys.stderr)
    print("Held-out residual after each parameter set: RMS of 10 s means, mean removed (gyro deg/s, accel m/s^2);"
          " mean over %d seeds x 3 axes, +- SD of the per-seed means" % args.seeds)
    for why_name, why in skipped.items():
        print("  %s skipped: %s" % (why_name, why))
    order = ["no correction", "PX4 script", "tempcal_IMU", "gyrocomp -> px4", "gyrocomp -> ardupilot",
             "gyrocomp -> px4 (--optimise-for warm-up)", "gyrocomp -> px4 (--optimise-for both)",
             "gyrocomp -> px4 (--static-weight time)", "gyrocomp -> px4 (--static-weight temperature)"] + \
        ["gyrocomp -> px4 (%d runs, pooled)" % k for k in range(2, args.runs + 1)] + \
        ["PX4 script, run 2", "tempcal_IMU, run 2", "gyrocomp -> px4, run 2", "gyrocomp -> ardupilot, run 2",
         "gyrocomp -> px4, pooled", "gyrocomp -> ardupilot, pooled"] + \
        ["gyrocomp -> px4, pooled (--optimise-for %s)" % c for c in args.pooled_conditions.split(",") if c != "steady"] + \
        ["true static curve"]
    names = [n for n in order if any(k[3] == n for k in rows)]
    for sensor in ("gyro", "accel"):
        print()
        print("| structure | %s parameter set | %s |" % (sensor, " | ".join(runs)))
        print("|---|---|" + "---|" * len(runs))
        for structure in structures:
            for n in names:
                cells = []
                for run_name in runs:
                    v = rows.get((structure, sensor, run_name, n))
                    per_seed = [x.mean() for x in v]
                    cells.append("%.3g +- %.2g" % (np.mean(per_seed), np.std(per_seed)))
                print("| %s | %s | %s |" % (structure, n, " | ".join(cells)))
        multi = [(sc, "gyrocomp -> px4 (%d runs, pooled)" % k) for sc in ("PX4 script", "tempcal_IMU")
                 for k in range(2, args.runs + 1)]
        for structure in structures:
            for script, mine in [("PX4 script", "gyrocomp -> px4"), ("tempcal_IMU", "gyrocomp -> ardupilot")] + multi:
                cells = []
                for run_name in runs:
                    a, b = rows.get((structure, sensor, run_name, mine)), rows.get((structure, sensor, run_name, script))
                    t = rows.get((structure, sensor, run_name, "true static curve"))
                    if a and b:
                        wins = sum(int(x < y) for xa, ya in zip(a, b) for x, y in zip(xa, ya))
                        ratio = np.mean([x.mean() for x in a]) / np.mean([x.mean() for x in b])
                        cells.append("%s %d/%d axes better, RMS ratio %.2f (true curve / script %.2f)" % (
                            run_name, wins, 3 * len(a), ratio, np.mean([x.mean() for x in t]) / np.mean([x.mean() for x in b])))
                if cells:
                    print("  %s %s, %s vs %s: %s" % (structure, sensor, mine, script, "; ".join(cells)))
        # The mean over the held-out heating and cooling runs, against the true curve's
        # and each script's; and the ratio in the scripts' own (heating) direction.
        for structure in structures:
            def hc(n, run_names=("heating", "cooling")):
                v = [rows.get((structure, sensor, r, n)) for r in run_names]
                return None if any(x is None for x in v) else np.mean([np.mean([x.mean() for x in a]) for a in v])
            true_hc = hc("true static curve")
            for n in names:
                if not n.startswith("gyrocomp -> px4") or "optimise" in n or ", run 2" in n or n.endswith(", pooled") \
                        or hc(n) is None:
                    continue
                parts = ["mean(heating, cooling) / true curve's %.3f" % (hc(n) / true_hc)]
                for script in ("PX4 script", "tempcal_IMU"):
                    if hc(script) is not None:
                        parts.append("/ %s %.3f (true / script %.3f; heating alone %.3f)" % (
                            script, hc(n) / hc(script), true_hc / hc(script),
                            hc(n, ("heating",)) / hc(script, ("heating",))))
                print("  %s %s, %s: %s" % (structure, sensor, n, ", ".join(parts)))
    if args.second_profile:
        print_second_profile(rows, structures, args.second_profile, args.pooled_conditions.split(","))


if __name__ == "__main__":
    main()
