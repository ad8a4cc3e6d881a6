#!/usr/bin/env python3
"""Writes scenes/street/windows.obj: the lit windows of a night street
(Lin et al. 2021 Fig. 18's setting — many small emitters in fog — as a stated
substitute for Bistro / Emerald Square, which cannot be downloaded here).
Two facades of `COLUMNS` × `FLOORS` windows face each other across the
street; each window is two triangles whose winding faces the street, so
the one-sided area emitter lights the street and not the houses behind.

    python3 tools/make_window_street.py   # 3200 triangles
"""
import pathlib

COLUMNS, FLOORS = 80, 10
HALF_WIDTH = 4.0          # facades at x = ±4
SPACING, STOREY = 0.8, 1.6
W, H = 0.5, 0.9           # window size

out = pathlib.Path(__file__).resolve().parent.parent / "scenes" / "street" / "windows.obj"
lines = ["# tools/make_window_street.py: %d windows" % (2 * COLUMNS * FLOORS)]
faces = []
n = 0
for side in (-1.0, 1.0):
    x = side * HALF_WIDTH
    for c in range(COLUMNS):
        z0 = -1.0 - c * SPACING
        for f in range(FLOORS):
            y0 = 0.8 + f * STOREY
            quad = [(x, y0, z0), (x, y0, z0 - W), (x, y0 + H, z0 - W), (x, y0 + H, z0)]
            lines += ["v %.4f %.4f %.4f" % v for v in quad]
            a, b, c2, d = n + 1, n + 2, n + 3, n + 4
            # Normal toward the street (−side along x).
            if side < 0:
                faces += ["f %d %d %d" % (a, b, c2), "f %d %d %d" % (a, c2, d)]
            else:
                faces += ["f %d %d %d" % (a, c2, b), "f %d %d %d" % (a, d, c2)]
            n += 4
out.write_text("\n".join(lines + faces) + "\n")
print(out, len(faces), "triangles")
