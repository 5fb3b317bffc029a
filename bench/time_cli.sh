#!/usr/bin/env bash
# Times the gyrocomp CLI on realistic sizes (simulated chamber runs at 10 Hz and 100 Hz, and the
# ADIS16405 recordings when ../shared/realdata is present). Timings are wall-clock and CPU (user +
# system) on whatever machine runs this: report them with the machine (e.g. "2 cores, shared") or
# as ratios; on a loaded machine the CPU time is the better estimate of the cost.
#   bench/time_cli.sh [BUILD_DIR] [--long]     (--long adds the 100 Hz, ~5 M sample cases)
# `process` prints its stage timings (JSON timings_s) under its line; the VMD's share is shown
# apart because it is not the rest of the pipeline. A quick check of the CLI on every size; the
# figures the manual quotes come from the commands in docs/explanation/performance.md.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
long=0
[ "${2:-}" = "--long" ] && long=1
bin="$build/gyrocomp"
[ -x "$bin" ] || { echo "time_cli.sh: $bin not built (scripts/build.sh $build)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

t() {  # t LABEL CMD...: prints wall seconds, CPU seconds and peak RSS of one run
  local label="$1"; shift
  local out
  out=$( { /usr/bin/time -f "%e %U %S %M" "$@" >/dev/null 2>"$work/err"; } 2>&1 ) || {
    echo "FAILED: $label"; cat "$work/err"; return 1; }
  tail -n 1 "$work/err" | awk -v l="$label" \
    '{printf "%-48s %8.2f s wall %8.2f s CPU %8.0f MB\n", l, $1, $2 + $3, $4/1024}'
}

stages() {  # stages JSON: the stage timings of a `process` run, VMD apart
  python3 -c 'import json,sys; t=json.load(open(sys.argv[1]))["timings_s"]; v=t.get("vmd",0); tot=t.get("total",0)
print("    stages (s): " + ", ".join("%s %.2f" % (k, x) for k, x in sorted(t.items())) +
      "; pipeline without the VMD %.2f" % (tot - v))' "$1" 2>/dev/null || true
}

echo "machine: $(nproc) cores, $(awk '/MemTotal/{printf "%.0f GiB", $2/1048576}' /proc/meminfo); $(date -u +%FT%TZ)"
t "simulate paper profile 10 Hz"        "$bin" simulate --profile paper --fs 10 --seed 1 -o "$work/p10.csv"
t "allan octave, paper 10 Hz"           "$bin" allan -i "$work/p10.csv" --json "$work/a.json"
head -n 100001 "$work/p10.csv" > "$work/se100k.csv"
t "entropy N=100k (paper 10 Hz rate_dps)" "$bin" entropy -i "$work/se100k.csv" --col rate_dps
if "$bin" process --help >/dev/null 2>&1; then
  t "process paper 10 Hz"               "$bin" process -i "$work/p10.csv" -o "$work/o10.csv" --json "$work/o10.json"
  stages "$work/o10.json"
  help=$("$bin" process --help 2>&1 || true)  # (grep -q in a pipe would SIGPIPE it under pipefail)
  if [[ "$help" == *--threads* ]]; then
    t "process paper 10 Hz, --threads 1"  "$bin" process -i "$work/p10.csv" -o "$work/o10t1.csv" --json "$work/o10t1.json" --threads 1
    stages "$work/o10t1.json"
    cmp -s "$work/o10.csv" "$work/o10t1.csv" || echo "    WARNING: --threads 1 output differs"
  fi
fi
if [ "$long" = 1 ]; then
  t "simulate paper profile 100 Hz"     "$bin" simulate --profile paper --fs 100 --seed 1 -o "$work/p100.csv"
  t "allan octave, paper 100 Hz"        "$bin" allan -i "$work/p100.csv" --json "$work/a.json"
  if "$bin" process --help >/dev/null 2>&1; then
    t "process paper 100 Hz"            "$bin" process -i "$work/p100.csv" -o "$work/o100.csv" --json "$work/o100.json"
    stages "$work/o100.json"
  fi
fi
real=../shared/realdata/adis16405_run1.csv.gz
if [ -f "$real" ]; then
  t "allan ADIS16405 run1 (3 axes, 1M rows)" "$bin" allan -i "$real" --time-col t_s \
      --rate-col gx_dps,gy_dps,gz_dps --json "$work/adis.json"
fi
