#!/usr/bin/env bash
# Builds the libFuzzer harnesses of fuzz/ (clang, ASan + UBSan) and runs each for SECONDS
# (default 60) on a seed corpus made from tests/, ../shared/fieldlogs and a simulated log.
#   scripts/fuzz.sh [SECONDS] [FUZZER...]      e.g. scripts/fuzz.sh 300 fuzz_csv
# A crash leaves its input in build-fuzz/crashes/<fuzzer>/ and makes the script exit 1; keep it in
# fuzz/regressions/<fuzzer>/ (replayed by every run) and turn it into a regression test (src/io/io_fuzz_regression_test.cc; numeric harnesses: the stage's *_test.cc)
# before fixing it.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
build=${FUZZ_BUILD_DIR:-build-fuzz}
CC=${FUZZ_CC:-clang} CXX=${FUZZ_CXX:-clang++} cmake -S fuzz -B "$build" -DCMAKE_BUILD_TYPE=None >/dev/null
cmake --build "$build" -j"$(nproc)"

# Seeds: small CSVs (plain and gzip) from tests/ and the field logs' IMU extracts (first 200
# lines), model files from tests/golden, and the fuzzer's own corpus kept between runs.
seeds=$build/seeds
mkdir -p "$seeds"/csv "$seeds"/gz "$seeds"/model "$seeds"/ulog "$seeds"/dataflash "$seeds"/mcap "$seeds"/rosbag1
if [ ! -e "$seeds/.done" ]; then
  i=0
  while IFS= read -r f; do
    i=$((i + 1))
    head -c 65536 "$f" > "$seeds/csv/t$i.csv"
    gzip -c "$seeds/csv/t$i.csv" > "$seeds/gz/t$i.csv.gz"
  done < <(find tests ../shared/fieldlogs -name '*.csv' -size -8M 2>/dev/null | head -n 40)
  while IFS= read -r f; do
    i=$((i + 1))
    head -n 200 "$f" > "$seeds/csv/f$i.csv"
    gzip -c "$seeds/csv/f$i.csv" > "$seeds/gz/f$i.csv.gz"
  done < <(find ../shared/fieldlogs -name '*.csv' 2>/dev/null)
  # gz seeds carry the mode byte of fuzz_gz.cc (even: raw gzip bytes follow).
  for f in "$seeds"/gz/*.gz; do { printf '\0'; cat "$f"; } > "$f.seed" && mv "$f.seed" "$f"; done
  cp fuzz/seeds/model/*.json "$seeds/model/"  # made by gyrocomp fit (poly, poly in T and dT/dt, svr)
  # Flight logs: the first 64 KiB of each (-max_len), which keeps the headers and formats.
  for f in ../shared/fieldlogs/px4/*.ulg tests/fieldlogs/*.ulg; do
    [ -e "$f" ] && head -c 65536 "$f" > "$seeds/ulog/$(basename "$f")"
  done
  for f in ../shared/fieldlogs/ardupilot/*.bin ../shared/fieldlogs/ardupilot/*.BIN; do
    [ -e "$f" ] && head -c 65536 "$f" > "$seeds/dataflash/$(basename "$f")"
  done
  # ROS bags: a 0.2 s simulated IMU with temperature and a small image topic, as MCAP
  # (none / zstd / lz4 chunks) and ROS 1 (none / bz2 / lz4; needs python3-rosbag), plus
  # rosbag2's talker MCAP.
  if /usr/bin/python3 tests/bags/make_imu_bags.py "$seeds/bags" --seconds 0.2 --camera-bytes 64 >/dev/null 2>&1 ||
     /usr/bin/python3 tests/bags/make_imu_bags.py "$seeds/bags" --seconds 0.2 --camera-bytes 64 \
       --formats mcap,mcap-zstd,mcap-lz4 >/dev/null 2>&1; then
    cp "$seeds"/bags/*.mcap "$seeds/mcap/" 2>/dev/null || true
    cp "$seeds"/bags/*.bag "$seeds/rosbag1/" 2>/dev/null || true
  fi
  cp tests/bags/rosbag2/talker_mcap/talker.mcap "$seeds/mcap/"
  touch "$seeds/.done"
fi
# Record-level fuzzing of ULog / DataFlash (fuzz/fuzz_records.h): the originals each harness
# checks recovered rows against ($GYROCOMP_FUZZ_ORIGINALS, ids 1.. in name order; id 0 is the
# harness's built-in simulated log), and one tagged seed per original ("GCSEED", id, the log).
if [ ! -e "$seeds/.done_records" ]; then
  for kind in ulog dataflash; do
    mkdir -p "$seeds/originals/$kind"
    cp "$seeds/$kind"/* "$seeds/originals/$kind/" 2>/dev/null || true
    id=0
    printf 'GCSEED\x00' > "$seeds/$kind/tagged_0"
    for f in $(ls "$seeds/originals/$kind" | sort); do
      id=$((id + 1))
      { printf "GCSEED\\x$(printf %02x $id)"; cat "$seeds/originals/$kind/$f"; } > "$seeds/$kind/tagged_$id"
    done
  done
  touch "$seeds/.done_records"
fi
# Numeric harnesses (hostile numbers): one small seed per shape x stage mask (fuzz_numeric_support.h):
# length byte, shape byte, then bytes that the harness reads as decades, values and options.
if [ ! -e "$seeds/numeric/.done" ]; then
  mkdir -p "$seeds/numeric"
  for shape in 0 1 2 3 4 5 6 7 8 9; do
    for mask in 1 2 4 8 15; do
      printf "\\x01\\x00\\x$(printf %02x $((shape * 7 + 40)))\\x$(printf %02x $shape)\\x66\\x01\\x3f\\xf0\\x00\\x00\\x00\\x00\\x00\\x00\\x$(printf %02x $mask)\\x05\\x03\\x11\\x22\\x33\\x44" \
        > "$seeds/numeric/s${shape}_m$mask"
    done
  done
  touch "$seeds/numeric/.done"
fi

# rosbag2 sqlite3 seeds: the simulated IMU as a .db3 and rosbag2's talker (its -wal
# is empty: the .db3 holds every row).
if [ ! -e "$seeds/.done_ros2_sqlite" ]; then
  mkdir -p "$seeds/ros2_sqlite"
  /usr/bin/python3 tests/bags/make_imu_bags.py "$seeds/bags_db3" --seconds 0.2 --camera-bytes 64 --formats db3 \
    >/dev/null 2>&1 && cp "$seeds"/bags_db3/imu_db3/*.db3 "$seeds/ros2_sqlite/" || true
  cp tests/bags/rosbag2/talker_db3/talker.db3 "$seeds/ros2_sqlite/"
  # rosbag2 per-file compression: the same files zstd-compressed whole (.db3.zstd, .mcap.zstd).
  for f in "$seeds"/ros2_sqlite/*.db3 tests/bags/rosbag2/talker_mcap/talker.mcap; do
    case "$f" in *.db3) d=ros2_sqlite ;; *) d=mcap ;; esac
    zstd -q -c "$f" > "$seeds/$d/$(basename "$f").zstd" || true
  done
  touch "$seeds/.done_ros2_sqlite"
fi

declare -A corpus_of=([fuzz_csv]=csv [fuzz_gz]=gz [fuzz_ulog]=ulog [fuzz_dataflash]=dataflash [fuzz_model]=model
                      [fuzz_mcap]=mcap [fuzz_rosbag1]=rosbag1 [fuzz_numeric_stages]=numeric [fuzz_numeric_drift]=numeric)
fuzzers=("$@")
[ ${#fuzzers[@]} -eq 0 ] && fuzzers=(fuzz_csv fuzz_gz fuzz_ulog fuzz_dataflash fuzz_model fuzz_mcap fuzz_rosbag1
                                     fuzz_numeric_stages fuzz_numeric_drift)
corpus_of[fuzz_ros2_sqlite]=ros2_sqlite
[ $# -eq 0 ] && fuzzers+=(fuzz_ros2_sqlite)
status=0
for fz in "${fuzzers[@]}"; do
  corpus=$build/corpus/$fz
  crashes=$build/crashes/$fz
  mkdir -p "$corpus" "$crashes"
  echo "== $fz: $seconds s"
  # fuzz/regressions/<fuzzer>/: inputs that once crashed or broke the invariant, replayed first.
  regressions=()
  [ -d "fuzz/regressions/$fz" ] && regressions=("fuzz/regressions/$fz")
  case $fz in
    fuzz_ulog) export GYROCOMP_FUZZ_ORIGINALS=$(realpath "$seeds/originals/ulog") ;;
    fuzz_dataflash) export GYROCOMP_FUZZ_ORIGINALS=$(realpath "$seeds/originals/dataflash") ;;
    *) unset GYROCOMP_FUZZ_ORIGINALS ;;
  esac
  if ! "$build/$fz" "$corpus" "$seeds/${corpus_of[$fz]}" "${regressions[@]}" -max_total_time="$seconds" -rss_limit_mb=2048 \
      -max_len=65536 -timeout=10 -artifact_prefix="$crashes/" -print_final_stats=1 2>"$build/$fz.log"; then
    echo "$fz: FAILED, see $build/$fz.log and $crashes/" >&2
    tail -n 40 "$build/$fz.log" >&2
    status=1
  else
    grep -E "^stat::(number_of_executed_units|peak_rss_mb)|^#[0-9]+ +DONE" "$build/$fz.log" | tr '\n' ' '
    echo
  fi
done
exit $status
