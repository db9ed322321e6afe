#!/usr/bin/env bash
# The short soak (ctest viewer.soak): bench/soak.sh's scripted window with 40 camera moves, 5
# live reloads and 5 region changes on cornell at 512x512 with BP (about 20 s). It must exit 0
# with every reload and region change made, never stall the UI thread over 1 s, and keep its
# resident memory within 10 % of its peak in the warm-up. At this size one BP method's
# per-pixel state is about 55 MB, a fifth or more of the process (bench/soak.sh prints it), so
# a replaced method kept until the next picture shows, during a ten-move drag, as a rise well
# past 10 %, and one leaked per restart as several hundred percent; allocator and Mesa noise
# stay within a few percent.
# Usage: soak_test.sh PENUMBRA SOURCE_DIR OUTPUT_DIR
set -u
penumbra=$1 src=$2 out=$3
rm -rf "$out"
mkdir -p "$out"
bash "$src/bench/soak.sh" "$src/scenes/cornell.json" --size 512x512 --moves 40 --reloads 5 \
  --regions 5 --reload-wait 0.7 --max-growth 10 --max-stall 1000 --out "$out" \
  --penumbra "$penumbra"
status=$?
[ $status -eq 0 ] || tail -20 "$out/log.txt"
exit $status
