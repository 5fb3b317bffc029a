#!/usr/bin/env bash
# Times `gyrocomp allan -i BAG --topic /imu0 --kalibr-yaml` on a simulated six-axis IMU bag,
# with /usr/bin/time -v (wall time, peak RSS), for a ROS 1 bag (Debian's
# python3-rosbag) and MCAP (zstd chunks), and the memory check: the same IMU with a camera topic
# of ten times the IMU's bytes must read in about the same memory.
#   bench/bag_allan_bench.sh [HOURS=3] [RATE_HZ=200] [WORK_DIR=/tmp/gyrocomp_bag_bench]
# The bags are written by tests/bags/make_imu_bags.py (minutes for 3 h: ~2.2 M messages).
# Reproduces the table "Reading ROS bags" of docs/explanation/performance.md.
set -euo pipefail
cd "$(dirname "$0")/.."
hours=${1:-3}
rate=${2:-200}
work=${3:-/tmp/gyrocomp_bag_bench}
bin=${GYROCOMP_BIN:-build/gyrocomp}
seconds=$(/usr/bin/python3 -c "print(int($hours * 3600))")
mkdir -p "$work"

if [ ! -e "$work/big/imu.bag" ]; then
  echo "writing a ${hours} h ${rate} Hz bag (ROS 1 + MCAP zstd) to $work/big ..."
  /usr/bin/time -f "  written in %e s" /usr/bin/python3 tests/bags/make_imu_bags.py "$work/big" \
    --seconds "$seconds" --rate "$rate" --formats ros1,mcap-zstd
fi
ls -l "$work/big"

run() {  # label, input
  local log="$work/time_$1.txt"
  /usr/bin/time -v "$bin" allan -i "$2" --topic /imu0 --kalibr-yaml "$work/imu_$1.yaml" --json "$work/allan_$1.json" \
    >/dev/null 2>"$log"
  printf '%-28s wall %8s s   peak RSS %8s MB\n' "$1" \
    "$(awk -F': ' '/Elapsed \(wall clock\)/{print $2}' "$log")" \
    "$(awk -F': ' '/Maximum resident set size/{printf "%.1f", $2 / 1024}' "$log")"
}
run "ros1_${hours}h" "$work/big/imu.bag"
run "mcap_zstd_${hours}h" "$work/big/imu_zstd.mcap"

# Memory follows the IMU rows: 10 minutes of IMU alone, and with a camera topic of ten times
# the IMU's bytes (one 36 kB image per 10 IMU messages of ~365 bytes each).
if [ ! -e "$work/cam/imu.mcap" ]; then
  /usr/bin/python3 tests/bags/make_imu_bags.py "$work/imu10" --seconds 600 --rate "$rate" --formats ros1,mcap
  /usr/bin/python3 tests/bags/make_imu_bags.py "$work/cam" --seconds 600 --rate "$rate" --formats ros1,mcap \
    --camera-bytes 36000
fi
ls -l "$work/imu10" "$work/cam"
run ros1_imu_only_10min "$work/imu10/imu.bag"
run ros1_with_camera_10min "$work/cam/imu.bag"
run mcap_imu_only_10min "$work/imu10/imu.mcap"
run mcap_with_camera_10min "$work/cam/imu.mcap"
