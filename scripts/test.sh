#!/usr/bin/env bash
# Builds (via setup.sh) and runs every test: unit, statistical, image and CLI tests.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cd build
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
