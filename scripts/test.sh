#!/usr/bin/env bash
# Quick start, command 2: install dependencies, build, and run the whole test suite.
#   --sanitize   build and test under AddressSanitizer + UndefinedBehaviorSanitizer instead
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--sanitize" ]; then
  scripts/install-deps.sh --browser
  # -O1 without debug info: about half the compile time of RelWithDebInfo on 2 cores, and
  # assertions stay on (no NDEBUG). Benchmarks are not built here (the Release run builds them).
  # The Python module is not built here: an ASan runtime would have to be preloaded into python3.
  CMAKE_BUILD_TYPE=None scripts/build.sh build-asan -DGYROCOMP_SANITIZE=ON \
    -DGYROCOMP_BUILD_BENCHMARKS=OFF -DGYROCOMP_BUILD_PYTHON=OFF -DCMAKE_CXX_FLAGS=-O1
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
  export GYROCOMP_SANITIZED=1
  ctest --test-dir build-asan --output-on-failure -j"$(nproc)"
else
  scripts/install-deps.sh --browser
  # Debian's python3 (its numpy, pytest, pybind11), whatever python3 comes first on PATH.
  scripts/build.sh build -DGYROCOMP_BUILD_TESTS=ON -DGYROCOMP_BUILD_BENCHMARKS=ON \
    -DGYROCOMP_BUILD_PYTHON=ON -DPython_EXECUTABLE=/usr/bin/python3
  ctest --test-dir build --output-on-failure -j"$(nproc)"
fi
