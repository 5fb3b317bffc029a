#!/usr/bin/env bash
# What it measures: wall time and peak memory (RSS) of `gyrocomp calibrate` on 20 simulated flight
# logs of one 3-IMU board, 30 min each at 1 kHz (PX4 ULog, sensor_gyro + sensor_accel per IMU):
# every log read, the still detector run on it, one pooled cubic per sensor over all still rows.
# The logs come from bench/calibrate_flights_gen.cc (SimulateFlight + EncodeFlightULog), compiled
# here against the built library.
#
# How to run (after building the CLI: cmake --build build --target gyrocomp_cli):
#   bench/calibrate_flights.sh [BUILD_DIR=build] [WORK_DIR=/tmp/gyrocomp_calibrate_flights] [N=20]
# The logs take about 0.5 GB each on disk (kept in WORK_DIR for reruns; delete it afterwards).
# Prints /usr/bin/time -v's wall clock and maximum resident set size, and the summary.
set -euo pipefail
src="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-build}" && pwd)"
work="${2:-/tmp/gyrocomp_calibrate_flights}"
n="${3:-20}"
mkdir -p "$work"
if [ ! -x "$work/gen" ]; then
  c++ -std=c++20 -O2 -I"$src/include" "$src/bench/calibrate_flights_gen.cc" "$build/libgyrocomp.a" \
    -lfftw3 -lz -lsvm -lzstd -llz4 -lsqlite3 -lbz2 -o "$work/gen"
fi
if [ ! -f "$work/flight$((n - 1)).ulg" ]; then
  "$work/gen" "$work" "$n"
fi
inputs=()
for ((k = 0; k < n; ++k)); do inputs+=(-i "$work/flight$k.ulg"); done
du -ch "$work"/flight*.ulg | tail -1
/usr/bin/time -v -o "$work/time.txt" "$build/gyrocomp" calibrate "${inputs[@]}" --format px4 -o "$work/tc.params" \
  --json "$work/cal.json"
grep -E "Elapsed \(wall clock\)|Maximum resident set size" "$work/time.txt"
