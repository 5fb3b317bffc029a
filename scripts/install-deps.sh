#!/usr/bin/env bash
# Installs what gyrocomp needs to build, test and write its report, from Debian 12 packages and
# the npm registry. Idempotent: safe to run again. Run as root (or with sudo).
#   --browser   also install Debian's chromium (used by the report's headless-browser test)
#   --allan-variance-ros   also the Debian ROS 1 / ROS 2 headers needed to build ori-drs/allan_variance_ros
#               outside catkin, and rosmaster / scipy / matplotlib to run it, for
#               bench/allan_variance_ros_side_by_side.sh (docs/guides/imu-noise.md; not needed by CI)
set -euo pipefail
cd "$(dirname "$0")/.."

want_browser=0
want_avr=0
for arg in "$@"; do
  case "$arg" in
    --browser) want_browser=1 ;;
    --allan-variance-ros) want_avr=1 ;;
    *) echo "install-deps.sh: unknown option $arg" >&2; exit 2 ;;
  esac
done

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

packages=(
  build-essential cmake pkg-config
  libfftw3-dev libeigen3-dev libsvm-dev zlib1g-dev
  libcli11-dev nlohmann-json3-dev
  libzstd-dev liblz4-dev libsqlite3-dev libbz2-dev  # ROS bag readers (MCAP, rosbag2 sqlite3, ROS 1)
  zstd lz4  # CLI compressors tests/bags/make_imu_bags.py and scripts/fuzz.sh use for MCAP chunks and .zstd seeds
  python3-rosbag python3-sensor-msgs python3-roslz4  # ROS 1 bags written / read back by the bag tests (independent reference)
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-dev python3-numpy python3-pytest pybind11-dev python3-distributed
  clang libclang-rt-14-dev  # libFuzzer for fuzz/ (scripts/fuzz.sh)
  mkdocs doxygen  # the manual and its C++ API reference (scripts/docs.sh)
  ccache  # rebuilds after a clean or a fresh clone take seconds
)
command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)
if [ "$want_browser" = 1 ]; then packages+=(chromium); fi
if [ "$want_avr" = 1 ]; then
  packages+=(libroscpp-dev librosbag-dev libsensor-msgs-dev libyaml-cpp-dev libboost-filesystem-dev pluginlib-dev
             libclass-loader-dev librcpputils-dev librcutils-dev libament-index-cpp-dev libroslib-dev libtinyxml2-dev
             python3-rosmaster python3-scipy python3-matplotlib python3-yaml)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install-deps: Debian packages already installed"
fi

# The charting library bundled into the HTML report (fetched here, at build time; never a CDN).
if [ ! -f src/report/web/node_modules/uplot/dist/uPlot.iife.min.js ]; then
  echo "install-deps: fetching report assets (npm ci in src/report/web/)"
  (cd src/report/web && npm ci --no-audit --no-fund --loglevel=error)
fi
