#!/usr/bin/env bash
# Renders the converged references of the shipped scenes (ALGORITHM.md §11: low
# discrepancy, >= 8192 spp, the same integrator) with `penumbra reference`, at each
# scene's shipped size, into out/ref/<scene>.exr (+ _var.exr and .json). A reference whose
# record already has the requested spp is kept.
# Usage: scripts/make_references.sh [--spp N] [--out DIR] [--force] [scene ...]
set -euo pipefail
cd "$(dirname "$0")/.."
spp=8192
out=out/ref
force=0
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --spp) spp="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --force) force=1; shift ;;
    -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
    -*) echo "make_references: unknown flag $1" >&2; exit 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
if [ ${#scenes[@]} -eq 0 ]; then
  for f in scenes/*.json; do scenes+=("$(basename "$f" .json)"); done
fi
penumbra=${PENUMBRA:-build/penumbra}
[ -x "$penumbra" ] || { echo "make_references: $penumbra not built (run scripts/setup.sh)" >&2; exit 1; }
mkdir -p "$out"
for s in "${scenes[@]}"; do
  [ -f "scenes/$s.json" ] || { echo "make_references: no scene scenes/$s.json" >&2; exit 1; }
  record="$out/$s.json"
  if [ $force -eq 0 ] && [ -f "$out/$s.exr" ] && [ -f "$record" ] &&
     python3 -c "import json,sys; sys.exit(0 if json.load(open('$record'))['spp'] == $spp else 1)" 2>/dev/null; then
    echo "make_references: $out/$s.exr is already at $spp spp"
    continue
  fi
  "$penumbra" reference "scenes/$s.json" --spp "$spp" -o "$out/$s.exr" -q
  python3 -c "import json; j=json.load(open('$record')); print('make_references: %s: %d spp, %.0f s, residual MSE %.3g' % ('$out/$s.exr', j['spp'], j['time_seconds'], j['residual_mse']))"
done
