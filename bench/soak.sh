#!/usr/bin/env bash
# Soak: every subcommand of the built CLI over a long 3-axis 100 Hz log and a
# 1 kHz multi-IMU PX4 ULog, each run twice:
#   1. to the end, under /usr/bin/time: wall time, peak RSS, exit status (must be 0);
#   2. again into an empty folder, with SIGINT at a random moment in [0, wall time of run 1]
#      (seeded; the moment is printed): the exit must be 130 (or 0 when the command finished
#      first), never another signal or status >= 128, and the folder must hold nothing afterwards
#      (after 130: no output at all, no folder it made; after 0: no temporary '.*.tmp*').
# `compare` runs on a 1 Hz record of min(DURATION_S, 2 h) (it fits every model family several
# times); `demo`, `plan` and `simulate` make their own data.
# Prints a table (Markdown) and exits 1 on any violation: the table "Soak" of
# docs/explanation/performance.md (about 22 min for the default day-long log on 2 cores).
#
#   bench/soak.sh [DURATION_S] [ULOG_DURATION_S] [SEED]
#     DURATION_S       length of the 100 Hz log (default 86400: a day, 8.64 M rows)
#     ULOG_DURATION_S  length of the 1 kHz 3-IMU ULog (default 3600)
#     SEED             seed of the SIGINT moments (default 1); the logs use simulate's seed 1
# Environment: GYROCOMP (default build/gyrocomp), SOAK_DIR (default a fresh mktemp -d folder,
# removed at the end unless SOAK_KEEP=1).
set -euo pipefail
cd "$(dirname "$0")/.."
duration=${1:-86400}
ulog_duration=${2:-3600}
seed=${3:-1}
G=$(realpath "${GYROCOMP:-build/gyrocomp}")
[ -x "$G" ] || { echo "soak: $G is not built (scripts/build.sh)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "soak: /usr/bin/time is missing (apt-get install time)" >&2; exit 2; }
work=${SOAK_DIR:-$(mktemp -d /tmp/gyrocomp_soak_XXXXXX)}
mkdir -p "$work/in"
cleanup() { [ "${SOAK_KEEP:-0}" = 1 ] || rm -rf "$work"; }
trap cleanup EXIT

# ---- inputs -----------------------------------------------------------------------------------
# The 3-axis 100 Hz log: simulate writes one rate column to CSV, so the board's three axes come
# from a one-IMU ULog converted to CSV (x_rad_s, y_rad_s, z_rad_s, temp_c).
in=$work/in
echo "soak: inputs in $in: ${duration} s at 100 Hz (3 axes), ${ulog_duration} s at 1 kHz (3 IMUs)" >&2
"$G" simulate --fs 100 --duration "$duration" -o "$in/axes.ulg" >/dev/null
"$G" convert -i "$in/axes.ulg" -o "$in/axes.csv" >/dev/null
rm "$in/axes.ulg"
# The ULog heats from 25 to 60 C over its length (calibrate needs a temperature span).
ramp_c_per_min=$(awk -v d="$ulog_duration" 'BEGIN{printf "%.6g", 35 * 60 / d}')
"$G" simulate --fs 1000 --imus 3 --duration "$ulog_duration" --profile ramp --room-hold 0 --ramp-rate "$ramp_c_per_min" \
  --thermal-lag 10 -o "$in/imus.ulg" >/dev/null
# compare fits every model family (CS-SVR included) several times: a 1 Hz record of at most 2 h.
compare_duration=$((duration < 7200 ? duration : 7200))
"$G" simulate --fs 1 --duration "$compare_duration" -o "$in/other.csv" --seed 2 >/dev/null
rows=$(($(wc -l < "$in/axes.csv") - 1))
axes=(--rate-col x_rad_s,y_rad_s,z_rad_s --rate-unit rads)
"$G" fit -i "$in/axes.csv" "${axes[@]}" --model poly -o "$in/model.json" >/dev/null

# ---- the commands: name, then the arguments; OUT is replaced by the run's output folder ---------
commands=(
  "simulate|simulate --fs 100 --duration $duration -o OUT/sim.csv --json OUT/sim.json"
  "demo|demo --out OUT/demo"
  "inspect|inspect -i $in/imus.ulg --json OUT/inspect.json"
  "convert|convert -i $in/imus.ulg --instance 1 -o OUT/imu1.csv"
  "allan|allan -i $in/axes.csv ${axes[*]} -o OUT/allan.csv --json OUT/allan.json"
  "decompose|decompose -i $in/axes.csv ${axes[*]} -o OUT/modes.csv --json OUT/modes.json"
  "entropy|entropy -i $in/axes.csv --col x_rad_s --json OUT/entropy.json"
  "denoise|denoise -i $in/axes.csv ${axes[*]} --method wflp -o OUT/denoised.csv --json OUT/denoise.json"
  "fit|fit -i $in/axes.csv ${axes[*]} -o OUT/model.json --json OUT/fit.json"
  "apply|apply -i $in/axes.csv ${axes[*]} -m $in/model.json -o OUT/applied.csv"
  "export|export -m $in/model.json --format px4 --device-id 2293768 -o OUT/tc.params --json OUT/export.json"
  "validate|validate -i $in/axes.csv ${axes[*]} -m $in/model.json --json OUT/validate.json"
  "calibrate|calibrate -i $in/imus.ulg --format px4 -o OUT/cal.params --json OUT/cal.json"
  "plan|plan --seeds 1 --json OUT/plan.json"
  "process|process -i $in/axes.csv ${axes[*]} -o OUT/processed.csv --json OUT/process.json"
  "compare|compare -i $in/other.csv --json OUT/compare.json"
)

# Every subcommand of --help must be in the list (a new one is soaked, or this fails).
for c in $("$G" --help | awk '/^Subcommands:/{f=1;next} f&&NF{print $1}'); do
  printf '%s\n' "${commands[@]}" | grep -q "^$c|" || { echo "soak: subcommand '$c' is not in bench/soak.sh" >&2; exit 1; }
done

# Runs argv with SIGINT after DELAY s; prints "<returncode> <finished-before-signal>" where a
# negative returncode is death by that signal (Python's convention).
interrupt() {
  /usr/bin/python3 - "$@" <<'EOF'
import signal, subprocess, sys, time
delay, argv = float(sys.argv[1]), sys.argv[2:]
p = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
try:
    p.wait(timeout=delay)
    print(p.returncode, 1)
except subprocess.TimeoutExpired:
    p.send_signal(signal.SIGINT)
    print(p.wait(), 0)
EOF
}

RANDOM=$seed
status=0
printf '| subcommand | input | wall s | peak RSS MB | exit | SIGINT at s | exit after SIGINT | left in folder | ok |\n'
printf '|---|---|---:|---:|---:|---:|---:|---|---|\n'
for entry in "${commands[@]}"; do
  name=${entry%%|*}
  template=${entry#*|}
  out=$work/out_$name
  rm -rf "$out" && mkdir -p "$out"
  read -r -a args <<< "${template//OUT/$out}"
  # Run 1: to the end.
  set +e
  /usr/bin/time -f '%e %M' -o "$work/time.txt" "$G" "${args[@]}" >"$work/stdout.txt" 2>"$work/stderr.txt"
  code=$?
  set -e
  read -r wall rss_kb < <(tail -n 1 "$work/time.txt" | awk '{print $(NF-1), $NF}')
  rss_mb=$(awk -v k="$rss_kb" 'BEGIN{printf "%.0f", k/1024}')
  ok=yes
  if [ "$code" != 0 ]; then
    ok="no: exit $code: $(tail -n 1 "$work/stderr.txt")"
  elif find "$out" -name '.*.tmp*' | grep -q .; then
    ok="no: temporaries after a clean run"
  fi
  # Run 2: SIGINT at a random moment of run 1's wall time.
  rm -rf "$out" && mkdir -p "$out"
  at=$(awk -v w="$wall" -v r="$RANDOM" 'BEGIN{printf "%.3f", w * r / 32767}')
  read -r rc finished < <(interrupt "$at" "$G" "${args[@]}")
  left=$(cd "$out" && find . -mindepth 1 | sed 's|^\./||' | sort | tr '\n' ' ')
  if [ "$rc" = -2 ] && [ -z "$left" ]; then
    # SIGINT before main() installed its handler (the first milliseconds): the default action,
    # nothing written yet; a shell sees 130 as well.
    rc="130 (SIGINT before the handler)"
  elif [ "$rc" -lt 0 ]; then
    ok="no: killed by signal $((-rc)) after SIGINT"
  elif [ "$rc" = 130 ]; then
    [ -z "$left" ] || ok="no: left after SIGINT: $left"
  elif [ "$rc" = 0 ]; then
    echo "$left" | grep -q '\.tmp' && ok="no: temporaries left: $left"
    left="(finished first) ${left:0:60}"
  else
    ok="no: exit $rc after SIGINT"
  fi
  case $name in
    simulate|demo|plan) input="(none: simulated)" ;;
    inspect|convert|calibrate) input="imus.ulg" ;;
    export) input="model.json" ;;
    compare) input="other.csv (1 Hz, $compare_duration s)" ;;
    *) input="axes.csv" ;;
  esac
  printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$input" "$wall" "$rss_mb" "$code" "$at" "$rc" \
    "${left:-nothing}" "$ok"
  [ "$ok" = yes ] || status=1
done
echo
echo "inputs: axes.csv $rows rows (3 axes, 100 Hz, $(du -h "$in/axes.csv" | cut -f1)); imus.ulg ${ulog_duration} s at 1 kHz, 3 IMUs ($(du -h "$in/imus.ulg" | cut -f1)); other.csv $compare_duration s at 1 Hz; SIGINT seed $seed"
exit $status
