#!/usr/bin/env bash
# Builds the asset-scene generator and writes the asset benchmark scene (docs/BENCHMARKS.md)
# into build/bench/asset_scene/ (or the folder given first). Extra arguments go to the
# generator: --texture-size N (2048), --env FILE.hdr (scenes/env/sky.hdr).
#   scripts/make_asset_scene.sh
#   scripts/make_asset_scene.sh /tmp/asset_small --texture-size 256
set -euo pipefail
cd "$(dirname "$0")/.."
out=build/bench/asset_scene
if [[ $# -gt 0 && $1 != -* ]]; then out=$1; shift; fi
if [[ ! -f build/build.ninja ]]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
ninja -C build penumbra_make_asset_scene
build/bench/penumbra_make_asset_scene "$out" "$@"
