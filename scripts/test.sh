#!/usr/bin/env bash
# Quick start, command 2: install dependencies, build, and run the whole test suite.
#   --sanitize   build and test under AddressSanitizer + UndefinedBehaviorSanitizer instead
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--sanitize" ]; then
  scripts/install-deps.sh --browser
  # -O1 without debug info: about half the compile time of RelWithDebInfo on 2 cores, and
  # assertions stay on (no NDEBUG). Benchmarks are not built here (the Release run builds them).
  CMAKE_BUILD_TYPE=None scripts/build.sh build-asan -DGYROCOMP_SANITIZE=ON \
    -DGYROCOMP_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_FLAGS=-O1
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
  export GYROCOMP_SANITIZED=1
  ctest --test-dir build-asan --output-on-failure -j"$(nproc)"
else
  scripts/install-deps.sh --browser
  scripts/build.sh build -DGYROCOMP_BUILD_TESTS=ON -DGYROCOMP_BUILD_BENCHMARKS=ON
  ctest --test-dir build --output-on-failure -j"$(nproc)"
fi
