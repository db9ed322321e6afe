#!/usr/bin/env bash
# Runs the unit tests once under AddressSanitizer + UndefinedBehaviorSanitizer in a
# Debug build (build-asan/). -O1 keeps the statistical render tests fast enough.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --no-build
log=$(mktemp)
trap 'rm -f "$log"' EXIT
if [ ! -f build-asan/CMakeCache.txt ]; then
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS=-O1 \
    -DPENUMBRA_SANITIZE=address,undefined -DPENUMBRA_BENCH=OFF >"$log" 2>&1 || { cat "$log"; exit 1; }
fi
cmake --build build-asan -j "$(nproc 2>/dev/null || echo 2)" >"$log" 2>&1 || { cat "$log"; exit 1; }
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
cd build-asan
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)"
