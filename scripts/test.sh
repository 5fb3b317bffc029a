#!/usr/bin/env bash
# Quick start, command 2: install dependencies, build, and run the whole test suite.
#   --sanitize   build and test under AddressSanitizer + UndefinedBehaviorSanitizer instead
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--sanitize" ]; then
  scripts/install-deps.sh --browser
  scripts/sanitize_build.sh   # build-asan: clang, ASan + UBSan (the fuzzers share its library)
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1
  export GYROCOMP_SANITIZED=1
  # The longest tests stay with the Release suite (tests/sanitizer_skip.txt says which and why).
  skip=$(grep -v '^#' tests/sanitizer_skip.txt | grep . | paste -sd'|')
  ctest --test-dir build-asan --output-on-failure -j"$(nproc)" -E "$skip"
else
  scripts/install-deps.sh --browser
  # Debian's python3 (its numpy, pytest, pybind11), whatever python3 comes first on PATH.
  scripts/build.sh build -DGYROCOMP_BUILD_TESTS=ON -DGYROCOMP_BUILD_BENCHMARKS=ON \
    -DGYROCOMP_BUILD_PYTHON=ON -DPython_EXECUTABLE=/usr/bin/python3
  ctest --test-dir build --output-on-failure -j"$(nproc)"
fi
