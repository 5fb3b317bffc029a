#!/usr/bin/env bash
# Builds the manual (MkDocs, --strict) with the C++ API reference (Doxygen over include/, a
# warning is an error) under it: build/site/index.html, build/site/api/index.html.
#   scripts/docs.sh            needs Debian's mkdocs and doxygen (scripts/install-deps.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
rm -rf build/api build/site
mkdir -p build
doxygen Doxyfile
mkdocs build --strict --quiet -d build/site
mkdir -p build/site/api && cp -r build/api/html/. build/site/api/
echo "docs: build/site/index.html, API reference build/site/api/index.html"
