#!/usr/bin/env bash
# The window's soak test (issue 25): a scripted window under Xvfb that makes camera moves
# (orbit drags, ten moves each, and dolly steps), live reloads (the script touches a copy of
# the scene file, as an editor saving it, and the viewer reads it again) and render-region
# changes (set, then cleared), while the window samples its resident memory twice a second
# and reads its exact peak (VmHWM) at the script's marks and when it closes.
# It prints and checks, against the issue's goals:
#   - the viewer exits 0 (no crash) with every reload and region change made;
#   - resident memory stays flat after warm-up: its peak after the warm-up (a full picture, the
#     first tenth of the events, a full picture again: the script's mark "warm") is at most
#     MAX_GROWTH % above its peak up to there;
#   - with --max-peak R: its peak over the whole run is at most R times its peak up to the
#     first full picture, before any event (the script's mark "start"): replaced methods are
#     freed at once, never piled up over a drag (off by default: a reload holds two scenes);
#   - no stall: the UI thread never went more than MAX_STALL ms without taking events.
# Usage: bench/soak.sh [SCENE] [--size WxH] [--moves 300] [--reloads 30] [--regions 30]
#          [--method bp] [--max-growth 5] [--max-stall 1000] [--max-peak 0] [--reload-wait 1]
#          [--out DIR]
#          [--penumbra build/penumbra]
#        bench/soak.sh --asset   (the asset scene at 1280x720, scripts/make_asset_scene.sh)
# Exits 0 on PASS, 1 on FAIL.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
scene=$root/scenes/cornell.json size=256x256 moves=300 reloads=30 regions=30 method=bp
growth=5 stall=1000 reload_wait=1 out="" penumbra=$root/build/penumbra peak=0
while [ $# -gt 0 ]; do
  case $1 in
    --asset) scene=$root/build/bench/asset_scene/scene.json size=1280x720 reload_wait=4; shift ;;
    --size) size=$2; shift 2 ;;
    --moves) moves=$2; shift 2 ;;
    --reloads) reloads=$2; shift 2 ;;
    --regions) regions=$2; shift 2 ;;
    --method) method=$2; shift 2 ;;
    --max-growth) growth=$2; shift 2 ;;
    --max-stall) stall=$2; shift 2 ;;
    --max-peak) peak=$2; shift 2 ;;
    --reload-wait) reload_wait=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --penumbra) penumbra=$2; shift 2 ;;
    *) scene=$(cd "$(dirname "$1")" && pwd)/$(basename "$1"); shift ;;
  esac
done
if [ "$scene" = "$root/build/bench/asset_scene/scene.json" ] && [ ! -f "$scene" ]; then
  (cd "$root" && scripts/make_asset_scene.sh >/dev/null)
fi
[ -f "$scene" ] || { echo "FAIL: no scene file $scene"; exit 1; }
command -v xvfb-run >/dev/null || { echo "FAIL: xvfb-run is not installed"; exit 1; }
if [ -z "$out" ]; then
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
fi
mkdir -p "$out/scene"
# The scene's copy, beside links to the files it names, so touching it leaves the original.
for f in "$(dirname "$scene")"/*; do
  [ "$f" = "$scene" ] || ln -sfn "$(cd "$(dirname "$f")" && pwd)/$(basename "$f")" "$out/scene/"
done
copy=$out/scene/$(basename "$scene")
rm -f "$copy"
cp "$scene" "$copy"
w=${size%x*} h=${size#*x}
python3 - "$out/script.txt" "$copy" "$w" "$h" "$moves" "$reloads" "$regions" "$reload_wait" <<'PY'
import sys
path, scene, w, h, moves, reloads, regions, reload_wait = sys.argv[1:]
w, h, moves, reloads, regions = int(w), int(h), int(moves), int(reloads), int(regions)
# The window shows the image at zoom 1 right of the panel (356 pixels): its centre on screen.
cx, cy = 356 + w // 2, h // 2
d = 40  # every step of a ten-step drag moves 4 pixels or more: a camera move each
events = []
left = moves
while left > 0:  # an orbit drag (ten moves) then, alternately, a dolly in or out (one move)
    if left >= 10:
        sign = 1 if len(events) % 2 == 0 else -1
        events.append("drag left %d %d %d %d" % (cx, cy, cx + sign * d, cy + d // 2))
        left -= 10
    else:
        events.append("scroll %d %d %d ctrl" % (1 if left % 2 else -1, cx, cy))
        left -= 1
other = []
for i in range(max(reloads, regions)):
    if i < reloads:
        other.append(["touch " + scene, "wait " + reload_wait])
    if i < regions:  # set a region (a different one each time), then clear it: two changes
        if i % 2 == 0:
            x, y = (i * 7) % max(1, w // 2), (i * 5) % max(1, h // 2)
            other.append(["region %d %d %d %d" % (x, y, max(1, w // 3), max(1, h // 3))])
        else:
            other.append(["region 0 0 0 0"])
# Warm-up: a full picture, then the first tenth of the events (every kind among them), then
# a full picture again; memory after it is compared with the peak up to there.
seq = []
a = b = 0
while a < len(events) or b < len(other):  # the reloads and regions spread among the moves
    if b >= len(other) or (a < len(events) and a * len(other) <= b * len(events)):
        seq.append([events[a]])
        a += 1
    else:
        seq.append(other[b])
        b += 1
warm = max(1, len(seq) // 10)
lines = ["wait-round 300", "wait 1", "mark start"]
for i, step in enumerate(seq):
    lines += step + ["wait 0.05"]
    if i + 1 == warm:
        lines += ["wait-round 300", "wait 1", "mark warm"]
lines += ["wait-round 300", "wait 1", "quit"]
open(path, "w").write("\n".join(lines) + "\n")
PY
# PENUMBRA_VIEW_ENV: variables for the viewer alone (a sanitizer build's), not for Xvfb.
read -r -a view_env <<<"${PENUMBRA_VIEW_ENV:-}"
start=$(date +%s.%N)
xvfb-run -a -s "-screen 0 1920x1080x24" env "${view_env[@]}" "$penumbra" view "$copy" --size "$size" --method "$method" \
  --script "$out/script.txt" --report "$out/report.json" >"$out/log.txt" 2>&1
status=$?
end=$(date +%s.%N)
python3 - "$out/report.json" "$status" "$moves" "$reloads" "$regions" "$growth" "$stall" \
  "$scene" "$size" "$method" "$start" "$end" "$peak" <<'PY'
import json, os, sys
path, status, moves, reloads, regions, growth, stall, scene, size, method, t0, t1, peak = sys.argv[1:]
peak = float(peak)
status, moves, reloads, regions = int(status), int(moves), int(reloads), int(regions)
growth, stall = float(growth), float(stall)
print("soak: %s at %s, %s: %d camera moves, %d reloads, %d region changes, %.0f s" %
      (scene, size, method, moves, reloads, regions, float(t1) - float(t0)))
fails = []
if status != 0:
    fails.append("the viewer exited with %d" % status)
if not os.path.exists(path):
    print("FAIL: no report (%s)" % "; ".join(fails or ["?"]))
    sys.exit(1)
r = json.load(open(path))
rss = [kib for _, kib in r["rss_kib"] if kib > 0]
if len(rss) < 10:
    fails.append("only %d memory samples" % len(rss))
warmAt = r.get("marks", {}).get("warm")
if warmAt is None:
    fails.append("the script did not reach the end of its warm-up")
    warmAt = 0
before = [kib for t, kib in r["rss_kib"] if kib > 0 and t <= warmAt] or [0]
after = [kib for t, kib in r["rss_kib"] if kib > 0 and t > warmAt] or [0]
first, last = max(before), max(after)
sampledGrowth = (last / first - 1) * 100 if first else float("inf")
# The peaks: exact (VmHWM at the marks and at the end, which only ever rises) where the report
# has them. Samples twice a second fall either side of a picture's short peak, so their growth
# moved by 15 points from run to run of one build.
peaks = r.get("peak_rss_kib_at_marks", {})
exact = "warm" in peaks and peaks["warm"] > 0 and r.get("peak_rss_kib", -1) > 0
if exact:
    first, last = peaks["warm"], r["peak_rss_kib"]
grew = (last / first - 1) * 100 if first else float("inf")
print("restarts %d, reloads %d (%d asked), frames %d, mean frame %.1f ms" %
      (r["restarts"], r["reloads"], reloads, r["frames"], r["mean_frame_ms"]))
print("resident memory: peak in the warm-up (to %.0f s) %.0f MiB, peak %s %.0f MiB, end %.0f MiB: "
      "growth %+.1f %% (goal <= %g %%)%s" %
      (warmAt, first / 1024, "over the whole run" if exact else "after it", last / 1024,
       after[-1] / 1024, grew, growth,
       "; in the samples twice a second %+.1f %%" % sampledGrowth if exact else ""))
startAt = r.get("marks", {}).get("start", 0)
still = max([kib for t, kib in r["rss_kib"] if kib > 0 and t <= startAt] or [1])
if exact and peaks.get("start", -1) > 0:
    still = peaks["start"]
ratio = max(first, last) / still
print("peak resident memory over the peak up to the first full picture, before any event: "
      "%.2fx%s" % (ratio, " (goal <= %g)" % peak if peak > 0 else ""))
if peak > 0 and ratio > peak:
    fails.append("resident memory peaked at %.2fx the first picture's" % ratio)
print("longest stall (UI thread busy without taking events): %.0f ms at %.1f s (goal <= %g ms)" %
      (r["longest_busy_ms"], r["longest_busy_at_seconds"], stall))
if r["reloads"] < reloads:
    fails.append("only %d of %d reloads happened" % (r["reloads"], reloads))
if r["restarts"] < moves:
    fails.append("only %d restarts for %d camera moves" % (r["restarts"], moves))
if grew > growth:
    fails.append("resident memory grew %.1f %% after warm-up" % grew)
if r["longest_busy_ms"] > stall:
    fails.append("a stall of %.0f ms" % r["longest_busy_ms"])
print("FAIL: " + "; ".join(fails) if fails else "PASS")
sys.exit(1 if fails else 0)
PY
