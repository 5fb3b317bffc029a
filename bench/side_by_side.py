#!/usr/bin/env python3
"""Side-by-side timings of gyrocomp against the Python references: the vmdpy, antropy and
allantools rows of docs/explanation/performance.md.

    bench/side_by_side.py [--build build] [--vmdpy DIR] [--antropy DIR] [--allantools DIR]
                          [--repeat 3] [--quick] [--baseline OTHER_GYROCOMP]

Each reference is optional and is *not* a dependency of gyrocomp: give the directory of a
checkout (vmdpy: the folder holding vmdpy/vmdpy.py; antropy: the folder holding antropy/ or
src/antropy/; allantools: the folder holding allantools/). A reference that is not given or
does not import (numpy, scipy, numba, scikit-learn are needed; Debian: python3-numpy
python3-scipy python3-numba python3-sklearn) is skipped with a message.

Cases:
  VMD         N = 20,000, K = 6, alpha = 2000, tau = 0, tol = 1e-7, uniform init
              gyrocomp decompose (whole process: start-up, parsing, VMD, sample entropy of the
              modes, writing) vs vmdpy: whole process (python start-up, numpy import, reading
              the same CSV, VMD) and the VMD call alone.
  SampEn      N = 100,000, m = 2, r = 0.2 SD: gyrocomp entropy (whole process) vs
              antropy.sample_entropy (the call alone, after a warm-up call for numba's JIT).
  Allan       N = 1,000,000, octave taus, overlapping ADEV: gyrocomp allan (whole process) vs
              allantools.oadev (the call alone).
Wall-clock seconds, the minimum over --repeat runs; on a shared machine they are upper bounds.
gyrocomp's CPU time (user + system, the minimum over the runs) is printed beside its wall time:
the better estimate of its cost on a loaded machine. --baseline times another gyrocomp binary
(e.g. an earlier build) on the same inputs, its runs interleaved with this build's so that both
see the same load, and prints both side by side.
"""
import argparse
import math
import os
import random
import subprocess
import sys
import tempfile
import time


def gyro_like(n, seed):
    """White noise (ARW) plus a slow sine and a ramp: the VMD benchmark's signal."""
    rng = random.Random(seed)
    return [0.2 * math.sin(2 * math.pi * i / (0.7 * n)) + 0.01 * i / n + rng.gauss(0, 0.05) for i in range(n)]


def write_csv(path, name, x):
    with open(path, "w") as f:
        f.write(name + "\n")
        f.write("\n".join(repr(v) for v in x))
        f.write("\n")


def run_timed(cmd):
    """Wall and CPU (user + system) seconds of one run of cmd."""
    t = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t
    if os.waitstatus_to_exitcode(status) != 0:
        raise subprocess.CalledProcessError(os.waitstatus_to_exitcode(status), cmd)
    return wall, usage.ru_utime + usage.ru_stime


def best_wall(cmd, repeat, args=None):
    """Minimum wall and minimum CPU seconds over `repeat` runs of this build's command; with
    args.baseline, the same command with the baseline binary interleaved, stored in args.last_baseline."""
    best, cpu = float("inf"), float("inf")
    base, base_cpu = float("inf"), float("inf")
    for _ in range(repeat):
        w, c = run_timed(cmd)
        best, cpu = min(best, w), min(cpu, c)
        if args is not None and args.baseline:
            w, c = run_timed([args.baseline] + cmd[1:])
            base, base_cpu = min(base, w), min(base_cpu, c)
    if args is not None:
        args.last_cpu = cpu
        args.last_baseline = (base, base_cpu) if args.baseline else None
    return best


def cpu_row(args):
    """This build's CPU time of the case just timed, and the baseline's wall and CPU time."""
    line = f"{'':<34} gyrocomp CPU {args.last_cpu:.3f} s"
    if args.last_baseline:
        line += f";  baseline {args.baseline}: {args.last_baseline[0]:.3f} s wall, {args.last_baseline[1]:.3f} s CPU"
    print(line)


def best_call(fn, repeat):
    best = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def row(case, ours, theirs, what):
    ratio = theirs / ours if ours > 0 else float("nan")
    print(f"{case:<34} gyrocomp {ours:8.3f} s   {what:<34} {theirs:8.3f} s   {ratio:6.1f}x")


def vmd_case(args, tmp):
    n = 20000
    csv = os.path.join(tmp, "vmd.csv")
    write_csv(csv, "rate_dps", gyro_like(n, 1))
    ours = best_wall([args.gyrocomp, "decompose", "-i", csv, "--fs", "100", "--modes", "6", "--tol", "1e-7",
                      "-o", os.path.join(tmp, "modes.csv"), "--json", os.path.join(tmp, "d.json")], args.repeat, args)
    if not args.vmdpy:
        print(f"{'VMD N=20k K=6 (whole process)':<34} gyrocomp {ours:8.3f} s   vmdpy: skipped (no --vmdpy DIR)")
        cpu_row(args)
        return
    mod = os.path.join(args.vmdpy, "vmdpy")
    script = (
        "import sys, time; sys.path.insert(0, %r)\n"
        "import numpy as np; from vmdpy import VMD\n"
        "x = np.loadtxt(%r, skiprows=1)\n"
        "t = time.perf_counter(); u, _, w = VMD(x, 2000.0, 0.0, 6, 0, 1, 1e-7)\n"
        "print(time.perf_counter() - t)\n" % (mod, csv))
    try:
        subprocess.run([sys.executable, "-c", "import sys; sys.path.insert(0, %r); import numpy, vmdpy" % mod],
                       check=True, capture_output=True)
    except subprocess.CalledProcessError as e:
        print("%-34s gyrocomp %8.3f s   vmdpy: skipped (does not import: %s)"
              % ("VMD N=20k K=6 (whole process)", ours, e.stderr.decode().strip().splitlines()[-1]))
        cpu_row(args)
        return
    whole = float("inf")
    call = float("inf")
    for _ in range(args.repeat):
        t = time.perf_counter()
        out = subprocess.run([sys.executable, "-c", script], check=True, capture_output=True, text=True)
        whole = min(whole, time.perf_counter() - t)
        call = min(call, float(out.stdout.split()[-1]))
    row("VMD N=20k K=6 (whole process)", ours, whole, "vmdpy (whole process)")
    row("", ours, call, "vmdpy (VMD call alone)")
    cpu_row(args)


def entropy_case(args, tmp):
    n = 100000
    x = gyro_like(n, 2)
    csv = os.path.join(tmp, "se.csv")
    write_csv(csv, "x", x)
    ours = best_wall([args.gyrocomp, "entropy", "-i", csv, "--col", "x", "--m", "2", "--r", "0.2",
                      "--json", os.path.join(tmp, "se.json")], args.repeat, args)
    label = "SampEn N=100k m=2 (whole process)"
    if not args.antropy:
        print(f"{label:<34} gyrocomp {ours:8.3f} s   antropy: skipped (no --antropy DIR)")
        cpu_row(args)
        return
    for sub in ("src", ""):
        sys.path.insert(0, os.path.join(args.antropy, sub))
    try:
        import numpy as np
        import antropy
    except Exception as e:  # noqa: BLE001 - any import failure means: skip
        print(f"{label:<34} gyrocomp {ours:8.3f} s   antropy: skipped (does not import: {e})")
        cpu_row(args)
        return
    a = np.asarray(x)
    antropy.sample_entropy(a[:1000], order=2)  # numba JIT compile outside the timing
    theirs = best_call(lambda: antropy.sample_entropy(a, order=2), args.repeat)
    row(label, ours, theirs, "antropy.sample_entropy (call)")
    cpu_row(args)


def allan_case(args, tmp):
    n = 200000 if args.quick else 1000000
    x = gyro_like(n, 3)
    csv = os.path.join(tmp, "allan.csv")
    write_csv(csv, "rate_dps", x)
    ours = best_wall([args.gyrocomp, "allan", "-i", csv, "--fs", "100", "--taus", "octave",
                      "--json", os.path.join(tmp, "a.json")], args.repeat, args)
    label = f"Allan N={n // 1000}k octave (whole proc.)"
    if not args.allantools:
        print(f"{label:<34} gyrocomp {ours:8.3f} s   allantools: skipped (no --allantools DIR)")
        cpu_row(args)
        return
    sys.path.insert(0, args.allantools)
    try:
        import numpy as np
        import allantools
    except Exception as e:  # noqa: BLE001
        print(f"{label:<34} gyrocomp {ours:8.3f} s   allantools: skipped (does not import: {e})")
        cpu_row(args)
        return
    a = np.asarray(x)
    theirs = best_call(lambda: allantools.oadev(a, rate=100.0, data_type="freq", taus="octave"), args.repeat)
    row(label, ours, theirs, "allantools.oadev (call)")
    cpu_row(args)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build")
    p.add_argument("--vmdpy")
    p.add_argument("--antropy")
    p.add_argument("--allantools")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--quick", action="store_true", help="smaller Allan case")
    p.add_argument("--baseline", help="another gyrocomp binary to time on the same inputs (interleaved)")
    args = p.parse_args()
    args.gyrocomp = os.path.join(args.build, "gyrocomp")
    if not os.access(args.gyrocomp, os.X_OK):
        sys.exit(f"side_by_side.py: {args.gyrocomp} not built")
    if args.baseline and not os.access(args.baseline, os.X_OK):
        sys.exit(f"side_by_side.py: --baseline {args.baseline} is not an executable")
    cores = os.cpu_count()
    mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    load = os.getloadavg()[0]
    print(f"machine: {cores} cores, {mem:.0f} GiB, load average {load:.1f}; python {sys.version.split()[0]}; "
          f"{time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())}")
    with tempfile.TemporaryDirectory() as tmp:
        vmd_case(args, tmp)
        entropy_case(args, tmp)
        allan_case(args, tmp)


if __name__ == "__main__":
    main()
