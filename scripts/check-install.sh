#!/usr/bin/env bash
# CI: installs the library from BUILD_DIR (default build) into a temporary prefix, then configures,
# builds and runs examples/consumer against it with find_package(gyrocomp), as a new user would.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${1:-build}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build_dir" --prefix "$tmp/prefix" >/dev/null
cmake -S examples/consumer -B "$tmp/consumer" -DCMAKE_PREFIX_PATH="$tmp/prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tmp/consumer" -j"$(nproc)" >/dev/null
"$tmp/consumer/consumer"
# The Python package, when the build has it: import it from the install prefix alone.
if [ -n "$(find "$tmp/prefix" -name '_core*.so' -print -quit)" ]; then
  pkg_dir=$(dirname "$(dirname "$(find "$tmp/prefix" -name '_core*.so' -print -quit)")")
  (cd "$tmp" && PYTHONPATH="$pkg_dir" /usr/bin/python3 -c \
    "import gyrocomp, numpy; r = gyrocomp.compute_allan(numpy.random.default_rng(1).standard_normal(1000), 10.0); print('check-install: python', gyrocomp.__version__, 'from', gyrocomp.__file__, r.terms.arw_deg_per_sqrt_h)")
fi
echo "check-install: consumer built against $tmp/prefix and ran"
