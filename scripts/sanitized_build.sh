#!/usr/bin/env bash
# Configures (once) and builds a Debug -O1 tree with the given sanitizers, quietly; shows the
# whole log on failure. Sourced by sanitize.sh and tsan.sh.
# Usage: sanitized_build DIR SANITIZERS [TARGET]
sanitized_build() {
  local dir=$1 sanitizers=$2 target=${3:-all} log
  log=$(mktemp)
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS=-O1 \
      -DPENUMBRA_SANITIZE="$sanitizers" -DPENUMBRA_BENCH=OFF >"$log" 2>&1 || { cat "$log"; rm -f "$log"; return 1; }
  fi
  cmake --build "$dir" -j "$(nproc 2>/dev/null || echo 2)" --target "$target" >"$log" 2>&1 || { cat "$log"; rm -f "$log"; return 1; }
  rm -f "$log"
}
