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
echo "check-install: consumer built against $tmp/prefix and ran"
