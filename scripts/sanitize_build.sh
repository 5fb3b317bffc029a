#!/usr/bin/env bash
# The sanitizer build (build-asan): clang, AddressSanitizer + UndefinedBehaviorSanitizer, the
# library instrumented for libFuzzer too, so that one compile of the library serves the
# sanitizer test suite (scripts/test.sh --sanitize) and the fuzzers (scripts/fuzz.sh).
#   scripts/sanitize_build.sh [TARGET...]      no target: everything (tests, CLI, fuzzers)
# -O1 with line tables only (test code -O0, CMakeLists.txt): about half the compile time of a debug build on 2 cores, stack
# traces keep file:line, and assertions stay on (no NDEBUG). Benchmarks and the Python module are
# not built here (the Release build has them; an ASan runtime would have to be preloaded into python3).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${GYROCOMP_ASAN_BUILD_DIR:-build-asan}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=None -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_C_FLAGS="-O1 -gline-tables-only" -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" \
  -DGYROCOMP_FUZZ=ON -DGYROCOMP_BUILD_BENCHMARKS=OFF -DGYROCOMP_BUILD_PYTHON=OFF >/dev/null
if [ $# -eq 0 ]; then
  cmake --build "$build" -j"$(nproc)"
else
  cmake --build "$build" -j"$(nproc)" --target "$@"
fi
