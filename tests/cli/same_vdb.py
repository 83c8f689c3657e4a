"""same_vdb.py A.vdb B.vdb: whether two .vdb files hold the same probes, grid by grid
(irradiance, validity, stderr, then any directional grids), bit for bit, read by pyopenvdb
(Debian's python3). A grid that only one file has is DIFFERENT."""
import sys

import numpy as np
import pyopenvdb as vdb


def dense(grid, lo, hi):
    """The grid over the box lo..hi as an array of bit patterns, NaN where no probe is."""
    grid.background = (float("nan"),) * 3 if isinstance(grid.background, tuple) else float("nan")
    shape = tuple(h - l + 1 for l, h in zip(lo, hi))
    if isinstance(grid.background, tuple):
        shape += (3,)
    a = np.empty(shape, np.float32)
    grid.copyToArray(a, ijk=lo)
    return a.view(np.uint32)


def same(path_a, path_b, name):
    a, b = vdb.read(path_a, name), vdb.read(path_b, name)
    count = a.activeVoxelCount()
    if count != b.activeVoxelCount():
        return count, False
    box_a, box_b = a.evalActiveVoxelBoundingBox(), b.evalActiveVoxelBoundingBox()
    if box_a != box_b:
        return count, False
    return count, np.array_equal(dense(a, *box_a), dense(b, *box_b))


def grids(path):
    return {g["name"] for g in vdb.readAllGridMetadata(path)}


first = ["irradiance", "validity", "stderr"]
in_a, in_b = grids(sys.argv[1]), grids(sys.argv[2])
for name in first + sorted((in_a | in_b) - set(first)):
    if name not in in_a or name not in in_b:
        print(name, "in one file only: DIFFERENT")
        continue
    count, equal = same(sys.argv[1], sys.argv[2], name)
    print(name, count, "probes,", "the same bits" if equal else "DIFFERENT")
