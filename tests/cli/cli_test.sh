#!/usr/bin/env bash
# The command line as a user runs it: renders, diffs, and every kind of bad input
# (unknown flag, bad value, missing or malformed file) exiting non-zero with a one-line
# message that names the flag, file and place. Usage: cli_test.sh PENUMBRA SOURCE_DIR
set -u
penumbra=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
passes=0

# expect_fail "description" "expected message fragment" command...
expect_fail() {
  local what=$1 expected=$2
  shift 2
  local out status
  out=$("$@" 2>&1)
  status=$?
  if [ $status -eq 0 ]; then
    echo "FAIL: $what: exited 0"; failures=$((failures + 1)); return
  fi
  if [ "$(printf '%s\n' "$out" | wc -l)" -ne 1 ]; then
    echo "FAIL: $what: expected one line, got:"; printf '%s\n' "$out"; failures=$((failures + 1)); return
  fi
  case "$out" in
    *"$expected"*) passes=$((passes + 1)) ;;
    *) echo "FAIL: $what: expected '$expected' in: $out"; failures=$((failures + 1)) ;;
  esac
}

expect_ok() {
  local what=$1
  shift
  if "$@" >"$work/out.txt" 2>&1; then passes=$((passes + 1)); else
    echo "FAIL: $what:"; cat "$work/out.txt"; failures=$((failures + 1)); fi
}

cornell="$src/scenes/cornell.json"
expect_ok "render png" "$penumbra" render "$cornell" --size 32x32 --spp 2 -o "$work/a.png" --stats "$work/s.json" -q
expect_ok "render exr" "$penumbra" render "$cornell" --size 32x32 --spp 2 -o "$work/a.exr" -q
expect_ok "render pfm into a new folder" "$penumbra" render "$cornell" --size 32x32 --spp 2 -o "$work/new/dir/a.pfm" -q
expect_ok "diff" "$penumbra" diff "$work/a.exr" "$work/a.exr" --out "$work/d.png" --json
for key in time_seconds rays mrays_per_second spp nan_samples; do
  grep -q "\"$key\"" "$work/s.json" || { echo "FAIL: stats.json lacks $key"; failures=$((failures + 1)); }
done
# Same seed, different thread counts: identical bytes.
"$penumbra" render "$cornell" --size 24x24 --spp 4 --seed 9 --threads 1 -o "$work/t1.pfm" -q
"$penumbra" render "$cornell" --size 24x24 --spp 4 --seed 9 --threads 2 -o "$work/t2.pfm" -q
cmp -s "$work/t1.pfm" "$work/t2.pfm" && passes=$((passes + 1)) || { echo "FAIL: thread count changed the image"; failures=$((failures + 1)); }

# An OBJ with an emissive MTL material is a scene; camera from flags.
printf 'mtllib l.mtl\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nv -.5 2 -.5\nv .5 2 -.5\nv .5 2 .5\nv -.5 2 .5\nusemtl floor\nf 1 4 3\nf 1 3 2\nusemtl lamp\nf 5 6 7\nf 5 7 8\n' >"$work/l.obj"
printf 'newmtl floor\nKd 0.7 0.7 0.7\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n' >"$work/l.mtl"
expect_ok "render an OBJ with camera flags" "$penumbra" render "$work/l.obj" --eye 0,1.5,5 --look-at 0,0.5,0 --fov 45 --size 32x32 --spp 4 -o "$work/l.pfm" --stats "$work/l.json" -q
grep -q '"nan_samples": 0' "$work/l.json" && passes=$((passes + 1)) || { echo "FAIL: OBJ render stats"; failures=$((failures + 1)); }

expect_fail "unknown flag" "--frobnicate" "$penumbra" render "$cornell" -o "$work/x.png" --frobnicate
expect_fail "bad spp" "--spp" "$penumbra" render "$cornell" -o "$work/x.png" --spp zero
expect_fail "spp out of range" "--spp" "$penumbra" render "$cornell" -o "$work/x.png" --spp 0
expect_fail "bad size" "--size: expected WxH" "$penumbra" render "$cornell" -o "$work/x.png" --size 12by12
expect_fail "bad eye" "--eye: expected x,y,z" "$penumbra" render "$cornell" -o "$work/x.png" --eye 1,2
expect_fail "bad shutter" "--shutter" "$penumbra" render "$cornell" -o "$work/x.png" --shutter 0.8,0.2
expect_fail "bad output format" "unsupported image format '.jpg'" "$penumbra" render "$cornell" -o "$work/x.jpg"
expect_fail "missing scene" "nowhere.json" "$penumbra" render "$work/nowhere.json" -o "$work/x.png"
expect_fail "missing output flag" "--output" "$penumbra" render "$cornell"
expect_fail "unknown command" "teleport" "$penumbra" teleport
printf '{"materials": {"m": {"type": "diffuse"}}, "objects": [{"shape": "sphere", "material": "n"}]}' >"$work/bad.json"
expect_fail "unknown material" "bad.json: objects[0].material: unknown material 'n'" "$penumbra" render "$work/bad.json" -o "$work/x.png"
printf '{"materials": {\n  "m": {"type": "diffuse",}\n}}' >"$work/syntax.json"
expect_fail "syntax error" "syntax.json:2:" "$penumbra" render "$work/syntax.json" -o "$work/x.png"
expect_fail "diff size mismatch" "size" "$penumbra" diff "$work/a.exr" "$work/t1.pfm"
[ -e "$work/x.png" ] && { echo "FAIL: a failed render left an output file"; failures=$((failures + 1)); }
ls "$work" | grep -q tmp && { echo "FAIL: temporary files left behind"; failures=$((failures + 1)); }

# The BP method: output, raw estimate, debug maps and statistics; same bytes for 1 and 2 threads.
expect_ok "render bp" "$penumbra" render "$cornell" --method bp --size 24x24 --spp 8 -o "$work/bp.pfm" --raw-out "$work/bp_raw.exr" --aov-dir "$work/aov" --stats "$work/bp.json" --threads 1 -q
for f in bias.exr bias.png network_error.png prediction.png selected.png slice_b.png slice_c.png samples.png traced.png alpha.png raw.exr reconstructed.exr; do
  [ -s "$work/aov/$f" ] || { echo "FAIL: --aov-dir lacks $f"; failures=$((failures + 1)); }
done
for key in kept_spp traced_spp rounds phases train select reconstruct trace bias_histogram alpha_histogram per_round training_gflops; do
  grep -q "\"$key\"" "$work/bp.json" || { echo "FAIL: bp stats lack $key"; failures=$((failures + 1)); }
done
grep -q '"kept_spp": 8.0' "$work/bp.json" && passes=$((passes + 1)) || { echo "FAIL: bp kept spp is not 8"; failures=$((failures + 1)); }
"$penumbra" render "$cornell" --method bp --size 24x24 --spp 8 -o "$work/bp2.pfm" --threads 2 -q
cmp -s "$work/bp.pfm" "$work/bp2.pfm" && passes=$((passes + 1)) || { echo "FAIL: thread count changed the bp image"; failures=$((failures + 1)); }
expect_ok "bp ablations" "$penumbra" render "$cornell" --method bp --size 16x16 --spp 8 -o "$work/bpa.exr" -q --inputs 5 --targets pixel-mean --prediction-draws 1 --candidate-mode predicted --no-warping --no-outlier-removal --no-second-pass --plain-mean --no-top-up --no-reconstruct --learning-rate proportional
expect_ok "bp tuned preset" "$penumbra" render "$cornell" --method bp --preset tuned --size 16x16 --spp 8 -o "$work/bpt.exr" --stats "$work/bpt.json" -q
grep -q '"preset": "tuned"' "$work/bpt.json" && grep -q '"traced_spp": 8.0' "$work/bpt.json" && passes=$((passes + 1)) || { echo "FAIL: tuned preset stats"; failures=$((failures + 1)); }
"$penumbra" render "$cornell" --method bp --preset tuned --sigma-c 0.2 --size 16x16 --spp 8 -o "$work/bpt2.exr" --stats "$work/bpt2.json" -q
grep -q '"sigma_c": 0.2' "$work/bpt2.json" && passes=$((passes + 1)) || { echo "FAIL: --sigma-c does not override the preset"; failures=$((failures + 1)); }
expect_fail "bad preset" "--preset" "$penumbra" render "$cornell" --method bp --preset best -o "$work/x.png"
expect_fail "bp phi count" "--phi" "$penumbra" render "$cornell" --method bp -o "$work/x.png" --phi 0.3,0.5
expect_fail "bp inputs" "--inputs" "$penumbra" render "$cornell" --method bp -o "$work/x.png" --inputs 6
expect_fail "aov dir needs an adaptive method" "--aov-dir needs an adaptive --method" "$penumbra" render "$cornell" -o "$work/x.png" --aov-dir "$work/aovx"
expect_fail "unknown method" "--method" "$penumbra" render "$cornell" --method magic -o "$work/x.png"

# The viewer, headless (no display): screenshots, the fallback without a display, bad flags.
# PENUMBRA_VIEW_ENV: variables the sanitizer build gives the viewer (tests/CMakeLists.txt).
read -r -a view_env <<<"${PENUMBRA_VIEW_ENV:-}"
expect_ok "view headless" env -u DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --size 24x24 --headless --rounds 2 --overlay bias --screenshot "$work/view.png"
[ -s "$work/view.png" ] && passes=$((passes + 1)) || { echo "FAIL: view wrote no screenshot"; failures=$((failures + 1)); }
grep -q "view.png: 24x" "$work/out.txt" && passes=$((passes + 1)) || { echo "FAIL: view did not print the screenshot path"; failures=$((failures + 1)); }
expect_ok "view without a display" env -u DISPLAY -u WAYLAND_DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --size 16x16 --rounds 1 --method ld --backend osmesa --screenshot "$work/auto.png"
grep -q "no display" "$work/out.txt" && [ -s "$work/auto.png" ] && passes=$((passes + 1)) || { echo "FAIL: no headless fallback without a display"; failures=$((failures + 1)); }
"$penumbra" render "$cornell" --size 16x16 --spp 4 -o "$work/ref16.exr" -q
expect_ok "view with reference" env -u DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --size 16x16 --headless --rounds 1 --reference "$work/ref16.exr" --overlay reference_error --with-ui --inspect 3,4 --screenshot "$work/ui.png"
expect_fail "view bad overlay" "--overlay: unknown overlay 'glitter'" env -u DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --headless --overlay glitter --screenshot "$work/x.png"
expect_fail "view bad backend" "--backend" env -u DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --headless --backend vulkan --screenshot "$work/x.png"
expect_fail "view screenshot format" "--screenshot: expected a .png" env -u DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --headless --screenshot "$work/x.jpg"
expect_fail "view bad inspect" "--inspect: expected X,Y" env -u DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --headless --inspect 3 --screenshot "$work/x.png"
expect_fail "view reference size" "is 16x16, the render 24x24" env -u DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --size 24x24 --headless --reference "$work/ref16.exr" --screenshot "$work/x.png"
expect_fail "view missing reference" "nothere.exr" env -u DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --headless --reference "$work/nothere.exr" --screenshot "$work/x.png"
expect_fail "view script needs a display" "--script needs a display" env -u DISPLAY -u WAYLAND_DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --script "$work/none.txt"
expect_fail "view bad window size" "--window-size" env -u DISPLAY "${view_env[@]}" "$penumbra" view "$cornell" --headless --window-size 0x5 --screenshot "$work/x.png"
expect_fail "view missing scene" "nowhere.json" env -u DISPLAY "${view_env[@]}" "$penumbra" view "$work/nowhere.json" --headless --screenshot "$work/x.png"
[ -e "$work/x.png" ] && { echo "FAIL: a failed view left a screenshot"; failures=$((failures + 1)); }

echo "$passes passed, $failures failed"
[ $failures -eq 0 ]
