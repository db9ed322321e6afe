#!/usr/bin/env bash
# Measures a sharded reference on the one-node Slurm against a plain local run (docs/farm.md):
# the wall time from submitting the plan to the merge's end, for 1, 2 and 4 shards, each
# merged reference checked byte for byte against the local one; then the parts of the cost
# a cluster's scaling depends on: one task's start-up (a shard with almost no samples) and the
# merge of 4, 16 and 64 parts. Needs root and scripts/setup.sh --farm.
# Usage: scripts/farm/measure_local.sh [SCENE] [SPP] [SIZE]   (default cornell, 1024, 256)
set -euo pipefail
cd "$(dirname "$0")/../.."
scene=${1:-scenes/cornell.json}
spp=${2:-1024}
size=${3:-256}
penumbra=$(pwd)/build/penumbra
work=$(mktemp -d /tmp/penumbra-measure.XXXXXX)
trap 'scripts/farm/local_slurm.sh stop "$work/slurm" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
eval "$(scripts/farm/local_slurm.sh start "$work/slurm")"
args=("$scene" --spp "$spp" --size "${size}x${size}")
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.2f", b - a }'; }

start=$(now)
"$penumbra" reference "${args[@]}" -o "$work/local/ref.exr" -q
echo "local, plain reference: $(since "$start") s"
for shards in 1 2 4; do
  start=$(now)
  "$penumbra" reference "${args[@]}" -o "$work/farm$shards/ref.exr" --plan "$work/plan$shards" \
    --shards "$shards" -q
  read -r array finish < <(scripts/farm/submit_slurm.sh "$work/plan$shards")
  deadline=$((SECONDS + 3600))
  while squeue -h -j "$array,$finish" | grep -q .; do
    [ $SECONDS -lt $deadline ] || { echo "timed out" >&2; exit 1; }
    sleep 0.2
  done
  took=$(since "$start")
  cmp -s "$work/local/ref.exr" "$work/farm$shards/ref.exr" && same="byte for byte equal" ||
    same="DIFFERENT"
  echo "Slurm, $shards shard(s): $took s (plan, submit, tasks, merge), $same"
done

start=$(now)
"$penumbra" reference "$scene" --spp 1 --size "${size}x${size}" --shard 0/64 -o "$work/tiny.exr" -q
echo "one task's start-up (scene, BVH, a 1-spp shard of 64): $(since "$start") s"
for parts in 4 16 64; do
  for ((k = 0; k < parts; k++)); do
    "$penumbra" reference "$scene" --spp 1 --size "${size}x${size}" --shard "$k/$parts" \
      -o "$work/m$parts/p$k.exr" -q
  done
  start=$(now)
  "$penumbra" merge "$work/m$parts"/*.shard.json -o "$work/m$parts/merged.exr" -q
  echo "merge of $parts parts (${size}x${size}): $(since "$start") s"
done
