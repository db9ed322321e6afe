#!/usr/bin/env bash
# `compare --plan` / `--collect` (docs/farm.md): the tasks of a plan, run one by one in any
# order (as a job array would), and the collect give the report of a local compare with the
# same arguments: the same images byte for byte, the same numbers, only the measured times
# differ. A missing task is an error naming its command; an equal-time report names the nodes.
# Usage: compare_farm_test.sh PENUMBRA SOURCE_DIR
set -u
penumbra=$(realpath "$1")
src=$(realpath "$2")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
check() {
  local what=$1
  shift
  if "$@"; then echo "ok: $what"; else echo "FAIL: $what"; failures=$((failures + 1)); fi
}

cornell="$src/scenes/cornell.json"
"$penumbra" reference "$cornell" --size 32x32 --spp 256 -o "$work/ref.exr" -q
args=(compare "$cornell" --size 32x32 --spp 8 --methods ld,gem,bp:tuned --seeds 2
  --reference ../ref.exr --out report -q)
mkdir -p "$work/local" "$work/farm"
(cd "$work/local" && "$penumbra" "${args[@]}")
(cd "$work/farm" && "$penumbra" "${args[@]}" --plan plan)
check "the plan has one task per method and seed" test "$(wc -l <"$work/farm/plan/tasks.txt")" -eq 6
# The tasks from another folder, last first (a farm runs them anywhere, in any order).
tac "$work/farm/plan/tasks.txt" | while IFS= read -r line; do (cd / && bash -c "$line"); done
(cd / && bash -c "$(cat "$work/farm/plan/finish.txt")") >/dev/null

same_images() {
  local f
  for f in $(cd "$work/local/report/images" && ls); do
    cmp -s "$work/local/report/images/$f" "$work/farm/report/images/$f" || { echo "  $f differs"; return 1; }
  done
  [ "$(ls "$work/local/report/images" | wc -l)" -eq "$(ls "$work/farm/report/images" | wc -l)" ]
}
check "every image of the report is byte for byte the local one" same_images
check "results.json, report.md and report.html are the local ones but for the times" python3 - \
  "$work/local/report" "$work/farm/report" <<'PY'
import json, re, sys
a, b = sys.argv[1:3]
TIMES = ("seconds", "trace", "train", "select", "reconstruct", "network")
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if k not in TIMES}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
ra, rb = (strip(json.load(open(f"{d}/results.json"))) for d in (a, b))
assert ra == rb, "results.json differs"
time = re.compile(r'\d[\d.e+-]* ?(ms|s)\b( ± [\d.e+-]+| <span class="sd">± [\d.e+-]+</span>)?')
# Which time is the best is a measured time too.
best = re.compile(r'<td class="best">([^<]*\bT\b[^<]*)</td>')
# The time-to-quality charts place their points by time: left out, their numbers are in the
# tables that stay.
charts = re.compile(r'<svg class="chart curve".*?</svg>', re.S)
for name in ("report.md", "report.html"):
    ta, tb = (best.sub(r"<td>\1</td>", time.sub("T", charts.sub("", open(f"{d}/{name}").read())))
              for d in (a, b))
    if ta != tb:
        at = next(i for i, (x, y) in enumerate(zip(ta, tb)) if x != y)
        sys.exit(f"{name} differs at {at}: {ta[at - 80:at + 80]!r} vs {tb[at - 80:at + 80]!r}")
PY

# A task that has not run: the collect names it and its command, and writes no report.
mkdir -p "$work/missing"
(cd "$work/missing" && "$penumbra" "${args[@]}" --plan plan)
(cd "$work/missing" && sed '3d' plan/tasks.txt | while IFS= read -r line; do bash -c "$line"; done)
err=$(cd "$work/missing" && bash -c "$(cat plan/finish.txt)" 2>&1 >/dev/null)
check "a missing task is named with its command line" \
  bash -c '[[ "$1" == *"runs/2/task.json: missing: task 2 (gem, seed 1)"*"line 3 of"* ]]' _ "$err"
check "and no report is written" test ! -e "$work/missing/report/report.html"
err=$("$penumbra" compare "$cornell" --size 8x8 --methods ld --out "$work/x" --plan "$work/p" 2>&1)
check "a plan needs a reference" bash -c '[ $1 -ne 0 ] && [[ "$2" == *"--plan needs --reference"* ]]' \
  _ $? "$err"

# Equal time: the report says on which nodes the runs were made.
mkdir -p "$work/time"
"$penumbra" reference "$cornell" --size 16x16 --spp 16 -o "$work/ref16.exr" -q
(cd "$work/time" && "$penumbra" compare "$cornell" --size 16x16 --methods ld --seeds 1 \
  --equal-time 0.05 --no-curve --reference ../ref16.exr --out report -q --plan plan &&
  bash -c "$(cat plan/tasks.txt)" && bash -c "$(cat plan/finish.txt)" >/dev/null)
check "an equal-time report names the nodes" grep -q "equal time (0.1 s per run), on $(hostname)" \
  "$work/time/report/report.md"

if [ "$failures" -ne 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all compare --plan/--collect checks passed"
