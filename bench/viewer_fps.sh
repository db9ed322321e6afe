#!/usr/bin/env bash
# The viewer's frame rate while it renders, on this machine's software GL (llvmpipe under
# Xvfb), measured in one run:
#   1. the window redrawing every frame (--continuous: the cost of a person dragging,
#      zooming or hovering the panel without pause) for SECONDS;
#   2. the same window left alone (it redraws only when a round lands) for SECONDS;
#   3. two orbit drags, each mouse step restarting rendering: restart to first picture.
# Prints the frame rate of (1) against the 60 fps goal and its 95th-percentile frame time,
# and how much rendering (kept spp reached) the continuous redraw costs against (2).
#
# With --asset: the asset scene (scripts/make_asset_scene.sh: textures, 510k triangles, an
# environment map) at 1280x720, opened in the window with the default method and with LD.
# Prints, for each: the time from a camera move to the first full picture (every pixel sampled,
# reconstructed; in a window of its own, without the saves), the window's trace speed against a batch render's (kept samples per second),
# and the shown picture's relMSE against an LD render of REF_SPP (default 64) at 0.5, 1, 2 and
# 4 s, and the reference's own noise: half the relMSE between it and a second reference of
# another seed. A figure near that floor is not resolved (raise REF_SPP, or give a reference
# rendered once as REF_EXR, with its own relMSE as REF_FLOOR). The references take seeds 2 and 1,
# not the windows' 0, whose samples they would otherwise share. BP_FLAGS (say
# "--coarse-recon-spp 4") go to the default method's batch render and window.
# With --asset --glb: the same for the asset's .glb opened directly (no floor, no set: lit by
# the default environment), as an artist opens a model. With --asset --on SCENE: the same for
# another scene at 1280x720.
#
# With --trace-speed: the asset scene at 1280x720 with LD (or --method M), the window's trace
# speed (kept spp over the method's own seconds at its newest picture shown, the report's
# trace_spp_per_second)
# against a batch render's (spp / time_seconds, measured the same way), left alone for SECONDS
# (default 30) and while the user pans the image (a scripted middle-button drag, back and forth,
# DRAGS times, default 40; rendering goes on under it), each with the window's frame pacing and
# without it
# (PENUMBRA_FRAME_PACING=off: any change drawn at up to 60 fps, as before the pacing), in one run.
# The batch render is of 4 spp with LD and 16 with any other method, whose adaptive rounds
# would otherwise not have started (its time includes one reconstruction, as the window's).
# Usage: bench/viewer_fps.sh [SCENE] [--size 512x512] [--seconds 10]
#        bench/viewer_fps.sh --asset [--glb | --on SCENE]
#        bench/viewer_fps.sh --trace-speed [--seconds 30] [--drags 40] [--method ld|bp|...]
set -euo pipefail
cd "$(dirname "$0")/.."
scene=scenes/balls.json size=512x512 seconds=10 asset=0 glb=0 on= speed=0 drags=40 method=ld
while [ $# -gt 0 ]; do
  case $1 in
    --trace-speed) speed=1; seconds=30; shift ;;
    --drags) drags=$2; shift 2 ;;
    --method) method=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --asset) asset=1; shift ;;
    --glb) glb=1; shift ;;
    --on) on=$2; shift 2 ;;
    *) scene=$1; shift ;;
  esac
done
if [ $speed -eq 1 ]; then
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  scene=build/bench/asset_scene/scene.json size=1280x720
  [ -f "$scene" ] || scripts/make_asset_scene.sh >/dev/null
  batch_spp=16
  [ "$method" = ld ] && batch_spp=4
  build/penumbra render "$scene" --method "$method" --spp $batch_spp --size $size -q \
    -o "$work/batch.exr" --stats "$work/batch.json" 2>/dev/null
  printf 'wait %s\nquit\n' "$seconds" >"$work/idle.txt"
  for i in $(seq "$drags"); do
    printf 'drag middle 700 400 900 450\ndrag middle 900 450 700 400\n'
  done >"$work/drag.txt"
  echo quit >>"$work/drag.txt"
  for pacing in off on; do
    for phase in idle drag; do
      PENUMBRA_FRAME_PACING=$pacing xvfb-run -a -s "-screen 0 1640x800x24" build/penumbra view \
        "$scene" --size $size --method "$method" --script "$work/$phase.txt" \
        --report "$work/${phase}_$pacing.json" >/dev/null 2>&1
    done
  done
  python3 - "$work" "$scene" "$size" "$method" <<'PY'
import json, os, sys
w = sys.argv[1]
b = json.load(open(os.path.join(w, "batch.json")))
batch = b["spp"] / max(b["time_seconds"], 1e-9)
print("%s at %s, %s: batch render %.3f spp/s (%d spp in %.1f s)" %
      (sys.argv[2], sys.argv[3], sys.argv[4], batch, b["spp"], b["time_seconds"]))
print("window            pacing   trace spp/s   x batch   frames   mean frame   seconds   (goal)")
for phase, goal in (("idle", 0.85), ("drag", 0.6)):
    for pacing in ("off", "on"):
        r = json.load(open(os.path.join(w, "%s_%s.json" % (phase, pacing))))
        rate = r["trace_spp_per_second"]
        # No round shown: less than one spp over the whole run.
        shown = ("%11.3f %9.2f" % (rate, rate / batch) if rate > 0 else
                 "%11s %9s" % ("< %.3f" % (1 / r["wall_seconds"]),
                               "< %.2f" % (1 / r["wall_seconds"] / batch)))
        print("%-17s %-6s %s %8d %9.1f ms %9.1f   (>= %.2f)" %
              ("left alone" if phase == "idle" else "panning (drag)", pacing, shown,
               r["frames"], r["mean_frame_ms"], r["wall_seconds"], goal))
PY
  exit 0
fi
if [ $asset -eq 1 ]; then
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  scene=build/bench/asset_scene/scene.json size=1280x720
  [ -f "$scene" ] || scripts/make_asset_scene.sh >/dev/null
  [ $glb -eq 1 ] && scene=build/bench/asset_scene/asset.glb
  [ -n "$on" ] && scene=$on
  ref_spp=${REF_SPP:-64}
  if [ -n "${REF_EXR:-}" ]; then
    # A reference rendered once (say 2048 spp, another seed than the windows' 0), and its own
    # noise as REF_FLOOR when known.
    echo "asset scene $scene at $size: reference $REF_EXR"
    cp "$REF_EXR" "$work/ref.exr"
    ref_spp="given"
    echo "${REF_FLOOR:-nan}" >"$work/floor.txt"
  else
    echo "asset scene $scene at $size: references (LD, $ref_spp spp, two seeds)..."
    build/penumbra render "$scene" --method ld --spp "$ref_spp" --seed 2 --size $size -q \
      -o "$work/ref.exr" 2>/dev/null
    build/penumbra render "$scene" --method ld --spp "$ref_spp" --seed 1 --size $size -q \
      -o "$work/ref2.exr" 2>/dev/null
    build/penumbra diff "$work/ref2.exr" "$work/ref.exr" | awk '$1 == "rel_mse" {print $2 / 2}' \
      >"$work/floor.txt"
  fi
  # Opening, then a camera move away and back (an orbit drag and its reverse, so the camera is
  # the reference's again): the saves are 0.5-4 s after the move back, when the scene is loaded
  # and only the restart's work is left, as after any camera move.
  printf 'wait 8\ndrag left 700 400 760 400\nwait 3\ndrag left 760 400 700 400\nwait 0.5\nsave %s/t0.5.exr\nwait 0.5\nsave %s/t1.exr\nwait 1\nsave %s/t2.exr\nwait 2\nsave %s/t4.exr\nquit\n' \
    "$work" "$work" "$work" "$work" >"$work/times.txt"
  # The first full picture is timed in a second window with the same moves and no saves: writing
  # an EXR keeps the UI thread busy for about 0.2 s (longest_busy_ms of a save), which the save
  # at 0.5 s took from the picture it waits for.
  printf 'wait 8\ndrag left 700 400 760 400\nwait 3\ndrag left 760 400 700 400\nwait 2\nquit\n' \
    >"$work/move.txt"
  for method in bp ld; do
    flags=()
    [ $method = bp ] && read -r -a flags <<<"${BP_FLAGS:-}"
    build/penumbra render "$scene" --method $method --spp 4 --size $size -q -o "$work/batch.exr" \
      --stats "$work/batch_$method.json" "${flags[@]}"
    mkdir -p "$work/$method"
    sed "s|$work/t|$work/$method/t|g" "$work/times.txt" >"$work/$method/times.txt"
    xvfb-run -a -s "-screen 0 1640x800x24" build/penumbra view "$scene" --size $size \
      --method $method --script "$work/$method/times.txt" --report "$work/$method/report.json" \
      "${flags[@]}" >/dev/null 2>&1
    xvfb-run -a -s "-screen 0 1640x800x24" build/penumbra view "$scene" --size $size \
      --method $method --script "$work/move.txt" --report "$work/$method/move.json" \
      "${flags[@]}" >/dev/null 2>&1
    for t in 0.5 1 2 4; do
      if [ -f "$work/$method/t$t.exr" ]; then
        build/penumbra diff "$work/$method/t$t.exr" "$work/ref.exr" | awk '$1 == "rel_mse" {print $2}'
      else
        echo nan
      fi >"$work/$method/relmse_$t.txt"
    done
  done
  python3 - "$work" "$ref_spp" <<'PY'
import json, os, sys
w = sys.argv[1]
rel = {m: [float(open(os.path.join(w, m, "relmse_%s.txt" % t)).read() or "nan")
           for t in ("0.5", "1", "2", "4")] for m in ("bp", "ld")}
for m in ("bp", "ld"):
    r = json.load(open(os.path.join(w, m, "report.json")))
    mv = json.load(open(os.path.join(w, m, "move.json")))  # the window without saves
    b = json.load(open(os.path.join(w, "batch_%s.json" % m)))
    window_rate = r["trace_spp_per_second"]  # kept spp over the method's seconds, newest picture
    batch_rate = b["spp"] / max(b["time_seconds"], 1e-9)
    print("%-3s first full picture %6.0f ms after the move (%d restarts reached one: mean %.0f, "
          "worst %.0f ms, opening included); window trace speed %.2f x batch (%.2f vs %.2f spp/s)"
          % (m, mv["first_full_picture_ms_last"], mv["first_full_pictures"],
             mv["first_full_picture_ms_mean"], mv["first_full_picture_ms_max"],
             window_rate / batch_rate, window_rate, batch_rate))
print("relMSE after a move     0.5 s      1 s      2 s      4 s")
for m in ("bp", "ld"):
    print("%-3s                  " % m + "  ".join("%8.3g" % v for v in rel[m]))
print("bp / ld               " + "  ".join("%8.2f" % (a / b) if b == b and b > 0 else "     nan"
                                           for a, b in zip(rel["bp"], rel["ld"])))
print("the reference's own relMSE (%s spp): about %.3g; figures near it are not resolved"
      % (sys.argv[2], float(open(os.path.join(w, "floor.txt")).read())))
PY
  exit 0
fi
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
