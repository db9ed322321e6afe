#!/usr/bin/env bash
# Configures (once) and builds a Debug -O1 tree with the given sanitizers, quietly; shows the
# whole log on failure. Sourced by sanitize.sh, tsan.sh and fuzz.sh.
#
# These trees are built as unity builds: CMake compiles each target's sources in batches of 16
# files, so the heavy headers (GoogleTest, nlohmann/json, oneTBB, GLM) are parsed once per batch
# instead of once per file. On 2 cores that takes the ASan build from about 15 minutes to about
# 5. The Release tree (scripts/setup.sh) is a unity build too but for its engine libraries
# (engine/CMakeLists.txt): about 3.7 minutes instead of 7.5, the same images byte for byte. A
# unity build needs every file's internal names to be distinct from the other files' of its
# target; shared helpers live in headers (tests/test_paths.h, core/constants.h).
PENUMBRA_UNITY_FLAGS=(-DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16)
# Usage: sanitized_build DIR SANITIZERS [TARGET]
sanitized_build() {
  local dir=$1 sanitizers=$2 target=${3:-all} log
  log=$(mktemp)
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS=-O1 \
      -DPENUMBRA_SANITIZE="$sanitizers" -DPENUMBRA_BENCH=OFF "${PENUMBRA_UNITY_FLAGS[@]}" >"$log" 2>&1 || { cat "$log"; rm -f "$log"; return 1; }
  fi
  cmake --build "$dir" -j "$(nproc 2>/dev/null || echo 2)" --target "$target" >"$log" 2>&1 || { cat "$log"; rm -f "$log"; return 1; }
  rm -f "$log"
}
