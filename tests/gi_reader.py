#!/usr/bin/python3
"""gi_reader.py FILE.gi.gz X,Y,Z...: a .gi reader and sampler written from
docs/format.md alone, in Python and numpy, to show that page is enough. Reads
versions 1, 2 and 5; prints the lookup (float32, as the page states it) at each
point as `x,y,z -> r g b`."""
import gzip
import math
import struct
import sys
import numpy as np

F = np.float32
N = 5  # a compact brick's texels a side
CORNERS = np.array([[c & 1, c >> 1 & 1, c >> 2 & 1] for c in range(8)])  # bit 0 x, 1 y, 2 z

def check_bounds(gi, spacing):
    """The header's sanity bounds (docs/format.md): the RGBM range, the spacing, the box."""
    if not 2.0 ** -16 <= gi['range'] <= 65504:
        raise ValueError('rgbm_range %g outside 2^-16..65504' % gi['range'])
    if not 1e-4 <= spacing <= 1e4:
        raise ValueError('spacing %g outside 1e-4..1e4' % spacing)
    for k in range(3):
        lo, hi = float(gi['box_min'][k]), float(gi['box_max'][k])
        if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
            raise ValueError('box not finite and ordered')
        corner, want = max(abs(lo), abs(hi)), 4.0 * int(gi['ind_dims'][k]) * spacing
        if corner > 1e9 + 2 ** 26 * spacing:
            raise ValueError('box reaches %g m' % corner)
        if abs(hi - lo - want) > 1e-3 * want + 2.0 ** -20 * corner:
            raise ValueError('box extent %g on axis %d, want %g' % (hi - lo, k, want))

def read(path):
    data = open(path, 'rb').read()
    if data[:2] == b'\x1f\x8b':
        data = gzip.decompress(data)
    if data[:8] != b'vdbgi.gi':
        raise ValueError('not a .gi file')
    u32 = lambda o, n=1: struct.unpack_from('<%dI' % n, data, o)  # noqa: E731
    f32 = lambda o, n=1: np.array(struct.unpack_from('<%df' % n, data, o), dtype=F)  # noqa: E731
    version, header_size, encoding = u32(8, 3)
    field = u32(104)[0]
    layout = {(1, 0): 1, (2, 0): 1, (2, 1): 1, (2, 2): 2, (2, 3): 2, (5, 2): 2}.get((version, field))
    if not layout:  # versions 3 and 4 were older compact forms
        raise ValueError('version %d, layout %d: not read here' % (version, field))
    gi = dict(version=version, layout=layout, encoding=encoding, range=f32(20)[0],
              ind_dims=np.array(u32(24, 3)), atlas_dims=np.array(u32(36, 3)),
              box_min=f32(48, 3), box_max=f32(60, 3), bricks=u32(80, 4), stored=u32(108)[0])
    check_bounds(gi, float(f32(72)[0]))
    body, cells = np.frombuffer(data, np.uint8, offset=header_size), np.prod(gi['ind_dims'])
    if version == 5:
        gi['ind'], gi['atlas'] = unpack(gi, body)
    else:
        gi['ind'] = body[:4 * cells].reshape(tuple(gi['ind_dims'][::-1]) + (4,))
        gi['atlas'] = body[4 * cells:].reshape(tuple(gi['atlas_dims'][::-1]) + (4,))
    return gi

def decode(gi, b):
    """Texel bytes (..., 4) to linear RGB, float32."""
    if gi['encoding'] == 1:
        w = b.astype(np.uint32) @ np.array([1, 256, 65536, 16777216], np.uint32)
        scale = np.ldexp(F(1), (w >> 27).astype(np.int32) - 24).astype(F)
        return np.stack([((w >> (9 * k)) & 511).astype(F) * scale for k in range(3)], -1)
    m = b[..., 3].astype(F) / F(255) * gi['range']
    return b[..., :3].astype(F) / F(255) * m[..., None]

def encode(gi, c):
    """One float32 colour to its texel bytes (docs/format.md, step 6)."""
    c = [F(0) if not v > 0 else F(v) for v in c]
    if gi['encoding'] == 1:
        c = [min(v, F(65408)) for v in c]
        mx = max(c)
        e = max(np.frexp(mx)[1] - 1 if mx > 0 else -16, -16) + 16
        d = 2.0 ** (e - 24)
        if np.floor(float(mx) / d + 0.5) == 512:
            e, d = e + 1, d * 2
        w = sum(int(np.floor(float(v) / d + 0.5)) << (9 * k) for k, v in enumerate(c)) | e << 27
        return [w >> s & 255 for s in (0, 8, 16, 24)]
    if not max(c) > 0:
        return [0, 0, 0, 0]
    m = max(np.ceil(min(max(c) / gi['range'], F(1)) * F(255)), F(1))
    scale = m / F(255) * gi['range']
    return [int(np.rint(min(v / scale, F(1)) * F(255))) for v in c] + [int(m)]

def unpack(gi, body):
    """Version 5: the textures from level bytes, placement and stored points."""
    ix, iy, iz = dims = gi['ind_dims']
    levels = body[:ix * iy * iz].reshape(iz, iy, ix)
    zz, yy, xx = np.indices(levels.shape)
    span = np.where(levels > 0, 1 << np.maximum(levels.astype(int) - 1, 0), 1)
    starts = (levels > 0) & (xx % span == 0) & (yy % span == 0) & (zz % span == 0)
    cz, cy, cx = np.nonzero(starts)  # scan order: z, then y, then x
    count, at = len(cz), ix * iy * iz
    lv = levels[cz, cy, cx].astype(int) - 1
    key = np.stack([cx, cy, cz], 1) >> lv[:, None]
    origin = np.frombuffer(body[at:at + 6 * count].tobytes(), '<u2').reshape(3, count).T.astype(int)
    cell_brick, ind = np.full(levels.shape, -1), np.zeros(levels.shape + (4,), np.uint8)
    block = lambda a, b, m=0: a[tuple(slice(max((key[b, k] << lv[b]) - m, 0),  # noqa: E731
                                            (key[b, k] + 1 << lv[b]) + m) for k in (2, 1, 0))]
    for b in range(count):
        o = origin[b]
        block(cell_brick, b)[...] = b
        block(ind, b)[...] = [o[0] >> 2, o[1] >> 2, o[2] >> 2, lv[b] | (o[0] & 3) << 2 | (o[1] & 3) << 4 | (o[2] & 3) << 6]
    # Every brick texel's lattice point, and the coarser brick it is stitched to (step 3).
    q = np.stack(np.unravel_index(np.arange(N ** 3), (N, N, N))[::-1], 1)  # x, y, z of texel t
    pts = (4 * key[:, None, :] + q[None]) << lv[:, None, None]
    coarse = np.full((count, N ** 3), -1)
    faces = [t for t in range(N ** 3) if not all(q[t] % 4)]
    for b in range(count):
        for t in faces if block(levels, b, 1).max() - 1 > lv[b] else []:  # a coarser cell near
            p, best = pts[b, t], lv[b]
            for down in CORNERS:
                cell = (p >> 2) - down
                if any(down & (p % 4 != 0)) or any(cell < 0) or any(cell >= dims):
                    continue
                j = cell_brick[cell[2], cell[1], cell[0]]
                if j >= 0 and lv[j] > best:
                    best, coarse[b, t] = lv[j], j
    # The stored points (step 4): unstitched, owner cell within dims + 2; sorted by owner, bit.
    g = dims + 2
    inside = (coarse < 0) & np.all(pts >> 2 < g, -1)
    order = lambda p: (((p[..., 2] >> 2) * g[1] + (p[..., 1] >> 2)) * g[0] + (p[..., 0] >> 2)) * 64 + \
        ((p[..., 2] & 3) * 4 + (p[..., 1] & 3)) * 4 + (p[..., 0] & 3)  # noqa: E731
    stored, first = np.unique(order(pts[inside]), return_index=True)
    if len(stored) != gi['stored']:
        raise ValueError('the bricks read %d points, the header says %d' % (len(stored), gi['stored']))

    def index_of(p):  # stored point index at lattice points p (..., 3), or -1
        k = order(p)
        i = np.minimum(np.searchsorted(stored, k), len(stored) - 1)
        return np.where(np.all(p >= 0, -1) & np.all(p >> 2 < g, -1) & (stored[i] == k), i, -1)
    # The values (step 5): residuals against the median predictor, in storage order.
    p = pts[inside][first]
    nb = [index_of(p - np.array(d)).tolist() for d in ((1, 0, 0), (0, 1, 0), (1, 1, 0), (0, 0, 1))]
    n, rgbm = len(stored), gi['encoding'] == 0
    planes = body[at + 6 * count:].reshape(4, n).astype(int).tolist()
    val = np.zeros((n, 4), int).tolist()
    for i in range(n):
        a, b, cc, e = nb[0][i], nb[1][i], nb[2][i], nb[3][i]
        for k in ((3, 0, 1, 2) if rgbm else (0, 1, 2, 3)):
            m = val[i][3] if rgbm and k < 3 else 0
            v = lambda j: min((2 * val[j][k] * val[j][3] + m) // (2 * m), 255) if m else val[j][k]  # noqa
            if a >= 0 and b >= 0 and cc >= 0:
                A, B, C = v(a), v(b), v(cc)
                pred = min(A, B) if C >= max(A, B) else max(A, B) if C <= min(A, B) else A + B - C
            else:
                j = a if a >= 0 else b if b >= 0 else e
                pred = v(j) if j >= 0 else 0
            val[i][k] = (planes[k][i] + pred) & 255
    values = np.array(val, np.uint8)
    # The atlas (step 6): stored bytes copied, stitched texels interpolated, coarsest first.
    atlas = np.zeros(tuple(gi['atlas_dims'][::-1]) + (4,), np.uint8)
    idx = index_of(pts)
    floats = np.where(idx[..., None] >= 0, decode(gi, values[np.maximum(idx, 0)]), F(0)).astype(F)
    for b in sorted(range(count), key=lambda b: -lv[b]):
        for t in range(N ** 3):
            x, y, z = origin[b] + q[t]
            j = coarse[b, t]
            if j < 0:
                atlas[z, y, x] = values[idx[b, t]] if idx[b, t] >= 0 else 0
                continue
            s = F(1 << lv[j])  # per axis t = (p - 4 k span) / span, i = floor(t), f = t - i
            tt = [(F(pts[b, t, k]) - F(key[j, k] * 4) * s) / s for k in range(3)]
            i0 = [min(int(np.floor(v)), 3) for v in tt]
            fr = [F(1) if np.floor(v) > 3 else v - F(np.floor(v)) for v in tt]
            rgb = [F(0)] * 3
            for c in range(8):
                w = (fr[0] if c & 1 else F(1) - fr[0]) * (fr[1] if c & 2 else F(1) - fr[1]) * \
                    (fr[2] if c & 4 else F(1) - fr[2])
                src = floats[j, (i0[2] + (c >> 2)) * 25 + (i0[1] + (c >> 1 & 1)) * 5 + i0[0] + (c & 1)]
                rgb = [rgb[k] + w * src[k] for k in range(3)]
            floats[b, t] = rgb
            atlas[z, y, x] = encode(gi, rgb)
    return ind, atlas

def sample(gi, pos):
    """The lookup (docs/format.md) at world positions pos (n, 3), float32."""
    dims = gi['ind_dims'].astype(F)
    p = (pos.astype(F) - gi['box_min']) / (gi['box_max'] - gi['box_min']) * (dims * F(4)) - F(0.5)
    base = np.floor(p / F(4))
    it = np.clip(np.floor((base + F(0.5)) / dims * dims), 0, dims - 1).astype(int)
    ind, compact = gi['ind'], gi['layout'] == 2
    if compact:  # the lift: below a column's lowest brick, that brick's bottom plane
        filled = ind.any(-1)
        ymin = np.where(filled.any(1), filled.argmax(1), -(1 << 30))[it[:, 2], it[:, 0]]  # none: no lift
        lift = base[:, 1] < ymin
        base[:, 1] = np.where(lift, ymin, base[:, 1]).astype(F)
        it[:, 1] = np.where(lift, ymin, it[:, 1])
    b = np.floor(ind[it[:, 2], it[:, 1], it[:, 0]].astype(F) / F(255) * F(255) + F(0.5))
    level = np.mod(b[:, 3], F(4)) if compact else np.maximum(b[:, 3] - F(1), F(0))
    span = np.exp2(level)[:, None]
    origin_cell = np.floor(base / span) * span * F(4)
    if compact:
        low = np.mod(np.floor(b[:, 3:4] / np.exp2(np.array([2, 4, 6], F))), F(4))
        q = (p - origin_cell) / span
        q[:, 1] = np.maximum(q[:, 1], F(0))
        texel = b[:, :3] * F(4) + low + q
    else:
        texel = b[:, :3] * F(6) + F(1) + ((p - origin_cell + F(0.5)) / span - F(0.5))
    ad = gi['atlas_dims'].astype(F)
    t = (texel + F(0.5)) / ad * ad - F(0.5)
    fl, fr = np.floor(t), t - np.floor(t)
    out = np.zeros((len(pos), 4), F)
    for corner in CORNERS:
        i = np.clip(fl.astype(int) + corner, 0, gi['atlas_dims'] - 1)
        w = np.prod(np.where(corner == 1, fr, F(1) - fr), 1, dtype=F)  # x * y, then * z
        texels = gi['atlas'][i[:, 2], i[:, 1], i[:, 0]]
        if gi['encoding'] == 1:  # RGB9E5 is decoded before filtering, RGBM after
            v = np.concatenate([decode(gi, texels), np.ones((len(pos), 1), F)], 1)
        else:
            v = texels.astype(F) / F(255)
        out += w[:, None] * v
    return out[:, :3] if gi['encoding'] == 1 else out[:, :3] * out[:, 3:] * gi['range']

if __name__ == '__main__':
    gi = read(sys.argv[1])
    pos = np.array([[float(v) for v in a.split(',')] for a in sys.argv[2:]], F)
    for xyz, rgb in zip(sys.argv[2:], sample(gi, pos)):
        print('%s -> %.9g %.9g %.9g' % (xyz, rgb[0], rgb[1], rgb[2]))
