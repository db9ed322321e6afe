#!/usr/bin/env bash
# Memory at a real size (issue 25): for the asset scene (scripts/make_asset_scene.sh) and
# scenes/tire.json, at 1280x720 and 1920x1080, the peak resident memory of a default-bp render
# (--spp, with its texture_bytes and memory_bytes_per_pixel from --stats) and of a headless
# view (--rounds), and (with xvfb-run, DRAG=1 by default) of the window under Xvfb through a
# scripted camera drag (30 s, two fast drags that restart the render, 30 s more), then the
# reconstruction's time at 1280x720 (bench/recon_bench.cpp). The goal: every peak under 1 GB
# (1e9 bytes).
#   bench/memory.sh                      # SPP=8 ROUNDS=4 DRAG=1 by default
#   SPP=4 SIZES=1920x1080 SCENES=tire DRAG=0 bench/memory.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD:-build}
spp=${SPP:-8}
rounds=${ROUNDS:-4}
sizes=${SIZES:-"1280x720 1920x1080"}
scenes=${SCENES:-"asset tire"}
kinds="render view"
if [[ ${DRAG:-1} == 1 ]] && command -v xvfb-run >/dev/null; then kinds="$kinds drag"; fi
goal=1000000000
asset=$build/bench/asset_scene/scene.json
if [[ " $scenes " == *" asset "* && ! -f $asset ]]; then scripts/make_asset_scene.sh; fi
ninja -C "$build" penumbra penumbra_bench_recon >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# peak KIND SCENE SIZE: runs one command under /usr/bin/time and prints its peak RSS in bytes.
peak() {
  local kind=$1 scene=$2 size=$3
  local cmd
  if [[ $kind == render ]]; then
    cmd=("$build/penumbra" render "$scene" --method bp --spp "$spp" --size "$size" -q
         --stats "$out/stats.json" -o "$out/render.exr")
  elif [[ $kind == drag ]]; then
    # /usr/bin/time reports the largest resident set among the command and its descendants:
    # the viewer's (Xvfb's is far smaller).
    printf 'wait 30\ndrag left 600 400 900 420\nwait 2\ndrag left 900 420 500 380\nwait 30\nquit\n' \
      >"$out/drag.txt"
    cmd=(xvfb-run -a -s "-screen 0 ${size}x24" "$build/penumbra" view "$scene" --method bp
         --size "$size" --script "$out/drag.txt" --report "$out/drag.json")
  else
    cmd=("$build/penumbra" view "$scene" --method bp --headless --rounds "$rounds" --size "$size"
         --screenshot "$out/view.png")
  fi
  /usr/bin/time -f %M -o "$out/time.txt" "${cmd[@]}" >"$out/log.txt" 2>&1 ||
    { cat "$out/log.txt" >&2; return 1; }
  echo $(( $(tail -1 "$out/time.txt") * 1024 ))
}

stat() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$@"; }

printf '%-6s %-10s %-7s %15s %9s %9s %13s %10s\n' scene size run peak_bytes GB GiB texture_bytes bytes/px
fail=0
for name in $scenes; do
  case $name in
    asset) scene=$asset ;;
    tire) scene=scenes/tire.json ;;
    *) scene=$name ;;
  esac
  for size in $sizes; do
    for kind in $kinds; do
      bytes=$(peak "$kind" "$scene" "$size")
      textures=- perpixel=-
      if [[ $kind == render ]]; then
        textures=$(stat "$out/stats.json" texture_bytes)
        perpixel=$(stat "$out/stats.json" memory_bytes_per_pixel)
      fi
      printf '%-6s %-10s %-7s %15s %9.3f %9.3f %13s %10s\n' "$name" "$size" "$kind" "$bytes" \
        "$(echo "$bytes / 1000000000" | bc -l)" "$(echo "$bytes / 1073741824" | bc -l)" \
        "$textures" "$perpixel"
      (( bytes < goal )) || fail=1
    done
  done
done
echo
"$build/bench/penumbra_bench_recon" --size 1280x720 --spp 4 --repeats 5
echo
if (( fail )); then echo "some peak is at or above 1 GB (1e9 bytes)"; else echo "every peak is under 1 GB (1e9 bytes)"; fi
