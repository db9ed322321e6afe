#!/usr/bin/env bash
# Regenerates the stored references of the render regression tests of `cornell` and of the
# glTF `studio` (tests/data/NAME_ref.exr and its per-pixel variance of the mean; the studio's
# with direct light only, as its test renders it). Run it only when
# a change to the renderer is meant to change the image, and say why in the commit.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
build/penumbra render scenes/cornell.json --size 64x64 --spp 16384 --sampler independent --seed 777 \
  -o tests/data/cornell_ref.exr --variance-out tests/data/cornell_ref_var.exr --stats /tmp/cornell_ref_stats.json
build/penumbra render scenes/studio/studio.gltf --size 64x64 --spp 16384 --max-depth 1 --sampler independent --seed 777 \
  -o tests/data/studio_ref.exr --variance-out tests/data/studio_ref_var.exr --stats /tmp/studio_ref_stats.json
