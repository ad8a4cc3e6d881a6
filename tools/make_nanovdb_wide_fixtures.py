#!/usr/bin/env python3
"""Makes the double-precision NanoVDB fixtures (`fog_double_zip.nvdb`,
`vec3d_zip.nvdb` in crates/volume/tests/fixtures/nanovdb).

NanoVDB's converter writes Double and Vec3d grids only from OpenVDB double
grids, which neither the OpenVDB tools nor pyopenvdb of Debian bookworm
make. So: convert the float fixture to an uncompressed float NanoVDB grid
(`nanovdb_convert`), widen it here to a double (or Vec3f to Vec3d) grid in
NanoVDB's node layout, and let NanoVDB turn that into an OpenVDB double
grid. For `double`, NanoVDB turns that back into a ZIP-compressed NanoVDB
file: the committed file is written by NanoVDB itself, this script only
gets a double grid into its hands (a wrong layout here would show as wrong
values after the round trip, which the tests compare with the float
fixture's). NanoVDB 32.4's converter does not write Vec3d grids from
OpenVDB ("Unsupported value type"), so `vec3d_zip.nvdb` is the widened
grid itself, ZIP-compressed here; NanoVDB reads it back to an OpenVDB
vec3d grid with the float grid's background, value range, active voxel
and tile counts and bounding box (`vdb_print -l` of both, printed below).

Needs nanovdb_convert (Debian: libnanovdb-tools). Run from the repository
root: python3 tools/make_nanovdb_wide_fixtures.py
"""

import os
import struct
import subprocess
import tempfile
import zlib

OUT = "crates/volume/tests/fixtures/nanovdb"
# Source, fixture, whether NanoVDB writes the fixture (else this script).
SOURCES = [
    ("crates/volume/tests/fixtures/vdb/fog_f32_zip.vdb", "fog_double_zip.nvdb", True),
    ("crates/volume/tests/fixtures/vdb/vec3_f32_zip.vdb", "vec3d_zip.nvdb", False),
]


def align(x, a):
    return (x + a - 1) // a * a


def layout(elem, comps):
    """Offsets and sizes of NanoVDB's nodes for values of `comps` elements
    of `elem` bytes (statistics of `elem` bytes), as NanoVDB.h lays them out."""
    value = elem * comps

    def fields(start, n):
        first = align(start, elem)
        avg = align(first + n * value, elem)
        return first, avg, avg + 2 * elem

    def node(log2):
        mask = (1 << (3 * log2)) // 8
        first, avg, end = fields(32 + 2 * mask, 2)
        table = align(end, 32)
        entry = align(max(value, 8), max(elem, 8))
        return dict(first=first, avg=avg, table=table, entry=entry,
                    size=align(table + (1 << (3 * log2)) * entry, 32), n=1 << (3 * log2))

    rfirst, ravg, rend = fields(28, 3)
    lfirst, lavg, lend = fields(80, 2)
    return dict(
        elem=elem, comps=comps, value=value,
        root_first=rfirst, root_avg=ravg, root_size=align(rend, 32),
        tile_value=align(20, elem), tile_size=align(align(20, elem) + value, 32),
        upper=node(5), lower=node(4),
        leaf_first=lfirst, leaf_avg=lavg, leaf_values=align(lend, 32),
        leaf_size=align(align(lend, 32) + 512 * value, 32),
    )


def widen(buf, at_src, n, out, at_dst):
    """n floats at buf[at_src:] (f32) written as f64 into out[at_dst:]."""
    for i in range(n):
        (v,) = struct.unpack_from("<f", buf, at_src + 4 * i)
        struct.pack_into("<d", out, at_dst + 8 * i, v)


def widen_grid(g, comps):
    src, dst = layout(4, comps), layout(8, comps)
    tree = 672
    offs = struct.unpack_from("<4Q", g, tree)
    counts = struct.unpack_from("<3I", g, tree + 32)
    root = tree + offs[3]
    table = struct.unpack_from("<I", g, root + 24)[0]
    levels = [("upper", 2), ("lower", 1)]
    # Old and new absolute offsets of every node, level by level (the
    # converter writes them breadth-first, each level contiguous).
    new_root = tree + 64
    pos = align(new_root + dst["root_size"] + table * dst["tile_size"], 32)
    where = {}
    starts = {}
    for name, lvl in levels + [("leaf", 0)]:
        size_s = src[name]["size"] if name != "leaf" else src["leaf_size"]
        size_d = dst[name]["size"] if name != "leaf" else dst["leaf_size"]
        starts[lvl] = pos
        for i in range(counts[lvl]):
            where[tree + offs[lvl] + i * size_s] = pos + i * size_d
        pos += counts[lvl] * size_d
    out = bytearray(pos)
    out[:672 + 64] = g[:672 + 64]
    struct.pack_into("<Q", out, 8, 0xFFFFFFFFFFFFFFFF)  # checksum: none
    struct.pack_into("<Q", out, 32, pos)
    struct.pack_into("<I", out, 636, 2 if comps == 1 else 7)
    struct.pack_into("<4Q", out, tree, starts[0] - tree, starts[1] - tree,
                     starts[2] - tree, new_root - tree)
    # Root: bbox and table size, background/min/max, avg/dev, tiles.
    out[new_root:new_root + 28] = g[root:root + 28]
    widen(g, root + src["root_first"], 3 * comps, out, new_root + dst["root_first"])
    widen(g, root + src["root_avg"], 2, out, new_root + dst["root_avg"])
    for i in range(table):
        t_s = root + src["root_size"] + i * src["tile_size"]
        t_d = new_root + dst["root_size"] + i * dst["tile_size"]
        key, child, state = struct.unpack_from("<QqI", g, t_s)
        if child:
            child = where[root + child] - new_root
        struct.pack_into("<QqI", out, t_d, key, child, state)
        widen(g, t_s + src["tile_value"], comps, out, t_d + dst["tile_value"])
    for name, lvl in levels:
        s, d = src[name], dst[name]
        for i in range(counts[lvl]):
            a = tree + offs[lvl] + i * s["size"]
            b = where[a]
            mask = s["n"] // 8
            out[b:b + 32 + 2 * mask] = g[a:a + 32 + 2 * mask]
            widen(g, a + s["first"], 2 * comps, out, b + d["first"])
            widen(g, a + s["avg"], 2, out, b + d["avg"])
            children = g[a + 32 + mask:a + 32 + 2 * mask]
            for n in range(s["n"]):
                e_s, e_d = a + s["table"] + n * s["entry"], b + d["table"] + n * d["entry"]
                if children[n >> 3] >> (n & 7) & 1:
                    (child,) = struct.unpack_from("<q", g, e_s)
                    struct.pack_into("<q", out, e_d, where[a + child] - b)
                else:
                    widen(g, e_s, comps, out, e_d)
    for i in range(counts[0]):
        a = tree + offs[0] + i * src["leaf_size"]
        b = where[a]
        out[b:b + 80] = g[a:a + 80]
        widen(g, a + src["leaf_first"], 2 * comps, out, b + dst["leaf_first"])
        widen(g, a + src["leaf_avg"], 2, out, b + dst["leaf_avg"])
        widen(g, a + src["leaf_values"], 512 * comps, out, b + dst["leaf_values"])
    return bytes(out)


def widen_file(data):
    """An uncompressed one-grid segment file, its grid widened."""
    name_size = struct.unpack_from("<I", data, 16 + 136)[0]
    start = 16 + 176 + name_size
    grid_type = struct.unpack_from("<I", data, 16 + 32)[0]
    comps = {1: 1, 6: 3}[grid_type]
    grid = widen_grid(data[start:], comps)
    head = bytearray(data[:start])
    struct.pack_into("<QQ", head, 16, len(grid), len(grid))
    struct.pack_into("<I", head, 16 + 32, 2 if comps == 1 else 7)
    return bytes(head) + grid


def zipped(data):
    """An uncompressed one-grid segment file with its grid ZIP-compressed."""
    name_size = struct.unpack_from("<I", data, 16 + 136)[0]
    start = 16 + 176 + name_size
    stream = zlib.compress(data[start:], 9)
    head = bytearray(data[:start])
    struct.pack_into("<H", head, 14, 1)
    struct.pack_into("<Q", head, 16 + 8, 8 + len(stream))
    struct.pack_into("<H", head, 16 + 168, 1)
    return bytes(head) + struct.pack("<Q", len(stream)) + stream


def main():
    with tempfile.TemporaryDirectory() as tmp:
        for vdb, name, by_nanovdb in SOURCES:
            flt = os.path.join(tmp, "float.nvdb")
            wide = os.path.join(tmp, "wide.nvdb")
            back = os.path.join(tmp, "wide.vdb")
            out = os.path.join(OUT, name)
            subprocess.run(["nanovdb_convert", "-f", vdb, flt], check=True)
            with open(flt, "rb") as f:
                data = widen_file(f.read())
            with open(wide, "wb") as f:
                f.write(data)
            subprocess.run(["nanovdb_convert", "-f", wide, back], check=True)
            if by_nanovdb:
                subprocess.run(["nanovdb_convert", "-f", "-z", back, out], check=True)
            else:
                with open(out, "wb") as f:
                    f.write(zipped(data))
                float_back = os.path.join(tmp, "float.vdb")
                subprocess.run(["nanovdb_convert", "-f", flt, float_back], check=True)
                for v in (float_back, back):
                    subprocess.run(["vdb_print", "-l", v], check=True)
            subprocess.run(["nanovdb_print", "-l", out], check=True)


if __name__ == "__main__":
    main()
