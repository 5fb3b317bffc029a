#!/usr/bin/env bash
# Builds the libFuzzer harnesses of fuzz/ in the sanitizer build (build-asan: clang, ASan + UBSan;
# scripts/sanitize_build.sh) and runs each for SECONDS (default 60), as many at once as there
# are cores, on a seed corpus made from tests/, ../shared/fieldlogs and a simulated log.
#   scripts/fuzz.sh [SECONDS] [FUZZER...]      e.g. scripts/fuzz.sh 300 fuzz_csv
# A crash leaves its input in build-asan/fuzz-work/crashes/<fuzzer>/ and makes the script exit 1; keep it in
# fuzz/regressions/<fuzzer>/ (replayed by every run) and turn it into a regression test (readers: src/io/log_recovery_test.cc and the reader's
# *_test.cc; numeric harnesses: the stage's *_test.cc)
# before fixing it.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
asan=${GYROCOMP_ASAN_BUILD_DIR:-build-asan}
scripts/sanitize_build.sh fuzzers
bin=$asan/fuzz
build=$asan/fuzz-work  # seeds, corpora, crashes and logs

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
# One harness: its corpus, then the seeds and fuzz/regressions/<fuzzer>/ (inputs that once crashed
# or broke the invariant, replayed first). Output goes to $build/<fuzzer>.log.
run_one() {
  local fz=$1 corpus=$build/corpus/$1 crashes=$build/crashes/$1 regressions=()
  mkdir -p "$corpus" "$crashes"
  [ -d "fuzz/regressions/$fz" ] && regressions=("fuzz/regressions/$fz")
  local originals=
  case $fz in
    fuzz_ulog) originals=$(realpath "$seeds/originals/ulog") ;;
    fuzz_dataflash) originals=$(realpath "$seeds/originals/dataflash") ;;
  esac
  GYROCOMP_FUZZ_ORIGINALS=$originals "$bin/$fz" "$corpus" "$seeds/${corpus_of[$fz]}" "${regressions[@]}" \
    -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=65536 -timeout=10 -artifact_prefix="$crashes/" \
    -print_final_stats=1 >"$build/$fz.log" 2>&1
  echo $? >"$build/$fz.rc"
}
# Run them nproc at a time; report each in the order given.
jobs_max=$(nproc)
for fz in "${fuzzers[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do wait -n || true; done
  echo "== $fz: $seconds s"
  rm -f "$build/$fz.rc"
  (set +e; run_one "$fz") &
done
wait
status=0
for fz in "${fuzzers[@]}"; do
  if [ "$(cat "$build/$fz.rc" 2>/dev/null)" != 0 ]; then
    echo "$fz: FAILED, see $build/$fz.log and $build/crashes/$fz/" >&2
    tail -n 40 "$build/$fz.log" >&2
    status=1
  else
    echo "$fz: $(grep -E "^stat::(number_of_executed_units|peak_rss_mb)" "$build/$fz.log" | tr -s ' ' | tr '\n' ' ')"
  fi
done
exit $status
