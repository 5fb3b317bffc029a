#!/usr/bin/env bash
# Peak memory of each log reader per GB of input (docs/explanation/performance.md, "Reader
# memory"): generates one
# input per format (not committed), runs `gyrocomp allan` on it (the reader, the sampling check
# and an Allan curve: what every -i command pays to read) under /usr/bin/time, and prints a
# table of peak RSS, peak over the baseline (allan on a 3-row CSV) and MB per GB of file.
#   bench/reader_memory.sh [SECONDS=3400] [WORK_DIR=/tmp/gyrocomp_reader_memory]
# SECONDS: length of the ULog / DataFlash board at 1 kHz, 3 IMUs (3400 s: a ~1 GB ULog); the CSV
# is 2 M rows x 6 columns (3 kept: time, rate, temperature); the bags 1 h at 200 Hz
# (tests/bags/make_imu_bags.py; ROS 1 needs Debian's python3-rosbag, skipped without it).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-3400}
work=${2:-/tmp/gyrocomp_reader_memory}
bin=$(realpath "${GYROCOMP_BIN:-build/gyrocomp}")
mkdir -p "$work"

if [ ! -e "$work/big.csv" ]; then
  /usr/bin/python3 - "$work/big.csv" <<'EOF'
import sys
import numpy as np
n = 2_000_000
rng = np.random.default_rng(1)
t = np.arange(n) / 100.0
cols = [t, rng.normal(0, 0.01, n), 20 + 10 * np.sin(t / 5000)] + [rng.normal(size=n) for _ in range(3)]
with open(sys.argv[1], "w") as f:
    f.write("time_s,rate_dps,temp_c,a,b,c\n")
    np.savetxt(f, np.column_stack(cols), fmt=["%.2f", "%.6g", "%.5f", "%.6g", "%.6g", "%.6g"], delimiter=",")
EOF
  gzip -1 -k "$work/big.csv"
  printf 'time_s,rate_dps,temp_c\n0,1,20\n0.01,1,20\n0.02,1,20\n' > "$work/tiny.csv"
fi
[ -e "$work/big.ulg" ] || "$bin" simulate --fs 1000 --duration "$seconds" --imus 3 --seed 1 -o "$work/big.ulg" 2>/dev/null
[ -e "$work/big.bin" ] || "$bin" simulate --fs 1000 --duration "$seconds" --imus 3 --seed 1 -o "$work/big.bin" 2>/dev/null
if [ ! -e "$work/bags/imu.mcap" ]; then
  formats=mcap,db3
  /usr/bin/python3 -c "import rosbag" 2>/dev/null && formats=ros1,$formats
  /usr/bin/python3 tests/bags/make_imu_bags.py "$work/bags" --seconds 3600 --rate 200 --formats "$formats" >/dev/null
fi

peak_kb() {  # command... -> peak RSS in KB (exit status ignored: printed when not 0)
  local log="$work/time.txt"
  if ! /usr/bin/time -f '%M' -o "$log" "$@" >/dev/null 2>"$work/stderr.txt"; then
    echo "  (exit $?: $(head -c 200 "$work/stderr.txt"))" >&2
  fi
  tail -1 "$log"
}

base=$(peak_kb "$bin" allan -i "$work/tiny.csv" --json /dev/null)
printf 'baseline (allan on a 3-row CSV): %.1f MB\n\n' "$(echo "$base / 1024" | bc -l)"
printf '| reader | input | file MB | rows read | peak MB | peak - baseline, MB | MB per GB of file |\n|---|---|---|---|---|---|---|\n'
row() {  # label, file, rows, command...
  local label=$1 file=$2 rows=$3
  shift 3
  local kb size
  kb=$(peak_kb "$@")
  size=$(du -sbL "$file" | cut -f1)
  printf '| %s | `%s` | %.0f | %s | %.1f | %.1f | %.0f |\n' "$label" "$(basename "$file")" "$(echo "$size / 1000000" | bc -l)" \
    "$rows" "$(echo "$kb / 1024" | bc -l)" "$(echo "($kb - $base) / 1024" | bc -l)" \
    "$(echo "($kb - $base) / 1024 / ($size / 1000000000)" | bc -l)"
}
row CSV "$work/big.csv" "2 M x 3 of 6 columns" "$bin" allan -i "$work/big.csv" --json /dev/null
row CSV.gz "$work/big.csv.gz" "2 M x 3 of 6 columns" "$bin" allan -i "$work/big.csv.gz" --json /dev/null
row "CSV (stdin)" "$work/big.csv" "2 M x 3 of 6 columns" sh -c "\"$bin\" allan -i - --json /dev/null < \"$work/big.csv\""
row ULog "$work/big.ulg" "$seconds k x 1 of 3 gyros" "$bin" allan -i "$work/big.ulg" --instance 1 --json /dev/null
row "ULog convert" "$work/big.ulg" "$seconds k x 1 of 3 gyros" "$bin" convert -i "$work/big.ulg" --instance 1 -o "$work/conv.csv"
row DataFlash "$work/big.bin" "$seconds k x 1 of 3 IMUs" "$bin" allan -i "$work/big.bin" --instance 1 --json /dev/null
[ -e "$work/bags/imu.bag" ] && row "ROS 1 bag" "$work/bags/imu.bag" "720 k (6 axes)" "$bin" allan -i "$work/bags/imu.bag" --topic /imu0 --json /dev/null
row MCAP "$work/bags/imu.mcap" "720 k (6 axes)" "$bin" allan -i "$work/bags/imu.mcap" --topic /imu0 --json /dev/null
row "rosbag2 db3" "$work/bags/imu_db3" "720 k (6 axes)" "$bin" allan -i "$work/bags/imu_db3" --topic /imu0 --json /dev/null
