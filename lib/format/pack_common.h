/*
 * pack_common.h: what the compact file's three parts share (packed.c, the
 * plan and the reader's rebuild; pack_place.c, the converter's placement;
 * pack_write.c, the converter's values): lattice arithmetic, stitching, the
 * predictor. Only those three include it.
 */
#ifndef VDBGI_PACK_COMMON_H
#define VDBGI_PACK_COMMON_H

#include "encode.h"
#include "packed.h"
#include "util.h"

#include <stdbool.h>
#include <stdint.h>

/*
 * Owner cells past the indirection's + faces: a position inside the box
 * reads lattice points up to cell dims + 1 (a level-3 brick's last step);
 * a brick texel beyond that only a lookup outside the box reaches, and it
 * is neither stored nor anything but zero.
 */
enum { N = VDBGI_BRICK_COMPACT, TEXELS = N * N * N, PAD = 2 };

/* Threads a pass runs on: what was asked, 1 to MAX_JOBS (vdbgi_run_threads' bound). */
enum { MAX_JOBS = 64 };
static inline int job_count(int threads)
{
    return threads > MAX_JOBS ? MAX_JOBS : threads < 1 ? 1 : threads;
}

static inline size_t cell_index(const uint32_t d[3], const int32_t c[3])
{
    return ((size_t)c[2] * d[1] + (size_t)c[1]) * d[0] + (size_t)c[0];
}

/*
 * Where lattice point p sits in the owner grid: its cell and its bit there
 * (z, then y, then x, 4 a side). False when p lies outside the grid.
 */
static inline bool grid_slot(const vdbgi_pack_plan *pl, const int32_t p[3], size_t *cell, int *bit)
{
    int32_t c[3];
    for (int k = 0; k < 3; k++) {
        if (p[k] < 0)
            return false;
        c[k] = p[k] >> 2;
        if (c[k] >= (int32_t)pl->grid[k])
            return false;
    }
    *cell = cell_index(pl->grid, c);
    *bit = ((p[2] & 3) * 4 + (p[1] & 3)) * 4 + (p[0] & 3);
    return true;
}

/* The stored point at relative lattice point p, or -1 if the file holds none there. */
static inline int64_t point_index(const vdbgi_pack_plan *pl, const int32_t p[3])
{
    size_t c;
    int bit;
    if (!grid_slot(pl, p, &c, &bit) || !(pl->mask[c] >> bit & 1u))
        return -1;
    return (int64_t)pl->offset[c] + __builtin_popcountll(pl->mask[c] & ((UINT64_C(1) << bit) - 1u));
}

/* Texel q of brick b stands at relative fine lattice point p. */
static inline void texel_point(const vdbgi_pack_plan *pl, size_t b, int t, int32_t p[3])
{
    const int q[3] = {t % N, t / N % N, t / (N * N)};
    const int span = 1 << pl->level[b];
    for (int k = 0; k < 3; k++)
        p[k] = (pl->key[b][k] * VDBGI_BRICK + q[k]) * span;
}

/*
 * Cell c of the up to eight that touch lattice point p: the cell holding p,
 * one down along axis k where bit k of c is set. False where p does not
 * touch it (p is not on that cell face) or it lies below cell 0.
 */
static inline bool touching_cell(const int32_t p[3], int c, int32_t cell[3])
{
    bool touches = true;
    for (int k = 0; k < 3; k++) {
        const int down = c >> k & 1;
        cell[k] = (p[k] >> 2) - down;
        touches = touches && (!down || p[k] % VDBGI_BRICK == 0) && cell[k] >= 0;
    }
    return touches;
}

/*
 * The coarsest brick whose cells touch lattice point p, if coarser than level:
 * its index and level. A point on a cell face, edge or corner touches two,
 * four or eight cells; cells past the indirection touch nothing.
 */
static inline bool coarser_brick_at(const vdbgi_pack_plan *pl, const int32_t p[3], int level,
                                    size_t *index, int *coarse_level)
{
    int best = level;
    for (int c = 0; c < 8; c++) {
        int32_t cell[3];
        if (!touching_cell(p, c, cell) || cell[0] >= (int32_t)pl->dims[0] ||
            cell[1] >= (int32_t)pl->dims[1] || cell[2] >= (int32_t)pl->dims[2])
            continue;
        const int32_t b = pl->cell_brick[cell_index(pl->dims, cell)];
        if (b < 0 || pl->level[b] <= best)
            continue;
        best = pl->level[b];
        *index = (size_t)b;
    }
    *coarse_level = best;
    return best > level;
}

/*
 * Does texel t of brick b take a coarser brick's value, and whose? The plan
 * knows which texels do; only those look the coarser brick up again.
 */
static inline bool stitched(const vdbgi_pack_plan *pl, size_t b, int t, size_t *coarse,
                            int *coarse_level)
{
    if (!(pl->stitch[b][t >> 5] >> (t & 31) & 1u))
        return false;
    int32_t p[3];
    texel_point(pl, b, t, p);
    return coarser_brick_at(pl, p, pl->level[b], coarse, coarse_level);
}

/* The brick whose level-`level` block is `key`, or -1. */
static inline int32_t brick_with_key(const vdbgi_pack_plan *pl, const int32_t key[3], int level)
{
    int32_t c[3];
    for (int k = 0; k < 3; k++) {
        c[k] = key[k] * (1 << level);
        if (c[k] < 0 || c[k] >= (int32_t)pl->dims[k])
            return -1;
    }
    const int32_t b = pl->cell_brick[cell_index(pl->dims, c)];
    return b >= 0 && pl->level[b] == level ? b : -1;
}

/*
 * The predictor (docs/format.md, "Version 5"). Its neighbours: the stored
 * points at p - x, p - y, p - x - y and p - z, or -1.
 */
static inline void neighbours(const vdbgi_pack_plan *pl, const int32_t p[3], int64_t n[4])
{
    const int32_t a[3] = {p[0] - 1, p[1], p[2]}, b[3] = {p[0], p[1] - 1, p[2]},
                  c[3] = {p[0] - 1, p[1] - 1, p[2]}, e[3] = {p[0], p[1], p[2] - 1};
    n[0] = point_index(pl, a);
    n[1] = point_index(pl, b);
    n[2] = point_index(pl, c);
    n[3] = point_index(pl, e);
}

/* LOCO-I's median edge detector on the -x, -y and -x-y neighbours' numbers a, b and c. */
static inline int median_edge(int a, int b, int c)
{
    const int lo = a < b ? a : b, hi = a < b ? b : a;
    return c >= hi ? lo : c <= lo ? hi : a + b - c;
}

/* The stored neighbour a prediction falls back on: -x, else -y, else -z; -1 for none. */
static inline int64_t first_stored(const int64_t n[4])
{
    return n[0] >= 0 ? n[0] : n[1] >= 0 ? n[1] : n[3];
}

/*
 * The prediction of a point's term byte k (docs/format.md, "Version 6" and
 * "Version 7"). Version 6: the same byte of the stored point at p - x, else
 * p - y, else p - z, else 0. Version 7: LOCO-I's median edge detector on the
 * signed bytes of the -x, -y and -x-y points where all three are stored,
 * else version 6's; a ratio field is as smooth as the colours it divides, so
 * the values' predictor fits it too.
 */
static inline int term_predict(uint32_t version, const uint8_t *sh, const int64_t n[4], int k)
{
    if (version >= 7 && n[0] >= 0 && n[1] >= 0 && n[2] >= 0)
        return median_edge((int8_t)sh[VDBGI_SH_BYTES * (size_t)n[0] + k],
                           (int8_t)sh[VDBGI_SH_BYTES * (size_t)n[1] + k],
                           (int8_t)sh[VDBGI_SH_BYTES * (size_t)n[2] + k]);
    const int64_t j = first_stored(n);
    return j >= 0 ? sh[VDBGI_SH_BYTES * (size_t)j + k] : 0;
}

/*
 * Point i's 24 term bytes to the residuals the file stores: each byte less
 * its prediction, and in version 7 a green or blue residual then less the
 * red or green one of the same term. The three channels' ratios describe one
 * direction of light and err together, so that difference is mostly zero.
 */
static inline void term_residuals(uint32_t version, const uint8_t *sh, const int64_t n[4], size_t i,
                                  uint8_t e[VDBGI_SH_BYTES])
{
    uint8_t d[VDBGI_SH_BYTES];
    for (int k = 0; k < VDBGI_SH_BYTES; k++)
        d[k] = (uint8_t)(sh[VDBGI_SH_BYTES * i + k] - term_predict(version, sh, n, k));
    for (int k = 0; k < VDBGI_SH_BYTES; k++)
        e[k] = version >= 7 && k % 3 ? (uint8_t)(d[k] - d[k - 1]) : d[k];
}

/* The inverse: point i's term bytes from residuals e, its neighbours decoded already. */
static inline void term_undo_residuals(uint32_t version, uint8_t *sh, const int64_t n[4], size_t i,
                                       const uint8_t e[VDBGI_SH_BYTES])
{
    uint8_t d = 0;
    for (int k = 0; k < VDBGI_SH_BYTES; k++) {
        d = version >= 7 && k % 3 ? (uint8_t)(e[k] + d) : e[k];
        sh[VDBGI_SH_BYTES * i + k] = (uint8_t)(d + term_predict(version, sh, n, k));
    }
}

/* An RGBM colour byte of point j as it would read under multiplier m (rounded, at most 255). */
static inline int rescaled(const uint8_t *values, int64_t j, int k, int m)
{
    if (m == 0)
        return values[4 * j + k];
    const int s = (2 * values[4 * j + k] * values[4 * j + 3] + m) / (2 * m);
    return s > 255 ? 255 : s;
}

/*
 * Byte k's prediction: the median edge detector (LOCO-I's) over the -x, -y
 * and -x-y neighbours where all three are stored, else the -x, -y or -z
 * one, else 0. An RGBM colour byte is first rescaled to m, the point's own
 * multiplier, which is decoded before its colour: neighbours on either side
 * of a step in M then still predict it.
 */
static inline uint8_t predict(const uint8_t *values, const int64_t n[4], int k, bool rgbm_colour,
                              int m)
{
    const int mm = rgbm_colour ? m : 0;
    if (n[0] >= 0 && n[1] >= 0 && n[2] >= 0)
        return (uint8_t)median_edge(rescaled(values, n[0], k, mm), rescaled(values, n[1], k, mm),
                                    rescaled(values, n[2], k, mm));
    const int64_t j = first_stored(n);
    return j >= 0 ? (uint8_t)rescaled(values, j, k, mm) : 0;
}

/* Byte o of a point in decoding order: an RGBM multiplier before the colour it scales. */
static inline int byte_order(bool rgbm, int o)
{
    return rgbm ? (o + 3) % 4 : o;
}

/*
 * Runs the statements for the stored points of the owner cells z0 <= cz < z1,
 * in storage order: lattice point p, index i (i0 the first one's). The
 * statements must not `continue`: that would skip the count.
 */
#define FOR_EACH_POINT_IN(pl, z0, z1, i0, p, i, ...)                                               \
    do {                                                                                           \
        size_t i = (i0);                                                                           \
        for (int32_t cz = (z0); cz < (z1); cz++)                                                   \
            for (int32_t cy = 0; cy < (int32_t)(pl)->grid[1]; cy++)                                \
                for (int32_t cx = 0; cx < (int32_t)(pl)->grid[0]; cx++) {                          \
                    const int32_t cc_[3] = {cx, cy, cz};                                           \
                    const uint64_t m_ = (pl)->mask[cell_index((pl)->grid, cc_)];                   \
                    for (int bit = 0; bit < 64; bit++) {                                           \
                        if (!(m_ >> bit & 1u))                                                     \
                            continue;                                                              \
                        const int32_t p[3] = {cx * 4 + (bit & 3), cy * 4 + (bit >> 2 & 3),         \
                                              cz * 4 + (bit >> 4)};                                \
                        __VA_ARGS__                                                                \
                        i++;                                                                       \
                    }                                                                              \
                }                                                                                  \
    } while (0)

/* Every stored point, in storage order. */
#define FOR_EACH_POINT(pl, p, i, ...)                                                              \
    FOR_EACH_POINT_IN(pl, 0, (int32_t)(pl)->grid[2], 0, p, i, __VA_ARGS__)

/* A texel's bytes to linear RGB and back, in the volume's encoding. */
static inline void decode_texel(const vdbgi_volume *v, const uint8_t in[4], float rgb[3])
{
    if (v->info.encoding == VDBGI_ENCODING_RGB9E5)
        vdbgi_rgb9e5_decode(vdbgi_get_u32(in), rgb);
    else
        vdbgi_rgbm_decode(in, v->info.rgbm_range, rgb);
}

static inline bool encode_texel(const vdbgi_volume *v, const float rgb[3], uint8_t out[4])
{
    if (v->info.encoding == VDBGI_ENCODING_RGB9E5) {
        uint32_t w;
        const bool clamped = vdbgi_rgb9e5_encode(rgb, &w);
        vdbgi_put_u32(out, w);
        return clamped;
    }
    return vdbgi_rgbm_encode(rgb, v->info.rgbm_range, out);
}

/* The converter's placement of pl's bricks (pack_place.c): origins and the atlas size. */
vdbgi_result vdbgi_pack_place(vdbgi_context *ctx, vdbgi_pack_plan *pl, uint32_t dims[3]);

/*
 * The atlas from the stored values (4 bytes a point, interleaved) and, with
 * sh not NULL, the L2 terms' texels from theirs (VDBGI_SH_BYTES a point),
 * over threads; *clamped gets how many stitched texels clamped (packed.c).
 */
vdbgi_result vdbgi_pack_rebuild_values(vdbgi_volume *v, const vdbgi_pack_plan *pl,
                                       const uint8_t *values, const int8_t *sh, int threads,
                                       size_t *clamped);

#endif /* VDBGI_PACK_COMMON_H */
