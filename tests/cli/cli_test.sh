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

# check "description" command...: the command's exit status is the verdict.
check() {
  local what=$1
  shift
  if "$@"; then passes=$((passes + 1)); else echo "FAIL: $what"; failures=$((failures + 1)); fi
}

cornell="$src/scenes/cornell.json"
# The viewer's flags for the run's shape, as a user reads them: its panel's stopping rules too.
"$penumbra" view --help >"$work/view_help.txt"
for flag in --time-limit --noise-threshold --sampler --round-spp --spp --seed; do
  check "view --help lists $flag" grep -q -- "  $flag " "$work/view_help.txt"
done
expect_ok "render png" "$penumbra" render "$cornell" --size 32x32 --spp 2 -o "$work/a.png" --stats "$work/s.json" -q
expect_ok "render exr" "$penumbra" render "$cornell" --size 32x32 --spp 2 -o "$work/a.exr" -q
expect_ok "render pfm into a new folder" "$penumbra" render "$cornell" --size 32x32 --spp 2 -o "$work/new/dir/a.pfm" -q
# The renders wrote their files, each in its format.
check "a.png is a PNG" test "$(head -c 4 "$work/a.png" 2>/dev/null | tail -c 3)" = PNG
check "a.exr is an OpenEXR file" test "$(od -An -tx1 -N4 "$work/a.exr" 2>/dev/null | tr -d ' \n')" = 762f3101
check "new/dir/a.pfm is a colour PFM" test "$(head -c 2 "$work/new/dir/a.pfm" 2>/dev/null)" = PF

# `diff` on a known answer: 4x2 PFMs, the reference (0.25, 0.5, 0.75) everywhere, the test
# off by +0.5 (red) in one pixel and by -0.25 (blue) in another, and NaN in a third, which
# is counted and left out of every average (7 pixels, 21 channels remain).
python3 - "$work/known_test.pfm" "$work/known_ref.pfm" <<'EOF'
import struct, sys
ref = [(0.25, 0.5, 0.75)] * 8
test = list(ref)
test[0] = (0.75, 0.5, 0.75)
test[5] = (0.25, 0.5, 0.5)
test[7] = (float("nan"), 0.5, 0.75)
for path, pixels in zip(sys.argv[1:], (test, ref)):
    with open(path, "wb") as f:
        f.write(b"PF\n4 2\n-1.0\n" + b"".join(struct.pack("<3f", *p) for p in pixels))
EOF
# diff_json "description" output.json diff-arguments...: runs `diff --json`, stdout to the file.
diff_json() {
  local what=$1 out=$2
  shift 2
  if "$penumbra" diff "$@" --json >"$out" 2>"$work/diff_err.txt"; then passes=$((passes + 1)); else
    echo "FAIL: $what:"; cat "$work/diff_err.txt"; failures=$((failures + 1)); fi
}
diff_json "diff, known answer" "$work/known.json" "$work/known_test.pfm" "$work/known_ref.pfm"
check "diff, known answer: the metrics" python3 -c '
import json, math, sys
j = json.load(open(sys.argv[1]))
def near(key, want):
    assert j[key] is not None and math.isclose(j[key], want, rel_tol=1e-9), (key, j[key], want)
n = 7 * 3
near("mse", (0.5**2 + 0.25**2) / n)
near("rel_mse", (0.5**2 / (0.25**2 + 1e-2) + 0.25**2 / (0.75**2 + 1e-2)) / n)
near("max_abs_error", 0.5)
near("psnr", 10 * math.log10(n / (0.5**2 + 0.25**2)))  # values in [0, 1]: clamping changes nothing
assert j["tone_mapped_mse"] is not None and j["tone_mapped_mse"] > 0, j
assert j["non_finite"] == 1 and j["width"] == 4 and j["height"] == 2, j
' "$work/known.json"

# Two renders with different seeds differ: every metric present, finite and positive, and
# the error map written.
expect_ok "render exr, another seed" "$penumbra" render "$cornell" --size 32x32 --spp 2 --seed 12345 -o "$work/b.exr" -q
diff_json "diff of two seeds" "$work/seeds.json" "$work/b.exr" "$work/a.exr" --out "$work/d.png"
check "diff of two seeds: metrics" python3 -c '
import json, math, sys
j = json.load(open(sys.argv[1]))
for key in ("mse", "rel_mse", "tone_mapped_mse", "psnr", "max_abs_error"):
    assert isinstance(j[key], (int, float)) and math.isfinite(j[key]), (key, j[key])
    assert j[key] > 0, (key, j[key])
assert j["max_abs_error"] ** 2 >= j["mse"], j  # the largest error bounds the mean square
assert j["non_finite"] == 0 and j["width"] == 32 and j["height"] == 32, j
assert j["diff_image"] == sys.argv[2] and j["diff_max"] > 0, j
' "$work/seeds.json" "$work/d.png"
check "diff --out d.png is a PNG" test "$(head -c 4 "$work/d.png" 2>/dev/null | tail -c 3)" = PNG
# An image against itself: no error at all (PSNR infinite, so null).
diff_json "diff of an image with itself" "$work/self.json" "$work/a.exr" "$work/a.exr"
check "diff of an image with itself: zero error" python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
for key in ("mse", "rel_mse", "tone_mapped_mse", "max_abs_error"):
    assert j[key] == 0, (key, j[key])
assert j["psnr"] is None and j["non_finite"] == 0, j
' "$work/self.json"
for key in time_seconds rays mrays_per_second spp nan_samples texture_bytes; do
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
check "the OBJ render is a colour PFM" test "$(head -c 2 "$work/l.pfm" 2>/dev/null)" = PF

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
expect_fail "diff size mismatch" "image sizes differ: $work/a.exr is 32x32, $work/t1.pfm is 24x24" "$penumbra" diff "$work/a.exr" "$work/t1.pfm"
[ -e "$work/x.png" ] && { echo "FAIL: a failed render left an output file"; failures=$((failures + 1)); }
[ -n "$(find "$work" -name '*.tmp-*')" ] && { echo "FAIL: temporary files left behind"; failures=$((failures + 1)); }

# The BP method: output, raw estimate, debug maps and statistics; same bytes for 1 and 2 threads.
expect_ok "render bp" "$penumbra" render "$cornell" --method bp --preset paper --size 24x24 --spp 8 -o "$work/bp.pfm" --raw-out "$work/bp_raw.exr" --aov-dir "$work/aov" --stats "$work/bp.json" --threads 1 -q
for f in bias.exr bias.png network_error.png prediction.png selected.png slice_b.png slice_c.png samples.png traced.png alpha.png raw.exr reconstructed.exr; do
  [ -s "$work/aov/$f" ] || { echo "FAIL: --aov-dir lacks $f"; failures=$((failures + 1)); }
done
for key in kept_spp traced_spp rounds phases train select reconstruct trace error_estimate_histogram filter_scale_histogram per_round training_gflops difficult_pixels coarse_spp; do
  grep -q "\"$key\"" "$work/bp.json" || { echo "FAIL: bp stats lack $key"; failures=$((failures + 1)); }
done
grep -q '"kept_spp": 8.0' "$work/bp.json" && passes=$((passes + 1)) || { echo "FAIL: bp kept spp is not 8"; failures=$((failures + 1)); }
"$penumbra" render "$cornell" --method bp --preset paper --size 24x24 --spp 8 -o "$work/bp2.pfm" --threads 2 -q
cmp -s "$work/bp.pfm" "$work/bp2.pfm" && passes=$((passes + 1)) || { echo "FAIL: thread count changed the bp image"; failures=$((failures + 1)); }
expect_ok "bp ablations" "$penumbra" render "$cornell" --method bp --preset paper --size 16x16 --spp 8 -o "$work/bpa.exr" -q --inputs 5 --targets pixel-mean --prediction-draws 1 --candidate-mode predicted --no-warping --no-outlier-removal --no-second-pass --plain-mean --no-top-up --no-reconstruct --learning-rate proportional
expect_ok "bp tuned preset" "$penumbra" render "$cornell" --method bp --preset tuned --size 16x16 --spp 8 -o "$work/bpt.exr" --stats "$work/bpt.json" -q
grep -q '"preset": "tuned"' "$work/bpt.json" && grep -q '"traced_spp": 8.0' "$work/bpt.json" && passes=$((passes + 1)) || { echo "FAIL: tuned preset stats"; failures=$((failures + 1)); }
"$penumbra" render "$cornell" --method bp --preset tuned --sigma-c 0.2 --size 16x16 --spp 8 -o "$work/bpt2.exr" --stats "$work/bpt2.json" -q
grep -q '"sigma_c": 0.2' "$work/bpt2.json" && passes=$((passes + 1)) || { echo "FAIL: --sigma-c does not override the preset"; failures=$((failures + 1)); }
expect_fail "bad preset" "--preset" "$penumbra" render "$cornell" --method bp --preset best -o "$work/x.png"
expect_fail "bp phi count" "--phi" "$penumbra" render "$cornell" --method bp -o "$work/x.png" --phi 0.3,0.5
expect_fail "bp inputs" "--inputs" "$penumbra" render "$cornell" --method bp -o "$work/x.png" --inputs 6
expect_fail "raw out needs a filter" "--raw-out needs a method that filters" "$penumbra" render "$cornell" -o "$work/x.png" --raw-out "$work/rawx.exr"
expect_fail "variance out needs a variance" "--variance-out needs a method that keeps" "$penumbra" render "$cornell" --method bp --preset tuned -o "$work/x.png" --variance-out "$work/varx.exr"
# A flag the chosen algorithm does not read is an error naming the algorithm and who reads it.
expect_fail "paper flag on the consistent preset" "--no-warping: bp's consistent algorithm does not read it; it is read by bp's paper algorithm (--preset paper or tuned)" "$penumbra" render "$cornell" --method bp --size 16x16 -o "$work/x.png" --no-warping
expect_fail "bp flag on ld" "--nit: ld does not read it" "$penumbra" render "$cornell" --size 16x16 -o "$work/x.png" --nit 5
expect_fail "noise threshold needs an estimate" "--noise-threshold: bp's paper algorithm (--preset paper or tuned) has no error estimate" "$penumbra" render "$cornell" --method bp --preset paper --size 16x16 -o "$work/x.png" --noise-threshold 0.01
expect_fail "view noise threshold needs an estimate" "--noise-threshold: bp's paper algorithm (--preset paper or tuned) has no error estimate" env -u DISPLAY "$penumbra" view "$cornell" --headless --method bp --preset tuned --size 16x16 --noise-threshold 0.01 --screenshot "$work/x.png"
# Every baseline stops on the noise threshold, with its variance written.
for m in gem fdiv cycles; do
  expect_ok "noise threshold $m" "$penumbra" render "$cornell" --method $m --size 16x16 --noise-threshold 0.05 -o "$work/nt_$m.exr" --variance-out "$work/nt_${m}_var.exr" --stats "$work/nt_$m.json" -q
  check "$m stops on the noise threshold" python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert 0 < j["kept_spp"] < 4096, j["kept_spp"]
' "$work/nt_$m.json"
done
# The film's features and buffers: LD's --aov-dir writes them, and every map as one layered EXR.
expect_ok "ld aov dir" "$penumbra" render "$cornell" --size 16x16 --spp 4 -o "$work/ldaov.exr" --aov-dir "$work/ldaov" -q
for f in albedo.exr normal.exr depth.exr emission.exr raw_error.exr layers.exr; do
  [ -f "$work/ldaov/$f" ] && passes=$((passes + 1)) || { echo "FAIL: ld --aov-dir did not write $f"; failures=$((failures + 1)); }
done
# The default bp (the consistent preset), the filtered LD ablation and the stopping rules.
expect_ok "bp consistent with variance" "$penumbra" render "$cornell" --method bp --size 16x16 --spp 16 -o "$work/bpc.exr" --variance-out "$work/bpc_var.exr" --stats "$work/bpc.json" -q
grep -q '"preset": "consistent"' "$work/bpc.json" && grep -q '"algorithm": "consistent"' "$work/bpc.json" && passes=$((passes + 1)) || { echo "FAIL: bp's default preset is not consistent"; failures=$((failures + 1)); }
expect_ok "ld filtered" "$penumbra" render "$cornell" --filter --size 16x16 --spp 8 -o "$work/ldf.exr" --raw-out "$work/ldf_raw.exr" -q
expect_ok "time limit" "$penumbra" render "$cornell" --method bp --size 16x16 --time-limit 0.5 -o "$work/tl.exr" --stats "$work/tl.json" -q
python3 - "$work/tl.json" <<'PY' && passes=$((passes + 1)) || { echo "FAIL: --time-limit did not stop near 0.5 s"; failures=$((failures + 1)); }
import json, sys
s = json.load(open(sys.argv[1]))
assert 0.5 <= s["time_seconds"] < 5, s["time_seconds"]
PY
expect_ok "noise threshold" "$penumbra" render "$cornell" --size 16x16 --noise-threshold 0.02 -o "$work/nt.exr" --stats "$work/nt.json" -q
expect_fail "unknown method" "--method" "$penumbra" render "$cornell" --method magic -o "$work/x.png"

# The baselines through `render`: statistics, debug maps and the raw estimate.
for m in gem fuzzy cycles; do
  expect_ok "render $m" "$penumbra" render "$cornell" --method $m --spp 8 --size 16x16 -o "$work/$m.exr" --raw-out "$work/${m}_raw.exr" --stats "$work/$m.json" --aov-dir "$work/aov_$m" -q
  check "$m stats (method, kept spp, filter histogram)" python3 -c '
import json, sys
m, path = sys.argv[1], sys.argv[2]
j = json.load(open(path))
assert j["method"] == m, j["method"]
assert j["kept_spp"] == 8, j["kept_spp"]
assert j["width"] == 16 and j["height"] == 16
if m == "gem":
    h = j["filter_scale_histogram"]
    assert len(h["counts"]) == len(h["labels"]) and sum(h["counts"]) == 16 * 16, h
' $m "$work/$m.json"
  for f in "$work/$m.exr" "$work/${m}_raw.exr" "$work/aov_$m/bias.png"; do
    [ -s "$f" ] || { echo "FAIL: render --method $m did not write $f"; failures=$((failures + 1)); }
  done
done

# `penumbra reference`: the image, its variance and a JSON record of how converged it is.
ref="$work/ref/ref.exr"
expect_ok "reference" "$penumbra" reference "$cornell" --size 24x24 --spp 32 -o "$ref" -q
for f in ref.exr ref_var.exr ref.json; do
  [ -s "$work/ref/$f" ] || { echo "FAIL: reference did not write $f"; failures=$((failures + 1)); }
done
check "reference record" python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert j["spp"] == 32 and j["width"] == 24 and j["height"] == 24, j
assert j["time_seconds"] > 0 and j["residual_mse"] > 0, j
' "$work/ref/ref.json"
expect_fail "reference to a png" "must be linear" "$penumbra" reference "$cornell" --size 24x24 --spp 4 -o "$work/refx.png"
expect_fail "reference spp 0" "--spp" "$penumbra" reference "$cornell" --size 24x24 --spp 0 -o "$work/refx.exr"
[ -e "$work/refx.png" ] || [ -e "$work/refx.exr" ] && { echo "FAIL: a failed reference left an image"; failures=$((failures + 1)); }

# `penumbra compare`: five entries (a preset, a per-entry spp) times two seeds.
cmp="$work/cmp"
expect_ok "compare" "$penumbra" compare "$cornell" --size 24x24 --methods ld,fdiv,gem,bp:tuned,ld@32 --spp 8 --seeds 2 --reference "$ref" --out "$cmp"
grep -q "report.html: .* has the lowest MSE" "$work/out.txt" && passes=$((passes + 1)) || { echo "FAIL: compare printed no summary line"; failures=$((failures + 1)); }
check "results.csv: header and 10 rows" test "$(wc -l <"$cmp/results.csv")" -eq 11
check "results.csv header" grep -q '^label,seed,spp,kept_spp,' "$cmp/results.csv"
check "results.csv: every entry has seeds 1 and 2" test "$(cut -d, -f1,2 "$cmp/results.csv" | tail -n +2 | LC_ALL=C sort | tr '\n' ' ')" = "bp:tuned,1 bp:tuned,2 fdiv,1 fdiv,2 gem,1 gem,2 ld,1 ld,2 ld@32,1 ld@32,2 "
check "results.csv: ld@32 keeps 32 spp" test "$(awk -F, '$1 == "ld@32" && $3 == 32 && $4 == 32' "$cmp/results.csv" | wc -l)" -eq 2
check "results.csv: ld keeps 8 spp" test "$(awk -F, '$1 == "ld" && $4 == 8' "$cmp/results.csv" | wc -l)" -eq 2
check "results.json" python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
labels = [m["label"] for m in j["methods"]]
assert labels == ["ld", "fdiv", "gem", "bp:tuned", "ld@32"], labels
assert all(len(m["runs"]) == 2 for m in j["methods"])
assert j["winner"]["mse"] in labels, j["winner"]
best = min(j["methods"], key=lambda m: m["mse"]["mean"])["label"]
assert j["winner"]["mse"] == best, (j["winner"]["mse"], best)
assert [m["kept_spp"]["mean"] for m in j["methods"]] == [8, 8, 8, 8, 32]
' "$cmp/results.json"
check "report.html embeds its images" grep -q "data:image/png;base64," "$cmp/report.html"
check "report.html links nothing outside" bash -c '! grep -Eq "https?://" "$1"' _ "$cmp/report.html"
check "report.md has a gem row" grep -q '^| gem | ' "$cmp/report.md"
for f in ld.png ld_32.png gem.png bp_tuned.png; do
  check "images/$f is a PNG" test "$(head -c 4 "$cmp/images/$f" 2>/dev/null | tail -c 3)" = PNG
done

# Equal time: every run gets at least its 0.3 s, so LD adds rounds past its 8 spp.
expect_ok "compare equal time" "$penumbra" compare "$cornell" --size 24x24 --methods ld,gem --spp 8 --seeds 1 --equal-time 0.3 --reference "$ref" --out "$work/eqt" -q
check "equal time runs" python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert j["mode"].startswith("equal time"), j["mode"]
assert [m["label"] for m in j["methods"]] == ["ld", "gem"]
for m in j["methods"]:
    for r in m["runs"]:
        assert r["seconds"] >= 0.3, (m["label"], r["seconds"])
assert j["methods"][0]["runs"][0]["kept_spp"] > 8, j["methods"][0]["runs"][0]
' "$work/eqt/results.json"
# Time to quality: each run's curve in curves.csv and results.json, checkpoints in order,
# times increasing, every error finite, the tone-mapped MSE lower at the end than at the first
# checkpoint, and the last point the run's final numbers.
check "equal time curves" python3 -c '
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert list(rows[0].keys()) == ["label", "seed", "checkpoint", "seconds", "mse", "rel_mse",
                                "tone_mapped_mse", "kept_spp"], rows[0].keys()
j = json.load(open(sys.argv[2]))
for m in j["methods"]:
    run = m["runs"][0]
    points = [r for r in rows if r["label"] == m["label"] and r["seed"] == "1"]
    assert len(points) >= 3 and len(points) == len(run["curve"]), (m["label"], len(points))
    checkpoints = [int(p["checkpoint"]) for p in points]
    assert checkpoints[-1] == -1 and checkpoints[:-1] == sorted(set(checkpoints[:-1])), checkpoints
    assert all(0 <= c < 8 for c in checkpoints[:-1]), checkpoints
    seconds = [float(p["seconds"]) for p in points]
    assert seconds[0] > 0 and all(a < b for a, b in zip(seconds, seconds[1:])), seconds
    for p in points:
        for key in ("mse", "rel_mse", "tone_mapped_mse", "kept_spp"):
            assert math.isfinite(float(p[key])) and float(p[key]) >= 0, (m["label"], key, p)
    kept = [float(p["kept_spp"]) for p in points]
    assert all(a <= b for a, b in zip(kept, kept[1:])), kept
    tone = [float(p["tone_mapped_mse"]) for p in points]
    assert tone[-1] < tone[0], (m["label"], tone)
    assert math.isclose(float(points[-1]["mse"]), run["mse"], rel_tol=1e-12), (points[-1], run)
    assert math.isclose(seconds[-1], run["seconds"], rel_tol=1e-12) and seconds[-1] >= 0.3, run
' "$work/eqt/curves.csv" "$work/eqt/results.json"
check "equal time report.html has the two curve charts" test "$(grep -o '<svg class="chart curve"' "$work/eqt/report.html" | wc -l)" -eq 2
check "report.md has the time-to-quality table" grep -q '^## Time to quality' "$work/eqt/report.md"
# Equal spp: the checkpoints are at kept spp 1, 2, 4 (LD) and the end; --no-curve measures no
# curve and leaves the final numbers as they are with one (the same final snapshot).
check "equal spp curves" python3 -c '
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["label"] == "ld" and r["seed"] == "1"]
assert [r["checkpoint"] for r in rows] == ["0", "1", "2", "-1"], rows
assert [float(r["kept_spp"]) for r in rows] == [1, 2, 4, 8], rows
' "$cmp/curves.csv"
nocurve="$work/nocurve"
expect_ok "compare --no-curve" "$penumbra" compare "$cornell" --size 24x24 --methods ld,gem,bp:tuned --spp 8 --seeds 2 --reference "$ref" --out "$nocurve" -q --no-curve
check "--no-curve: curves.csv has only its header" test "$(wc -l <"$nocurve/curves.csv")" -eq 1
check "--no-curve: no curve in results.json, report.html or report.md" python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
assert all(run["curve"] == [] for m in j["methods"] for run in m["runs"]), j["methods"][0]["runs"]
assert "Time to quality" not in open(sys.argv[2]).read()
assert "Time to quality" not in open(sys.argv[3]).read()
' "$nocurve/results.json" "$nocurve/report.html" "$nocurve/report.md"
check "--no-curve: the same final numbers as with curves" python3 -c '
import json, sys
def finals(path):
    return {(m["label"], r["seed"]): [r[k] for k in ("mse", "rel_mse", "tone_mapped_mse", "kept_spp",
                                                      "traced_spp")]
            for m in json.load(open(path))["methods"] for r in m["runs"]}
with_curves, without = finals(sys.argv[1]), finals(sys.argv[2])
assert len(without) == 6, without
for key, values in without.items():
    assert with_curves[key] == values, (key, with_curves[key], values)
' "$cmp/results.json" "$nocurve/results.json"

# Bad compares: one line naming the problem, and no report in the output folder.
bad="$work/bad"
compare_args=(compare "$cornell" --size 24x24 --spp 2 --seeds 1 --reference "$ref")
expect_fail "compare unknown method" "unknown method 'magic'" "$penumbra" "${compare_args[@]}" --methods ld,magic --out "$bad"
expect_fail "compare unknown modifier" "unknown modifier 'fast' in 'ld:fast'" "$penumbra" "${compare_args[@]}" --methods ld:fast --out "$bad"
expect_fail "compare preset on a baseline" "unknown modifier 'tuned' in 'gem:tuned'" "$penumbra" "${compare_args[@]}" --methods gem:tuned --out "$bad"
expect_fail "compare duplicate entry" "'ld' is listed twice" "$penumbra" "${compare_args[@]}" --methods ld,gem,ld --out "$bad"
expect_fail "compare bad entry spp" "ld@0: expected a positive whole number" "$penumbra" "${compare_args[@]}" --methods ld@0 --out "$bad"
expect_fail "compare trailing comma" "empty entry in 'ld,'" "$penumbra" "${compare_args[@]}" --methods ld, --out "$bad"
expect_fail "compare 8-bit reference" "a reference must be linear" "$penumbra" compare "$cornell" --size 24x24 --methods ld --reference "$work/x.png" --out "$bad"
expect_fail "compare missing reference" "nothere.exr: no such file (render one with \`penumbra reference" "$penumbra" compare "$cornell" --size 24x24 --methods ld --reference "$work/nothere.exr" --out "$bad"
expect_fail "compare reference size" "is 24x24 but the render is 16x16 (give --size)" "$penumbra" compare "$cornell" --size 16x16 --methods ld --reference "$ref" --out "$bad"
expect_fail "compare crop outside" "--crop 20,20,8,8: outside the 24x24 image" "$penumbra" "${compare_args[@]}" --methods ld --crop 20,20,8,8 --out "$bad"
expect_fail "compare without --out" "--out" "$penumbra" "${compare_args[@]}" --methods ld
[ -e "$bad/results.json" ] && { echo "FAIL: a failed compare left results.json"; failures=$((failures + 1)); }
# A compare that fails while writing leaves no partial results.json and no temporaries.
mkdir -p "$work/broken/report.md"
expect_fail "compare unwritable report" "report.md" "$penumbra" "${compare_args[@]}" --methods ld --out "$work/broken" -q
[ ! -e "$work/broken/results.json" ] || python3 -c 'import json, sys; json.load(open(sys.argv[1]))' "$work/broken/results.json" ||
  { echo "FAIL: a failed compare left a partial results.json"; failures=$((failures + 1)); }
[ -n "$(find "$work/broken" -name '*.tmp-*')" ] && { echo "FAIL: a failed compare left temporary files"; failures=$((failures + 1)); }

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
check "view with reference wrote its screenshot" test -s "$work/ui.png"
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

# The environment. An OBJ file with no lights opens lit by the built-in environment and says so;
# --env none turns it off; a JSON scene is the author's and gets none.
printf 'v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n' >"$work/quad.obj"
"$penumbra" render "$work/quad.obj" --size 16x16 --spp 1 -q -o "$work/quad.png" 2>"$work/quad_err.txt"
check "an unlit OBJ notes the built-in environment" grep -q "built-in studio environment lights it (--env none turns it off" "$work/quad_err.txt"
"$penumbra" render "$work/quad.obj" --env none --size 16x16 --spp 1 -q -o "$work/quad_dark.png" 2>"$work/quad_err.txt"
check "--env none: no note" test ! -s "$work/quad_err.txt"
"$penumbra" render "$cornell" --size 16x16 --spp 1 -q -o "$work/c.png" 2>"$work/c_err.txt"
check "a JSON scene gets no default environment" test ! -s "$work/c_err.txt"
expect_ok "render under an environment map" "$penumbra" render "$cornell" --env "$src/scenes/env/sky.hdr" --env-strength 2 --env-rotation 90 --size 16x16 --spp 1 -q -o "$work/sky.png"
expect_ok "transparent EXR" "$penumbra" render "$work/quad.obj" --transparent --size 16x16 --spp 1 -q -o "$work/quad.exr"
expect_fail "missing environment map" "nowhere.hdr" "$penumbra" render "$cornell" --env "$work/nowhere.hdr" -o "$work/x.png"
expect_fail "strength without an environment" "--env-strength" "$penumbra" render "$cornell" --env-strength 2 -o "$work/x.png"
expect_fail "transparent PFM" "PFM cannot hold" "$penumbra" render "$cornell" --transparent -o "$work/x.pfm"
printf '{"materials": {"m": {"type": "diffuse"}}, "objects": [{"shape": "sphere", "material": "m"}], "environment": {"file": "nowhere.hdr"}}' >"$work/env_missing.json"
expect_fail "scene with a missing environment map" "environment.file" "$penumbra" render "$work/env_missing.json" -o "$work/x.png"
printf 'not a picture' >"$work/bad.hdr"
expect_fail "malformed environment map" "bad.hdr: cannot decode image" "$penumbra" render "$cornell" --env "$work/bad.hdr" -o "$work/x.png"
[ -e "$work/x.png" ] && { echo "FAIL: a failed render left an image"; failures=$((failures + 1)); }

echo "$passes passed, $failures failed"
[ $failures -eq 0 ]
