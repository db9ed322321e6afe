#!/usr/bin/env bash
# Sharded renders (docs/farm.md): `reference|render --shard K/N` then `merge` gives the
# unsharded render byte for byte, for 1 to 5 shards, any thread counts and any order of the
# parts; and a merge of parts that do not belong together, or of too few or too many, is an
# error that names the part and leaves no output file.
# Usage: shard_test.sh PENUMBRA SOURCE_DIR
set -u
penumbra=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
cornell="$src/scenes/cornell.json"

check() {
  local what=$1
  shift
  if "$@" >/dev/null 2>&1; then echo "ok: $what"; else echo "FAIL: $what"; failures=$((failures + 1)); fi
}

# expect_fail "description" "fragment" merge-arguments...: fails with the fragment, no output.
expect_fail() {
  local what=$1 fragment=$2
  shift 2
  rm -f "$work/bad.exr" "$work/bad_var.exr" "$work/bad.json"
  local err status
  err=$("$penumbra" merge "$@" -o "$work/bad.exr" 2>&1 >/dev/null)
  status=$?
  if [ "$status" -ne 1 ] || [[ "$err" != *"$fragment"* ]] || [ -e "$work/bad.exr" ] ||
    [ -e "$work/bad.json" ]; then
    echo "FAIL: $what (status $status): $err"
    failures=$((failures + 1))
  else
    echo "ok: $what"
  fi
}

# 80 x 72: 3 x 3 tiles, the last row and column cut short.
size=(--size 80x72)
"$penumbra" reference "$cornell" "${size[@]}" --spp 16 -o "$work/full.exr" -q
for n in 1 2 3 5; do
  parts=()
  for ((k = 0; k < n; k++)); do
    "$penumbra" reference "$cornell" "${size[@]}" --spp 16 --shard "$k/$n" --threads $((1 + k % 2)) \
      -o "$work/ref$n/part$k.exr" -q
    parts=("$work/ref$n/part$k.exr" "${parts[@]}")  # reversed: the order must not matter
  done
  "$penumbra" merge "${parts[@]}" -o "$work/ref$n/merged.exr" -q
  check "reference, $n shard(s): the image is byte for byte the unsharded one" \
    cmp "$work/full.exr" "$work/ref$n/merged.exr"
  check "reference, $n shard(s): so is its variance" \
    cmp "$work/full_var.exr" "$work/ref$n/merged_var.exr"
done
check "the merged record is the reference's" python3 -c '
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
keep = lambda r: {k: v for k, v in r.items() if k not in ("image", "variance", "time_seconds", "shards")}
assert keep(a) == keep(b), (keep(a), keep(b))
assert b["shards"] == 3' "$work/full.json" "$work/ref3/merged.json"

# render --shard (plain LD, any seed), the parts' records given instead of their images.
"$penumbra" render "$src/scenes/balls.json" --size 70x40 --spp 4 --seed 3 -o "$work/balls.exr" \
  --variance-out "$work/balls_var.exr" -q
for k in 0 1 2; do
  "$penumbra" render "$src/scenes/balls.json" --size 70x40 --spp 4 --seed 3 --shard "$k/3" \
    -o "$work/balls$k.exr" -q
done
"$penumbra" merge "$work/balls1.shard.json" "$work/balls2.exr" "$work/balls0.exr" \
  -o "$work/balls_merged.exr" -q
check "render, 3 shards: byte for byte" cmp "$work/balls.exr" "$work/balls_merged.exr"
check "render, 3 shards: variance too" cmp "$work/balls_var.exr" "$work/balls_merged_var.exr"

# Parts copied away from where they were rendered: found beside their records.
mkdir -p "$work/moved"
cp "$work/ref3/"part* "$work/moved/"
rm -rf "$work/ref3"
"$penumbra" merge "$work/moved/part0.exr" "$work/moved/part1.exr" "$work/moved/part2.exr" \
  -o "$work/moved/merged.exr" -q
check "parts moved to another folder still merge" cmp "$work/full.exr" "$work/moved/merged.exr"

r5="$work/ref5"
expect_fail "a missing shard" "missing shard(s) 1, 4 of 5" "$r5/part0.exr" "$r5/part2.exr" "$r5/part3.exr"
expect_fail "a shard given twice" "shard 2 is given twice" "$r5/part0.exr" "$r5/part1.exr" \
  "$r5/part2.exr" "$r5/part2.shard.json" "$r5/part3.exr" "$r5/part4.exr"
"$penumbra" reference "$cornell" "${size[@]}" --spp 16 --seed 7 --shard 1/5 -o "$work/seed7.exr" -q
expect_fail "a part with another seed" "seed7.shard.json: its settings" "$r5/part0.exr" \
  "$work/seed7.exr" "$r5/part2.exr" "$r5/part3.exr" "$r5/part4.exr"
"$penumbra" reference "$src/scenes/balls.json" "${size[@]}" --spp 16 --shard 1/5 -o "$work/balls_part.exr" -q
expect_fail "a part of another scene" "balls_part.shard.json: its scene" "$r5/part0.exr" \
  "$work/balls_part.exr" "$r5/part2.exr" "$r5/part3.exr" "$r5/part4.exr"
expect_fail "a part of another shard count" "part0.shard.json: its shard count differs" "$r5/part0.exr" \
  "$work/moved/part0.exr"
echo '{"kind": "something else"}' >"$work/junk.shard.json"
expect_fail "not a shard record" "junk.shard.json: not a shard record" "$work/junk.shard.json"
expect_fail "a part without its record" "nowhere.shard.json: cannot open" "$work/nowhere.exr"
cp "$r5/part1.shard.json" "$work/lost.shard.json"
sed -i 's/"image": ".*"/"image": "lost.exr"/' "$work/lost.shard.json"
expect_fail "a record whose image is gone" "'lost.exr' not found" "$r5/part0.exr" \
  "$work/lost.shard.json" "$r5/part2.exr" "$r5/part3.exr" "$r5/part4.exr"

if [ "$failures" -ne 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all shard checks passed"
