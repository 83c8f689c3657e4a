#!/usr/bin/python3
"""band_drop.py FILE.vdb: how much of a volume could drop its L2 terms.

For every valid probe of a `gi-bake --basis sh2` grid, the largest error (over
46 normals: the six axes and 40 fixed random ones, in luminance, relative to
L0) of reading it without its terms (L0 alone) and without its L2 band (L0
and L1). A level-0 cell (4^3 probes) may drop a band only if every valid
probe in it may. Prints the share of cells that may at each tolerance: what
bricks that drop bands where light barely depends on direction could save.
Runs under Debian's /usr/bin/python3 (numpy, pyopenvdb); docs/directional.md.
"""
import sys

import numpy as np
import pyopenvdb as vdb

LUMA = np.array([0.2126, 0.7152, 0.0722], np.float32)
TOLERANCES = (0.02, 0.05, 0.1, 0.2, 0.5)


def normals():
    rng = np.random.default_rng(1)
    n = rng.normal(size=(40, 3))
    n /= np.linalg.norm(n, axis=1)[:, None]
    n = np.vstack([np.eye(3), -np.eye(3), n])
    x, y, z = n.T
    # estimate.c's vdbgi_sh2_terms: the polynomials the stored terms multiply.
    return np.stack([x, y, z, x * y, y * z, 3 * z * z - 1, x * z, x * x - y * y], 1)


def main(path):
    grids = {g.name: g for g in vdb.readAll(path)[0]}
    names = ['irradiance_sh%d' % k for k in range(1, 9)]
    if 'irradiance' not in grids or any(n not in grids for n in names):
        sys.exit('band_drop.py: %s: no L2 terms (bake with gi-bake --basis sh2)' % path)
    lo, hi = (np.array(c) for c in grids['irradiance'].evalActiveVoxelBoundingBox())
    lo -= np.mod(lo, 4)  # whole level-0 cells
    P = normals()
    threshold = float(grids['validity'].metadata.get('invalid_threshold', 0.5)) \
        if 'validity' in grids else 0.5
    worst_all, worst_l2, probes = [], [], 0
    slab = 16  # probes along x at a time: bounded memory on any world
    for x0 in range(int(lo[0]), int(hi[0]) + 1, slab):
        shape = (slab, (int(hi[1] - lo[1]) // 4 + 1) * 4, (int(hi[2] - lo[2]) // 4 + 1) * 4)
        at = (x0, int(lo[1]), int(lo[2]))

        def dense(name, channels=3):
            a = np.zeros(shape + ((channels,) if channels > 1 else ()), np.float32)
            grids[name].copyToArray(a, ijk=at)
            return a
        l0 = dense('irradiance') @ LUMA
        t = np.stack([dense(n) @ LUMA for n in names], -1)
        valid = l0 > 0
        if 'validity' in grids:
            valid &= dense('validity', 1) <= threshold
        probes += int(valid.sum())
        e1 = t[..., :3] @ P[:, :3].T
        e2 = t[..., 3:] @ P[:, 3:].T
        full = np.maximum(l0[..., None] + e1 + e2, 0)
        scale = np.maximum(l0, 1e-30)[..., None]
        drop_all = np.abs(l0[..., None] - full).max(-1) / scale[..., 0]
        drop_l2 = np.abs(np.maximum(l0[..., None] + e1, 0) - full).max(-1) / scale[..., 0]
        X, Y, Z = (s // 4 for s in shape)

        def cells(a):
            a = np.where(valid, a, -1.0).reshape(X, 4, Y, 4, Z, 4)
            return a.max((1, 3, 5))
        ca, c2 = cells(drop_all), cells(drop_l2)
        has = ca >= 0
        worst_all.append(ca[has])
        worst_l2.append(c2[has])
    worst_all, worst_l2 = np.concatenate(worst_all), np.concatenate(worst_l2)
    print('%s: %d valid probes, %d level-0 cells holding one' % (path, probes, worst_all.size))
    print('| tolerance | cells that may drop every term | cells that may keep L1 only |')
    print('|---:|---:|---:|')
    for tol in TOLERANCES:
        print('| %g %% | %.1f %% | %.1f %% |' % (100 * tol, 100 * (worst_all < tol).mean(),
                                             100 * (worst_l2 < tol).mean()))


if __name__ == '__main__':
    if len(sys.argv) != 2 or sys.argv[1] in ('-h', '--help'):
        print(__doc__.strip())
        sys.exit(0 if len(sys.argv) == 2 else 2)
    main(sys.argv[1])
