#!/usr/bin/env python3
"""Generate the "studio" glTF 2.0 test scene, which exercises every glTF feature Penumbra reads.

A small photo studio, made here from scratch (Blender's export conventions: Y up, metres,
metallic-roughness materials, cameras and lights looking along their node's -Z):
  * cameras "Camera" (front view, the default: it is the first camera node) and "Top" (from above);
  * a 4 m x 4 m tiled floor: base colour texture, tangent-space normal map and TANGENTs;
  * a plain back wall; a brass uv sphere (metallic 0.6 on purpose); a textured crate rotated
    30 degrees about Y; a red torus "Spinner" with a LINEAR translation + rotation animation;
  * an emissive ceiling panel (emissive texture, KHR_materials_emissive_strength);
  * a double-sided leaf cut-out (RGBA texture, alphaMode MASK);
  * KHR_lights_punctual: spot light "Key" and point light "Fill".

Tangent-space conventions (glTF): bitangent = cross(normal, tangent.xyz) * tangent.w, and the
normal map's +Y (green) is "up" in the image, so the bitangent points towards the top of the
image, i.e. towards *decreasing* v (glTF's uv origin is the image's top-left, v runs down).
This is what Blender exports (its v runs up) and what the Khronos sample viewer assumes.

Output (deterministic, byte-identical on every run): studio.gltf (sorted, indented JSON),
studio.bin (one little-endian buffer) and textures/*.png (written by a minimal PNG writer).
The files are re-read and checked at the end.  Standard library and numpy only.  Usage:
    python3 scripts/make_studio.py [--out DIR]     (default scenes/studio)
"""
import argparse
import json
import math
import os
import struct
import sys
import zlib

import numpy as np

F32, U16, U32 = 5126, 5123, 5125                   # glTF componentType codes
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
DTYPES = {F32: "<f4", U16: "<u2", U32: "<u4"}


def r6(x):
    """A float for the JSON: 6 decimals, never -0.0."""
    return round(float(x), 6) + 0.0


def normalize(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


# ------------------------------------------------------------------------- rotations
def quat_axis_angle(axis, degrees):
    """Unit quaternion (x, y, z, w) for a rotation about `axis`."""
    h = math.radians(degrees) / 2
    a = normalize(axis) * math.sin(h)
    return [a[0], a[1], a[2], math.cos(h)]


def quat_mul(a, b):
    """The Hamilton product a * b of quaternions (x, y, z, w): b's rotation, then a's."""
    av, bv = np.array(a[:3], dtype=np.float64), np.array(b[:3], dtype=np.float64)
    return [*(a[3] * bv + b[3] * av + np.cross(av, bv)), a[3] * b[3] - np.dot(av, bv)]


def look_at(eye, target):
    """Rotation of a node at `eye` whose -Z looks at `target`, with +Y up (no roll): a pitch
    about X, then a yaw about Y.  (Not for looking straight up or down.)"""
    f = normalize(np.subtract(target, eye))
    yaw, pitch = math.atan2(-f[0], -f[2]), math.asin(f[1])
    return quat_mul(quat_axis_angle((0, 1, 0), math.degrees(yaw)),
                    quat_axis_angle((1, 0, 0), math.degrees(pitch)))


# ---------------------------------------------------------------------------- meshes
def orient(pos, nrm, tris):
    """Triangles wound counter-clockwise seen from the side their vertex normals point to."""
    tris = np.asarray(tris, dtype=np.int64)
    a, b, c = pos[tris[:, 0]], pos[tris[:, 1]], pos[tris[:, 2]]
    face = np.cross(b - a, c - a)
    flip = np.einsum("ij,ij->i", face, nrm[tris].sum(axis=1)) < 0
    tris[flip] = tris[flip][:, [0, 2, 1]]
    return tris


def quad(corners, normal, uvs):
    """One quad from 4 corners (in order around it) with their uvs."""
    pos = np.array(corners, dtype=np.float64)
    nrm = np.tile(normalize(normal), (4, 1))
    return {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": np.array(uvs, dtype=np.float64),
            "indices": orient(pos, nrm, [(0, 1, 2), (0, 2, 3)])}


def local_quad(w, h):
    """A w x h quad centred on the origin in the local XY plane, facing +Z, image upright."""
    return quad([(-w / 2, -h / 2, 0), (w / 2, -h / 2, 0), (w / 2, h / 2, 0), (-w / 2, h / 2, 0)],
                (0, 0, 1), [(0, 1), (1, 1), (1, 0), (0, 0)])


def floor_mesh():
    """4 m x 4 m at y = 0, x in [-2, 2], z in [-1.5, 2.5] (its back edge meets the wall).
    u runs along +x, v along +z (the image's top at the back), 4 repeats each way.
    TANGENT: +x (increasing u); w = +1 so that cross(+Y, +X) * w = -Z, the image's up."""
    m = quad([(-2, 0, 2.5), (2, 0, 2.5), (2, 0, -1.5), (-2, 0, -1.5)], (0, 1, 0),
             [(0, 4), (4, 4), (4, 0), (0, 0)])
    m["TANGENT"] = np.tile([1.0, 0.0, 0.0, 1.0], (4, 1))
    return m


def surface(rows, cols, shape, poles=False):
    """A (rows+1) x (cols+1) grid of vertices at uvs (u, v) spanning [0, 1]^2, placed by
    shape(u, v) -> (positions, normals); two triangles a cell, less the degenerate ones when
    `poles` (the first and the last row each collapse to a point)."""
    u, v = np.meshgrid(np.linspace(0, 1, cols + 1), np.linspace(0, 1, rows + 1))
    pos, nrm = (a.reshape(-1, 3) for a in shape(u, v))
    tris = []
    for i in range(rows):
        for j in range(cols):
            a = i * (cols + 1) + j
            if not (poles and i == 0): tris.append((a, a + cols + 1, a + 1))
            if not (poles and i == rows - 1): tris.append((a + 1, a + cols + 1, a + cols + 2))
    return {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": np.stack([u, v], -1).reshape(-1, 2),
            "indices": orient(pos, nrm, tris)}


def sphere_mesh(radius, seg=48, rings=24):
    """uv sphere: u around (seam duplicated), v = 0 at the north pole."""
    def shape(u, v):
        th, ph = v * math.pi, u * 2 * math.pi
        n = np.stack([np.sin(th) * np.cos(ph), np.cos(th), -np.sin(th) * np.sin(ph)], -1)
        n[np.abs(n) < 1e-12] = 0.0                  # exact poles and equator
        return n * radius, n
    return surface(rings, seg, shape, poles=True)


def torus_mesh(major, minor, seg=48, sides=24):
    """Torus around the local Z axis (standing up, facing the camera at rest); u runs around
    the ring, v around the tube."""
    def shape(u, v):
        a, b = u * 2 * math.pi, v * 2 * math.pi
        ring = np.stack([np.cos(a), np.sin(a), 0 * a], -1)
        n = ring * np.cos(b)[..., None] + np.array([0, 0, 1.0]) * np.sin(b)[..., None]
        return ring * major + n * minor, n
    return surface(sides, seg, shape)


def box_mesh(size):
    """Cube with flat normals and each face's uvs the full [0, 1]^2, image upright on the
    sides; (s, t) are a face's image right and up directions, s x t = its normal."""
    h, parts = size / 2, []
    faces = [((1, 0, 0), (0, 0, -1), (0, 1, 0)), ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
             ((0, 0, 1), (1, 0, 0), (0, 1, 0)), ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
             ((0, 1, 0), (1, 0, 0), (0, 0, -1)), ((0, -1, 0), (1, 0, 0), (0, 0, 1))]
    for n, s, t in faces:
        n, s, t = (np.array(v, dtype=np.float64) for v in (n, s, t))
        corners = [h * (n + i * s + j * t) for i, j in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
        parts.append(quad(corners, n, [(0, 1), (1, 1), (1, 0), (0, 0)]))
    out = {k: np.concatenate([p[k] for p in parts]) for k in ("POSITION", "NORMAL", "TEXCOORD_0")}
    out["indices"] = np.concatenate([p["indices"] + 4 * i for i, p in enumerate(parts)])
    return out


# -------------------------------------------------------------------------- textures
def png_bytes(img):
    """Minimal PNG: 8-bit RGB or RGBA, filter 0 on every row, zlib level 9."""
    img = np.ascontiguousarray(img, dtype=np.uint8)
    h, w, c = img.shape
    raw = b"".join(b"\x00" + img[y].tobytes() for y in range(h))
    def chunk(kind, data):
        crc = zlib.crc32(kind + data)
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)
    ihdr = struct.pack(">IIBBBBB", w, h, 8, {3: 2, 4: 6}[c], 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9))
            + chunk(b"IEND", b""))


def hash01(x, y, seed):
    """Deterministic per-integer-coordinate noise in [0, 1)."""
    h = (x.astype(np.uint32) * np.uint32(374761393) + y.astype(np.uint32) * np.uint32(668265263)
         + np.uint32(seed * 2654435761 % 2**32))
    h = (h ^ (h >> np.uint32(13))) * np.uint32(1274126177)
    return (h ^ (h >> np.uint32(16))).astype(np.float64) / 2.0**32


def pixel_grid(size):
    """Pixel column and row indices of a square image (row 0 is the top of the image)."""
    return np.meshgrid(np.arange(size), np.arange(size))


TILE, GROUT, BEVEL, BEVEL_DEPTH = 128, 2.5, 6.0, 3.5   # pixels: 2 x 2 tiles per texture


def tile_textures(size=256):
    """Tiles' base colour and their tangent-space normal map (tile edges bevelled down)."""
    px, py = pixel_grid(size)
    fx, fy = (px + 0.5) % TILE, (py + 0.5) % TILE
    edge = np.minimum(np.minimum(fx, TILE - fx), np.minimum(fy, TILE - fy))   # to the grout
    tx, ty = px // TILE, py // TILE
    light = ((tx + ty) % 2 == 0)[..., None]
    tone = 0.94 + 0.06 * hash01(tx, ty, 1)[..., None] + 0.03 * (hash01(px, py, 2)[..., None] - 0.5)
    tile = np.where(light, [205, 196, 182], [148, 136, 122]) * tone
    grout = np.array([72, 66, 60]) * (1 + 0.1 * (hash01(px, py, 3)[..., None] - 0.5))
    color = np.where((edge < GROUT)[..., None], grout, tile)
    b = np.clip((edge - GROUT) / BEVEL, 0, 1)
    height = BEVEL_DEPTH * b * b * (3 - 2 * b)                    # smoothstep: a rounded bevel
    dhdx = (np.roll(height, -1, 1) - np.roll(height, 1, 1)) / 2    # wraps, as the sampler does
    dhdrow = (np.roll(height, -1, 0) - np.roll(height, 1, 0)) / 2  # rows run down the image
    n = normalize(np.stack([-dhdx, dhdrow, np.ones_like(height)], -1))  # +y = image up
    return np.rint(color).clip(0, 255), np.rint((n * 0.5 + 0.5) * 255)


def crate_texture(size=128):
    """Wooden planks with grain inside a darker frame, a nail at each corner."""
    px, py = pixel_grid(size)
    border = 12
    inner = (px >= border) & (px < size - border) & (py >= border) & (py < size - border)
    plank = (py - border) * 4 // (size - 2 * border)
    wobble = 3 * np.sin(px * 0.07 + plank * 1.7) + 1.5 * np.sin(px * 0.23 + plank)
    grain = 0.5 + 0.5 * np.sin((py + wobble) * 1.3 + plank * 2.1)
    grain = np.where(inner, grain, 0.5 + 0.5 * np.sin((px + py) * 0.9 + 1.5 * np.sin(py * 0.15)))
    shade = (0.8 + 0.15 * grain + 0.05 * hash01(px, py, 4)) * np.where(inner, 1.0, 0.72)
    gap = inner & (((py - border) * 4) % (size - 2 * border) < 4)
    ring = np.maximum(np.abs(px - (size - 1) / 2), np.abs(py - (size - 1) / 2))  # square rings
    frame_edge = ~inner & ((ring > size / 2 - 2) | (ring < size / 2 - border + 1))
    shade = np.where(gap | frame_edge, 0.35, shade)
    corners = (6, size - 7)
    nail = np.min([(px - cx) ** 2 + (py - cy) ** 2 for cx in corners for cy in corners], 0) <= 4
    color = np.array([176, 122, 70]) * shade[..., None]
    color = np.where(nail[..., None], [70, 70, 75], color)
    return np.rint(color).clip(0, 255)


def leaf_texture(size=128):
    """A green leaf with a stem, lighter veins and three holes; alpha 255 on it, 0 elsewhere.
    The transparent pixels are green too, so filtering at the outline brings in no dark fringe."""
    px, py = pixel_grid(size)
    x = (px + 0.5) / size * 2 - 1
    y = 1 - (py + 0.5) / size * 2                    # +y = image up
    t = (y + 0.72) / 1.65                            # 0 at the leaf's base, 1 at its tip
    half = 0.78 * np.sin(np.pi * np.clip(t, 0, 1)) ** 0.75 * (1 - 0.25 * t)
    half *= 1 - 0.06 * np.abs(np.sin(t * 9 * np.pi))  # serrated edge
    lamina = (t > 0) & (t < 1) & (np.abs(x) < half)
    stem = (np.abs(x + 0.02 * (y + 0.72)) < 0.035) & (y > -0.98) & (y <= -0.6)
    holes = np.min([((x - cx) ** 2 + (y - cy) ** 2) / r ** 2
                    for cx, cy, r in ((-0.32, 0.05, 0.07), (0.3, 0.3, 0.06), (0.22, -0.25, 0.05))],
                   0) < 1
    opaque = (lamina & ~holes) | stem
    side_vein = np.abs(((y - 0.55 * np.abs(x)) * 5) % 1 - 0.5) < 0.06   # raked up and out
    vein = (np.abs(x) < 0.025) | side_vein
    green = np.where((vein & lamina)[..., None], [120, 170, 70], [52, 118, 38])
    green = green * (0.9 + 0.1 * hash01(px, py, 5))[..., None]
    alpha = np.where(opaque, 255, 0)[..., None]
    return np.concatenate([np.rint(green).clip(0, 255), alpha], -1)


def panel_texture(w=64, h=16):
    """White with three darker horizontal bars (the emission's visible modulation)."""
    row = np.full(h, 255.0)
    row[[3, 4, 7, 8, 11, 12]] = 90
    return np.broadcast_to(row[:, None, None], (h, w, 3))


# ------------------------------------------------------------------------ the glTF
class Buffer:
    """The one binary buffer: each accessor in its own bufferView, 4-byte aligned."""

    def __init__(self, gltf):
        self.gltf, self.data = gltf, bytearray()

    def add(self, values, kind, component=F32, target=None, minmax=False):
        arr = np.ascontiguousarray(values, dtype=DTYPES[component])
        arr = arr.reshape(len(arr), -1)
        self.data += b"\x00" * (-len(self.data) % 4)
        view = {"buffer": 0, "byteOffset": len(self.data), "byteLength": arr.nbytes}
        if target: view["target"] = target
        self.data += arr.tobytes()
        self.gltf["bufferViews"].append(view)
        acc = {"bufferView": len(self.gltf["bufferViews"]) - 1, "componentType": component,
               "count": len(arr), "type": kind}
        if minmax:   # exact float32 values, so the bounds match the data bit for bit
            acc["min"], acc["max"] = arr.min(axis=0).tolist(), arr.max(axis=0).tolist()
        self.gltf["accessors"].append(acc)
        return len(self.gltf["accessors"]) - 1

    def mesh(self, name, m, material):
        kinds = {"POSITION": "VEC3", "NORMAL": "VEC3", "TANGENT": "VEC4", "TEXCOORD_0": "VEC2"}
        attrs = {k: self.add(m[k], kinds[k], target=ARRAY_BUFFER, minmax=(k == "POSITION"))
                 for k in kinds if k in m}
        component = U16 if len(m["POSITION"]) <= 65535 else U32
        idx = self.add(np.asarray(m["indices"]).reshape(-1), "SCALAR", component,
                       ELEMENT_ARRAY_BUFFER)
        self.gltf["meshes"].append({"name": name, "primitives": [
            {"attributes": attrs, "indices": idx, "material": material, "mode": 4}]})
        return len(self.gltf["meshes"]) - 1


CAMERA_EYE, CAMERA_TARGET = (0.0, 1.1, 3.2), (0.0, 0.7, 0.0)
TOP_EYE, TOP_TARGET = (0.0, 4.5, 1.6), (0.0, 0.3, -0.3)     # steeply down, in front of the panel
KEY_POS, KEY_TARGET = (1.2, 2.0, 1.2), (0.0, 0.3, 0.0)
SPINNER_POS = (0.0, 0.5, 0.4)


def build():
    """The glTF JSON (a dict), the binary buffer and the images {relative uri: pixels}."""
    g = {k: [] for k in ("accessors", "bufferViews", "meshes", "nodes", "materials", "textures",
                         "images", "cameras", "animations")}
    g["asset"] = {"version": "2.0", "generator": "penumbra scripts/make_studio.py"}
    g["samplers"] = [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497},
                     {"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}]
    tiles, tiles_normal = tile_textures()
    images = {"textures/tiles.png": tiles, "textures/tiles_normal.png": tiles_normal,
              "textures/crate.png": crate_texture(), "textures/leaf.png": leaf_texture(),
              "textures/panel.png": panel_texture()}
    samplers = {"textures/leaf.png": 1, "textures/panel.png": 1}       # clamp; the rest repeat
    for i, uri in enumerate(images):
        g["images"].append({"uri": uri, "mimeType": "image/png",
                            "name": os.path.splitext(os.path.basename(uri))[0]})
        g["textures"].append({"source": i, "sampler": samplers.get(uri, 0)})
    tex = {os.path.basename(u)[:-4]: {"index": i} for i, u in enumerate(images)}

    def pbr(name, color=(1, 1, 1, 1), metallic=0.0, roughness=1.0, texture=None, **extra):
        p = {"baseColorFactor": [r6(c) for c in color], "metallicFactor": metallic,
             "roughnessFactor": roughness}
        if texture: p["baseColorTexture"] = tex[texture]
        g["materials"].append({"name": name, "pbrMetallicRoughness": p, **extra})
        return len(g["materials"]) - 1

    tiles_mat = pbr("Tiles", roughness=0.8, texture="tiles",
                    normalTexture={**tex["tiles_normal"], "scale": 1.0})
    wall_mat = pbr("Wall", (0.7, 0.72, 0.75, 1))
    brass = pbr("Brass", (0.95, 0.75, 0.35, 1), metallic=0.6, roughness=0.3)
    crate = pbr("Crate", roughness=0.6, texture="crate")
    panel = pbr("Panel", (0, 0, 0, 1), emissiveFactor=[1.0, 0.92, 0.8],
                emissiveTexture=tex["panel"],
                extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 6.0}})
    red = pbr("Red plastic", (0.8, 0.1, 0.08, 1), roughness=0.5)
    leaf = pbr("Leaf", roughness=0.7, texture="leaf", alphaMode="MASK", alphaCutoff=0.5,
               doubleSided=True)

    buf = Buffer(g)

    def node(name, **fields):
        for k in ("translation", "rotation"):
            if k in fields: fields[k] = [r6(v) for v in fields[k]]
        g["nodes"].append({"name": name, **fields})
        return len(g["nodes"]) - 1

    g["cameras"] = [{"name": n, "type": "perspective", "perspective": {
        "yfov": 0.75, "aspectRatio": 1.0, "znear": 0.05, "zfar": 100.0}} for n in ("Camera", "Top")]
    node("Camera", camera=0, translation=CAMERA_EYE, rotation=look_at(CAMERA_EYE, CAMERA_TARGET))
    node("Top", camera=1, translation=TOP_EYE, rotation=look_at(TOP_EYE, TOP_TARGET))
    node("Floor", mesh=buf.mesh("Floor", floor_mesh(), tiles_mat))
    node("Wall", mesh=buf.mesh("Wall", local_quad(4, 2.5), wall_mat), translation=(0, 1.25, -1.5))
    node("Sphere", mesh=buf.mesh("Sphere", sphere_mesh(0.35), brass), translation=(-0.8, 0.35, 0))
    node("Crate", mesh=buf.mesh("Box", box_mesh(0.5), crate), translation=(0.8, 0.25, -0.2),
         rotation=quat_axis_angle((0, 1, 0), 30))
    node("Panel", mesh=buf.mesh("Panel", local_quad(1.2, 0.4), panel), translation=(0, 2.0, -0.6),
         rotation=quat_axis_angle((1, 0, 0), 90))          # local +Z (its front) -> -Y
    node("Leaf", mesh=buf.mesh("Leaf", local_quad(0.6, 0.9), leaf), translation=(-0.2, 0.45, -0.9))
    spinner = node("Spinner", mesh=buf.mesh("Torus", torus_mesh(0.22, 0.07), red),
                   translation=SPINNER_POS, rotation=(0, 0, 0, 1))
    g["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"name": "Key", "type": "spot", "color": [1.0, 0.95, 0.9], "intensity": 8.0,
         "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.6}},
        {"name": "Fill", "type": "point", "color": [0.8, 0.85, 1.0], "intensity": 1.5}]}}
    node("Key", translation=KEY_POS, rotation=look_at(KEY_POS, KEY_TARGET),
         extensions={"KHR_lights_punctual": {"light": 0}})
    node("Fill", translation=(-1.5, 1.5, 1.0), extensions={"KHR_lights_punctual": {"light": 1}})

    # "Spin": up 0.15 m and back over 2 s; a full turn about Y, a key every quarter turn.
    x, y, z = SPINNER_POS
    t_move = buf.add([0.0, 1.0, 2.0], "SCALAR", minmax=True)
    moves = buf.add([(x, y, z), (x, y + 0.15, z), (x, y, z)], "VEC3")
    t_turn = buf.add([0.0, 0.5, 1.0, 1.5, 2.0], "SCALAR", minmax=True)
    turns = buf.add([quat_axis_angle((0, 1, 0), 90 * k) for k in range(5)], "VEC4")
    g["animations"] = [{"name": "Spin", "samplers": [
        {"input": t_move, "output": moves, "interpolation": "LINEAR"},
        {"input": t_turn, "output": turns, "interpolation": "LINEAR"}], "channels": [
        {"sampler": 0, "target": {"node": spinner, "path": "translation"}},
        {"sampler": 1, "target": {"node": spinner, "path": "rotation"}}]}]

    g["scenes"] = [{"name": "Studio", "nodes": list(range(len(g["nodes"])))}]
    g["scene"] = 0
    g["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_emissive_strength"]
    buf.data += b"\x00" * (-len(buf.data) % 4)
    g["buffers"] = [{"uri": "studio.bin", "byteLength": len(buf.data)}]
    return g, bytes(buf.data), images


# ------------------------------------------------------------------------ self-check
def need(ok, what):
    if not ok: sys.exit("make_studio.py: self-check failed: " + what)


def read_png(path):
    """Decode one of our PNGs (8-bit RGB/RGBA, filter 0) back to pixels, checking the CRCs."""
    blob = open(path, "rb").read()
    need(blob[:8] == b"\x89PNG\r\n\x1a\n", path)
    pos, idat, ihdr = 8, b"", None
    while pos < len(blob):
        n, kind = struct.unpack(">I4s", blob[pos:pos + 8])
        body = blob[pos + 8:pos + 8 + n]
        need(blob[pos + 8 + n:pos + 12 + n] == struct.pack(">I", zlib.crc32(kind + body)), path)
        if kind == b"IHDR": ihdr = struct.unpack(">IIBBBBB", body)
        if kind == b"IDAT": idat += body
        pos += 12 + n
    w, h, depth, ctype = ihdr[:4]
    need(depth == 8 and ctype in (2, 6), path)
    c = 3 if ctype == 2 else 4
    rows = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(h, 1 + w * c)
    need(not rows[:, 0].any(), path + ": a filter other than 0")
    return rows[:, 1:].reshape(h, w, c)


def check(out_dir, images):
    """Re-read what was written and check the structure, the data and the conventions."""
    g = json.load(open(os.path.join(out_dir, "studio.gltf")))
    data = open(os.path.join(out_dir, g["buffers"][0]["uri"]), "rb").read()
    need(len(data) == g["buffers"][0]["byteLength"], "buffer length")

    def read(i):
        a = g["accessors"][i]
        v = g["bufferViews"][a["bufferView"]]
        dt = np.dtype(DTYPES[a["componentType"]])
        n = COMPONENTS[a["type"]]
        start = v["byteOffset"] + a.get("byteOffset", 0)
        need(start % 4 == 0 and "byteStride" not in v, f"accessor {i} alignment")
        need(a.get("byteOffset", 0) + a["count"] * n * dt.itemsize <= v["byteLength"]
             and v["byteOffset"] + v["byteLength"] <= len(data), f"accessor {i} range")
        arr = np.frombuffer(data, dt, a["count"] * n, start).reshape(a["count"], n)
        if "min" in a:
            need(a["min"] == arr.min(0).tolist() and a["max"] == arr.max(0).tolist(), f"{i} bounds")
        return arr.astype(np.float64)

    rotate = lambda q, v: np.array(quat_mul(quat_mul(q, [*v, 0]), [-q[0], -q[1], -q[2], q[3]])[:3])
    unit = lambda v, tol=1e-5: bool(np.all(np.abs(np.linalg.norm(v, axis=-1) - 1) < tol))
    for mesh in g["meshes"]:
        for p in mesh["primitives"]:
            at = {k: read(i) for k, i in p["attributes"].items()}
            pos, nrm, idx = at["POSITION"], at["NORMAL"], read(p["indices"]).astype(int)
            need(all(len(v) == len(pos) for v in at.values()), mesh["name"] + " counts")
            need(idx.max() < len(pos) and len(idx) % 3 == 0, mesh["name"] + " indices")
            need(unit(nrm), mesh["name"] + " normals")
            tri = idx.reshape(-1, 3)
            face = np.cross(pos[tri[:, 1]] - pos[tri[:, 0]], pos[tri[:, 2]] - pos[tri[:, 0]])
            need(np.all(np.linalg.norm(face, axis=1) > 1e-9), mesh["name"] + " degenerate")
            need(np.all(np.einsum("ij,ij->i", face, nrm[tri].sum(1)) > 0), mesh["name"] + " ccw")
            if "TANGENT" in at:                  # the bitangent must point to decreasing v
                t = at["TANGENT"]
                need(unit(t[:, :3]) and np.all(np.abs(np.abs(t[:, 3]) - 1) < 1e-6)
                     and np.all(np.abs(np.einsum("ij,ij->i", t[:, :3], nrm)) < 1e-6), "tangents")
                uv = at["TEXCOORD_0"]
                for a, b, c in tri:                   # d position / du and / dv
                    du, dv = np.linalg.solve([uv[b] - uv[a], uv[c] - uv[a]],
                                             [pos[b] - pos[a], pos[c] - pos[a]])
                    bit = np.cross(nrm[a], t[a, :3]) * t[a, 3]
                    need(np.dot(normalize(du), t[a, :3]) > 0.999 and np.dot(bit, dv) < 0, "frame")
    for n in g["nodes"]:
        need("rotation" not in n or unit(np.array(n["rotation"])), n["name"] + " rotation")
    for s in g["animations"][0]["samplers"]:
        times, values = read(s["input"]), read(s["output"])
        need(np.all(np.diff(times[:, 0]) > 0) and len(times) == len(values), "keyframes")
        if values.shape[1] == 4: need(unit(values), "animation quaternions")
    spin = next(n for n in g["nodes"] if n["name"] == "Spinner")
    for ch in g["animations"][0]["channels"]:
        first = read(g["animations"][0]["samplers"][ch["sampler"]]["output"])[0]
        need(np.allclose(first, spin[ch["target"]["path"]], atol=1e-6), "rest pose != time 0")
    for name, eye, target in (("Camera", CAMERA_EYE, CAMERA_TARGET), ("Top", TOP_EYE, TOP_TARGET),
                              ("Key", KEY_POS, KEY_TARGET)):
        n = next(n for n in g["nodes"] if n["name"] == name)
        need(np.dot(rotate(n["rotation"], (0, 0, -1)),
                    normalize(np.subtract(target, eye))) > 0.99999, name + " aim")
        need(rotate(n["rotation"], (0, 1, 0))[1] > 0, name + " up")
    for img in g["images"]:
        px = read_png(os.path.join(out_dir, img["uri"]))
        need(np.array_equal(px, images[img["uri"]]), img["uri"] + " round trip")
    normal = read_png(os.path.join(out_dir, "textures/tiles_normal.png")) / 255.0 * 2 - 1
    need(unit(normal, 0.02) and normal[..., 2].min() > 0.3, "normal map")
    row = int(GROUT + BEVEL / 2)               # the bevel below a tile's top edge faces up
    need(normal[row, 64, 1] > 0.2 and abs(normal[row, 64, 0]) < 0.01, "normal map's green is up")
    alpha = read_png(os.path.join(out_dir, "textures/leaf.png"))[..., 3]
    need(set(np.unique(alpha).tolist()) == {0, 255}, "leaf alpha")
    return g


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(root, "scenes", "studio"), help="output folder")
    out_dir = ap.parse_args().out
    g, data, images = build()
    os.makedirs(os.path.join(out_dir, "textures"), exist_ok=True)
    files = {"studio.gltf": (json.dumps(g, indent=2, sort_keys=True) + "\n").encode(),
             "studio.bin": data, **{uri: png_bytes(img) for uri, img in images.items()}}
    for name, blob in files.items():
        with open(os.path.join(out_dir, name), "wb") as f:
            f.write(blob)
    g = check(out_dir, images)
    for name, blob in sorted(files.items()):
        print(f"{os.path.join(out_dir, name)}: {len(blob)} bytes")
    print(f"{len(g['nodes'])} nodes, {len(g['meshes'])} meshes, {len(g['materials'])} materials, "
          f"{sum(len(b) for b in files.values())} bytes in all; self-check passed")


if __name__ == "__main__":
    main()
