#!/usr/bin/env python3
"""Write scenes/env/sky.hdr: a procedural clear sky with a sun, as an equirectangular map.

A simple analytic sky made here from scratch (not a published sky model's coefficients):
  * the sky above the horizon: a zenith colour fading to a paler, brighter horizon band,
    times a circumsolar glow (brighter around the sun) and a cos^2 term (darker 90 degrees
    from the sun), as in Perez's form; --turbidity whitens and widens both;
  * the sun: a uniform disk of --sun-radius degrees, warm-tinted by the air mass it shines
    through; its radiance is chosen so that the sun's irradiance on a surface facing it is
    --sun-ratio times the sky's irradiance on an upward plane (a clear day: 5 to 10);
  * the ground below the horizon: a uniform grey-brown Lambertian ground lit by the sun and
    the sky, radiance = albedo * E_up / pi;
  * the scale: sun + sky give --irradiance (default pi) on an upward plane, so a white
    Lambertian floor in the open has radiance 1.

Layout (Radiance RGBE, "-Y H +X W", the top row first): equirectangular latitude-longitude,
Blender's convention for a Y-up world.  A pixel at column i, row j (0 = top) has
    u = (i + 0.5) / W,  t = (j + 0.5) / H        (t from the top of the image)
    phi = 2 pi (u - 0.5),  theta = pi t
    direction(u, t) = (sin(theta) cos(phi),  cos(theta),  sin(theta) sin(phi))   (x, y, z)
and conversely u = 0.5 + atan2(z, x) / (2 pi) (mod 1), t = acos(y) / pi.  So the top row is
+y (up), the middle row is the horizon, the bottom row is -y; the image's centre (u = 0.5)
looks along +x, u = 0.75 along +z, u = 0.25 along -z, and the left and right edges along -x.
This is Blender's world mapping (Cycles: u = 0.5 - atan2(b_y, b_x) / (2 pi), v = 1 -
acos(b_z) / pi with v up, in Blender's Z-up world b) carried into a Y-up world the way the
glTF exporter carries it (x, y, z) = (b_x, b_z, -b_y): Blender's +X stays +x, its up +Z is
+y, its front -Y (what the front view looks at from) is +z.  A map made here and loaded in
Blender as the world's Environment Texture shows the sun where a glTF export places it.

The sun's position: --sun-elevation above the horizon and --sun-azimuth phi in the formula
above (degrees from +x towards +z), so the direction towards the sun is
    (cos(el) cos(az), sin(el), cos(el) sin(az)).

Output is deterministic (byte-identical on every run): scanlines are run-length encoded as
Radiance's "new" RLE, which stb_image, OpenEXR's tools and Blender read.  The script prints
the sun's direction and the map's irradiance integrals, computed from the stored (quantised)
pixels, each pixel read as a constant over its exact solid angle (the way stb_image decodes
RGBE: mantissa * 2^(exponent - 136), no half-step offset).  Standard library only.  Usage:
    python3 scripts/make_sky.py [--out scenes/env/sky.hdr] [--sun-elevation 35]
        [--sun-azimuth 120] [--turbidity 3] [--sun-ratio 7] [--size 1024x512] [--json FILE]
"""
import argparse
import json
import math
import os
import sys

# Rec. 709 luminance weights (linear RGB), used for every "luminance" below.
LUMA = (0.2126, 0.7152, 0.0722)


def luminance(c):
    return LUMA[0] * c[0] + LUMA[1] * c[1] + LUMA[2] * c[2]


def lerp(a, b, s):
    return tuple(x + (y - x) * s for x, y in zip(a, b))


def unit_luminance(c):
    y = luminance(c)
    return tuple(x / y for x in c)


def direction(u, t):
    """The world direction (x, y, z) of map coordinates u (across) and t (down from the top)."""
    phi, theta = 2.0 * math.pi * (u - 0.5), math.pi * t
    s = math.sin(theta)
    return (s * math.cos(phi), math.cos(theta), s * math.sin(phi))


def map_coordinates(d):
    """The inverse of direction(): (u, t) of a unit direction."""
    u = 0.5 + math.atan2(d[2], d[0]) / (2.0 * math.pi)
    return (u - math.floor(u), math.acos(max(-1.0, min(1.0, d[1]))) / math.pi)


class Sky:
    """The unscaled radiance of the sky dome (above the horizon, without the sun)."""

    def __init__(self, sun, turbidity):
        self.sun = sun
        haze = min(max((turbidity - 2.0) / 8.0, 0.0), 1.0)       # 0: very clear, 1: hazy
        self.zenith = unit_luminance(lerp((0.10, 0.26, 0.80), (0.38, 0.47, 0.66), haze))
        self.horizon = unit_luminance(lerp((0.62, 0.78, 1.00), (0.92, 0.92, 0.93), haze))
        self.zenith_level = 0.28 + 0.30 * haze                   # zenith / horizon radiance
        self.band = 0.16 + 0.14 * haze                          # horizon band, in sin(elevation)
        self.glow = 5.0 + 5.0 * haze                            # circumsolar peak over the dome
        self.glow_width = math.radians(9.0 + 12.0 * haze)
        self.glow_tint = (1.0, 0.93, 0.80)

    def radiance(self, d):
        s = max(d[1], 0.0)
        fade = math.exp(-s / self.band)                          # 1 at the horizon, 0 up high
        colour = lerp(self.zenith, self.horizon, fade)
        level = self.zenith_level + (1.0 - self.zenith_level) * fade
        cos_g = max(-1.0, min(1.0, d[0] * self.sun[0] + d[1] * self.sun[1] + d[2] * self.sun[2]))
        gamma = math.acos(cos_g)
        glow = self.glow * math.exp(-gamma / self.glow_width)
        angular = 0.55 + 0.45 * cos_g * cos_g
        return tuple(c * level * (angular + glow * g) for c, g in zip(colour, self.glow_tint))


def sun_colour(elevation, turbidity):
    """Sunlight's tint after the air mass at this elevation (Kasten and Young's formula),
    with luminance 1."""
    el = max(math.degrees(elevation), 0.0)
    air_mass = 1.0 / (math.sin(math.radians(el)) + 0.50572 * (el + 6.07995) ** -1.6364)
    depth = tuple(k * (0.4 + 0.2 * turbidity) for k in (0.035, 0.075, 0.16))
    return unit_luminance(tuple(math.exp(-k * air_mass) for k in depth))


# ------------------------------------------------------------------------------ RGBE
def rgbe(c):
    """A linear RGB colour as 4 RGBE bytes, rounded to the nearest value stb_image decodes."""
    v = max(c)
    if not v > 1e-32:
        return (0, 0, 0, 0)
    e = math.frexp(v)[1]                                     # v = m 2^e, m in [0.5, 1)
    q = [int(math.floor(x * 2.0 ** (8 - e) + 0.5)) for x in c]
    if max(q) > 255:                                         # rounded up to 256: next exponent
        e += 1
        q = [int(math.floor(x * 2.0 ** (8 - e) + 0.5)) for x in c]
    if e + 128 > 255:
        raise ValueError("radiance too large for RGBE: %r" % (c,))
    if e + 128 < 1:
        return (0, 0, 0, 0)
    return (q[0], q[1], q[2], e + 128)


def decode_rgbe(p):
    if p[3] == 0:
        return (0.0, 0.0, 0.0)
    f = math.ldexp(1.0, p[3] - 136)
    return (p[0] * f, p[1] * f, p[2] * f)


def rle_channel(data):
    """Radiance's run-length code of one channel of one scanline: a byte 128 + n (n <= 127)
    then a value repeated n times, or a byte n (n <= 128) then n literal values."""
    out = bytearray()
    n, i = len(data), 0
    while i < n:
        run = 1                                          # the run that starts at i
        while i + run < n and run < 127 and data[i + run] == data[i]:
            run += 1
        if run >= 3:
            out += bytes((128 + run, data[i]))
            i += run
            continue
        start = i                                        # literals up to the next run of 3
        while i < n and i - start < 128:
            if i + 2 < n and data[i] == data[i + 1] == data[i + 2]:
                break
            i += 1
        out.append(i - start)
        out += bytes(data[start:i])
    return out


def encode_hdr(width, height, rows, comment):
    """Radiance .hdr bytes: header, then each row of RGBE pixels (a list of 4-tuples)."""
    out = bytearray(b"#?RADIANCE\n")
    out += ("# " + comment + "\n").encode("ascii")
    out += b"FORMAT=32-bit_rle_rgbe\n\n"
    out += ("-Y %d +X %d\n" % (height, width)).encode("ascii")
    for row in rows:
        out += bytes((2, 2, width >> 8, width & 255))
        for k in range(4):
            out += rle_channel(bytes(p[k] for p in row))
    return bytes(out)


def decode_hdr_rows(data, width, height):
    """Reads back what encode_hdr wrote (a self-check of the run-length code)."""
    pos = data.index(b"\n\n") + 2
    pos = data.index(b"\n", pos) + 1
    rows = []
    for _ in range(height):
        assert data[pos:pos + 4] == bytes((2, 2, width >> 8, width & 255))
        pos += 4
        channels = []
        for _ in range(4):
            ch = bytearray()
            while len(ch) < width:
                c = data[pos]
                if c > 128:
                    ch += bytes((data[pos + 1],)) * (c - 128)
                    pos += 2
                else:
                    ch += data[pos + 1:pos + 1 + c]
                    pos += 1 + c
            assert len(ch) == width
            channels.append(ch)
        rows.append(list(zip(*channels)))
    assert pos == len(data)
    return rows


# ---------------------------------------------------------------------------- the map
def make_sky(args):
    width, height = args.width, args.height
    el, az = math.radians(args.sun_elevation), math.radians(args.sun_azimuth)
    sun = (math.cos(el) * math.cos(az), math.sin(el), math.cos(el) * math.sin(az))
    sun_radius = math.radians(args.sun_radius)
    sky = Sky(sun, args.turbidity)
    sun_rgb = sun_colour(el, args.turbidity)

    dphi = 2.0 * math.pi / width
    # Per row: the solid angle of one pixel and its integral of cos(theta) (an upward plane).
    cos_edges = [math.cos(math.pi * j / height) for j in range(height + 1)]
    solid = [dphi * (cos_edges[j] - cos_edges[j + 1]) for j in range(height)]
    up_weight = [dphi * 0.5 * max(cos_edges[j] ** 2 * (1 if cos_edges[j] > 0 else 0)
                                  - cos_edges[j + 1] ** 2 * (1 if cos_edges[j + 1] > 0 else 0), 0.0)
                 for j in range(height)]
    # (Rows never straddle the horizon when the height is even: the horizon is a pixel edge.)
    sky_rows = height // 2

    # The unscaled sky, sampled at pixel centres (it is smooth at this resolution).
    dome = [[sky.radiance(direction((i + 0.5) / width, (j + 0.5) / height)) for i in range(width)]
            for j in range(sky_rows)]

    # The sun's coverage of each pixel near it: 16 x 16 samples of equal solid angle (uniform
    # in phi and in cos(theta) across the pixel); directions below the horizon are ground.
    coverage = {}
    su, st = map_coordinates(sun)
    reach = sun_radius + 2.5 * math.pi / height
    j0 = max(int(math.floor((st - reach / math.pi) * height)), 0)
    j1 = min(int(math.floor((st + reach / math.pi) * height)), sky_rows - 1)
    cos_r, n = math.cos(sun_radius), 16
    for j in range(j0, j1 + 1):
        sin_t = max(math.sin(math.pi * (j + 0.5) / height), 1e-3)
        half = min(reach / sin_t / (2.0 * math.pi), 0.5)
        for i in range(int(math.floor((su - half) * width)), int(math.floor((su + half) * width)) + 1):
            inside = 0
            for a in range(n):
                phi = dphi * (i % width + (a + 0.5) / n) - math.pi
                for b in range(n):
                    y = cos_edges[j] + (cos_edges[j + 1] - cos_edges[j]) * (b + 0.5) / n
                    s = math.sqrt(max(1.0 - y * y, 0.0))
                    d = (s * math.cos(phi), y, s * math.sin(phi))
                    if y > 0 and d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2] >= cos_r:
                        inside += 1
            if inside:
                coverage[(j, i % width)] = inside / (n * n)
    if not coverage:
        raise SystemExit("make_sky: the sun is below the horizon")

    # Scale: E_sun_normal = ratio * E_sky_up, and E_sky_up + E_sun_up = the target irradiance.
    sky_up = sum(luminance(dome[j][i]) * up_weight[j] for j in range(sky_rows) for i in range(width))
    sun_normal = sum(c * solid[j] * sum(a * b for a, b in zip(direction((i + 0.5) / width,
                                                                        (j + 0.5) / height), sun))
                     for (j, i), c in coverage.items())
    sun_up = sum(c * up_weight[j] for (j, i), c in coverage.items())
    k_sky = args.irradiance / (sky_up * (1.0 + args.sun_ratio * sun_up / sun_normal))
    k_sun = args.sun_ratio * k_sky * sky_up / sun_normal
    total_up = k_sky * sky_up + k_sun * sun_up
    ground = tuple(a * total_up / math.pi for a in args.ground_albedo)

    rows = []
    for j in range(height):
        if j >= sky_rows:
            rows.append([rgbe(ground)] * width)
            continue
        row = []
        for i in range(width):
            c = tuple(k_sky * x for x in dome[j][i])
            f = coverage.get((j, i), 0.0)
            if f:
                c = tuple((1.0 - f) * x + f * k_sun * s for x, s in zip(c, sun_rgb))
            row.append(rgbe(c))
        rows.append(row)

    comment = ("scripts/make_sky.py --sun-elevation %g --sun-azimuth %g --sun-radius %g "
               "--turbidity %g --sun-ratio %g --irradiance %g --ground-albedo %s" %
               (args.sun_elevation, args.sun_azimuth, args.sun_radius, args.turbidity,
                args.sun_ratio, args.irradiance, ",".join("%g" % a for a in args.ground_albedo)))
    data = encode_hdr(width, height, rows, comment)
    assert decode_hdr_rows(data, width, height) == rows

    # The integrals of what is stored.
    def integrate(select):
        e_up, e_sun_dir, power = [0.0] * 3, [0.0] * 3, [0.0] * 3
        for j in range(height):
            for i in range(width):
                if not select(j, i):
                    continue
                c = decode_rgbe(rows[j][i])
                d = direction((i + 0.5) / width, (j + 0.5) / height)
                facing = max(sum(a * b for a, b in zip(d, sun)), 0.0)
                for k in range(3):
                    e_up[k] += c[k] * up_weight[j]
                    e_sun_dir[k] += c[k] * solid[j] * facing
                    power[k] += c[k] * solid[j]
        return e_up, e_sun_dir, power

    sky_e_up, sky_e_facing, sky_total = integrate(lambda j, i: j < sky_rows and (j, i) not in coverage)
    sun_e_up, sun_e_normal, _ = integrate(lambda j, i: (j, i) in coverage)
    _, _, all_total = integrate(lambda j, i: True)

    def lum3(c):
        return {"rgb": [round(x, 6) for x in c], "luminance": round(luminance(c), 6)}

    sun_solid = sum(c * solid[j] for (j, i), c in coverage.items())
    report = {
        "file": os.path.basename(args.out),
        "size": [width, height],
        "direction_formula": "u=(i+0.5)/W, t=(j+0.5)/H (j=0 top), phi=2*pi*(u-0.5), theta=pi*t, "
                             "d=(sin(theta)cos(phi), cos(theta), sin(theta)sin(phi))",
        "sun_direction": [round(x, 6) for x in sun],
        "sun_light_direction": [round(-x, 6) for x in sun],
        "sun_elevation_deg": args.sun_elevation,
        "sun_azimuth_deg": args.sun_azimuth,
        "sun_radius_deg": args.sun_radius,
        "sun_solid_angle_sr": round(sun_solid, 9),
        "sun_pixels": len(coverage),
        "sun_radiance": [round(k_sun * s, 3) for s in sun_rgb],
        "sun_irradiance_normal": lum3(sun_e_normal),
        "sun_irradiance_up": lum3(sun_e_up),
        "sky_irradiance_up": lum3(sky_e_up),
        "sky_irradiance_facing_sun": lum3(sky_e_facing),
        "total_irradiance_up": lum3([a + b for a, b in zip(sky_e_up, sun_e_up)]),
        "sun_normal_over_sky_up": round(luminance(sun_e_normal) / luminance(sky_e_up), 4),
        "ground_radiance": [round(decode_rgbe(rgbe(ground))[k], 6) for k in range(3)],
        "sky_radiance_zenith": [round(x, 6) for x in decode_rgbe(rows[0][width // 2])],
        "sky_radiance_horizon_opposite_sun": [round(x, 6) for x in decode_rgbe(
            rows[sky_rows - 1][int(map_coordinates((-sun[0], 0.0, -sun[2]))[0] * width) % width])],
        "sphere_integral": lum3(all_total),
    }
    return data, report


def parse_size(text):
    w, h = (int(x) for x in text.lower().split("x"))
    if w < 8 or w > 32767 or h < 2 or h % 2 or w != 2 * h:
        raise argparse.ArgumentTypeError("want WxH with W = 2H, H even, 8 <= W <= 32767")
    return w, h


def parse_colour(text):
    c = [float(x) for x in text.split(",")]
    if len(c) == 1:
        c = c * 3
    if len(c) != 3 or min(c) < 0 or max(c) > 1:
        raise argparse.ArgumentTypeError("want r,g,b in [0, 1] (or one number)")
    return c


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(root, "scenes", "env", "sky.hdr"), help="output .hdr")
    ap.add_argument("--size", type=parse_size, default=(1024, 512), help="WxH, W = 2H (1024x512)")
    ap.add_argument("--sun-elevation", type=float, default=35.0, help="degrees above the horizon (35)")
    ap.add_argument("--sun-azimuth", type=float, default=120.0,
                    help="degrees from +x towards +z (120: up-left-front of a camera on +z)")
    ap.add_argument("--sun-radius", type=float, default=0.75, help="angular radius, degrees (0.75)")
    ap.add_argument("--turbidity", type=float, default=3.0,
                    help="haze, 2 (very clear) to 10 (hazy): paler sky, wider glow, warmer sun (3)")
    ap.add_argument("--sun-ratio", type=float, default=7.0,
                    help="sun irradiance facing it / sky irradiance on an upward plane (7)")
    ap.add_argument("--irradiance", type=float, default=math.pi,
                    help="sun + sky irradiance on an upward plane (pi: a white floor has radiance 1)")
    ap.add_argument("--ground-albedo", type=parse_colour, default=[0.26, 0.22, 0.18],
                    help="r,g,b of the ground below the horizon (0.26,0.22,0.18)")
    ap.add_argument("--json", help="also write the printed figures to this file")
    args = ap.parse_args()
    args.width, args.height = args.size
    if not 0.0 < args.sun_elevation < 90.0:
        ap.error("--sun-elevation must be in (0, 90)")
    if not 0.05 <= args.sun_radius <= 10.0:
        ap.error("--sun-radius must be in [0.05, 10]")
    if not (args.sun_ratio > 0 and args.irradiance > 0):
        ap.error("--sun-ratio and --irradiance must be positive")

    data, report = make_sky(args)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    tmp = args.out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, args.out)
    text = json.dumps(report, indent=2)
    print(text)
    if args.json:
        with open(args.json, "w") as f:
            f.write(text + "\n")
    print("wrote %s (%d bytes)" % (args.out, len(data)), file=sys.stderr)


if __name__ == "__main__":
    main()
