#!/usr/bin/env python3
"""Writes a sparse 1024³ test volume: a narrow-band level-set sphere of
radius 480 voxels (half width 3) centred in a 1024³ index box, 17.4 M active
voxels, for measuring fogbank's memory per active voxel and build time
(docs/results/thread_scaling.md). Needs Debian's python3-openvdb.

    /usr/bin/python3 tools/sparse_shell_vdb.py /tmp/shell1024.vdb
"""
import sys

import pyopenvdb as vdb

out = sys.argv[1] if len(sys.argv) > 1 else "shell1024.vdb"
grid = vdb.createLevelSetSphere(radius=480.0, center=(512, 512, 512), voxelSize=1.0, halfWidth=3.0)
grid.name = "density"
vdb.write(out, grids=[grid])
print(f"{out}: {grid.activeVoxelCount()} active voxels, bbox {grid.evalActiveVoxelBoundingBox()}")
