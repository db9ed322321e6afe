#!/usr/bin/env bash
# Every malformed input file, of every parser, gets a clear error and leaves no output file.
# Each case renders a damaged file (directly, or through a JSON scene that uses it as a mesh or
# a texture) and must: exit with status 1 or 2 (not 0, not a signal), within 20 s; print one
# line on stderr naming the damaged file and the place (line, byte, element or field); and
# leave neither the output image nor a temporary file behind. A control renders each file's
# undamaged form first, so every error comes from the one defect.
# Usage: malformed_files_test.sh PENUMBRA SOURCE_DIR
#
# The kinds (32):
#   OBJ   1  a coordinate that is not a number (v 0 zero 0)
#         2  a face index past the vertex count
#         3  a face index 0 (OBJ counts from 1)
#         4  a face with 2 vertices
#         5  a truncated last line (v 1 2)
#         6  an MTL number that is not a number (Kd 0.5 x 0.5)
#   PLY   7  a binary body cut off in the middle of the faces
#         8  a header element count larger than the data holds
#         9  a face index out of range
#        10  an unknown format line (binary_middle_endian)
#        11  no end_header
#   glTF 12  invalid JSON (cut off)
#        13  an accessor whose elements run past its buffer view
#        14  an index past the vertex count
#        15  a buffer URI with http:// (network refused)
#        16  a buffer URI that is an absolute path
#        17  a buffer URI naming a missing .bin file
#        18  a .glb cut off in its JSON chunk
#        19  a .glb with the wrong magic (glTX)
#        20  a node that is its own ancestor (a cycle)
#        21  --camera naming a camera the file lacks
#        31  a node's KHR_lights_punctual naming a light the file lacks
#        32  animation keyframe times that go backwards
#   JSON 22  a syntax error (reported as file:line:column)
#        23  an object using an unknown material
#        24  a mesh file that does not exist
#        25  a sphere of negative radius
#   images used as textures
#        26  a PNG cut off in its IDAT chunk
#        27  a PNG whose chunk length runs past the end of the file
#        28  an EXR cut off in its pixel data
#        29  a PFM whose header has no height
#        30  a PFM whose pixel data is shorter than its header says
#
# Not a case: an OBJ whose mtllib names a missing file renders with the default material (and
# a warning naming the library).
set -u
penumbra=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
passes=0
n=0

# expect_error "description" NAME "fragment" render-arguments...: renders to a fresh output
# file and checks the outcome above; NAME is the damaged file's name, the fragment gives the
# place and the gist of the message.
expect_error() {
  local what=$1 name=$2 expected=$3
  shift 3
  n=$((n + 1))
  local out="$work/out_$n.png" err status problem=""
  timeout 20 "$penumbra" render "$@" --size 8x8 --spp 1 -o "$out" >/dev/null 2>"$work/err.txt"
  status=$?
  err=$(cat "$work/err.txt")
  if [ $status -eq 0 ]; then problem="exited 0"
  elif [ $status -eq 124 ]; then problem="did not finish within 20 s"
  elif [ $status -ge 128 ]; then problem="crashed (status $status)"
  elif [ $status -gt 2 ]; then problem="exit status $status"
  elif [ "$(printf '%s\n' "$err" | wc -l)" -ne 1 ]; then problem="expected one line on stderr"
  elif [[ "$err" != *"$name"* ]]; then problem="the message does not name $name"
  elif [[ "$err" != *"$expected"* ]]; then problem="expected '$expected'"
  fi
  [ -z "$problem" ] && [ -e "$out" ] && problem="left the output file"
  [ -z "$problem" ] && [ -n "$(find "$work" -name '*.tmp-*')" ] && problem="left a temporary file"
  if [ -z "$problem" ]; then
    echo "ok: $what"; passes=$((passes + 1))
  else
    echo "FAIL: $what: $problem; stderr:"; printf '  %s\n' "$err"; failures=$((failures + 1))
  fi
}

# expect_render "description" render-arguments...: the undamaged form renders.
expect_render() {
  local what=$1
  shift
  if timeout 20 "$penumbra" render "$@" --size 8x8 --spp 1 -o "$work/control.png" -q 2>"$work/err.txt"; then
    echo "ok: control: $what"; passes=$((passes + 1))
  else
    echo "FAIL: control: $what:"; sed 's/^/  /' "$work/err.txt"; failures=$((failures + 1))
  fi
}

# mesh_scene NAME FILE / texture_scene NAME FILE: a JSON scene $work/NAME.json that uses FILE
# as a mesh, or as the image texture of a sphere.
mesh_scene() {
  printf '{"materials": {"m": {"type": "diffuse"}},\n "objects": [{"shape": "mesh", "file": "%s", "material": "m"}]}\n' \
    "$2" >"$work/$1.json"
}
texture_scene() {
  printf '{"textures": {"t": {"type": "image", "file": "%s"}},\n "materials": {"m": {"type": "diffuse", "albedo": "t"}},\n "objects": [{"shape": "sphere", "material": "m"}]}\n' \
    "$2" >"$work/$1.json"
}

# ---- OBJ and MTL ----------------------------------------------------------------------------
obj() { printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n%b' "$1"; }
obj 'f 1 2 3\n' >"$work/tri.obj"
expect_render "OBJ triangle" "$work/tri.obj"
printf 'v 0 zero 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$work/obj_nan.obj"
expect_error "OBJ: non-number coordinate" obj_nan.obj "obj_nan.obj:1: 'v' y: 'zero' is not a number" "$work/obj_nan.obj"
obj 'f 1 2 4\n' >"$work/obj_past.obj"
expect_error "OBJ: face index past the vertex count" obj_past.obj "out of bounds (line 4" "$work/obj_past.obj"
obj 'f 0 1 2\n' >"$work/obj_zero.obj"
expect_error "OBJ: face index 0" obj_zero.obj "obj_zero.obj:4: 'f' corner 1, vertex index 0" "$work/obj_zero.obj"
obj 'f 1 2\n' >"$work/obj_two.obj"
expect_error "OBJ: face with 2 vertices" obj_two.obj "obj_two.obj:4: 'f' needs at least 3 vertices" "$work/obj_two.obj"
obj 'f 1 2 3\nv 1 2' >"$work/obj_cut.obj"
expect_error "OBJ: truncated line" obj_cut.obj "obj_cut.obj:5: 'v' needs 3 to 7 numbers, got 2" "$work/obj_cut.obj"
obj 'mtllib lib.mtl\nusemtl m\nf 1 2 3\n' >"$work/mtl.obj"
printf 'newmtl m\nKd 0.5 0.5 0.5\n' >"$work/lib.mtl"
expect_render "OBJ with an MTL library" "$work/mtl.obj"
obj 'mtllib bad.mtl\nusemtl m\nf 1 2 3\n' >"$work/mtl_bad.obj"
printf 'newmtl m\nKd 0.5 x 0.5\n' >"$work/bad.mtl"
expect_error "MTL: non-number colour" bad.mtl "bad.mtl:2: 'Kd' g: 'x' is not a number" "$work/mtl_bad.obj"

# ---- binary files: PLY bodies, glTF and .glb ---------------------------------------------------
# Written here: ply_tri.bin (a triangle as a binary PLY body), gltf_*.gltf and *.glb (a
# triangle with a camera "Cam": gltf_ok and ok.glb as they should be, the others damaged).
python3 - "$work" <<'EOF'
import base64, json, struct, sys
work = sys.argv[1]
positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
open(f"{work}/ply_tri.bin", "wb").write(positions + struct.pack("<B3i", 3, 0, 1, 2))

def model(uri=None, count=3, indices=(0, 1, 2), children=()):
    data = positions + struct.pack("<3H", *indices) + b"\0\0"
    return {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
            "nodes": [{"mesh": 0, "children": list(children)},
                      {"name": "Cam", "camera": 0, "translation": [0.3, 0.3, 3]}],
            "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
                           "min": [0, 0, 0], "max": [1, 1, 0]},
                          {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
            "bufferViews": [{"buffer": 0, "byteLength": 36},
                            {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
            "buffers": [{"uri": uri or "data:application/octet-stream;base64," +
                         base64.b64encode(data).decode(), "byteLength": len(data)}]}

gltfs = {"ok": model(), "accessor": model(count=4), "index": model(indices=(0, 1, 5)),
         "http": model(uri="http://example.com/tri.bin"), "absolute": model(uri="/nowhere/tri.bin"),
         "nobin": model(uri="missing.bin"), "cycle": model(children=[0])}
gltfs["light"] = model()
gltfs["light"]["nodes"][0]["extensions"] = {"KHR_lights_punctual": {"light": 5}}
keys = struct.pack("<2f", 1, 0) + struct.pack("<6f", 0, 0, 0, 1, 0, 0)
gltfs["anim"] = model()
gltfs["anim"]["buffers"].append({"uri": "data:application/octet-stream;base64," +
                                 base64.b64encode(keys).decode(), "byteLength": len(keys)})
gltfs["anim"]["bufferViews"] += [{"buffer": 1, "byteLength": 8},
                                 {"buffer": 1, "byteOffset": 8, "byteLength": 24}]
gltfs["anim"]["accessors"] += [{"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR"},
                               {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"}]
gltfs["anim"]["animations"] = [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
                                "samplers": [{"input": 2, "output": 3}]}]
for name, m in gltfs.items():
    open(f"{work}/gltf_{name}.gltf", "w").write(json.dumps(m))
open(f"{work}/gltf_syntax.gltf", "w").write(json.dumps(model())[:120])

glb_model = model()
del glb_model["buffers"][0]["uri"]
js = json.dumps(glb_model).encode()
js += b" " * (-len(js) % 4)
data = positions + struct.pack("<3H", 0, 1, 2) + b"\0\0"
glb = (b"glTF" + struct.pack("<2I", 2, 12 + 8 + len(js) + 8 + len(data)) +
       struct.pack("<I", len(js)) + b"JSON" + js + struct.pack("<I", len(data)) + b"BIN\0" + data)
open(f"{work}/ok.glb", "wb").write(glb)
open(f"{work}/cut.glb", "wb").write(glb[:20 + len(js) // 2])
open(f"{work}/magic.glb", "wb").write(b"glTX" + glb[4:])
EOF

# ---- PLY ------------------------------------------------------------------------------------
# ply_header FORMAT VERTICES FACES
ply_header() {
  printf 'ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n' "$1" "$2"
  printf 'element face %d\nproperty list uchar int vertex_indices\nend_header\n' "$3"
}
{ ply_header ascii 3 1; printf '0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n'; } >"$work/ascii.ply"
{ ply_header binary_little_endian 3 1; cat "$work/ply_tri.bin"; } >"$work/binary.ply"
mesh_scene ply_ascii ascii.ply
mesh_scene ply_binary binary.ply
expect_render "PLY ascii" "$work/ply_ascii.json"
expect_render "PLY binary" "$work/ply_binary.json"
head -c -7 "$work/binary.ply" >"$work/ply_cut.ply"
mesh_scene ply_cut ply_cut.ply
expect_error "PLY: truncated binary body" ply_cut.ply "truncated binary data in element 'face' at byte" "$work/ply_cut.json"
{ ply_header binary_little_endian 1000 1; cat "$work/ply_tri.bin"; } >"$work/ply_count.ply"
mesh_scene ply_count ply_count.ply
expect_error "PLY: element count larger than the data" ply_count.ply "element 'vertex' declares 1000 entries, more than" "$work/ply_count.json"
{ ply_header ascii 3 1; printf '0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n'; } >"$work/ply_index.ply"
mesh_scene ply_index ply_index.ply
expect_error "PLY: face index out of range" ply_index.ply "face 0: vertex index 7 out of range" "$work/ply_index.json"
{ ply_header binary_middle_endian 3 1; cat "$work/ply_tri.bin"; } >"$work/ply_format.ply"
mesh_scene ply_format ply_format.ply
expect_error "PLY: unknown format line" ply_format.ply "line 2: unknown format 'binary_middle_endian'" "$work/ply_format.json"
{ ply_header ascii 3 1 | grep -v end_header; printf '0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n'; } >"$work/ply_noend.ply"
mesh_scene ply_noend ply_noend.ply
expect_error "PLY: missing end_header" ply_noend.ply "line 9: unknown header keyword" "$work/ply_noend.json"

# ---- glTF -----------------------------------------------------------------------------------
expect_render "glTF triangle" "$work/gltf_ok.gltf" --camera Cam
expect_render "glb triangle" "$work/ok.glb"
expect_error "glTF: invalid JSON" gltf_syntax.gltf "parse error at line 1, column 121" "$work/gltf_syntax.gltf"
expect_error "glTF: accessor past its buffer view" gltf_accessor.gltf "POSITION (accessors[0]): 4 elements run past the end" "$work/gltf_accessor.gltf"
expect_error "glTF: index past the vertex count" gltf_index.gltf "indices (accessors[1]): index 5" "$work/gltf_index.gltf"
expect_error "glTF: http:// buffer URI" gltf_http.gltf "buffers[0].uri: URI 'http://example.com/tri.bin' names a network location" "$work/gltf_http.gltf"
expect_error "glTF: absolute-path buffer URI" gltf_absolute.gltf "buffers[0].uri: URI '/nowhere/tri.bin' is an absolute path" "$work/gltf_absolute.gltf"
expect_error "glTF: missing .bin file" gltf_nobin.gltf "not found : missing.bin" "$work/gltf_nobin.gltf"
expect_error "glb: truncated in its JSON chunk" cut.glb "JSON chunk of" "$work/cut.glb"
expect_error "glb: wrong magic" magic.glb "not a binary glTF file (no 'glTF' header)" "$work/magic.glb"
expect_error "glTF: node its own ancestor" gltf_cycle.gltf "nodes[0]: is its own ancestor" "$work/gltf_cycle.gltf"
expect_error "glTF: --camera names no camera" gltf_ok.gltf "no camera named 'Nope' (there are: Cam)" "$work/gltf_ok.gltf" --camera Nope
expect_error "glTF: a light the file lacks" gltf_light.gltf "nodes[0].extensions.KHR_lights_punctual.light: light 5 does not exist" "$work/gltf_light.gltf"
expect_error "glTF: keyframes going backwards" gltf_anim.gltf "animations[0].channels[0].input (accessors[2]): keyframe time 0 at 1" "$work/gltf_anim.gltf"

# ---- JSON scenes ----------------------------------------------------------------------------
printf '{"materials": {\n  "m": {"type": "diffuse",}\n}}' >"$work/json_syntax.json"
expect_error "JSON: syntax error" json_syntax.json "json_syntax.json:2:27: syntax error" "$work/json_syntax.json"
printf '{"materials": {"m": {"type": "diffuse"}}, "objects": [{"shape": "sphere", "material": "n"}]}' >"$work/json_material.json"
expect_error "JSON: unknown material" json_material.json "objects[0].material: unknown material 'n'" "$work/json_material.json"
mesh_scene json_nomesh nowhere.ply
expect_error "JSON: missing mesh file" nowhere.ply "objects[0].file: cannot open" "$work/json_nomesh.json"
printf '{"materials": {"m": {"type": "diffuse"}}, "objects": [{"shape": "sphere", "radius": -1, "material": "m"}]}' >"$work/json_radius.json"
expect_error "JSON: negative sphere radius" json_radius.json "objects[0].radius: expected a positive number" "$work/json_radius.json"

# ---- images used as textures ----------------------------------------------------------------
"$penumbra" render "$src/scenes/cornell.json" --size 8x8 --spp 1 -o "$work/good.png" -q
"$penumbra" render "$src/scenes/cornell.json" --size 8x8 --spp 1 -o "$work/good.exr" -q
printf 'PF\n4 4\n-1.0\n' >"$work/good.pfm"
head -c 192 /dev/zero >>"$work/good.pfm"
for f in good.png good.exr good.pfm; do
  texture_scene "tex_$f" "$f"
  expect_render "texture $f" "$work/tex_$f.json"
done
head -c 60 "$work/good.png" >"$work/cut.png"
texture_scene tex_cut_png cut.png
expect_error "PNG: truncated" cut.png "truncated or damaged PNG: chunk 'IDAT' at byte 33" "$work/tex_cut_png.json"
cp "$work/good.png" "$work/chunk.png"
# The second chunk (IDAT, at byte 33) claims 2 GB.
printf '\177\377\377\000' | dd of="$work/chunk.png" bs=1 seek=33 conv=notrunc status=none
texture_scene tex_chunk_png chunk.png
expect_error "PNG: corrupt chunk length" chunk.png "chunk 'IDAT' at byte 33 claims 2147483392 bytes" "$work/tex_chunk_png.json"
head -c $(($(stat -c %s "$work/good.exr") / 2)) "$work/good.exr" >"$work/cut.exr"
texture_scene tex_cut_exr cut.exr
expect_error "EXR: truncated" cut.exr "unexpected end of file at byte" "$work/tex_cut_exr.json"
{ printf 'PF\n4 x\n-1.0\n'; head -c 192 /dev/zero; } >"$work/header.pfm"
texture_scene tex_header_pfm header.pfm
expect_error "PFM: bad header" header.pfm "malformed PFM header (expected width and height)" "$work/tex_header_pfm.json"
head -c -92 "$work/good.pfm" >"$work/short.pfm"
texture_scene tex_short_pfm short.pfm
expect_error "PFM: data shorter than the header says" short.pfm "truncated pixel data (4x4 pixels of 12 bytes, but only 100 bytes" "$work/tex_short_pfm.json"

echo "$n malformed files; $passes passed, $failures failed"
[ $failures -eq 0 ]
