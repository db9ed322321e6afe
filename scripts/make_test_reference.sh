#!/usr/bin/env bash
# Regenerates the stored reference of the `cornell` render regression test
# (tests/data/cornell_ref.exr and its per-pixel variance of the mean). Run it only when
# a change to the renderer is meant to change the image, and say why in the commit.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
build/penumbra render scenes/cornell.json --size 64x64 --spp 16384 --sampler independent --seed 777 \
  -o tests/data/cornell_ref.exr --variance-out tests/data/cornell_ref_var.exr --stats /tmp/cornell_ref_stats.json
