#!/usr/bin/env bash
# Submits a plan (a folder written by `penumbra reference --plan DIR --shards N`, docs/farm.md)
# to Slurm: its tasks as one job array, and its finish.txt as a job that runs once every task
# succeeded. Prints the two job ids ("ARRAY FINISH") and writes them to DIR/jobs.txt; the jobs'
# logs go to DIR/logs/.
# Usage: scripts/farm/submit_slurm.sh PLAN_DIR [sbatch options for both jobs, e.g. -p batch]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
[ $# -ge 1 ] || { echo "usage: submit_slurm.sh PLAN_DIR [sbatch options...]" >&2; exit 2; }
plan=$(cd "$1" && pwd)
shift
[ -f "$plan/tasks.txt" ] && [ -f "$plan/finish.txt" ] ||
  { echo "submit_slurm: $plan has no tasks.txt and finish.txt (not a plan)" >&2; exit 2; }
count=$(grep -c . "$plan/tasks.txt" || true)
[ "$count" -ge 1 ] || { echo "submit_slurm: $plan/tasks.txt is empty" >&2; exit 2; }
mkdir -p "$plan/logs"
array=$(sbatch --parsable --array="0-$((count - 1))" --output="$plan/logs/task_%a.out" \
  --export="ALL,PENUMBRA_PLAN=$plan" "$@" "$here/slurm_task.sbatch")
array=${array%%;*}
finish=$(sbatch --parsable --dependency="afterok:$array" --kill-on-invalid-dep=yes \
  --output="$plan/logs/finish.out" --export="ALL,PENUMBRA_PLAN=$plan" "$@" \
  "$here/slurm_finish.sbatch")
finish=${finish%%;*}
echo "$array $finish" >"$plan/jobs.txt"
echo "$array $finish"
