#!/usr/bin/env python3
"""Writes scenes/probes/sky.hdr: a synthetic lat-long light probe (Radiance
RGBE, flat scanlines) with a small bright sun, a blue sky brightening to the
horizon and a dim ground. Deterministic; pure Python, no packages.

fogbank's envmap convention (Mitsuba 3's): +y up, top row = zenith,
column u = phi / 2pi with phi = atan2(x, -z).

    python3 tools/make_sky_probe.py [OUT.hdr] [WIDTH]
"""
import math
import struct
import sys

def rgbe(r, g, b):
    v = max(r, g, b)
    if v < 1e-32:
        return bytes([0, 0, 0, 0])
    m, e = math.frexp(v)
    s = m * 256.0 / v
    return bytes([int(r * s), int(g * s), int(b * s), e + 128])

def radiance(theta, phi):
    d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
    # Sun: 35 degrees above the horizon, behind-right of a camera looking down -z.
    se, sa = math.radians(35.0), math.radians(120.0)
    s = (math.cos(se) * math.sin(sa), math.sin(se), -math.cos(se) * math.cos(sa))
    cos_sun = sum(a * b for a, b in zip(d, s))
    if cos_sun > math.cos(math.radians(2.5)):
        return (1100.0, 1000.0, 880.0)
    if d[1] < 0.0:
        return (0.16, 0.14, 0.12)
    t = d[1] ** 0.5
    zenith, horizon = (0.18, 0.35, 0.85), (0.85, 0.9, 1.0)
    glow = 0.6 * math.exp(-(1.0 - cos_sun) * 8.0)  # forward-scattered glow around the sun
    return tuple(h + (z - h) * t + glow for z, h in zip(zenith, horizon))

def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/probes/sky.hdr"
    w = int(sys.argv[2]) if len(sys.argv) > 2 else 256
    h = w // 2
    with open(out, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {h} +X {w}\n".encode())
        for i in range(h):
            theta = (i + 0.5) / h * math.pi
            row = bytearray()
            for j in range(w):
                phi = (j + 0.5) / w * 2.0 * math.pi
                row += rgbe(*radiance(theta, phi))
            f.write(row)

if __name__ == "__main__":
    main()
