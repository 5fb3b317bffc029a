#!/usr/bin/env bash
# Side by side: gyrocomp and ori-drs/allan_variance_ros on the same simulated six-axis
# ROS 1 bag: wall and CPU time and peak memory (/usr/bin/time -v), and every noise figure (gyro
# and accelerometer noise density N and random walk K, per axis) next to the simulated truth.
#
#   bench/allan_variance_ros_side_by_side.sh AVR_BIN AVR_ANALYSIS_PY [AVR_CONFIG] \
#       [--hours 3] [--rate 200] [--work DIR] [--bag BAG] [--port 11377]
#
#   AVR_BIN          allan_variance_ros's `allan_variance` executable, built by you from its
#                    source (this repository never carries its code nor a recipe to fetch it; see
#                    docs/explanation/accuracy.md, "Allan deviation of a ROS bag", for how it was built)
#   AVR_ANALYSIS_PY  its scripts/analysis.py (the line fits that turn its ADEV CSV into figures)
#   AVR_CONFIG       its config yaml (imu_topic, imu_rate, measure_rate, sequence_time); written
#                    here for /imu0 at --rate when not given
#   --bag BAG        reuse a bag written by tests/bags/make_imu_bags.py (its default seed);
#                    otherwise one is written to WORK/bag (about 140-300 s for 3 h)
#
# allan_variance_ros is a ROS 1 node: it needs a ROS master even to read a bag, so one is started
# here on 127.0.0.1:PORT (Debian's python3-rosmaster) and stopped at the end by its process id.
# Reproduces the tables of docs/explanation/accuracy.md "Allan deviation of a ROS bag" (a few
# minutes for the 3 h bag, most of it allan_variance_ros).
# Needs: /usr/bin/time, python3 with numpy, scipy and matplotlib (analysis.py), rosmaster.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)

usage() { sed -n '2,23p' "$0" >&2; exit 2; }
[ $# -ge 2 ] || usage
avr_bin=$(realpath "$1"); avr_analysis=$(realpath "$2"); shift 2
avr_config=""
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then avr_config=$(realpath "$1"); shift; fi
hours=3; rate=200; work=/tmp/gyrocomp_avr_side_by_side; bag=""; port=11377
while [ $# -gt 0 ]; do
  case "$1" in
    --hours) hours=$2; shift 2 ;;
    --rate) rate=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --bag) bag=$(realpath "$2"); shift 2 ;;
    --port) port=$2; shift 2 ;;
    *) usage ;;
  esac
done
bin=$(realpath "${GYROCOMP_BIN:-build/gyrocomp}")
for f in "$avr_bin" "$avr_analysis" "$bin" /usr/bin/time; do
  [ -e "$f" ] || { echo "allan_variance_ros_side_by_side: $f: not found" >&2; exit 2; }
done
command -v rosmaster >/dev/null || { echo "allan_variance_ros_side_by_side: rosmaster not found (apt-get install python3-rosmaster)" >&2; exit 2; }
seconds=$(/usr/bin/python3 -c "print(int($hours * 3600))")
mkdir -p "$work"

if [ -z "$bag" ]; then
  bag=$work/bag/imu.bag
  if [ ! -e "$bag" ]; then
    echo "writing a ${hours} h ${rate} Hz ROS 1 bag to $work/bag ..."
    /usr/bin/time -f "  written in %e s" /usr/bin/python3 tests/bags/make_imu_bags.py "$work/bag" \
      --seconds "$seconds" --rate "$rate" --formats ros1
  fi
fi
if [ -z "$avr_config" ]; then
  avr_config=$work/avr_config.yaml
  # measure_rate = imu_rate: no subsampling; sequence_time covers the whole bag.
  printf 'imu_topic: "/imu0"\nimu_rate: %s\nmeasure_rate: %s\nsequence_time: %s\n' \
    "$rate" "$rate" "$seconds" >"$avr_config"
fi
ls -l "$bag"

# allan_variance_ros reads every *.bag of a folder (the first one) and writes allan_variance.csv
# into that folder: give it a folder holding only a link to the bag.
avr_dir=$work/avr
rm -rf "$avr_dir"; mkdir -p "$avr_dir"
ln -s "$bag" "$avr_dir/imu.bag"

export ROS_MASTER_URI=http://127.0.0.1:$port ROS_HOSTNAME=127.0.0.1 ROS_HOME=$work/ros_home
mkdir -p "$ROS_HOME"
rosmaster --core -p "$port" >"$work/rosmaster.log" 2>&1 &
master_pid=$!
trap 'kill "$master_pid" 2>/dev/null || true' EXIT
sleep 3

# Both read the bag from a warm page cache (whichever ran first would otherwise pay the disk).
cat "$bag" >/dev/null
echo "gyrocomp allan ..."
(cd "$work" && /usr/bin/time -v "$bin" allan -i "$bag" --topic /imu0 --kalibr-yaml "$work/imu_gyrocomp.yaml" \
  --json "$work/allan_gyrocomp.json" >"$work/gyrocomp.log" 2>"$work/time_gyrocomp.txt")
echo "allan_variance_ros allan_variance (ADEV CSV) ..."
(cd "$avr_dir" && /usr/bin/time -v "$avr_bin" "$avr_dir" "$avr_config" \
  >"$work/avr.log" 2>"$work/time_avr.txt")
echo "allan_variance_ros analysis.py (line fits; non-interactive matplotlib) ..."
(cd "$avr_dir" && MPLBACKEND=Agg /usr/bin/time -v /usr/bin/python3 "$avr_analysis" \
  --data "$avr_dir/allan_variance.csv" --config "$avr_config" --output "$work/imu_avr.yaml" \
  >"$work/avr_analysis.log" 2>"$work/time_avr_analysis.txt")

/usr/bin/python3 - "$work" "$repo/tests/bags/make_imu_bags.py" <<'EOF'
import json, math, re, sys
import numpy as np
from scipy.optimize import curve_fit

work, sim = sys.argv[1], open(sys.argv[2]).read()
# The simulated truth: make_imu_bags.py simulate() (continuous-time N and K).
truth = {}
for key in ("gyro_n, gyro_k", "acc_n, acc_k"):
    m = re.search(re.escape(key) + r"\s*=\s*([0-9.e+-]+),\s*([0-9.e+-]+)", sim)
    truth[key.split(",")[0][:-2]] = (float(m.group(1)), float(m.group(2)))

def time_v(path):
    t = open(path).read()
    get = lambda label: re.search(re.escape(label) + r": (.*)", t).group(1).strip()
    wall = get("Elapsed (wall clock) time (h:mm:ss or m:ss)").split(":")
    wall_s = sum(float(p) * 60 ** i for i, p in enumerate(reversed(wall)))
    return wall_s, float(get("User time (seconds)")) + float(get("System time (seconds)")), \
        int(get("Maximum resident set size (kbytes)")) / 1024

g = json.load(open(f"{work}/allan_gyrocomp.json"))
d2r = math.pi / 180
gc = {"gyro": [], "acc": []}
for ax in ("x", "y", "z"):
    a = g["axes"][f"{ax}_rad_s"]
    n = a["arw_deg_per_sqrt_h"] / 60 * d2r                     # deg/sqrt(h) -> rad/s/sqrt(Hz)
    k = a.get("rrw_deg_per_h_per_sqrt_h")
    gc["gyro"].append((n, None if k is None else k / 216000 * d2r))  # deg/h/sqrt(h) -> rad/s^2/sqrt(Hz)
    b = g["accel_axes"][f"{ax}_m_s2"]
    gc["acc"].append((b["noise_density_m_s2_per_sqrt_hz"], b.get("random_walk_m_s3_per_sqrt_hz")))

# allan_variance_ros: its CSV (tau, accel xyz ADEV m/s^2, gyro xyz ADEV deg/s) and analysis.py's
# fits, recomputed here at full precision with analysis.py's own get_intercept (it prints 5
# decimals only): N = the -1/2 line fitted to tau in [0.1, 10) s read at 1 s; K = the +1/2 line
# fitted to EVERY tau (0.1 .. 999.9 s) read at 3 s.
csv = np.loadtxt(f"{work}/avr/allan_variance.csv")
period = csv[:, 0]
def get_intercept(x, y, m, b):
    coeffs, _ = curve_fit(lambda x, m, b: m * x + b, np.log(x), np.log(y),
                          bounds=([m, -np.inf], [m + 0.001, np.inf]))
    return float(np.exp(np.poly1d(coeffs)(np.log(b))))
brk = np.where(period == 10)[0][0]
avr = {"gyro": [], "acc": []}
for i in range(3):
    for name, col, scale in (("acc", 1 + i, 1.0), ("gyro", 4 + i, d2r)):
        y = csv[:, col]
        avr[name].append((get_intercept(period[:brk], y[:brk], -0.5, 1.0) * scale,
                          get_intercept(period, y, 0.5, 3.0) * scale))
# Check against what analysis.py printed (5 decimals, deg/s/sqrt(s) for the gyro).
printed = open(f"{work}/avr_analysis.log").read()
for name, label_n, label_k, scale in (("acc", "Velocity Random Walk", "Accel Random Walk", 1.0),
                                      ("gyro", "Angle Random Walk", "Rate Random Walk", d2r)):
    for i, ax in enumerate("XYZ"):
        for label, val in ((label_n, avr[name][i][0]), (label_k, avr[name][i][1])):
            p = float(re.search(rf"{ax} {label}:\s*(-?[0-9.]+)", printed).group(1))
            assert abs(p - val / scale) <= 0.5e-5 + 1e-12, (ax, label, p, val / scale)

print()
print("| | wall (s) | CPU user+sys (s) | peak RSS (MB) |")
print("|---|---|---|---|")
rows = [("gyrocomp allan (bag -> ADEV, fits, imu.yaml)", "time_gyrocomp.txt"),
        ("allan_variance_ros allan_variance (bag -> ADEV CSV)", "time_avr.txt"),
        ("allan_variance_ros analysis.py (CSV -> fits, imu.yaml, 2 PNGs)", "time_avr_analysis.txt")]
times = {}
for label, f in rows:
    times[f] = time_v(f"{work}/{f}")
    print("| %s | %.2f | %.2f | %.1f |" % ((label,) + times[f]))
gw, gcpu, _ = times["time_gyrocomp.txt"]
aw, acpu, _ = times["time_avr.txt"]
print(f"\nallan_variance (C++ only) / gyrocomp: {aw / gw:.0f}x wall, {acpu / gcpu:.0f}x CPU")

print("\n| figure | axis | truth | gyrocomp | gyrocomp / truth | allan_variance_ros | avr / truth |")
print("|---|---|---|---|---|---|---|")
names = {("gyro", 0): "gyro N (rad/s/sqrt(Hz))", ("gyro", 1): "gyro K (rad/s^2/sqrt(Hz))",
         ("acc", 0): "accel N (m/s^2/sqrt(Hz))", ("acc", 1): "accel K (m/s^3/sqrt(Hz))"}
fmt = lambda v: "-" if v is None else f"{v:.4g}"
ratio = lambda v, t: "-" if v is None else f"{v / t:.3f}"
for sensor, j in (("gyro", 0), ("gyro", 1), ("acc", 0), ("acc", 1)):
    t = truth[sensor][j]
    for i, ax in enumerate("xyz"):
        gv, av = gc[sensor][i][j], avr[sensor][i][j]
        print(f"| {names[(sensor, j)]} | {ax} | {t:.4g} | {fmt(gv)} | {ratio(gv, t)} | {fmt(av)} | {ratio(av, t)} |")
print("\nKalibr files: " + f"{work}/imu_gyrocomp.yaml (gyrocomp), {work}/imu_avr.yaml (allan_variance_ros)")
EOF
