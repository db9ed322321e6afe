#!/usr/bin/env bash
# The GLFW window under Xvfb, driven by tests/viewer/app/window_script.txt: overlays, zoom, a
# pixel click, camera orbit, pan, dolly and fly (each restarts rendering), resizes (to zero
# too), minimise and restore, pause and step; it must exit 0, restart on every camera move,
# keep drawing, and write its screenshot.
# Usage: window_test.sh PENUMBRA SOURCE_DIR OUTPUT_DIR [extra view flags...]
set -u
penumbra=$1 src=$2 out=$3
shift 3
mkdir -p "$out"
command -v xvfb-run >/dev/null || { echo "FAIL: xvfb-run is not installed (scripts/setup.sh installs it)"; exit 1; }
rm -f "$out/window.png" "$out/report.json"
sed "s|SCREENSHOT|$out/window.png|" "$src/tests/viewer/app/window_script.txt" >"$out/script.txt"
# PENUMBRA_VIEW_ENV: variables for the viewer alone (the sanitizer build's), not for Xvfb.
read -r -a view_env <<<"${PENUMBRA_VIEW_ENV:-}"
xvfb-run -a -s "-screen 0 1280x720x24" env "${view_env[@]}" "$penumbra" view "$src/scenes/cornell.json" --size 128x128 \
  --script "$out/script.txt" --report "$out/report.json" "$@" >"$out/log.txt" 2>&1
status=$?
tail -5 "$out/log.txt"
failures=0
[ "$status" -eq 0 ] || { echo "FAIL: the viewer exited with $status (log: $out/log.txt)"; head -60 "$out/log.txt"; failures=$((failures + 1)); }
[ -s "$out/window.png" ] || { echo "FAIL: no screenshot at $out/window.png"; failures=$((failures + 1)); }
[ -s "$out/report.json" ] || { echo "FAIL: no report"; exit 1; }
field() { python3 -c "import json,sys; print(json.load(open('$out/report.json'))['$1'])"; }
restarts=$(field restarts) frames=$(field frames) round=$(field round)
echo "restarts $restarts, frames $frames, round $round"
# One start, plus the orbit drag, the camera pan drag, the dolly and the fly (several each).
[ "$restarts" -ge 5 ] || { echo "FAIL: camera moves restarted rendering only $restarts times"; failures=$((failures + 1)); }
[ "$frames" -ge 20 ] || { echo "FAIL: only $frames frames drawn"; failures=$((failures + 1)); }
[ "$round" -ge 1 ] || { echo "FAIL: no round finished after the last restart"; failures=$((failures + 1)); }
[ $failures -eq 0 ] && echo "window test passed"
[ $failures -eq 0 ]
