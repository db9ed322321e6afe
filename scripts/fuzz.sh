#!/usr/bin/env bash
# Fuzzes the scene parser with libFuzzer (clang, ASan + UBSan) for a bounded time.
# Usage: scripts/fuzz.sh [SECONDS]   (default 60). Seeds: the shipped scenes.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
scripts/setup.sh --no-build
log=$(mktemp)
trap 'rm -f "$log"' EXIT
if [ ! -f build-fuzz/CMakeCache.txt ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DPENUMBRA_FUZZ=ON -DPENUMBRA_BENCH=OFF >"$log" 2>&1 || { cat "$log"; exit 1; }
fi
cmake --build build-fuzz --target scene_fuzz -j "$(nproc 2>/dev/null || echo 2)" >"$log" 2>&1 || { cat "$log"; exit 1; }
corpus=build-fuzz/corpus
mkdir -p "$corpus"
cp scenes/*.json "$corpus"/
echo "fuzzing the scene parser for ${seconds}s"
build-fuzz/scene_fuzz -max_total_time="$seconds" -max_len=8192 -rss_limit_mb=2048 -timeout=20 \
  -print_final_stats=1 "$corpus" 2>&1 | tail -n 12
