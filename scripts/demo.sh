#!/usr/bin/env bash
# Quick start, command 1: install dependencies, build, and run `gyrocomp demo`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh build -DGYROCOMP_BUILD_TESTS=OFF -DGYROCOMP_BUILD_BENCHMARKS=OFF
./build/gyrocomp demo --out "${1:-demo-out}"
