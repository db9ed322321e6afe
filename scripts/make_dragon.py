#!/usr/bin/env python3
"""Generate the procedural dragon mesh used by Penumbra's depth-of-field test scene.

The paper we reproduce rendered the Stanford dragon; we may not ship it, so this
script builds a stylised dragon of our own: a scaly body swept along a smooth 3D
spline (curled tail, S-curved back, rising neck, head with snout, jaw, horns,
eyes and whiskers), four short legs with clawed toes and a row of dorsal spikes.
The scales give the high-frequency geometric detail a depth-of-field test needs.

Output: binary little-endian PLY (float x y z nx ny nz, uchar/int triangle
lists), about 2 units long in x, centred on x = z = 0, feet at y = 0, head at +x.
Standard library only and deterministic.  Usage:
    python3 scripts/make_dragon.py [output.ply]   (default scenes/meshes/dragon.ply)
"""
import math
import os
import random
import struct
import sys
import time

TAU = 2.0 * math.pi


# ----------------------------------------------------------------- vector helpers
def add(a, b): return (a[0] + b[0], a[1] + b[1], a[2] + b[2])
def sub(a, b): return (a[0] - b[0], a[1] - b[1], a[2] - b[2])
def mul(a, k): return (a[0] * k, a[1] * k, a[2] * k)
def dot(a, b): return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def length(a): return math.sqrt(dot(a, a))
def normalize(a): return mul(a, 1.0 / max(length(a), 1e-30))


def comb(*terms):
    """Sum of (vector, weight) pairs."""
    return tuple(sum(v[i] * k for v, k in terms) for i in range(3))


def smoothstep(e0, e1, x):
    t = min(1.0, max(0.0, (x - e0) / (e1 - e0)))
    return t * t * (3.0 - 2.0 * t)


def scale_bump(w, th, cols):
    """Overlapping scales: rows at integer w, `cols` staggered scales around (angle th);
    height in [0, 1], highest at the free edge (w just above an integer)."""
    row, a = math.floor(w), w - math.floor(w)
    col = th / TAU * cols + 0.5 * (row & 1)
    b = col - math.floor(col)
    return max(0.0, 1 - a - 0.7 * (2 * b - 1) ** 2) * smoothstep(0.0, 0.12, a)


def round_cap(d, cap):
    """Radius factor that closes a tube with a round cap over the last `cap` of length d."""
    return math.sqrt(max(0.0, 1 - (1 - d / cap) ** 2)) if 0 < d < cap else 1.0


def interp(keys, x):
    """Smooth (cubic Hermite, Catmull-Rom tangents) interpolation of (x, value) keys."""
    if x <= keys[0][0]: return keys[0][1]
    if x >= keys[-1][0]: return keys[-1][1]
    i = 0
    while keys[i + 1][0] < x: i += 1
    (x0, v0), (x1, v1) = keys[i], keys[i + 1]
    def slope(k):
        a, b = keys[max(k - 1, 0)], keys[min(k + 1, len(keys) - 1)]
        return (b[1] - a[1]) / (b[0] - a[0])
    h, t = x1 - x0, (x - x0) / (x1 - x0)
    t2, t3 = t * t, t * t * t
    return ((2 * t3 - 3 * t2 + 1) * v0 + (t3 - 2 * t2 + t) * h * slope(i)
            + (-2 * t3 + 3 * t2) * v1 + (t3 - t2) * h * slope(i + 1))


# ----------------------------------------------------------------------- curves
class Curve:
    """Centripetal Catmull-Rom spline through 3D points, queried by arclength.

    at(s) returns (u, p): u is the spline parameter (control point index space,
    0 .. n-1), handy for placing features relative to control points."""

    def __init__(self, pts, per_seg=120):
        pts = [tuple(map(float, p)) for p in pts]
        ext = [sub(mul(pts[0], 2), pts[1])] + pts + [sub(mul(pts[-1], 2), pts[-2])]
        self.us, self.ps, self.ss = [], [], []
        for seg in range(len(pts) - 1):            # Barry-Goldman pyramid per segment
            p0, p1, p2, p3 = ext[seg:seg + 4]
            t0 = 0.0
            t1 = t0 + max(length(sub(p1, p0)), 1e-9) ** 0.5
            t2 = t1 + max(length(sub(p2, p1)), 1e-9) ** 0.5
            t3 = t2 + max(length(sub(p3, p2)), 1e-9) ** 0.5
            for k in range(per_seg + (seg == len(pts) - 2)):
                t = t1 + (t2 - t1) * k / per_seg
                lerp = lambda a, b, ta, tb: comb((a, (tb - t) / (tb - ta)), (b, (t - ta) / (tb - ta)))
                a1, a2, a3 = lerp(p0, p1, t0, t1), lerp(p1, p2, t1, t2), lerp(p2, p3, t2, t3)
                self.us.append(seg + k / per_seg)
                self.ps.append(lerp(lerp(a1, a2, t0, t2), lerp(a2, a3, t1, t3), t1, t2))
        s = 0.0
        for i, p in enumerate(self.ps):
            if i: s += length(sub(p, self.ps[i - 1]))
            self.ss.append(s)
        self.length = s

    def at(self, s):
        lo, hi = 0, len(self.ss) - 1
        s = min(max(s, 0.0), self.length)
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if self.ss[mid] <= s: lo = mid
            else: hi = mid
        f = (s - self.ss[lo]) / max(self.ss[hi] - self.ss[lo], 1e-12)
        u = self.us[lo] + (self.us[hi] - self.us[lo]) * f
        return u, comb((self.ps[lo], 1 - f), (self.ps[hi], f))


def frames(pts, up):
    """Rotation-minimising frames (double reflection method) along a polyline.
    Returns (T, U, S) per point with S = T x U; U starts as `up` made orthogonal."""
    n = len(pts)
    ts = [normalize(sub(pts[min(i + 1, n - 1)], pts[max(i - 1, 0)])) for i in range(n)]
    us = [normalize(sub(up, mul(ts[0], dot(up, ts[0]))))]
    for i in range(n - 1):
        v1 = sub(pts[i + 1], pts[i]); c1 = dot(v1, v1)
        if c1 < 1e-24:
            us.append(us[-1]); continue
        rl = sub(us[i], mul(v1, 2 * dot(v1, us[i]) / c1))
        tl = sub(ts[i], mul(v1, 2 * dot(v1, ts[i]) / c1))
        v2 = sub(ts[i + 1], tl); c2 = dot(v2, v2)
        r = sub(rl, mul(v2, 2 * dot(v2, rl) / c2)) if c2 > 1e-24 else rl
        us.append(normalize(sub(r, mul(ts[i + 1], dot(r, ts[i + 1])))))
    return [(t, u, cross(t, u)) for t, u in zip(ts, us)]


def side_frames(pts):
    """Frames for a curve that lives roughly in the x-y plane: U = z x T lies in
    that plane (the dorsal side, "up" where the curve heads to +x), S = T x U."""
    tu = [(t, normalize(cross((0.0, 0.0, 1.0), t))) for t, _, _ in frames(pts, (0.0, 1.0, 0.0))]
    return [(t, u, cross(t, u)) for t, u in tu]


# ------------------------------------------------------------------ mesh parts
class Part:
    """One closed surface; normals are averaged per part."""

    def __init__(self):
        self.verts, self.faces = [], []

    def tube(self, rings, pole0, pole1):
        """Stitch rings (same vertex count, angle increasing from U towards S) into
        a tube closed by two poles, wound counter-clockwise seen from outside."""
        m, base = len(rings[0]), len(self.verts)
        for ring in rings: self.verts.extend(ring)
        for i in range(len(rings) - 1):
            a0, a1 = base + i * m, base + (i + 1) * m
            for j in range(m):
                j1 = (j + 1) % m
                self.faces += [(a0 + j, a0 + j1, a1 + j1), (a0 + j, a1 + j1, a1 + j)]
        last = base + (len(rings) - 1) * m
        p0, p1 = len(self.verts), len(self.verts) + 1
        self.verts += [pole0, pole1]
        for j in range(m):
            j1 = (j + 1) % m
            self.faces += [(p0, base + j1, base + j), (p1, last + j, last + j1)]
        return self


def sweep(ctrl, rings, around, radius, up=(0.0, 1.0, 0.0), cap=0.15, disp=None):
    """Tube along a spline through `ctrl`.  radius(t) -> (ra, rb), the half-axes of
    the elliptic section along U and S, t in [0, 1]; ends are rounded over the
    fraction `cap` of the length (0: flat fans) and closed by poles."""
    curve = Curve(ctrl, 40)
    samples = [curve.at(curve.length * (i + 1) / (rings + 1))[1] for i in range(rings)]
    fr = frames(samples, up)
    out = []
    for i, (c, (t_, u, s)) in enumerate(zip(samples, fr)):
        t = (i + 1) / (rings + 1)
        env = round_cap(t, cap) * round_cap(1 - t, cap)
        ra, rb = radius(t)
        ring = []
        for j in range(around):
            th = TAU * j / around
            k = env * (disp(t, th) if disp else 1.0)
            ring.append(comb((c, 1), (u, ra * k * math.cos(th)), (s, rb * k * math.sin(th))))
        out.append(ring)
    return Part().tube(out, curve.at(0)[1], curve.at(curve.length)[1])


def ellipsoid(c, rx, ry, rz, around=24, rings=14):
    return sweep([sub(c, (rx, 0, 0)), add(c, (rx, 0, 0))], rings, around, lambda t: (ry, rz), cap=0.5)


# ---------------------------------------------------------------- the creature
SPINE = [  # tail tip (inside the curl) ... snout tip; indices are the "u" of Curve.at
    (-0.63, 0.40, 0.10), (-0.71, 0.50, 0.09), (-0.83, 0.46, 0.07), (-0.87, 0.31, 0.05),
    (-0.76, 0.16, 0.03), (-0.55, 0.09, 0.00), (-0.30, 0.13, -0.04), (-0.05, 0.23, -0.06),
    (0.20, 0.28, -0.03), (0.40, 0.32, 0.03), (0.54, 0.47, 0.06), (0.60, 0.67, 0.05),
    (0.67, 0.83, 0.02), (0.79, 0.87, 0.0), (0.93, 0.82, 0.0)]
RADIUS = [(0, 0.012), (2, 0.018), (4, 0.028), (5, 0.036), (6, 0.058), (7, 0.098), (8, 0.112),
          (9, 0.100), (10, 0.066), (11, 0.050), (12, 0.060), (12.8, 0.070), (13.5, 0.052),
          (14, 0.040)]
ASPECT = [(0, 1.0, 1.0), (7, 1.05, 0.95), (10, 1.0, 1.0), (12.5, 0.85, 1.0), (14, 0.62, 0.85)]
SCALE_COLS = 24            # scales around the body


def body(n_rings, around):
    """Scaly body, neck and head as one sweep.  Returns the part, spine(u) -> (centre,
    (T, U, S) frame, ry, rz) at spline parameter u for placing other parts, and the curve."""
    curve = Curve(SPINE)
    L = curve.length
    ss = [L * (i + 1) / (n_rings + 1) for i in range(n_rings)]
    samp = [curve.at(s) for s in ss]
    fr = side_frames([p for _, p in samp])

    def shape(u):
        r = interp(RADIUS, u)
        return r * interp([(k, a) for k, a, _ in ASPECT], u), r * interp([(k, b) for k, _, b in ASPECT], u)

    rings, w = [], 0.0
    for i, ((u, c), (t, up, side)) in enumerate(zip(samp, fr)):
        ry, rz = shape(u)
        if i: w += (ss[i] - ss[i - 1]) / (0.22 * max(0.5 * (ry + rz), 0.075))   # scale rows
        env = round_cap(ss[i], 0.012) * round_cap(L - ss[i], 0.035)      # tail tip, snout
        head = smoothstep(12.0, 12.5, u)
        a = w - math.floor(w)
        ring = []
        for j in range(around):
            th = TAU * j / around
            thw = th if th <= math.pi else th - TAU
            h_scale = scale_bump(w, th, SCALE_COLS)     # free edges face the tail
            # belly plates: broad transverse ridges underneath
            h_plate = (1 - a) ** 0.6 * smoothstep(0.0, 0.15, a)
            belly = smoothstep(0.45, 0.75, -math.cos(th))
            crest = math.exp(-(thw / 0.2) ** 2)
            k = 1.0 + (1 - 0.7 * head) * (0.075 * h_scale * (1 - belly) + 0.06 * h_plate * belly)
            k += (1 - head) * 0.16 * crest
            # head: brow ridges over the eyes and nostril bumps on the snout
            k += head * (0.22 * math.exp(-((u - 12.85) / 0.18) ** 2 - ((abs(thw) - 0.75) / 0.28) ** 2)
                         + 0.16 * math.exp(-((u - 13.75) / 0.08) ** 2 - ((abs(thw) - 0.55) / 0.22) ** 2)
                         + 0.08 * math.exp(-((u - 12.5) / 0.25) ** 2 - (thw / 0.25) ** 2))
            k *= env
            ring.append(comb((c, 1), (up, ry * k * math.cos(th)), (side, rz * k * math.sin(th))))
        rings.append(ring)
    part = Part().tube(rings, curve.at(0)[1], curve.at(L)[1])

    def spine(u):
        i = min(range(n_rings), key=lambda k: abs(samp[k][0] - u))
        ry, rz = shape(samp[i][0])
        return samp[i][1], fr[i], ry, rz
    return part, spine, curve


def scaly(rows, cols, amp):
    """Scale displacement for small sweeps (free edges towards the end of the sweep)."""
    return lambda t, th: 1.0 + amp * scale_bump(-t * rows, th, cols)


def legs(spine):
    """Four short, scaly legs ending in flat feet with three clawed toes each."""
    parts = []
    prof = [(0, 0.062), (0.25, 0.058), (0.55, 0.036), (0.85, 0.03), (1, 0.032)]
    for u, knee_dx, ankle_dx in ((7.35, 0.07, 0.0), (9.0, -0.06, 0.03)):
        c, (t, up, side), ry, rz = spine(u)
        for sgn in (-1, 1):
            hip = comb((c, 1), (side, sgn * 0.35 * rz), (up, -0.1 * ry))
            knee = (c[0] + knee_dx, c[1] - 0.8 * ry, c[2] + sgn * (rz + 0.03))
            ankle = (c[0] + ankle_dx, 0.025, c[2] + sgn * (rz + 0.045))
            parts.append(sweep([hip, knee, ankle], 56, 24, lambda t: (interp(prof, t),) * 2,
                               up=(1, 0, 0), cap=0.06, disp=scaly(24, 10, 0.07)))
            foot = (ankle[0] + 0.015, 0.025, ankle[2])
            parts.append(ellipsoid(foot, 0.052, 0.025, 0.04, 24, 16))
            for a in (-0.5, 0.0, 0.5):            # three clawed toes fanning forward
                d = (math.cos(a), 0.0, math.sin(a) * 0.8 + 0.15 * sgn)
                base = add(foot, (0, 0.002, 0))
                toe = [base, comb((base, 1), (d, 0.055), ((0, 1, 0), -0.004)),
                       comb((base, 1), (d, 0.085), ((0, 1, 0), -0.008)),
                       comb((base, 1), (d, 0.105), ((0, 1, 0), -0.022))]
                parts.append(sweep(toe, 20, 12, lambda t: (0.015 * (1 - t) ** 0.8 + 0.0008,) * 2,
                                   up=(0, 1, 0), cap=0.1, disp=scaly(6, 6, 0.08)))
    return parts


def tail_spade(curve, spine):
    """Flat arrow-head fin at the tail tip, lying in the plane of the curl."""
    _, (t, up, _), _, _ = spine(0.25)
    tip = curve.at(0)[1]
    shape = [(0, 0.008), (0.55, 0.04), (1, 0.0005)]
    return [sweep([comb((tip, 1), (t, 0.05)), comb((tip, 1), (t, -0.05))], 30, 24,
                  lambda f: (interp(shape, f), 0.007), up=up, cap=0.0)]


def spikes(spine, curve, rng):
    """Row of flat, backward-raked dorsal plates from the tail to the back of the head."""
    parts = []
    height = [(3.2, 0.012), (5.0, 0.03), (6.5, 0.05), (7.8, 0.065), (9.0, 0.05), (10.3, 0.032),
              (12.0, 0.03)]
    s = 0.0
    while s < curve.length:
        u, _ = curve.at(s)
        if 3.2 <= u <= 12.05:
            c, (t, up, side), ry, rz = spine(u)
            h = interp(height, u) * (0.9 + 0.2 * rng.random()) + 0.25 * ry
            base = comb((c, 1), (up, ry * 0.85))
            tip = comb((base, 1), (up, h), (t, -0.5 * h))
            mid = comb((base, 1), (up, 0.55 * h), (t, -0.12 * h))
            half = 0.3 * h + 0.25 * ry
            width = min(0.014, 0.35 * rz)
            parts.append(sweep([base, mid, tip], 10, 14,
                               lambda t, half=half, width=width: (half * (1 - t) ** 1.1 + 1e-4,
                                                                 width * (1 - t) + 1e-4),
                               up=t, cap=0.0))
            s += max(0.03, 0.9 * half)
        else:
            s += 0.01
    return parts


def head_parts(spine):
    """Lower jaw, eyes, swept-back horns, drooping whiskers and teeth."""
    parts = []
    c0, (t0, u0, s0), ry0, rz0 = spine(12.4)
    c1, (t1, u1, s1), ry1, rz1 = spine(13.2)
    c2, (t2, u2, s2), ry2, rz2 = spine(13.85)
    down = (0.0, -1.0, 0.0)
    jaw = [comb((c0, 1), (u0, -0.45 * ry0)), comb((c1, 1), (u1, -0.9 * ry1), (down, 0.012)),
           comb((c2, 1), (u2, -0.9 * ry2), (down, 0.04), (t2, 0.01))]
    parts.append(sweep(jaw, 60, 32, lambda t: (0.6 * (0.034 - 0.014 * t), 0.034 - 0.012 * t),
                       up=(0, 1, 0), cap=0.12))
    ce, (te, ue, se), rye, rze = spine(12.85)
    for sgn in (-1, 1):
        eye = comb((ce, 1), (ue, 0.3 * rye), (se, sgn * 0.78 * rze), (te, 0.01))
        parts.append(ellipsoid(eye, 0.016, 0.014, 0.016, 20, 12))
        hb = comb((c0, 1), (u0, 0.7 * ry0), (s0, sgn * 0.45 * rz0))
        horn = [hb, comb((hb, 1), (t0, -0.06), (u0, 0.06), (s0, sgn * 0.02)),
                comb((hb, 1), (t0, -0.16), (u0, 0.09), (s0, sgn * 0.05)),
                comb((hb, 1), (t0, -0.25), (u0, 0.14), (s0, sgn * 0.06))]
        parts.append(sweep(horn, 40, 16, lambda t: (0.02 * (1 - t) ** 0.9 + 3e-4,) * 2,
                           up=(0, 1, 0), cap=0.05))
        wb = comb((c2, 1), (s2, sgn * 0.7 * rz2), (u2, -0.1 * ry2))
        back = (-1.0, 0.0, 0.0)
        whisker = [wb, comb((wb, 1), (s2, sgn * 0.04), (back, 0.03), (down, 0.02)),
                   comb((wb, 1), (s2, sgn * 0.07), (back, 0.14), (down, 0.07)),
                   comb((wb, 1), (s2, sgn * 0.08), (back, 0.26), (down, 0.07)),
                   comb((wb, 1), (s2, sgn * 0.07), (back, 0.34), (down, 0.03))]
        parts.append(sweep(whisker, 60, 8, lambda t: (0.005 * (1 - t) + 5e-4,) * 2,
                           up=(0, 1, 0), cap=0.03))
        for k in range(6):                         # teeth along the upper jaw
            ct, (tt, ut, st), ryt, rzt = spine(13.15 + 0.13 * k)
            tb = comb((ct, 1), (ut, -0.55 * ryt), (st, sgn * 0.72 * rzt))
            tip = comb((tb, 1), (ut, -0.45 * ryt - 0.012), (tt, -0.004))
            parts.append(sweep([tb, tip], 5, 8, lambda t: (0.005 * (1 - t) + 2e-4,) * 2,
                               up=tt, cap=0.0))
    return parts


# ----------------------------------------------------------------- output
def normals(part):
    acc = [[0.0, 0.0, 0.0] for _ in part.verts]
    v = part.verts
    for a, b, c in part.faces:
        n = cross(sub(v[b], v[a]), sub(v[c], v[a]))      # |n| = 2 * area
        for i in (a, b, c):
            m = acc[i]; m[0] += n[0]; m[1] += n[1]; m[2] += n[2]
    return [normalize(m) for m in acc]


def write_ply(path, parts):
    nv = sum(len(p.verts) for p in parts)
    nf = sum(len(p.faces) for p in parts)
    header = ("ply\nformat binary_little_endian 1.0\n"
              "comment generated by scripts/make_dragon.py (procedural dragon for the DOF scene)\n"
              f"element vertex {nv}\nproperty float x\nproperty float y\nproperty float z\n"
              "property float nx\nproperty float ny\nproperty float nz\n"
              f"element face {nf}\nproperty list uchar int vertex_indices\nend_header\n")
    vfmt, ffmt = struct.Struct("<6f"), struct.Struct("<B3i")
    chunks = [header.encode("ascii")]
    for p in parts:
        chunks += [vfmt.pack(*v, *n) for v, n in zip(p.verts, normals(p))]
    base = 0
    for p in parts:
        chunks += [ffmt.pack(3, a + base, b + base, c + base) for a, b, c in p.faces]
        base += len(p.verts)
    data = b"".join(chunks)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)
    return len(data)


def bbox(parts):
    pts = [v for p in parts for v in p.verts]
    return [min(v[k] for v in pts) for k in range(3)], [max(v[k] for v in pts) for k in range(3)]


def main():
    t_start = time.time()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "scenes", "meshes", "dragon.ply")
    rng = random.Random(1234)
    body_part, spine, curve = body(640, 96)
    parts = ([body_part] + legs(spine) + tail_spade(curve, spine) + spikes(spine, curve, rng)
             + head_parts(spine))
    # fit: 2 units long in x, centred on x = z = 0, lowest point at y = 0
    lo, hi = bbox(parts)
    k = 2.0 / (hi[0] - lo[0])
    off = (-(lo[0] + hi[0]) / 2, -lo[1], -(lo[2] + hi[2]) / 2)
    for p in parts:
        p.verts = [((v[0] + off[0]) * k, (v[1] + off[1]) * k, (v[2] + off[2]) * k) for v in p.verts]
    size = write_ply(path, parts)
    lo, hi = bbox(parts)
    print(f"wrote {path}")
    print(f"  triangles {sum(len(p.faces) for p in parts)}, "
          f"vertices {sum(len(p.verts) for p in parts)}, parts {len(parts)}")
    print("  bbox min ({:.4f}, {:.4f}, {:.4f}) max ({:.4f}, {:.4f}, {:.4f})".format(*lo, *hi))
    print(f"  file size {size} bytes ({size / 2**20:.2f} MiB), {time.time() - t_start:.1f} s")


if __name__ == "__main__":
    main()
