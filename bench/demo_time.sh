#!/bin/sh
# CPU and wall time of `gyrocomp demo` (the `demo` row of docs/explanation/performance.md), with its own
# per-phase split (summary.json demo_phases: process CPU of all threads / wall). Not a test:
# timings never decide a test. Extra arguments go to demo (e.g. --full-budget).
# Usage: G=build/gyrocomp D=/tmp/demo-time sh bench/demo_time.sh [demo options...]
set -e
G=${G:-gyrocomp}
D=${D:-/tmp/gyrocomp-demo-time}
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg) ($(nproc) cores)"
/usr/bin/time -f "demo $*: %e s wall, %U s user, %S s sys, %M KB peak" $G demo --out "$D" -q "$@" |
  grep -E "time by phase|reduced budgets|full search budgets" | awk '!seen[$0]++'
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
