#!/usr/bin/env python3
"""Writes an equirectangular Radiance .hdr of a clear sky: a blue gradient over a warm ground,
and a sun (a small disc much brighter than the sky, with a soft glow around it).

    scripts/sky-hdr.py OUT.hdr [--size 512] [--sun-azimuth 135] [--sun-elevation 35] [--sun 4000]

Azimuth is measured from -Z (the image's centre, behind a model seen from sinew's default camera)
towards +X, in degrees. The mapping is sinew's and three.js's: u = 0.5 + atan2(x, -z) / 2pi,
v = acos(y) / pi with row 0 on top. Plain Python, no dependencies; uncompressed RGBE scanlines,
which every .hdr reader accepts.
"""
import argparse
import math
import struct


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return b"\0\0\0\0"
    e = math.frexp(m)[1]
    s = 256.0 / 2.0**e
    return struct.pack("BBBB", int(r * s), int(g * s), int(b * s), e + 128)


def sky(d, sun, sun_radiance, glow):
    x, y, z = d
    if y < 0.0:  # the ground: warm grey, darker towards the nadir
        t = math.sqrt(-y)
        base = (0.32 - 0.12 * t, 0.28 - 0.10 * t, 0.24 - 0.08 * t)
    else:  # the sky: pale at the horizon, deep blue at the zenith
        t = math.sqrt(y)
        base = (0.85 - 0.55 * t, 0.92 - 0.42 * t, 1.05 - 0.15 * t)
    c = sum(a * b for a, b in zip(d, sun))
    angle = math.acos(max(-1.0, min(1.0, c)))
    disc = sun_radiance if angle < math.radians(1.2) else 0.0
    halo = glow * math.exp(-angle / math.radians(6.0))
    return tuple(b + disc * w + halo * w for b, w in zip(base, (1.0, 0.93, 0.82)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--size", type=int, default=512, help="width in texels (height is half)")
    ap.add_argument("--sun-azimuth", type=float, default=135.0)
    ap.add_argument("--sun-elevation", type=float, default=35.0)
    ap.add_argument("--sun", type=float, default=4000.0, help="the disc's radiance (the sky's is about 1)")
    a = ap.parse_args()
    w, h = a.size, a.size // 2
    az, el = math.radians(a.sun_azimuth), math.radians(a.sun_elevation)
    sun = (math.cos(el) * math.sin(az), math.sin(el), -math.cos(el) * math.cos(az))
    rows = []
    for j in range(h):
        theta = (j + 0.5) / h * math.pi
        row = bytearray()
        for i in range(w):
            phi = (i + 0.5) / w * 2.0 * math.pi - math.pi
            d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
            row += rgbe(*sky(d, sun, a.sun, 3.0))
        rows.append(bytes(row))
    with open(a.out, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(b"-Y %d +X %d\n" % (h, w))
        for r in rows:
            f.write(r)


if __name__ == "__main__":
    main()
