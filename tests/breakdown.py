#!/usr/bin/python3
"""breakdown.py [--row NAME] BAKE.vdb VOLUME.gi.gz: where the bytes of a .gi volume go.

Run under Debian's system python3 (pyopenvdb, numpy). Reads the baked probes
(which are valid) and the volume (docs/format.md), and prints one JSON object:
the VRAM (atlas and the indirection as columns, as vdbgi's runtime uploads
them) and file bytes per valid probe, and what each suspect of issue 11
costs: the apron, cells and bricks that hold no valid probe, coarsening,
the atlas's unused slots, 4-byte texels, and what gzip makes of the atlas
interleaved, as separate planes, and without its aprons (seed layout) or
borders (compact layout). With --row NAME,
one Markdown table row instead (HEADER below is its header).
"""
import gzip
import json
import os
import struct
import subprocess
import sys
import tempfile
import zlib

import numpy as np
import pyopenvdb as vdb


def read_gi(path):
    raw = gzip.open(path, "rb").read()
    file_bytes = len(open(path, "rb").read())
    if struct.unpack_from("<I", raw, 8)[0] == 5:
        # A packed file: its textures as the C reader rebuilds them (gi-inspect --textures).
        tool = os.path.join(os.environ.get("BIN", "build/release/bin"), "gi-inspect")
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "textures.gi")
            subprocess.run([tool, path, "--textures", out, "--max-bytes", "64G"], check=True, stdout=subprocess.DEVNULL)
            raw = open(out, "rb").read()
    (magic, version, header_size, encoding, rgbm_range) = struct.unpack_from("<8sIIIf", raw, 0)
    assert magic == b"vdbgi.gi" and version in (1, 2), path
    layout = struct.unpack_from("<I", raw, 104)[0] if version == 2 else 1  # docs/format.md
    ind_dims = struct.unpack_from("<3I", raw, 24)
    atlas_dims = struct.unpack_from("<3I", raw, 36)
    box_min = struct.unpack_from("<3f", raw, 48)
    box_max = struct.unpack_from("<3f", raw, 60)
    spacing, max_level = struct.unpack_from("<fI", raw, 72)
    ind_bytes, atlas_bytes = struct.unpack_from("<II", raw, 96)
    ind = np.frombuffer(raw, np.uint8, ind_bytes, header_size)
    ind = ind.reshape(ind_dims[2], ind_dims[1], ind_dims[0], 4)
    atlas = np.frombuffer(raw, np.uint8, atlas_bytes, header_size + ind_bytes)
    atlas = atlas.reshape(atlas_dims[2], atlas_dims[1], atlas_dims[0], 4)
    return dict(raw=raw, ind=ind, atlas=atlas, box_min=box_min, box_max=box_max,
                spacing=spacing, ind_dims=ind_dims, atlas_dims=atlas_dims,
                file_bytes=file_bytes, encoding=encoding, layout=layout)


def valid_probes(path):
    grids, _ = vdb.readAll(path)
    by = {g.name: g for g in grids}
    irr, val = by["irradiance"], by["validity"]
    threshold = float(irr["invalid_threshold"])
    ijk = []
    acc = val.getConstAccessor()
    for item in irr.citerOnValues():
        if acc.getValue(item.min) <= threshold:
            ijk.append(item.min)
    origin = irr.transform.indexToWorld((0, 0, 0))
    return np.array(ijk, np.int64), np.array(origin), irr.transform.voxelSize()[0], irr.activeVoxelCount()


def columns_bytes(ind):
    """The runtime's indirection (docs/format.md): two texels a column, then each
    column's run from its lowest to its highest non-empty cell, at most 2048 wide."""
    full = ind.astype(np.int64).sum(axis=-1) > 0  # z, y, x
    ys = np.arange(full.shape[1])[None, :, None]
    lo = np.where(full, ys, full.shape[1]).min(axis=1)
    hi = np.where(full, ys, -1).max(axis=1)
    total = 2 * lo.size + int(np.where(hi >= 0, hi - lo + 1, 0).sum())
    rows = -(-total // 2048)
    return 4 * rows * -(-total // rows)


def gz(b):
    return len(zlib.compress(bytes(b), 6))


HEADER = ("| world | valid probes | bricks L0 / L1 / L2 / L3 | bricks holding no valid probe "
          "| slots per valid probe | textures | B per valid probe | file | B per valid probe "
          "| dense RGBA8 | aprons in the atlas | gzip of the bricks without aprons |\n"
          "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")


def row(name, d):
    """One line of HEADER's table."""
    empty = sum(d["bricks_without_valid_probe"]) / d["bricks"]
    return ("| %s | %d | %s | %.0f %% | %.2f | %.2f MB | %.1f | %.2f MB | %.1f | %.2f MB | %.0f %% | %.2f MB |"
            % (name, d["valid_probes"], " / ".join(str(n) for n in d["bricks_per_level"]), 100 * empty,
               d["probe_slots_per_valid_probe"], d["vram_bytes"] / 1e6, d["vram_per_valid_probe"],
               d["file_bytes"] / 1e6, d["file_per_valid_probe"], d["dense_rgba8_bytes"] / 1e6,
               100 * d["apron_bytes"] / d["atlas_bytes"], d["gzip_bricks_no_apron_interleaved"] / 1e6))


def main(vdb_path, gi_path, name=None):
    gi = read_gi(gi_path)
    ijk, origin, spacing, probes = valid_probes(vdb_path)
    ind, atlas = gi["ind"], gi["atlas"]
    # The indirection's first cell, in lattice cells: box_min = origin + spacing (4 c0 - 0.5).
    c0 = np.rint(((np.array(gi["box_min"]) - origin) / spacing + 0.5) / 4).astype(np.int64)
    compact = gi["layout"] in (2, 3)  # 3: the compact layout's number before version 5
    a = ind[..., 3].astype(np.int64)
    if compact:  # a: level in bits 0-1, the brick's first texel mod 4 per axis above
        level = np.where(ind.astype(np.int64).sum(axis=-1) == 0, -1, a & 3)
    else:
        level = a - 1  # -1: empty
    occupied = level >= 0
    # Valid probes per level-0 cell (indirection order z, y, x).
    cell = ijk // 4 - c0
    counts = np.zeros(ind.shape[:3], np.int64)
    np.add.at(counts, (cell[:, 2], cell[:, 1], cell[:, 0]), 1)
    # A brick is one slot (seed) or first texel (compact); its footprint is the cells pointing at it.
    if compact:
        first = [4 * ind[..., k].astype(np.int64) + (a >> (2 + 2 * k) & 3) for k in range(3)]
        slots = first[0] + 1024 * (first[1] + 1024 * first[2])
    else:
        slots = ind[..., 0].astype(np.int64) + 256 * (ind[..., 1].astype(np.int64) + 256 * ind[..., 2])
    occ_slots, occ_counts, occ_levels = slots[occupied], counts[occupied], level[occupied]
    # Cells a receiver can read: a valid probe among the 6^3 the filter reaches from the
    # cell (its 4^3 and one probe beyond each face, the apron's).
    valid = np.zeros(tuple(4 * d + 2 for d in ind.shape[2::-1])[::-1], bool)
    p = ijk - (4 * c0 - 1)
    valid[p[:, 2], p[:, 1], p[:, 0]] = True
    reads = np.zeros(ind.shape[:3], bool)
    Z, Y, X = reads.shape
    for dz in range(6):
        for dy in range(6):
            for dx in range(6):
                reads |= valid[dz:dz + 4 * Z:4, dy:dy + 4 * Y:4, dx:dx + 4 * X:4]
    brick_valid = {}
    brick_level = {}
    for s, n, lv in zip(occ_slots.tolist(), occ_counts.tolist(), occ_levels.tolist()):
        brick_valid[s] = brick_valid.get(s, 0) + n
        brick_level[s] = lv
    bricks = len(brick_valid)
    per_level = [sum(1 for s in brick_level if brick_level[s] == lv) for lv in range(4)]
    empty_bricks = [sum(1 for s in brick_valid if brick_valid[s] == 0 and brick_level[s] == lv)
                    for lv in range(4)]
    n_valid = len(ijk)
    atlas_bytes = atlas.size
    ind_bytes = ind.size
    # What vdbgi's runtime uploads: the atlas and the indirection as columns.
    col_bytes = columns_bytes(ind)
    vram = atlas_bytes + col_bytes
    b = 5 if compact else 6  # texels a brick edge
    # Each brick's b^3 texels (compact bricks may share border planes).
    slot_ids = np.array(sorted(brick_valid), np.int64)
    if compact:
        ox, oy, oz = slot_ids % 1024, (slot_ids // 1024) % 1024, slot_ids // 1048576
    else:
        ox, oy, oz = b * (slot_ids % 256), b * ((slot_ids // 256) % 256), b * (slot_ids // 65536)
    r = np.arange(b)
    zz = oz[:, None, None, None] + r[None, :, None, None]
    yy = oy[:, None, None, None] + r[None, None, :, None]
    xx = ox[:, None, None, None] + r[None, None, None, :]
    kept = atlas[zz, yy, xx]
    covered = np.zeros(atlas.shape[:3], bool)
    covered[zz, yy, xx] = True
    used_texels = int(covered.sum())
    # The atlas without aprons or borders: each brick's 4^3 probes, interleaved RGBA and as planes.
    first = 0 if b == 5 else 1
    inner = np.ascontiguousarray(kept[:, first:first + 4, first:first + 4, first:first + 4, :])
    planes = np.ascontiguousarray(inner.transpose(4, 0, 1, 2, 3))
    out = {
        "probes": int(probes),
        "valid_probes": n_valid,
        "bricks": bricks,
        "bricks_per_level": per_level,
        "level0_share": round(per_level[0] / bricks, 3),
        "bricks_without_valid_probe": empty_bricks,
        "probe_slots": bricks * 64,
        "probe_slots_per_valid_probe": round(bricks * 64 / n_valid, 2),
        "occupied_cells": int(occupied.sum()),
        "occupied_cells_without_valid_probe": int((occupied & (counts == 0)).sum()),
        "indirection_cells": int(ind.size // 4),
        "occupied_cells_a_receiver_reads": int((occupied & reads).sum()),
        "vram_bytes": vram,
        "vram_per_valid_probe": round(vram / n_valid, 2),
        "file_bytes": gi["file_bytes"],
        "file_per_valid_probe": round(gi["file_bytes"] / n_valid, 2),
        "indirection_bytes": ind_bytes,
        "columns_bytes": col_bytes,
        "atlas_bytes": atlas_bytes,
        "atlas_slack_bytes": atlas_bytes - 4 * used_texels,
        "layout": "compact" if b == 5 else "seed",
        "apron_bytes": 4 * (used_texels - 64 * bricks),
        "unique_probe_bytes": 4 * bricks * 64,
        "dense_rgba8_bytes": 4 * int(np.prod(ijk.max(0) - ijk.min(0) + 1)),
        "gzip_indirection": gz(ind),
        "gzip_atlas": gz(atlas),
        "gzip_bricks_interleaved": gz(kept),
        "gzip_bricks_no_apron_interleaved": gz(inner),
        "gzip_bricks_no_apron_planes": gz(planes),
    }
    print(row(name, out) if name else json.dumps(out, indent=1))


if __name__ == "__main__":
    args = sys.argv[1:]
    name = None
    if len(args) == 4 and args[0] == "--row":
        name, args = args[1], args[2:]
    if len(args) != 2:
        sys.stderr.write(__doc__)
        sys.exit(2)
    main(args[0], args[1], name)
