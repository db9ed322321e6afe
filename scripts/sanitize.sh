#!/usr/bin/env bash
# Runs the unit tests once under AddressSanitizer + UndefinedBehaviorSanitizer in a
# Debug build (build-asan/). -O1 keeps the statistical render tests fast enough.
# The viewer tests and the window test are part of it (see tests/CMakeLists.txt).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --no-build
source scripts/sanitized_build.sh
sanitized_build build-asan address,undefined
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
cd build-asan
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
