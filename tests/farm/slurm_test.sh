#!/usr/bin/env bash
# Integration test against a real Slurm (docs/farm.md): starts a one-node Slurm on localhost
# (scripts/farm/local_slurm.sh), plans a sharded reference of cornell (64x64, 256 spp, 4
# shards), submits it as a job array with its dependent merge job (scripts/farm/submit_slurm.sh),
# waits, and compares the merged reference byte for byte with the unsharded one. A task run a
# second time (as a retry would) changes nothing. Every wait is bounded; a failure prints the
# Slurm and job logs. Needs root and `scripts/setup.sh --farm`; .ci/run runs it.
# Usage: tests/farm/slurm_test.sh PENUMBRA SOURCE_DIR
set -u
penumbra=$(realpath "$1")
src=$(realpath "$2")
work=$(mktemp -d)
slurm="$work/slurm"
cleanup() {
  "$src/scripts/farm/local_slurm.sh" stop "$slurm" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $1"
  for log in "$slurm"/log/*.log "$work"/plan/logs/*.out; do
    [ -f "$log" ] && { echo "---- $log"; tail -n 30 "$log"; }
  done
  exit 1
}

started=$("$src/scripts/farm/local_slurm.sh" start "$slurm") || fail "Slurm did not start"
eval "$started"  # export SLURM_CONF=...
echo "ok: a one-node Slurm is up ($(sinfo -h -o '%P %T %D'))"

args=("$src/scenes/cornell.json" --size 64x64 --spp 256)
"$penumbra" reference "${args[@]}" --plan "$work/plan" --shards 4 -o "$work/farm/ref.exr" -q ||
  fail "planning"
[ "$(wc -l <"$work/plan/tasks.txt")" -eq 4 ] || fail "the plan has not 4 tasks"
read -r array finish < <("$src/scripts/farm/submit_slurm.sh" "$work/plan") || fail "sbatch"
echo "ok: submitted the array $array and the merge $finish"

# Wait (at most 180 s) until both jobs have left the queue, then ask how the merge ended.
deadline=$((SECONDS + 180))
while squeue -h -j "$array,$finish" 2>/dev/null | grep -q .; do
  [ $SECONDS -lt $deadline ] || fail "the jobs did not finish within 180 s: $(squeue)"
  sleep 0.5
done
state=$(scontrol show job "$finish" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -n 1)
[ "$state" = JobState=COMPLETED ] || fail "the merge job ended as '$state'"
echo "ok: the array and the merge completed"

"$penumbra" reference "${args[@]}" -o "$work/single/ref.exr" -q || fail "the unsharded reference"
cmp "$work/single/ref.exr" "$work/farm/ref.exr" || fail "the merged reference differs"
cmp "$work/single/ref_var.exr" "$work/farm/ref_var.exr" || fail "its variance differs"
echo "ok: the merged reference equals the unsharded one byte for byte"

# A retried task rewrites its part atomically; the merge is unchanged.
bash -c "$(sed -n 2p "$work/plan/tasks.txt")" || fail "re-running task 1"
bash -c "$(cat "$work/plan/finish.txt")" >/dev/null || fail "re-running the merge"
cmp "$work/single/ref.exr" "$work/farm/ref.exr" || fail "a retried task changed the reference"
echo "ok: a retried task changes nothing"
echo "all Slurm checks passed"
