#!/usr/bin/python3
"""Writes data/sphere.vdb with OpenVDB itself: the level-set sphere of the
openvdb.org sample models (radius 3, voxel size 0.05, narrow band of 3
voxels, stored as half floats), made with OpenVDB's own
`createLevelSetSphere` so that the repository can carry it under its own
licence (the sample models' download page states none).

Run with Debian's python (python3-openvdb):

    /usr/bin/python3 tools/make_sphere_vdb.py

When the openvdb.org file is at ../shared/data/sphere.vdb the script compares
the two voxel by voxel and fails unless they hold the same active voxels with
the same (half-float) values and the same background.
"""

import os
import sys

import pyopenvdb as vdb

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "data", "sphere.vdb")
SAMPLE = os.path.join(os.path.dirname(ROOT), "shared", "data", "sphere.vdb")


def active_values(grid):
    return {it.min: it.value for it in grid.citerOnValues()}


def main():
    grid = vdb.createLevelSetSphere(radius=3.0, center=(0.0, 0.0, 0.0), voxelSize=0.05, halfWidth=3.0)
    grid.name = "ls_sphere"
    grid.saveFloatAsHalf = True
    vdb.write(OUT, grids=[grid])
    written = vdb.read(OUT, "ls_sphere")
    print("wrote %s: %d active voxels, background %g" % (OUT, written.activeVoxelCount(), written.background))
    if not os.path.exists(SAMPLE):
        print("no %s to compare with" % SAMPLE)
        return
    sample = vdb.read(SAMPLE, "ls_sphere")
    a, b = active_values(written), active_values(sample)
    differ = [k for k in a.keys() & b.keys() if a[k] != b[k]]
    if a.keys() != b.keys() or differ or written.background != sample.background:
        sys.exit("differs from %s: %d active voxels only in one, %d values differ, background %g vs %g"
                 % (SAMPLE, len(a.keys() ^ b.keys()), len(differ), written.background, sample.background))
    print("equal to %s: the same %d active voxels and values, background %g" % (SAMPLE, len(a), sample.background))


if __name__ == "__main__":
    main()
