#!/usr/bin/env bash
# Fuzzes every file parser with libFuzzer (clang, ASan + UBSan), one target after the other,
# each for a bounded time, and prints the executions each ran. A crash, leak, sanitizer report
# or timeout fails the run and leaves the input under build-fuzz/artifacts/TARGET/.
#
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]
#   SECONDS_PER_TARGET  default 60; CI runs 20 (eight targets, two at a time: under 3 minutes in all)
#   TARGET              scene obj mtl ply gltf exr png pfm (default: all)
#   FUZZ_JOBS=N         run N targets at a time (default: the number of cores)
# Seeds: the shipped scenes, and small files of every format that build-fuzz/fuzz_seeds writes
# with the project's own writers. Each target's corpus grows in build-fuzz/corpus/TARGET/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene obj mtl ply gltf exr png pfm)
case "$seconds" in '' | *[!0-9]*) echo "fuzz.sh: SECONDS_PER_TARGET must be a whole number" >&2; exit 2 ;; esac
for t in "${targets[@]}"; do
  case "$t" in scene | obj | mtl | ply | gltf | exr | png | pfm) ;;
    *) echo "fuzz.sh: unknown target '$t' (scene obj mtl ply gltf exr png pfm)" >&2; exit 2 ;;
  esac
done

scripts/setup.sh --no-build
source scripts/sanitized_build.sh  # PENUMBRA_UNITY_FLAGS
log=$(mktemp)
trap 'rm -f "$log"' EXIT
if [ ! -f build-fuzz/CMakeCache.txt ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DPENUMBRA_FUZZ=ON -DPENUMBRA_BENCH=OFF "${PENUMBRA_UNITY_FLAGS[@]}" >"$log" 2>&1 || { cat "$log"; exit 1; }
fi
build_targets=(fuzz_seeds)
for t in "${targets[@]}"; do build_targets+=("${t}_fuzz"); done
cmake --build build-fuzz --target "${build_targets[@]}" -j "$(nproc 2>/dev/null || echo 2)" \
  >"$log" 2>&1 || { cat "$log"; exit 1; }

seeds=build-fuzz/seeds
rm -rf "$seeds"
build-fuzz/fuzz_seeds "$seeds" >/dev/null
mkdir -p "$seeds/scene"
cp scenes/*.json "$seeds/scene/"

jobs=${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 2)}
case "$jobs" in '' | *[!0-9]* | 0) echo "fuzz.sh: FUZZ_JOBS must be a positive number" >&2; exit 2 ;; esac

# One target: its corpus grows in build-fuzz/corpus/TARGET, its log is build-fuzz/TARGET.log.
run_target() {
  local t=$1 corpus=build-fuzz/corpus/$1 artifacts=build-fuzz/artifacts/$1
  mkdir -p "$corpus" "$artifacts"
  cp -n "$seeds/$t"/* "$corpus"/ 2>/dev/null || true
  "build-fuzz/${t}_fuzz" -max_total_time="$seconds" -max_len=8192 -rss_limit_mb=2048 \
    -timeout=20 -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" \
    >"build-fuzz/$t.log" 2>&1
}

echo "fuzzing ${targets[*]} for ${seconds}s each, $jobs at a time"
declare -A pids
running=0
for t in "${targets[@]}"; do
  run_target "$t" &
  pids[$t]=$!
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
failed=()
for t in "${targets[@]}"; do
  wait "${pids[$t]}" || failed+=("$t")
done

total=0
printf '%-6s %12s %10s\n' target executions "exec/s"
for t in "${targets[@]}"; do
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "build-fuzz/$t.log" | tail -n 1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "build-fuzz/$t.log" | tail -n 1)
  printf '%-6s %12s %10s\n' "$t" "${runs:-?}" "${rate:-?}"
  total=$((total + ${runs:-0}))
done
if [ ${#failed[@]} -gt 0 ]; then
  for t in "${failed[@]}"; do
    echo "fuzz.sh: $t failed; the input is under build-fuzz/artifacts/$t/, its log follows" >&2
    tail -n 60 "build-fuzz/$t.log" >&2
  done
  exit 1
fi
echo "total executions: $total, no crash"
