#!/usr/bin/python3
"""Writes the OpenVDB test fixtures of fogbank-volume and their reference values.

Run with Debian's python (python3-openvdb, libopenvdb-tools, python3-blosc):

    /usr/bin/python3 tools/make_vdb_fixtures.py

Grids are built with pyopenvdb, then rewritten by `vdb_tool` to choose the
compression (none / zip / blosc / active-mask only) and the storage precision
(32 or 16 bits): pyopenvdb itself always writes Blosc + active-mask. OpenVDB
drops Zip for fog volumes and level sets, so the Zip fixtures use class
`unknown`.

Reference values come from OpenVDB itself: each written file is read back with
pyopenvdb (so half-float rounding is included) and its active voxel count and
bounding box are cross-checked against `vdb_print -l`. They go to
`crates/volume/tests/fixtures/vdb/manifest.json`, together with the same
numbers for the real files: the committed ones of `data/` and the external
ones (`data/fetched/` or `../shared/data/`) when those exist. `--only real`
refreshes just those entries.

Vector fixtures (`vec3_*`, `density_vel.vdb`, `vec3_instance.vdb`,
`vec3_stream.vdb`) hold `vec3s` grids; their manifest entries list, under
`vec3_reads`, one reference per component (`vel.x`, `vel.y`, `vel.z`) in the
same form as the float entries. The uncompressed ones are stored gzipped
(`*.vdb.gz`): an uncompressed vec3 32^3 internal node alone takes 384 KiB.
`--only vec3` rewrites just those and merges them into the existing manifest.

The script also writes `blosc_frames.json`: Blosc frames made with
python-blosc using codecs and shuffles OpenVDB never writes (blosclz, zlib,
lz4hc, bit shuffle), to test the frame decoder on its own.
"""

import argparse
import base64
import gzip
import json
import math
import os
import random
import re
import subprocess
import sys
import tempfile
import zlib

import pyopenvdb as vdb

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "crates", "volume", "tests", "fixtures", "vdb")
DATA = os.path.join(ROOT, "data")
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "data")

CLASS_NAMES = {
    vdb.GridClass.FOG_VOLUME: "fog volume",
    vdb.GridClass.LEVEL_SET: "level set",
    vdb.GridClass.STAGGERED: "staggered",
    vdb.GridClass.UNKNOWN: "unknown",
}


# ---------------------------------------------------------------------------
# Grid builders


def fog_source():
    """A smooth blob plus hand-made leaves and tiles that exercise every
    per-node inactive-value mode OpenVDB can write for a fog-like grid."""
    g = vdb.FloatGrid(0.0)
    g.name = "density"
    g.gridClass = vdb.GridClass.FOG_VOLUME
    acc = g.getAccessor()
    # Blob: values in (0.05, 1], spanning several leaves and 16^3 nodes but a
    # single 32^3 node (uncompressed, each of those stores 128 KiB of tiles).
    for i in range(100, 148):
        for j in range(108, 141):
            for k in range(0, 41):
                x, y, z = (i - 124) / 14.0, (j - 124) / 10.0, (k - 20) / 12.0
                v = math.exp(-2.0 * (x * x + y * y + z * z))
                if v > 0.05:
                    acc.setValueOn((i, j, k), v)
    # Leaf with one distinct non-background inactive value (mode 2).
    for n in range(512):
        ijk = (64 + (n >> 6), (n >> 3) & 7, n & 7)
        if n % 9 == 0:
            acc.setValueOn(ijk, 0.9)
        else:
            acc.setValueOff(ijk, 0.5)
    # Two distinct non-background inactive values (mode 5).
    for n in range(512):
        ijk = (72 + (n >> 6), (n >> 3) & 7, n & 7)
        if n % 11 == 0:
            acc.setValueOn(ijk, 0.8)
        else:
            acc.setValueOff(ijk, 0.5 if n % 2 else 0.75)
    # One non-background inactive value next to background ones (mode 4).
    for n in range(0, 512, 3):
        ijk = (80 + (n >> 6), (n >> 3) & 7, n & 7)
        if n % 5 == 0:
            acc.setValueOn(ijk, 0.7)
        else:
            acc.setValueOff(ijk, 0.3)
    # More than two distinct inactive values: everything is stored (mode 6).
    for n in range(512):
        ijk = (88 + (n >> 6), (n >> 3) & 7, n & 7)
        if n % 13 == 0:
            acc.setValueOn(ijk, 0.6)
        elif n % 3 == 0:
            acc.setValueOff(ijk, 0.1 + 0.1 * (n % 4))
    # A completely active leaf: no inactive values to rebuild.
    for n in range(512):
        acc.setValueOn((96 + (n >> 6), (n >> 3) & 7, n & 7), 0.01 * (n % 97))
    # Tiles: an active 128^3 tile of a 32^3 node, an active and an inactive
    # (non-background) 8^3 tile of a 16^3 node.
    g.fill((256, 0, 0), (383, 127, 127), 0.5, True)
    g.fill((0, 64, 0), (7, 71, 7), 0.25, True)
    g.fill((8, 64, 0), (15, 71, 7), 0.125, False)
    g.transform = vdb.createLinearTransform(0.1)
    g.transform.translate((1.0, -2.0, 0.5))
    return g


def affine_grid():
    g = vdb.FloatGrid(0.0)
    g.name = "density"
    g.gridClass = vdb.GridClass.FOG_VOLUME
    acc = g.getAccessor()
    for i in range(-6, 7):
        for j in range(-6, 7):
            for k in range(-6, 7):
                r2 = i * i + j * j + k * k
                if r2 <= 36:
                    acc.setValueOn((i, j, k), 1.0 - r2 / 40.0)
    # Rotation of 30 degrees about (1, 1, 1), scales (0.1, 0.2, 0.05), a
    # translation; OpenVDB's row-vector convention: rows are images of axes.
    ax = [1 / math.sqrt(3)] * 3
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    rot = [[0.0] * 3 for _ in range(3)]
    for a in range(3):
        for b in range(3):
            rot[a][b] = (c if a == b else 0.0) + (1 - c) * ax[a] * ax[b]
    rot[0][1] -= s * ax[2]
    rot[0][2] += s * ax[1]
    rot[1][0] += s * ax[2]
    rot[1][2] -= s * ax[0]
    rot[2][0] -= s * ax[1]
    rot[2][1] += s * ax[0]
    scale = [0.1, 0.2, 0.05]
    m = [[scale[r] * rot[r][col] for col in range(3)] + [0.0] for r in range(3)]
    m.append([1.0, 2.0, 3.0, 1.0])
    g.transform = vdb.createLinearTransform(m)
    return g


def level_set():
    g = vdb.createLevelSetSphere(radius=2.0, center=(0.3, -0.2, 0.1), voxelSize=0.1, halfWidth=3.0)
    g.name = "surface"
    return g


def tiles_grid():
    """Constant tiles at every level, including root tiles (4096^3)."""
    g = vdb.FloatGrid(0.0)
    g.name = "density"
    g.gridClass = vdb.GridClass.FOG_VOLUME
    g.fill((-4096, -4096, -4096), (-1, -1, -1), 2.0, True)  # active root tile
    g.fill((4096, 0, 0), (8191, 4095, 4095), 3.0, False)  # inactive root tile
    g.fill((0, 0, 0), (127, 127, 127), 1.0, True)  # 32^3-node tile
    g.fill((128, 0, 0), (135, 7, 7), 0.75, True)  # 16^3-node tile
    g.fill((136, 0, 0), (143, 7, 7), 0.5, False)  # inactive 16^3-node tile
    acc = g.getAccessor()
    for n in range(40):
        acc.setValueOn((200 + n % 7, 3 + n % 5, 9 + n), 0.01 * n)
    g.transform = vdb.createLinearTransform([[0.5, 0, 0, 0], [0, 0.25, 0, 0], [0, 0, 2.0, 0], [0, 0, 0, 1]])
    return g


def multi_grids():
    dens = vdb.FloatGrid(0.0)
    dens.name = "density"
    dens.gridClass = vdb.GridClass.FOG_VOLUME
    acc = dens.getAccessor()
    for i in range(10):
        for j in range(10):
            for k in range(10):
                acc.setValueOn((i, j, k), (i + j + k) / 27.0)
    temp = vdb.FloatGrid(300.0)
    temp.name = "temperature"
    acc = temp.getAccessor()
    for i in range(-5, 5):
        acc.setValueOn((i, 2 * i, 3), 300.0 + 10 * i)
    vel = vdb.Vec3SGrid()
    vel.name = "vel"
    vel.getAccessor().setValueOn((1, 2, 3), (1.0, 2.0, 3.0))
    mask = vdb.BoolGrid()
    mask.name = "mask"
    mask.getAccessor().setValueOn((4, 5, 6), True)
    heat0 = vdb.FloatGrid(0.0)
    heat0.name = "heat"
    heat0.getAccessor().setValueOn((1, 1, 1), 10.0)
    heat1 = vdb.FloatGrid(0.0)
    heat1.name = "heat"
    heat1.getAccessor().setValueOn((2, 2, 2), 20.0)
    inst = dens.copy()  # shares the tree: written as an instance
    inst.name = "density_instance"
    xf = vdb.createLinearTransform([[0.2, 0, 0, 0], [0, 0.3, 0, 0], [0, 0, 0.4, 0], [5, 6, 7, 1]])
    for g in (dens, temp, vel, mask, heat0, heat1, inst):
        g.transform = xf
    return [vel, mask, temp, dens, heat0, heat1, inst]


def vec3_leaf(acc, x0, active, inactive):
    """One 8^3 leaf at (x0, 0, 0): `active(n)` gives the value of voxel n or
    None, `inactive(n)` the inactive value (None leaves the voxel alone)."""
    for n in range(512):
        ijk = (x0 + (n >> 6), (n >> 3) & 7, n & 7)
        v = active(n)
        if v is not None:
            acc.setValueOn(ijk, v)
        else:
            w = inactive(n)
            if w is not None:
                acc.setValueOff(ijk, w)


def swirl_source():
    """A swirl v = (-(z-c), 0.3 + (y-c)/100, x-c) / 20 in a ball of radius 11
    inside 32^3, with a background that is not a half float, leaves for each
    per-node inactive-value mode and tiles at every level. Root tiles, the
    background and stored inactive values are written at full width even in
    half grids; root tile values are not even rounded."""
    bg = (0.1, -0.2, 0.3)
    neg = tuple(-v for v in bg)
    g = vdb.Vec3SGrid(bg)
    g.name = "vel"
    g.gridClass = vdb.GridClass.UNKNOWN  # OpenVDB drops Zip for fog volumes
    acc = g.getAccessor()
    c = 16
    for i in range(32):
        for j in range(32):
            for k in range(32):
                if (i - c) ** 2 + (j - c) ** 2 + (k - c) ** 2 <= 121:
                    acc.setValueOn((i, j, k), (-(k - c) / 20.0, 0.3 + (j - c) / 100.0, (i - c) / 20.0))
    on = lambda step, v: (lambda n: v if n % step == 0 else None)
    # One non-background inactive value (mode 2).
    vec3_leaf(acc, 40, on(9, (0.9, 0.1, -0.3)), lambda n: (0.5, 0.25, -0.125))
    # Two non-background inactive values (mode 5).
    vec3_leaf(acc, 48, on(11, (0.8, -0.6, 0.4)), lambda n: (0.5, 0.5, 0.5) if n % 2 else (0.75, 0.0, -1.0))
    # Background and one other inactive value (mode 4).
    vec3_leaf(acc, 56, on(5, (0.7, 0.7, 0.7)), lambda n: (0.3, -0.3, 0.3) if n % 3 == 0 else None)
    # +background and -background (mode 3), all -background (mode 1).
    vec3_leaf(acc, 64, on(7, (0.6, 0.0, -0.6)), lambda n: neg if n % 2 else None)
    vec3_leaf(acc, 72, on(13, (-0.5, 0.5, 1.5)), lambda n: neg)
    # More than two inactive values: everything is stored (mode 6).
    vec3_leaf(acc, 80, on(13, (0.6, 0.6, 0.6)), lambda n: (0.1 * (n % 4), 0.2, -0.1 * (n % 5)) if n % 3 == 0 else None)
    # Tiles: active and inactive 8^3 tiles of a 16^3 node, an active 128^3
    # tile of the 32^3 node (half in half grids), root tiles (never half).
    g.fill((0, 64, 0), (7, 71, 7), (0.25, 0.5, -0.75), True)
    g.fill((8, 64, 0), (15, 71, 7), (0.125, 0.1, 0.0), False)
    g.fill((128, 0, 0), (255, 127, 127), (0.1, 0.2, -0.3), True)
    g.fill((-4096, -4096, -4096), (-1, -1, -1), (0.7, -0.1, 0.2), True)
    g.fill((4096, 0, 0), (8191, 4095, 4095), (-0.3, 0.6, 0.9), False)
    g.transform = vdb.createLinearTransform(0.05)
    g.transform.translate((-0.8, 0.0, 0.25))
    return g


def density_vel_grids():
    """A float density and two vec3s grids; `vel` is not the first one, so
    the default choice must go by name. `vel` is saved as half."""
    dens = vdb.FloatGrid(0.0)
    dens.name = "density"
    dens.gridClass = vdb.GridClass.FOG_VOLUME
    curl = vdb.Vec3SGrid()
    curl.name = "curl"
    vel = vdb.Vec3SGrid()
    vel.name = "vel"
    vel.gridClass = vdb.GridClass.STAGGERED
    vel.saveFloatAsHalf = True
    da, ca, va = dens.getAccessor(), curl.getAccessor(), vel.getAccessor()
    # Non-negative coordinates: one 32^3 node (8 KiB of masks) per grid.
    for i in range(4, 17):
        for j in range(0, 13):
            for k in range(2, 15):
                r2 = (i - 10) ** 2 + (j - 6) ** 2 + (k - 8) ** 2
                if r2 <= 30:
                    da.setValueOn((i, j, k), 1.0 - r2 / 32.0)
                    va.setValueOn((i, j, k), ((j - 6) * 0.3, -(i - 10) * 0.3, 0.1 * k))
                    if r2 <= 9:
                        ca.setValueOn((i, j, k), (0.0, 0.0, 0.6 + 0.01 * r2))
    xf = vdb.createLinearTransform(0.2)
    for g in (dens, curl, vel):
        g.transform = xf
    return [dens, curl, vel]


def vec3_instance_grids():
    """A half vec3s grid and an instance of it with its own transform; no
    `vel` among them, so the default choice is the first vec3s grid."""
    flow = vdb.Vec3SGrid((0.0, 0.0, -1.0))
    flow.name = "flow"
    flow.saveFloatAsHalf = True
    acc = flow.getAccessor()
    for n in range(300):
        i, j, k = n % 11, (n // 11) % 9, n // 99
        acc.setValueOn((i - 5, j, 2 * k), (0.01 * i, -0.02 * j, 1.0 / (1 + k)))
    flow.fill((16, 16, 16), (23, 23, 23), (1.0, 1.5, -2.0), True)
    flow.transform = vdb.createLinearTransform(0.1)
    inst = flow.copy()  # shares the tree: written as an instance
    inst.name = "flow_copy"
    inst.transform = vdb.createLinearTransform([[0.3, 0, 0, 0], [0, 0.3, 0, 0], [0, 0, 0.3, 0], [1, 2, 3, 1]])
    return [flow, inst]


# ---------------------------------------------------------------------------
# Writing


def run(cmd):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def rewrite(src, dst, codec, bits):
    if os.path.exists(dst):
        os.remove(dst)
    run(["vdb_tool", "-read", src, "-write", "codec=" + codec, "bits=%d" % bits, dst])


# ---------------------------------------------------------------------------
# Reference values


def vdb_print_stats(path):
    out = subprocess.run(["vdb_print", "-l", path], check=True, capture_output=True, text=True).stdout
    stats = {}
    name = None
    for line in out.splitlines():
        m = re.match(r"Name: (.*)", line)
        if m:
            name = m.group(1).strip()
            stats[name] = {}
        m = re.search(r"Number of active voxels:\s+([\d,]+)", line)
        if m and name is not None:
            stats[name]["count"] = int(m.group(1).replace(",", ""))
        m = re.search(r"Bounding box of active voxels: \[(.*)\] -> \[(.*)\]", line)
        if m and name is not None:
            lo = [int(v) for v in m.group(1).split(",")]
            hi = [int(v) for v in m.group(2).split(",")]
            stats[name]["bbox"] = [lo, hi]
    return stats


def transform_matrix(grid):
    """Row-major matrix for column vectors: world = M (i, j, k, 1)."""
    xf = grid.transform
    o = xf.indexToWorld((0, 0, 0))
    cols = [[xf.indexToWorld(e)[r] - o[r] for r in range(3)] for e in ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
    m = [[cols[c][r] for c in range(3)] + [o[r]] for r in range(3)]
    m.append([0.0, 0.0, 0.0, 1.0])
    return m


def grid_reference(grid, seed, component=None):
    """Reference values of a float grid, or of one component of a vec3s grid
    (named `name.x` etc.; the same sample points for every component)."""
    val = (lambda v: v) if component is None else (lambda v: v[component])
    rng = random.Random(seed)
    count = 0
    total = 0.0
    vmin, vmax = math.inf, -math.inf
    voxels, tiles = [], []
    for it in grid.citerOnValues():
        value = val(it.value)
        count += it.count
        total += value * it.count
        vmin, vmax = min(vmin, value), max(vmax, value)
        if it.count == 1:
            voxels.append(it.min)
        else:
            tiles.append((it.min, it.max))
    off_voxels, off_tiles = [], []
    for it in grid.citerOffValues():
        if it.count == 1:
            off_voxels.append(it.min)
        elif it.value != grid.background:
            off_tiles.append((it.min, it.max))
        if len(off_voxels) > 20000 and len(off_tiles) > 50:
            break
    assert count == grid.activeVoxelCount(), (count, grid.activeVoxelCount())
    bbox = grid.evalActiveVoxelBoundingBox()
    pts = []
    pts += rng.sample(voxels, min(20, len(voxels)))
    pts += rng.sample(off_voxels, min(10, len(off_voxels)))
    for lo, hi in rng.sample(tiles, min(4, len(tiles))) + rng.sample(off_tiles, min(4, len(off_tiles))):
        pts.append(lo)
        pts.append(hi)
        pts.append(tuple(rng.randint(lo[c], hi[c]) for c in range(3)))
    if count:
        lo, hi = bbox
        for _ in range(10):
            pts.append(tuple(rng.randint(lo[c] - 20, hi[c] + 20) for c in range(3)))
    pts += [(1000000, 0, 0), (-7, -300000, 5), (0, 0, 0), (-1, -1, -1)]
    acc = grid.getConstAccessor()
    samples = [[int(p[0]), int(p[1]), int(p[2]), float(val(acc.getValue(tuple(p))))] for p in pts]
    return {
        "name": grid.name if component is None else grid.name + "." + "xyz"[component],
        "grid_class": CLASS_NAMES[grid.gridClass],
        "stored_as_half": bool(grid.saveFloatAsHalf),
        "background": float(val(grid.background)),
        "active_voxel_count": count,
        "bbox": [list(bbox[0]), list(bbox[1])] if count else None,
        "sum": total,
        "range": [vmin, vmax] if count else None,
        "transform": transform_matrix(grid),
        "samples": samples,
    }


def describe_file(path, rel, reads, compression, extra=None, vec3_reads=()):
    """Reference entry for one file; `reads` and `vec3_reads` list the float
    and vec3s grid names to check as (request, expect) pairs (request None =
    the reader's default choice, which must be `expect`)."""
    metas = vdb.readAllGridMetadata(path)
    grids = []
    for m in metas:
        grids.append({"name": m.name, "value_type": m.valueTypeName, "grid_class": CLASS_NAMES[m.gridClass]})
    stats = vdb_print_stats(path)
    entries = []
    for request, expect in reads:
        g = vdb.read(path, expect)
        ref = grid_reference(g, seed=zlib.crc32((rel + expect).encode()))
        s = stats.get(expect)
        if s is not None:
            assert s["count"] == ref["active_voxel_count"], (path, s, ref["active_voxel_count"])
            if ref["bbox"] is not None and "bbox" in s:
                assert s["bbox"] == ref["bbox"], (path, s["bbox"], ref["bbox"])
        ref["request"] = request
        ref["compression"] = compression
        entries.append(ref)
    vec3_entries = []
    for request, expect in vec3_reads:
        g = vdb.read(path, expect)
        assert g.valueTypeName == "vec3s", (path, expect, g.valueTypeName)
        seed = zlib.crc32((rel + expect).encode())
        comps = [grid_reference(g, seed, c) for c in range(3)]
        s = stats.get(expect)
        for ref in comps:
            if s is not None:
                assert s["count"] == ref["active_voxel_count"], (path, s, ref["active_voxel_count"])
                if ref["bbox"] is not None and "bbox" in s:
                    assert s["bbox"] == ref["bbox"], (path, s["bbox"], ref["bbox"])
            ref["compression"] = compression
        vec3_entries.append({"request": request, "name": expect, "components": comps})
    with open(path, "rb") as f:
        head = f.read(12)
    entry = {
        "file": rel,
        "file_version": int.from_bytes(head[8:12], "little"),
        "size": os.path.getsize(path),
        "grids": grids,
        "reads": entries,
    }
    if vec3_entries:
        entry["vec3_reads"] = vec3_entries
    if extra:
        entry.update(extra)
    return entry


def blosc_frames():
    """Frames in codec/shuffle combinations OpenVDB does not write."""
    import blosc
    import struct

    rng = random.Random(7)
    floats = [math.sin(i * 0.05) * 0.5 + 0.5 + rng.random() * 1e-3 for i in range(1200)]
    data = struct.pack("<%df" % len(floats), *floats)
    # Float data, float data with a size that is not a multiple of the type
    # size, and byte data (type size 1: no split, no byte shuffle).
    payloads = [(4, data, 0), (4, data[:900 * 4 + 3], 0), (1, bytes(range(256)) * 5, 0)]
    frames = []
    for cname in ("blosclz", "lz4", "lz4hc", "zlib"):
        for shuffle, sname in ((blosc.NOSHUFFLE, "none"), (blosc.SHUFFLE, "byte"), (blosc.BITSHUFFLE, "bit")):
            for index, (typesize, payload, blocksize) in enumerate(payloads):
                blosc.set_blocksize(blocksize)
                frame = blosc.compress(payload, typesize=typesize, clevel=5, shuffle=shuffle, cname=cname)
                frames.append({
                    "codec": cname,
                    "shuffle": sname,
                    "typesize": typesize,
                    "payload": index,
                    "frame": base64.b64encode(frame).decode(),
                })
    # A 40 003-byte payload: blosc picks a 40 000-byte block, so the frame has
    # two blocks, the second a 3-byte leftover that is neither split nor shuffled.
    big = [math.sin(i * 0.01) + rng.random() * 1e-2 for i in range(10001)]
    payloads.append((4, struct.pack("<%df" % len(big), *big)[:40003], 0))
    for cname, shuffle, sname in (("blosclz", blosc.SHUFFLE, "byte"), ("lz4", blosc.BITSHUFFLE, "bit"),
                                  ("zlib", blosc.SHUFFLE, "byte")):
        frame = blosc.compress(payloads[-1][1], typesize=4, clevel=5, shuffle=shuffle, cname=cname)
        frames.append({"codec": cname, "shuffle": sname, "typesize": 4, "payload": len(payloads) - 1,
                       "frame": base64.b64encode(frame).decode()})
    blosc.set_blocksize(0)
    return {"payloads": [base64.b64encode(p[1]).decode() for p in payloads], "frames": frames}


def float_fixtures(tmp):
    fixtures = []
    # Fog source in every precision x compression; Zip needs class unknown.
    fog = fog_source()
    src_fog = os.path.join(tmp, "fog.vdb")
    vdb.write(src_fog, grids=[fog])
    fog.gridClass = vdb.GridClass.UNKNOWN
    src_unknown = os.path.join(tmp, "unknown.vdb")
    vdb.write(src_unknown, grids=[fog])
    variants = [
        ("none", "none", src_fog),
        ("active", "active-mask", src_fog),
        ("zip", "zip + active-mask", src_unknown),
        ("blosc", "blosc + active-mask", src_fog),
    ]
    for bits, prec in ((32, "f32"), (16, "half")):
        for codec, cname, src in variants:
            rel = "fog_%s_%s.vdb" % (prec, codec)
            dst = os.path.join(OUT, rel)
            rewrite(src, dst, codec, bits)
            fixtures.append(describe_file(dst, rel, [(None, "density")], cname))

    src = os.path.join(tmp, "affine.vdb")
    vdb.write(src, grids=[affine_grid()])
    rewrite(src, os.path.join(OUT, "affine_half_blosc.vdb"), "blosc", 16)
    fixtures.append(describe_file(os.path.join(OUT, "affine_half_blosc.vdb"), "affine_half_blosc.vdb",
                                  [(None, "density")], "blosc + active-mask"))

    src = os.path.join(tmp, "ls.vdb")
    vdb.write(src, grids=[level_set()])
    for codec, bits, cname in (("blosc", 32, "blosc + active-mask"), ("active", 16, "active-mask")):
        rel = "levelset_%s_%s.vdb" % ("f32" if bits == 32 else "half", codec)
        rewrite(src, os.path.join(OUT, rel), codec, bits)
        fixtures.append(describe_file(os.path.join(OUT, rel), rel, [(None, "surface"), ("surface", "surface")], cname))

    src = os.path.join(tmp, "tiles.vdb")
    vdb.write(src, grids=[tiles_grid()])
    rewrite(src, os.path.join(OUT, "tiles_f32_zip.vdb"), "zip", 32)
    # Zip is dropped for fog volumes, so this one ends up active-mask only.
    fixtures.append(describe_file(os.path.join(OUT, "tiles_f32_zip.vdb"), "tiles_f32_zip.vdb",
                                  [(None, "density")], "active-mask"))

    # A stream (no grid offsets): vdb_tool writes one when the output is stdout.
    dst = os.path.join(OUT, "stream_tiles.vdb")
    with open(dst, "wb") as f:
        subprocess.run(["vdb_tool", "-read", src, "-write", "codec=blosc", "stdout.vdb"], check=True, stdout=f)
    fixtures.append(describe_file(dst, "stream_tiles.vdb", [(None, "density")], "blosc + active-mask",
                                  extra={"has_grid_offsets": False}))

    # Written by pyopenvdb directly so that the instance survives.
    dst = os.path.join(OUT, "multi.vdb")
    vdb.write(dst, grids=multi_grids())
    fixtures.append(describe_file(dst, "multi.vdb", [
        (None, "density"), ("temperature", "temperature"), ("density_instance", "density_instance"),
    ], "blosc + active-mask", extra={"unsupported": ["vel", "mask"]}))

    return fixtures


def vec3_fixtures(tmp):
    fixtures = []
    src = os.path.join(tmp, "swirl.vdb")
    vdb.write(src, grids=[swirl_source()])
    for bits, prec in ((32, "f32"), (16, "half")):
        for codec, cname in (("none", "none"), ("active", "active-mask"), ("zip", "zip + active-mask"),
                             ("blosc", "blosc + active-mask")):
            rel = "vec3_%s_%s.vdb" % (prec, codec)
            if codec == "none":
                # Uncompressed, the 32^3 node's tile values alone take 384 KiB.
                dst = os.path.join(tmp, rel)
                rewrite(src, dst, codec, bits)
                entry = describe_file(dst, rel + ".gz", [], cname, vec3_reads=[(None, "vel")], extra={"gzip": True})
                with open(dst, "rb") as f, open(os.path.join(OUT, rel + ".gz"), "wb") as out:
                    with gzip.GzipFile(filename=rel, mode="wb", fileobj=out, mtime=0) as z:
                        z.write(f.read())
            else:
                dst = os.path.join(OUT, rel)
                rewrite(src, dst, codec, bits)
                entry = describe_file(dst, rel, [], cname, vec3_reads=[(None, "vel")])
            fixtures.append(entry)

    # Written by pyopenvdb directly (Blosc): mixed precision, and instances.
    dst = os.path.join(OUT, "density_vel.vdb")
    vdb.write(dst, grids=density_vel_grids())
    fixtures.append(describe_file(dst, "density_vel.vdb", [(None, "density")], "blosc + active-mask",
                                  vec3_reads=[(None, "vel"), ("curl", "curl")]))
    dst = os.path.join(OUT, "vec3_instance.vdb")
    vdb.write(dst, grids=vec3_instance_grids())
    fixtures.append(describe_file(dst, "vec3_instance.vdb", [], "blosc + active-mask",
                                  vec3_reads=[("flow_copy", "flow_copy")]))
    # A stream (no grid offsets) whose vec3s grids precede the float grid.
    src = os.path.join(tmp, "dv.vdb")
    grids = density_vel_grids()
    vdb.write(src, grids=grids[1:] + grids[:1])
    dst = os.path.join(OUT, "vec3_stream.vdb")
    with open(dst, "wb") as f:
        subprocess.run(["vdb_tool", "-read", src, "-write", "codec=blosc", "stdout.vdb"], check=True, stdout=f)
    fixtures.append(describe_file(dst, "vec3_stream.vdb", [(None, "density")], "blosc + active-mask",
                                  extra={"has_grid_offsets": False}, vec3_reads=[("curl", "curl")]))
    return fixtures


def write_manifest(fixtures):
    with open(os.path.join(OUT, "manifest.json"), "w") as f:
        json.dump({"generator": "tools/make_vdb_fixtures.py", "openvdb": list(vdb.LIBRARY_VERSION),
                   "fixtures": fixtures}, f, indent=1)
    total = sum(os.path.getsize(os.path.join(OUT, n)) for n in os.listdir(OUT))
    print("wrote %d fixtures, %d bytes in %s" % (len(fixtures), total, OUT))


def real_fixtures():
    """Entries for the real files: the committed ones of data/ ("data:NAME")
    and, when present, the external ones ("shared:NAME", from data/fetched/
    or ../shared/data, see tools/fetch_data.sh)."""
    fixtures = []
    for name, grid, cname in (("dragon.vdb", "density", "blosc + active-mask"),
                              ("sphere.vdb", "ls_sphere", "blosc + active-mask")):
        fixtures.append(describe_file(os.path.join(DATA, name), "data:" + name, [(None, grid)], cname))
    for name, grid, cname in (("sphere.vdb", "ls_sphere", "active-mask"),
                              ("cube.vdb", "ls_cube", "active-mask")):
        found = [p for p in (os.path.join(DATA, "fetched", name), os.path.join(SHARED, name)) if os.path.exists(p)]
        if found:
            fixtures.append(describe_file(found[0], "shared:" + name, [(None, grid)], cname))
        else:
            print("skipping missing external", name, file=sys.stderr)
    return fixtures


def is_real(entry):
    return entry["file"].startswith(("data:", "shared:"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", choices=["vec3", "real"],
                    help="rewrite only the vec3 fixtures or only the real files' entries, keeping the others")
    args = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    tmp = tempfile.mkdtemp()
    if args.only:
        with open(os.path.join(OUT, "manifest.json")) as f:
            entries = json.load(f)["fixtures"]
        plain = [e for e in entries if "vec3_reads" not in e and not is_real(e)]
        vec3 = [e for e in entries if "vec3_reads" in e]
        real = [e for e in entries if is_real(e)]
        if args.only == "vec3":
            write_manifest(plain + vec3_fixtures(tmp) + real)
        else:
            write_manifest(plain + vec3 + real_fixtures())
        return
    write_manifest(float_fixtures(tmp) + vec3_fixtures(tmp) + real_fixtures())
    try:
        frames = blosc_frames()
        with open(os.path.join(OUT, "blosc_frames.json"), "w") as f:
            json.dump(frames, f)
    except ImportError:
        print("python3-blosc missing: blosc_frames.json not updated", file=sys.stderr)


if __name__ == "__main__":
    main()
