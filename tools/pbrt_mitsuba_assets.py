#!/usr/bin/env python3
"""Volume data shared by the pbrt-v4 scenes of scenes/pbrt/ and their
hand-written Mitsuba 3 twins in scenes/pbrt/mitsuba/.

Writes, from the same float32 arrays (fixed formulas, no randomness):

    scenes/pbrt/data/blob.nvdb          a 20^3 density for pbrt's `nanovdb`
                                        medium: written as OpenVDB by
                                        python3-openvdb (pyopenvdb), turned into
                                        NanoVDB by Debian's `nanovdb_convert`
    scenes/pbrt/mitsuba/data/blob.vol   the same voxels as a Mitsuba gridvolume
    scenes/pbrt/mitsuba/data/ugrid.vol  the 12 x 10 x 8 density inlined in
                                        scenes/pbrt/uniformgrid_area.pbrt
    scenes/pbrt/mitsuba/data/rgb_*.vol  the rgbgrid's sigma_t and albedo

Placement. pbrt's `nanovdb` medium samples voxel (i, j, k) at index point
(i, j, k); a Mitsuba gridvolume puts its N cells' centres at
(i + 0.5)/N of its box, so the Mitsuba box spans index -0.5 .. N - 0.5.
pbrt's `uniformgrid` is cell-centred over p0..p1, as Mitsuba's gridvolume
over its box. Every grid has a zero outer layer, so pbrt's interpolation
towards zero outside and Mitsuba's clamping to the edge agree.

Run with Debian's python3 (it has pyopenvdb and numpy):
    /usr/bin/python3 tools/pbrt_mitsuba_assets.py
"""

import os
import struct
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PBRT = os.path.join(ROOT, "scenes", "pbrt")
MI_DATA = os.path.join(PBRT, "mitsuba", "data")

BLOB_N = 20
BLOB_VOXEL = 0.1


def write_vol(path, data, bbox):
    """Mitsuba .vol v3 (float32), data indexed [z, y, x] or [z, y, x, c]."""
    if data.ndim == 3:
        data = data[..., None]
    nz, ny, nx, nc = data.shape
    with open(path, "wb") as f:
        f.write(b"VOL" + bytes([3]))
        f.write(struct.pack("<iiiii", 1, nx, ny, nz, nc))
        f.write(struct.pack("<6f", *bbox))
        f.write(np.ascontiguousarray(data, dtype="<f4").tobytes())


def blob():
    """[z, y, x] density: two overlapping smooth bumps, zero outer layer."""
    n = BLOB_N
    z, y, x = np.meshgrid(*(np.arange(n, dtype=np.float64),) * 3, indexing="ij")
    c = (n - 1) / 2.0

    def bump(cx, cy, cz, r):
        q = ((x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2) / r**2
        return np.clip(1.0 - q, 0.0, None) ** 2

    d = bump(c - 2, c, c, 8.0) + 0.8 * bump(c + 3.5, c + 2, c - 1, 5.0)
    d[[0, -1], :, :] = 0
    d[:, [0, -1], :] = 0
    d[:, :, [0, -1]] = 0
    return d.astype(np.float32)


def ugrid():
    """[z, y, x] 8 x 10 x 12 density for the uniformgrid: a ramp times a
    bump, zero outer layer."""
    nz, ny, nx = 8, 10, 12
    z, y, x = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    u = (x + 0.5) / nx
    q = ((x - 5.5) / 5) ** 2 + ((y - 4.5) / 4.5) ** 2 + ((z - 3.5) / 3.5) ** 2
    d = np.clip(1.0 - q, 0.0, None) * (0.4 + 1.2 * u)
    d[[0, -1], :, :] = 0
    d[:, [0, -1], :] = 0
    d[:, :, [0, -1]] = 0
    return d.astype(np.float32)


def rgb_grids():
    """[z, y, x, c] sigma_a and sigma_s of the rgbgrid (6 x 6 x 6, zero
    outer layer): sigma_s reddish towards +x, bluish towards -x."""
    n = 6
    z, y, x = np.meshgrid(*(np.arange(n),) * 3, indexing="ij")
    inner = ((x > 0) & (x < n - 1) & (y > 0) & (y < n - 1) & (z > 0) & (z < n - 1))
    t = x / (n - 1.0)
    s = np.stack([0.4 + 1.2 * t, 0.8 + 0.0 * t, 1.6 - 1.2 * t], axis=-1)
    a = np.stack([0.1 + 0.0 * t, 0.3 - 0.2 * t, 0.2 + 0.0 * t], axis=-1)
    return (a * inner[..., None]).astype(np.float32), (s * inner[..., None]).astype(np.float32)


def pbrt_floats(a):
    """x fastest, as pbrt's grids (and the [z, y, x] arrays' C order)."""
    return " ".join(f"{v:.6g}" for v in np.asarray(a, dtype=np.float32).ravel())


def write_nvdb(path, d):
    import pyopenvdb as vdb

    g = vdb.FloatGrid()
    g.copyFromArray(np.ascontiguousarray(np.transpose(d, (2, 1, 0))))  # [x, y, z]
    g.transform = vdb.createLinearTransform(voxelSize=BLOB_VOXEL)
    g.name = "density"
    g.gridClass = vdb.GridClass.FOG_VOLUME
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "blob.vdb")
        vdb.write(src, grids=[g])
        subprocess.run(["nanovdb_convert", "-f", "-z", src, path], check=True)


def main():
    os.makedirs(MI_DATA, exist_ok=True)
    os.makedirs(os.path.join(PBRT, "data"), exist_ok=True)
    d = blob()
    write_nvdb(os.path.join(PBRT, "data", "blob.nvdb"), d)
    lo, hi = -0.5 * BLOB_VOXEL, (BLOB_N - 0.5) * BLOB_VOXEL
    write_vol(os.path.join(MI_DATA, "blob.vol"), d, (lo, lo, lo, hi, hi, hi))
    u = ugrid()
    write_vol(os.path.join(MI_DATA, "ugrid.vol"), u, (0, 0, 0, 1, 1, 1))
    with open(os.path.join(PBRT, "data", "ugrid_density.txt"), "w") as f:
        f.write(pbrt_floats(u) + "\n")
    a, s = rgb_grids()
    t = a + s
    alb = np.where(t > 0, s / np.where(t > 0, t, 1), 0)
    write_vol(os.path.join(MI_DATA, "rgb_sigma_t.vol"), t, (0, 0, 0, 1, 1, 1))
    write_vol(os.path.join(MI_DATA, "rgb_albedo.vol"), alb, (0, 0, 0, 1, 1, 1))
    with open(os.path.join(PBRT, "data", "rgb_sigma_a.txt"), "w") as f:
        f.write(pbrt_floats(a) + "\n")
    with open(os.path.join(PBRT, "data", "rgb_sigma_s.txt"), "w") as f:
        f.write(pbrt_floats(s) + "\n")
    print("assets written under", PBRT)


if __name__ == "__main__":
    sys.exit(main())
