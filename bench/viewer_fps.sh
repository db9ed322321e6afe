#!/usr/bin/env bash
# The viewer's frame rate while it renders, on this machine's software GL (llvmpipe under
# Xvfb), measured in one run:
#   1. the window redrawing every frame (--continuous: the cost of a person dragging,
#      zooming or hovering the panel without pause) for SECONDS;
#   2. the same window left alone (it redraws only when a round lands) for SECONDS;
#   3. two orbit drags, each mouse step restarting rendering: restart to first picture.
# Prints the frame rate of (1) against the 60 fps goal and its 95th-percentile frame time,
# and how much rendering (kept spp reached) the continuous redraw costs against (2).
# Usage: bench/viewer_fps.sh [SCENE] [--size 512x512] [--seconds 10]
set -euo pipefail
cd "$(dirname "$0")/.."
scene=scenes/balls.json size=512x512 seconds=10
while [ $# -gt 0 ]; do
  case $1 in
    --size) size=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    *) scene=$1; shift ;;
  esac
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf 'wait %s\nquit\n' "$seconds" >"$work/script.txt"
run() {  # $1: report file, rest: extra flags
  local report=$1
  shift
  xvfb-run -a -s "-screen 0 1280x720x24" build/penumbra view "$scene" --size "$size" \
    --script "$work/script.txt" --report "$report" "$@" >/dev/null 2>&1
}
run "$work/continuous.json" --continuous
run "$work/idle.json"
# 3. camera moves: an orbit drag restarts rendering at every mouse step.
printf 'wait 2\ndrag left 400 300 600 320\nwait 1\ndrag left 600 320 400 300\nwait 1\nquit\n' >"$work/moves.txt"
xvfb-run -a -s "-screen 0 1280x720x24" build/penumbra view "$scene" --size "$size" \
  --script "$work/moves.txt" --report "$work/moves.json" >/dev/null 2>&1
python3 - "$work/continuous.json" "$work/idle.json" "$work/moves.json" "$scene" "$size" <<'PY'
import json, sys
c, i, c2 = (json.load(open(p)) for p in sys.argv[1:4])
print("scene %s, image %s, window redrawing every frame vs left alone, %.0f s each" %
      (sys.argv[4], sys.argv[5], c["wall_seconds"]))
print("frame rate           %6.1f fps   ratio %.2f of 60 (goal >= 1)" %
      (c["frames_per_second"], c["frames_per_second"] / 60))
print("frame time           mean %.1f ms, p95 %.1f ms, max %.1f ms" %
      (c["mean_frame_ms"], c["p95_frame_ms"], c["max_frame_ms"]))
print("first picture after a restart: mean %.0f ms, worst %.0f ms over %d restarts (goal ~100 ms)" %
      (c2["first_picture_ms_mean"], c2["first_picture_ms_max"], c2["first_pictures"]))
print("rendering progress   %.1f spp while redrawing, %.1f spp left alone: ratio %.2f" %
      (c["kept_spp"], i["kept_spp"], c["kept_spp"] / max(i["kept_spp"], 1e-9)))
PY
