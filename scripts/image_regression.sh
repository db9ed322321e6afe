#!/usr/bin/env bash
# Image regression: renders every method and preset on every shipped scene with two builds of
# penumbra (a base commit and the working tree) and compares the output files byte for byte.
# A refactor must leave every file identical; an issue that may change some images says which.
#
# Usage: scripts/image_regression.sh [--base COMMIT | --base-bin PATH] [--new-bin PATH]
#                                    [--out DIR] [--only REGEX]
#   --base COMMIT   build COMMIT in a temporary worktree (default: the commit recorded in
#                   BASE_COMMIT below, the last one before the issue-11 refactor)
#   --base-bin PATH use an already built penumbra of that commit as the base; it reads the
#                   commit's own shaders (PENUMBRA_SHADER_DIR), exported from git
#   --new-bin PATH  the build to check (default: build/penumbra, built by scripts/setup.sh)
#   --only REGEX    only the cases whose name matches (e.g. 'bp|gem')
# Exit status: 0 when every file is identical, 1 when one differs (listed), 2 on a usage error.
#
# Renders are small (64x64, 8 spp) and use the SSE training kernel, so the files do not depend
# on the CPU's widest instruction set: both builds run on the same machine anyway.
# Besides render (with --aov-dir maps) it runs headless views with overlays and compare (its
# report images).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

BASE_COMMIT=7541218
base=""
base_bin=""
new_bin="$root/build/penumbra"
out="$root/out/image_regression"
only="."
while [ $# -gt 0 ]; do
  case "$1" in
    --base) base="$2"; shift 2 ;;
    --base-bin) base_bin="$2"; shift 2 ;;
    --new-bin) new_bin="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --only) only="$2"; shift 2 ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    *) echo "image_regression: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -n "$base" ] || base=$BASE_COMMIT
[ -x "$new_bin" ] || { echo "image_regression: no build at $new_bin (run scripts/setup.sh)" >&2; exit 2; }

tree=$(mktemp -d /tmp/penumbra-base.XXXXXX)
trap 'git -C "$root" worktree remove --force "$tree/src" >/dev/null 2>&1 || true; rm -rf "$tree"' EXIT
# The base's viewer must draw with the base's shaders, whatever the binary was built from.
base_shaders="$tree/base-shaders"
mkdir -p "$base_shaders"
git -C "$root" archive "$base" shaders | tar -x -C "$base_shaders"
if [ -z "$base_bin" ]; then
  echo "image_regression: building $base in $tree/src"
  git -C "$root" worktree add --detach "$tree/src" "$base" >/dev/null
  cmake -S "$tree/src" -B "$tree/src/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$tree/src/build" --target penumbra -j "$(nproc 2>/dev/null || echo 2)" >/dev/null
  base_bin="$tree/src/build/penumbra"
fi
[ -x "$base_bin" ] || { echo "image_regression: no base build at $base_bin" >&2; exit 2; }

export PENUMBRA_NET_SIMD=sse DISPLAY=
scenes=(balls cornell dragon stairs tire studio)
# A case's scene file: scenes/NAME.json, or the glTF studio (scripts/make_studio.py).
scene_file() { if [ "$1" = studio ]; then echo scenes/studio/studio.gltf; else echo "scenes/$1.json"; fi; }
# name|render flags. Adaptive methods also write their raw estimate and their debug maps.
cases=(
  "ld|--method ld --variance-out VAR"
  "ld-independent|--method ld --sampler independent"
  "bp-paper|--method bp --preset paper --raw-out RAW --aov-dir AOV"
  "bp-tuned|--method bp --preset tuned --raw-out RAW --aov-dir AOV"
  "bp-ablations|--method bp --preset paper --no-warping --no-second-pass --candidate-mode predicted --inputs 5"
  "fdiv|--method fdiv --raw-out RAW --aov-dir AOV"
  "fdiv-kl|--method fdiv --divergence kl"
  "fdiv-chi2|--method fdiv --divergence chi2"
  "fuzzy|--method fuzzy --raw-out RAW --aov-dir AOV"
  "gem|--method gem --raw-out RAW --aov-dir AOV"
  "cycles|--method cycles --raw-out RAW --aov-dir AOV"
  "bp-noise|--method bp --noise-threshold 0.05 --variance-out VAR"
  "ld-noise|--method ld --noise-threshold 0.05 --filter --raw-out RAW"
  "gem-noise|--method gem --noise-threshold 0.05"
)
# Open-ended runs: the viewer's progressive rounds, headless, with an overlay.
views=(
  "view-ld|--method ld --overlay samples"
  "view-bp|--method bp --overlay bias"
  "view-bp-paper|--method bp --preset paper --overlay alpha"
  "view-gem|--method gem --overlay bias"
  "view-fdiv|--method fdiv --overlay selected"
  "view-bp-er|--method bp --overlay network_error"
  "view-bp-traced|--method bp --overlay traced"
  "view-gem-alpha|--method gem --overlay alpha"
  "view-ld-traced|--method ld --overlay traced"
)
# compare's report on one scene: its PNG images (its text files carry timings and paths).
compare_methods=ld,fdiv,fuzzy,gem,cycles,bp:tuned,bp:paper,bp:raw

run_all() {  # binary, output folder
  local bin=$1 dir=$2 name flags scene d f
  rm -rf "$dir"
  mkdir -p "$dir"
  for scene in "${scenes[@]}"; do
    for c in "${cases[@]}"; do
      name=${c%%|*}; flags=${c#*|}
      [[ "$scene/$name" =~ $only ]] || continue
      d="$dir/$scene/$name"
      mkdir -p "$d"
      f=${flags//VAR/$d/var.exr}; f=${f//RAW/$d/raw.exr}; f=${f//AOV/$d/aov}
      # shellcheck disable=SC2086
      "$bin" render "$(scene_file "$scene")" --size 64x64 --spp 8 --seed 7 --threads 2 -q \
        -o "$d/image.exr" $f >"$d/log.txt" 2>&1 || { echo "  $scene/$name failed:"; cat "$d/log.txt"; }
    done
  done
  for scene in tire balls; do
    for c in "${views[@]}"; do
      name=${c%%|*}; flags=${c#*|}
      [[ "$scene/$name" =~ $only ]] || continue
      d="$dir/$scene/$name"
      mkdir -p "$d"
      # shellcheck disable=SC2086
      "$bin" view "scenes/$scene.json" --headless --backend osmesa --size 64x64 --rounds 3 \
        --seed 7 --threads 2 --screenshot "$d/view.png" $flags >"$d/log.txt" 2>&1 ||
        { echo "  $scene/$name failed:"; cat "$d/log.txt"; }
    done
  done
  if [[ "tire/compare" =~ $only ]]; then
    d="$dir/tire/compare"
    mkdir -p "$d"
    "$bin" compare scenes/tire.json --size 32x32 --spp 8 --methods "$compare_methods" \
      --reference-spp 32 --seeds 1 --threads 2 --out "$d" -q >"$d/log.txt" 2>&1 ||
      { echo "  tire/compare failed:"; cat "$d/log.txt"; }
    find "$d" -type f ! -path "$d/images/*" ! -name log.txt -delete
  fi
  # Logs carry timings; they are not compared.
  find "$dir" -name log.txt -delete
}

echo "image_regression: rendering with the base ($base_bin)"
PENUMBRA_SHADER_DIR="$base_shaders/shaders" run_all "$base_bin" "$out/base"
echo "image_regression: rendering with the new build ($new_bin)"
run_all "$new_bin" "$out/new"

status=0
count=$(cd "$out/base" && find . -type f | wc -l)
if ! diff <(cd "$out/base" && find . -type f | sort) <(cd "$out/new" && find . -type f | sort) \
  >"$out/files.diff"; then
  echo "image_regression: the two builds wrote different files:"
  cat "$out/files.diff"
  status=1
fi
while read -r f; do
  [ -f "$out/new/$f" ] || continue
  cmp -s "$out/base/$f" "$out/new/$f" || { echo "  differs: $f"; status=1; }
done < <(cd "$out/base" && find . -type f | sort)
if [ $status -eq 0 ]; then
  echo "image_regression: all $count files identical"
else
  echo "image_regression: FAILED (base in $out/base, new in $out/new)"
fi
exit $status
