/*
 * packed.c: the compact layout's file, version 3 (docs/format.md, "Version
 * 3"). The runtime atlas repeats every probe on a brick face in the next
 * brick's border, and holds stitched values any reader can recompute; the
 * file keeps neither. It stores one level byte a cell, then each lattice
 * point some brick reads unstitched, once, in owner-cell order, as four
 * planes of residuals against the point's -x (else -y, else -z) neighbour.
 * The converter builds its own textures through the reader's code, so what
 * it measures is what a reader gets.
 */
#include "packed.h"
#include "atlas.h"
#include "encode.h"
#include "gifile.h"
#include "util.h"

#include <stdlib.h>
#include <string.h>

/*
 * Owner cells past the indirection's + faces: a position inside the box
 * reads lattice points up to cell dims + 1 (a level-3 brick's last step);
 * a brick texel beyond that only a lookup outside the box reaches, and it
 * is neither stored nor anything but zero.
 */
enum { N = VDBGI_BRICK_COMPACT, TEXELS = N * N * N, PAD = 2 };

static size_t cell_index(const uint32_t d[3], const int32_t c[3])
{
    return ((size_t)c[2] * d[1] + (size_t)c[1]) * d[0] + (size_t)c[0];
}

/*
 * Where lattice point p sits in the owner grid: its cell and its bit there
 * (z, then y, then x, 4 a side). False when p lies outside the grid.
 */
static bool grid_slot(const vdbgi_pack_plan *pl, const int32_t p[3], size_t *cell, int *bit)
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
static int64_t point_index(const vdbgi_pack_plan *pl, const int32_t p[3])
{
    size_t c;
    int bit;
    if (!grid_slot(pl, p, &c, &bit) || !(pl->mask[c] >> bit & 1u))
        return -1;
    return (int64_t)pl->offset[c] + __builtin_popcountll(pl->mask[c] & ((UINT64_C(1) << bit) - 1u));
}

/* Texel q of brick b stands at relative fine lattice point p. */
static void texel_point(const vdbgi_pack_plan *pl, size_t b, int t, int32_t p[3])
{
    const int q[3] = {t % N, t / N % N, t / (N * N)};
    const int span = 1 << pl->level[b];
    for (int k = 0; k < 3; k++)
        p[k] = (pl->key[b][k] * VDBGI_BRICK + q[k]) * span;
}

/*
 * The coarsest brick whose cells touch lattice point p, if coarser than level:
 * its index and level. A point on a cell face, edge or corner touches two,
 * four or eight cells; cells past the indirection touch nothing.
 */
static bool coarser_brick_at(const vdbgi_volume *v, const int32_t p[3], int level, size_t *index,
                             int *coarse_level)
{
    const uint32_t *const d = v->info.indirection_dims;
    const uint32_t sx = v->info.atlas_dims[0] / N, sy = v->info.atlas_dims[1] / N;
    int best = level;
    for (int c = 0; c < 8; c++) {
        int32_t cell[3];
        bool inside = true;
        for (int k = 0; k < 3; k++) {
            const int down = c >> k & 1;
            cell[k] = (p[k] >> 2) - down;
            inside = inside && (!down || p[k] % VDBGI_BRICK == 0) && cell[k] >= 0 &&
                     cell[k] < (int32_t)d[k];
        }
        if (!inside)
            continue;
        const uint8_t *const t = &v->indirection[4 * cell_index(d, cell)];
        if (t[3] == 0 || t[3] - 1 <= best)
            continue;
        best = t[3] - 1;
        *index = ((size_t)t[2] * sy + t[1]) * sx + t[0] - 1;
    }
    *coarse_level = best;
    return best > level;
}

/*
 * Does texel t of brick b take a coarser brick's value, and whose? The plan
 * knows which texels do; only those look the coarser brick up again.
 */
static bool stitched(const vdbgi_volume *v, const vdbgi_pack_plan *pl, size_t b, int t,
                     size_t *coarse, int *coarse_level)
{
    if (!(pl->stitch[b][t >> 5] >> (t & 31) & 1u))
        return false;
    int32_t p[3];
    texel_point(pl, b, t, p);
    return coarser_brick_at(v, p, pl->level[b], coarse, coarse_level);
}

/* Could any face of brick b touch a coarser brick? Not if no cell around its block is coarser. */
static bool near_coarser(const vdbgi_volume *v, const vdbgi_pack_plan *pl, size_t b)
{
    const uint32_t *const d = pl->dims;
    const int32_t span = 1 << pl->level[b];
    int32_t lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = pl->key[b][k] * span - 1;
        hi[k] = pl->key[b][k] * span + span;
        lo[k] = lo[k] < 0 ? 0 : lo[k];
        hi[k] = hi[k] >= (int32_t)d[k] ? (int32_t)d[k] - 1 : hi[k];
    }
    for (int32_t z = lo[2]; z <= hi[2]; z++)
        for (int32_t y = lo[1]; y <= hi[1]; y++)
            for (int32_t x = lo[0]; x <= hi[0]; x++) {
                const int32_t c[3] = {x, y, z};
                if (v->indirection[4 * cell_index(d, c) + 3] > pl->level[b] + 1)
                    return true;
            }
    return false;
}

static void find_stitches(const vdbgi_volume *v, vdbgi_pack_plan *pl, size_t b)
{
    memset(pl->stitch[b], 0, sizeof(pl->stitch[b]));
    if (!near_coarser(v, pl, b))
        return;
    for (int t = 0; t < TEXELS; t++) {
        const int q[3] = {t % N, t / N % N, t / (N * N)};
        if (q[0] % 4 && q[1] % 4 && q[2] % 4)
            continue; /* inside: only faces meet other bricks */
        int32_t p[3];
        size_t j;
        int cl;
        texel_point(pl, b, t, p);
        if (coarser_brick_at(v, p, pl->level[b], &j, &cl))
            pl->stitch[b][t >> 5] |= 1u << (t & 31);
    }
}

void vdbgi_pack_plan_free(vdbgi_context *ctx, vdbgi_pack_plan *pl)
{
    vdbgi_free(ctx, pl->key);
    vdbgi_free(ctx, pl->level);
    vdbgi_free(ctx, pl->stitch);
    vdbgi_free(ctx, pl->mask);
    vdbgi_free(ctx, pl->offset);
    memset(pl, 0, sizeof(*pl));
}

/* Every cell of each brick's block (inside the indirection) carries the brick's level. */
static vdbgi_result scan_bricks(vdbgi_context *ctx, const uint32_t d[3], const uint8_t *levels,
                                uint32_t max_level, const char *name, vdbgi_pack_plan *pl)
{
    size_t n = 0;
    for (int32_t z = 0; z < (int32_t)d[2]; z++)
        for (int32_t y = 0; y < (int32_t)d[1]; y++)
            for (int32_t x = 0; x < (int32_t)d[0]; x++) {
                const int32_t c[3] = {x, y, z};
                const uint8_t b = levels[cell_index(d, c)];
                if (b == 0)
                    continue;
                VDBGI_FAIL_IF(ctx, b > max_level + 1, VDBGI_ERR_FORMAT,
                              "%s: cell %d,%d,%d has level %d, above the file's max level %u", name,
                              x, y, z, b - 1, max_level);
                const int32_t span = 1 << (b - 1);
                const int32_t first[3] = {x - x % span, y - y % span, z - z % span};
                if (first[0] != x || first[1] != y || first[2] != z) {
                    /* The block's first cell checked this one already, if it is a brick. */
                    VDBGI_FAIL_IF(ctx, levels[cell_index(d, first)] != b, VDBGI_ERR_FORMAT,
                                  "%s: cell %d,%d,%d is level %d but its block's first cell "
                                  "is not",
                                  name, x, y, z, b - 1);
                    continue;
                }
                for (int32_t k = z; k < z + span && k < (int32_t)d[2]; k++)
                    for (int32_t j = y; j < y + span && j < (int32_t)d[1]; j++)
                        for (int32_t i = x; i < x + span && i < (int32_t)d[0]; i++) {
                            const int32_t e[3] = {i, j, k};
                            VDBGI_FAIL_IF(ctx, levels[cell_index(d, e)] != b, VDBGI_ERR_FORMAT,
                                          "%s: the level-%d block at cell %d,%d,%d has a cell "
                                          "of another level",
                                          name, b - 1, x, y, z);
                        }
                if (pl->key) {
                    for (int k = 0; k < 3; k++)
                        pl->key[n][k] = c[k] / span;
                    pl->level[n] = (uint8_t)(b - 1);
                } else {
                    pl->per_level[b - 1]++;
                }
                n++;
            }
    pl->brick_count = n;
    return VDBGI_OK;
}

/* Point every cell a brick covers at its slot and level. */
static void mark_indirection(vdbgi_volume *v, const vdbgi_pack_plan *pl, size_t b)
{
    const uint32_t *const d = v->info.indirection_dims;
    const uint32_t sx = v->info.atlas_dims[0] / N, sy = v->info.atlas_dims[1] / N;
    const size_t slot = b + 1;
    const uint8_t texel[4] = {(uint8_t)(slot % sx), (uint8_t)(slot / sx % sy),
                              (uint8_t)(slot / (sx * sy)), (uint8_t)(pl->level[b] + 1)};
    const int32_t span = 1 << pl->level[b];
    int32_t lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = pl->key[b][k] * span;
        hi[k] = lo[k] + span < (int32_t)d[k] ? lo[k] + span : (int32_t)d[k];
    }
    for (int32_t z = lo[2]; z < hi[2]; z++)
        for (int32_t y = lo[1]; y < hi[1]; y++)
            for (int32_t x = lo[0]; x < hi[0]; x++) {
                const int32_t c[3] = {x, y, z};
                memcpy(&v->indirection[4 * cell_index(d, c)], texel, 4);
            }
}

vdbgi_result vdbgi_pack_plan_make(vdbgi_volume *v, const uint8_t *levels,
                                  const vdbgi_volume_info *expect, const char *name,
                                  vdbgi_pack_plan *pl)
{
    vdbgi_context *const ctx = v->ctx;
    vdbgi_volume_info *const info = &v->info;
    memset(pl, 0, sizeof(*pl));
    size_t grid_cells = 1;
    for (int k = 0; k < 3; k++) {
        pl->dims[k] = info->indirection_dims[k];
        pl->grid[k] = pl->dims[k] + PAD;
        grid_cells *= pl->grid[k];
    }
    /* Count, check, then list: the bricks' arrays are sized by what the levels hold. */
    VDBGI_TRY(scan_bricks(ctx, pl->dims, levels, info->max_level, name, pl));
    const size_t count = pl->brick_count;
    vdbgi_result r = vdbgi_atlas_dims(ctx, count + 1, VDBGI_LAYOUT_COMPACT, info->atlas_dims);
    if (r != VDBGI_OK)
        return r;
    /* A reader's header must count these bricks before anything is allocated for them. */
    VDBGI_FAIL_IF(
        ctx,
        expect && (memcmp(expect->bricks, pl->per_level, sizeof(pl->per_level)) != 0 ||
                   memcmp(expect->atlas_dims, info->atlas_dims, sizeof(info->atlas_dims)) != 0),
        VDBGI_ERR_FORMAT, "%s: the level bytes hold other bricks than the header counts", name);
    pl->key = vdbgi_alloc(ctx, (count ? count : 1) * sizeof(*pl->key));
    pl->level = vdbgi_alloc(ctx, count ? count : 1);
    pl->stitch = vdbgi_alloc(ctx, (count ? count : 1) * sizeof(*pl->stitch));
    pl->mask = vdbgi_calloc(ctx, grid_cells, sizeof(*pl->mask));
    pl->offset = vdbgi_alloc(ctx, grid_cells * sizeof(*pl->offset));
    if (!pl->key || !pl->level || !pl->stitch || !pl->mask || !pl->offset) {
        vdbgi_pack_plan_free(ctx, pl);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    scan_bricks(ctx, pl->dims, levels, info->max_level, name, pl);
    memset(info->bricks, 0, sizeof(info->bricks));
    memset(pl->per_level, 0, sizeof(pl->per_level));
    for (size_t b = 0; b < count; b++)
        info->bricks[pl->level[b]]++;
    memcpy(pl->per_level, info->bricks, sizeof(pl->per_level));
    info->brick_count = (uint32_t)count;
    info->atlas_size = 4 * (size_t)info->atlas_dims[0] * info->atlas_dims[1] * info->atlas_dims[2];
    if ((r = vdbgi_gifile_alloc(v)) != VDBGI_OK) {
        vdbgi_pack_plan_free(ctx, pl);
        return r;
    }
    for (size_t b = 0; b < count; b++)
        mark_indirection(v, pl, b);
    for (size_t b = 0; b < count; b++)
        find_stitches(v, pl, b);
    /* The stored points: every texel no stitching overwrites. */
    for (size_t b = 0; b < count; b++)
        for (int t = 0; t < TEXELS; t++) {
            size_t j;
            int cl;
            if (stitched(v, pl, b, t, &j, &cl))
                continue;
            int32_t p[3];
            size_t c;
            int bit;
            texel_point(pl, b, t, p);
            if (grid_slot(pl, p, &c, &bit))
                pl->mask[c] |= UINT64_C(1) << bit;
        }
    size_t sum = 0;
    for (size_t c = 0; c < grid_cells; c++) {
        pl->offset[c] = (uint32_t)sum;
        sum += (size_t)__builtin_popcountll(pl->mask[c]);
    }
    pl->points = sum;
    return VDBGI_OK;
}

static void decode_texel(const vdbgi_volume *v, const uint8_t in[4], float rgb[3])
{
    if (v->info.encoding == VDBGI_ENCODING_RGB9E5)
        vdbgi_rgb9e5_decode(vdbgi_get_u32(in), rgb);
    else
        vdbgi_rgbm_decode(in, v->info.rgbm_range, rgb);
}

static bool encode_texel(const vdbgi_volume *v, const float rgb[3], uint8_t out[4])
{
    if (v->info.encoding == VDBGI_ENCODING_RGB9E5) {
        uint32_t w;
        const bool clamped = vdbgi_rgb9e5_encode(rgb, &w);
        vdbgi_put_u32(out, w);
        return clamped;
    }
    return vdbgi_rgbm_encode(rgb, v->info.rgbm_range, out);
}

static uint8_t *atlas_texel(const vdbgi_volume *v, size_t b, int t)
{
    const uint32_t *const d = v->info.atlas_dims;
    const size_t slot = b + 1, sx = d[0] / N, sy = d[1] / N;
    const size_t x = slot % sx * N + (size_t)(t % N), y = slot / sx % sy * N + (size_t)(t / N % N),
                 z = slot / (sx * sy) * N + (size_t)(t / (N * N));
    return &v->atlas[4 * ((z * d[1] + y) * d[0] + x)];
}

/*
 * The atlas from the stored values (4 bytes a point, interleaved). Coarse
 * bricks' samples are kept as floats, coarsest level first, so a stitched
 * texel interpolates exactly what the converter's stitching always did:
 * the coarser brick's values, its own stitched ones unrounded.
 */
static vdbgi_result rebuild(vdbgi_volume *v, const vdbgi_pack_plan *pl, const uint8_t *values,
                            size_t *clamped_out)
{
    vdbgi_context *const ctx = v->ctx;
    const size_t count = pl->brick_count;
    size_t coarse = 0, clamped = 0;
    int32_t *const cidx = vdbgi_alloc(ctx, (count ? count : 1) * sizeof(*cidx));
    if (!cidx)
        return VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t b = 0; b < count; b++)
        cidx[b] = pl->level[b] ? (int32_t)coarse++ : -1;
    float(*fs)[TEXELS][3] = vdbgi_alloc(ctx, (coarse ? coarse : 1) * sizeof(*fs));
    if (!fs) {
        vdbgi_free(ctx, cidx);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    for (int level = (int)v->info.max_level; level >= 1; level--)
        for (size_t b = 0; b < count; b++) {
            if (pl->level[b] != level)
                continue;
            for (int t = 0; t < TEXELS; t++) {
                size_t j;
                int cl;
                int32_t p[3];
                texel_point(pl, b, t, p);
                if (stitched(v, pl, b, t, &j, &cl)) {
                    const double pos[3] = {p[0], p[1], p[2]};
                    vdbgi_brick_interpolate((const float(*)[3])fs[cidx[j]], VDBGI_LAYOUT_COMPACT,
                                            pl->key[j], cl, pos, fs[cidx[b]][t]);
                } else {
                    const int64_t i = point_index(pl, p);
                    static const uint8_t zero[4];
                    decode_texel(v, i >= 0 ? &values[4 * i] : zero, fs[cidx[b]][t]);
                }
            }
        }
    for (size_t b = 0; b < count; b++)
        for (int t = 0; t < TEXELS; t++) {
            size_t j;
            int cl;
            int32_t p[3];
            texel_point(pl, b, t, p);
            uint8_t *const out = atlas_texel(v, b, t);
            if (!stitched(v, pl, b, t, &j, &cl)) {
                const int64_t i = point_index(pl, p);
                if (i >= 0)
                    memcpy(out, &values[4 * i], 4);
                continue;
            }
            float rgb[3];
            if (cidx[b] >= 0) {
                memcpy(rgb, fs[cidx[b]][t], sizeof(rgb));
            } else {
                const double pos[3] = {p[0], p[1], p[2]};
                vdbgi_brick_interpolate((const float(*)[3])fs[cidx[j]], VDBGI_LAYOUT_COMPACT,
                                        pl->key[j], cl, pos, rgb);
            }
            clamped += encode_texel(v, rgb, out);
        }
    vdbgi_free(ctx, fs);
    vdbgi_free(ctx, cidx);
    *clamped_out = clamped;
    return VDBGI_OK;
}

/*
 * The predictor (docs/format.md, "Version 3"). Its neighbours: the stored
 * points at p - x, p - y, p - x - y and p - z, or -1.
 */
static void neighbours(const vdbgi_pack_plan *pl, const int32_t p[3], int64_t n[4])
{
    const int32_t a[3] = {p[0] - 1, p[1], p[2]}, b[3] = {p[0], p[1] - 1, p[2]},
                  c[3] = {p[0] - 1, p[1] - 1, p[2]}, e[3] = {p[0], p[1], p[2] - 1};
    n[0] = point_index(pl, a);
    n[1] = point_index(pl, b);
    n[2] = point_index(pl, c);
    n[3] = point_index(pl, e);
}

/* An RGBM colour byte of point j as it would read under multiplier m (rounded, at most 255). */
static int rescaled(const uint8_t *values, int64_t j, int k, int m)
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
static uint8_t predict(const uint8_t *values, const int64_t n[4], int k, bool rgbm_colour, int m)
{
    const int mm = rgbm_colour ? m : 0;
    if (n[0] >= 0 && n[1] >= 0 && n[2] >= 0) {
        const int a = rescaled(values, n[0], k, mm), b = rescaled(values, n[1], k, mm),
                  c = rescaled(values, n[2], k, mm);
        const int lo = a < b ? a : b, hi = a < b ? b : a;
        return (uint8_t)(c >= hi ? lo : c <= lo ? hi : a + b - c);
    }
    const int64_t j = n[0] >= 0 ? n[0] : n[1] >= 0 ? n[1] : n[3];
    return j >= 0 ? (uint8_t)rescaled(values, j, k, mm) : 0;
}

/* Byte order within a point: an RGBM multiplier before the colour it scales. */
static const int byte_order[2][4] = {{3, 0, 1, 2}, {0, 1, 2, 3}};

/* Runs the statements for every stored point in storage order: lattice point p, index i. */
#define FOR_EACH_POINT(pl, p, i, ...)                                                              \
    do {                                                                                           \
        size_t i = 0;                                                                              \
        for (int32_t cz = 0; cz < (int32_t)(pl)->grid[2]; cz++)                                    \
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

vdbgi_result vdbgi_pack_rebuild(vdbgi_volume *v, const vdbgi_pack_plan *pl, const uint8_t *planes,
                                size_t *clamped)
{
    uint8_t *const values = vdbgi_calloc(v->ctx, pl->points ? pl->points : 1, 4);
    if (!values)
        return VDBGI_ERR_OUT_OF_MEMORY;
    const size_t n = pl->points;
    const bool rgbm = v->info.encoding == VDBGI_ENCODING_RGBM;
    FOR_EACH_POINT(pl, p, i, {
        int64_t nb[4];
        neighbours(pl, p, nb);
        for (int o = 0; o < 4; o++) {
            const int k = byte_order[!rgbm][o];
            values[4 * i + k] = (uint8_t)(planes[k * n + i] +
                                          predict(values, nb, k, rgbm && k < 3, values[4 * i + 3]));
        }
    });
    const vdbgi_result r = rebuild(v, pl, values, clamped);
    vdbgi_free(v->ctx, values);
    return r;
}

/* ---- the converter's half ---------------------------------------------------------------- */

/*
 * Slot order: by each brick's first cell, z, then y, then x, as the reader
 * lists them (absolute cells: the indirection's corner shifts all alike).
 */
static int brick_order(const void *pa, const void *pb)
{
    const vdbgi_brick *a = pa, *b = pb;
    for (int k = 2; k >= 0; k--) {
        const int32_t ca = a->key[k] * (1 << a->level), cb = b->key[k] * (1 << b->level);
        if (ca != cb)
            return ca < cb ? -1 : 1;
    }
    return 0;
}

typedef struct sample_job {
    const vdbgi_volume *v;
    const vdbgi_brick *bricks;
    float (*samples)[TEXELS][3];
    size_t begin, end, fallbacks;
} sample_job;

static void *sample_worker(void *arg)
{
    sample_job *const job = arg;
    for (size_t i = job->begin; i < job->end; i++) {
        const vdbgi_brick *const k = &job->bricks[i];
        job->fallbacks += vdbgi_brick_samples(&job->v->filled, k->key, k->level, k->mean,
                                              VDBGI_LAYOUT_COMPACT, job->samples[i]);
    }
    return NULL;
}

/* Valid probes, a bit each, over the owner grid. */
static uint64_t *valid_bits(vdbgi_volume *v, const vdbgi_pack_plan *pl, const vdbgi_probes *pr)
{
    const size_t cells = (size_t)pl->grid[0] * pl->grid[1] * pl->grid[2];
    uint64_t *const bits = vdbgi_calloc(v->ctx, cells, sizeof(*bits));
    if (!bits)
        return NULL;
    for (size_t i = 0; i < pr->count; i++) {
        if (pr->backface[i] > pr->invalid_threshold)
            continue;
        int32_t p[3];
        size_t c;
        int bit;
        for (int k = 0; k < 3; k++)
            p[k] = pr->ijk[3 * i + k] - v->origin_cell[k] * VDBGI_BRICK;
        if (grid_slot(pl, p, &c, &bit))
            bits[c] |= UINT64_C(1) << bit;
    }
    return bits;
}

/*
 * The valid bits grown by one point along an axis: a cell's 4^3 bits are
 * x fastest (1 bit), then y (4), then z (16); the neighbour cells' faces
 * carry in. Three passes grow them to the 26 neighbours.
 */
static void grow(const vdbgi_pack_plan *pl, const uint64_t *in, uint64_t *out, int axis)
{
    static const uint64_t low_face[3] = {UINT64_C(0x1111111111111111), UINT64_C(0x000F000F000F000F),
                                         UINT64_C(0xFFFF)};
    const int step = axis == 0 ? 1 : axis == 1 ? 4 : 16;
    const uint64_t low = low_face[axis], high = low << (3 * step);
    const size_t stride = axis == 0   ? 1
                          : axis == 1 ? pl->grid[0]
                                      : (size_t)pl->grid[0] * pl->grid[1];
    for (int32_t z = 0; z < (int32_t)pl->grid[2]; z++)
        for (int32_t y = 0; y < (int32_t)pl->grid[1]; y++)
            for (int32_t x = 0; x < (int32_t)pl->grid[0]; x++) {
                const int32_t c[3] = {x, y, z};
                const size_t i = cell_index(pl->grid, c);
                const uint64_t m = in[i];
                uint64_t g = m | (m << step & ~low) | (m >> step & ~high);
                if (c[axis] > 0)
                    g |= in[i - stride] >> (3 * step) & low;
                if (c[axis] + 1 < (int32_t)pl->grid[axis])
                    g |= in[i + stride] << (3 * step) & high;
                out[i] = g;
            }
}

vdbgi_result vdbgi_pack_write(vdbgi_volume *v, vdbgi_brick *bricks, size_t count,
                              const vdbgi_probes *probes, int threads, uint8_t **payload,
                              size_t *payload_size)
{
    vdbgi_context *const ctx = v->ctx;
    *payload = NULL;
    *payload_size = 0;
    qsort(bricks, count, sizeof(*bricks), brick_order);
    const uint32_t *const d = v->info.indirection_dims;
    const size_t cells = (size_t)d[0] * d[1] * d[2];
    uint8_t *const levels = vdbgi_calloc(ctx, cells, 1);
    if (!levels)
        return VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t b = 0; b < count; b++) {
        const int32_t span = 1 << bricks[b].level;
        int32_t lo[3], hi[3];
        for (int k = 0; k < 3; k++) {
            lo[k] = bricks[b].key[k] * span - v->origin_cell[k];
            hi[k] = lo[k] + span < (int32_t)d[k] ? lo[k] + span : (int32_t)d[k];
        }
        for (int32_t z = lo[2]; z < hi[2]; z++)
            for (int32_t y = lo[1]; y < hi[1]; y++)
                for (int32_t x = lo[0]; x < hi[0]; x++) {
                    const int32_t c[3] = {x, y, z};
                    levels[cell_index(d, c)] = (uint8_t)(bricks[b].level + 1);
                }
    }
    vdbgi_pack_plan pl;
    float(*samples)[TEXELS][3] = NULL;
    uint8_t *values = NULL, *written = NULL, *out = NULL;
    uint64_t *valid = NULL, *near = NULL;
    vdbgi_result r = vdbgi_pack_plan_make(v, levels, NULL, "converter", &pl);
    if (r != VDBGI_OK) {
        vdbgi_free(ctx, levels);
        return r;
    }
    const size_t n = pl.points;
    samples = vdbgi_alloc(ctx, (count ? count : 1) * sizeof(*samples));
    values = vdbgi_calloc(ctx, 4 * (n ? n : 1), 1);
    written = vdbgi_calloc(ctx, n ? n : 1, 1); /* 1 stored, 2 also read by a coarse brick */
    out = vdbgi_alloc(ctx, cells + 4 * n);
    valid = valid_bits(v, &pl, probes);
    const size_t grid_cells = (size_t)pl.grid[0] * pl.grid[1] * pl.grid[2];
    near = vdbgi_alloc(ctx, grid_cells * sizeof(*near));
    if (!samples || !values || !written || !out || !valid || !near) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto done;
    }
    enum { MAX_JOBS = 64 };
    sample_job jobs[MAX_JOBS];
    const int nt = threads > MAX_JOBS ? MAX_JOBS : threads < 1 ? 1 : threads;
    for (int t = 0; t < nt; t++)
        jobs[t] = (sample_job){v,
                               bricks,
                               samples,
                               count * (size_t)t / (size_t)nt,
                               count * (size_t)(t + 1) / (size_t)nt,
                               0};
    vdbgi_run_threads(nt, sample_worker, jobs, sizeof(jobs[0]));
    for (int t = 0; t < nt; t++)
        v->info.fallback_count += jobs[t].fallbacks;
    /* Each point takes the first brick's sample, in slot order. */
    size_t clamped = 0;
    for (size_t b = 0; b < count; b++)
        for (int t = 0; t < TEXELS; t++) {
            size_t j;
            int cl;
            if (stitched(v, &pl, b, t, &j, &cl))
                continue;
            int32_t p[3];
            texel_point(&pl, b, t, p);
            const int64_t i = point_index(&pl, p);
            if (i < 0)
                continue;
            if (!written[i]) {
                clamped += encode_texel(v, samples[b][t], &values[4 * i]);
                written[i] = 1;
            }
            if (pl.level[b])
                written[i] = 2;
        }
    /*
     * Residuals in storage order. A point no receiver reads takes the
     * prediction itself: its residual is zero, which gzip all but drops.
     */
    /* Points with a valid probe among their 26 neighbours, or themselves valid. */
    grow(&pl, valid, near, 0);
    grow(&pl, near, valid, 1);
    grow(&pl, valid, near, 2);
    memcpy(out, levels, cells);
    const bool rgbm = v->info.encoding == VDBGI_ENCODING_RGBM;
    size_t unread = 0;
    FOR_EACH_POINT(&pl, p, i, {
        int64_t nb[4];
        neighbours(&pl, p, nb);
        size_t c;
        int own;
        grid_slot(&pl, p, &c, &own); /* every stored point is in the grid */
        const bool needed = written[i] == 2 || near[c] >> own & 1u;
        unread += !needed;
        for (int o = 0; o < 4; o++) {
            const int k = byte_order[!rgbm][o];
            const uint8_t pred = predict(values, nb, k, rgbm && k < 3, values[4 * i + 3]);
            if (!needed)
                values[4 * i + k] = pred;
            out[cells + k * n + i] = (uint8_t)(values[4 * i + k] - pred);
        }
    });
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "%zu stored points, %zu of them read by no receiver", n,
              unread);
    size_t stitched_clamps = 0;
    if ((r = rebuild(v, &pl, values, &stitched_clamps)) != VDBGI_OK)
        goto done;
    v->info.clamped_count += clamped + stitched_clamps;
    v->info.stored_points = n;
    *payload = out;
    *payload_size = cells + 4 * n;
    out = NULL;
done:
    vdbgi_pack_plan_free(ctx, &pl);
    vdbgi_free(ctx, levels);
    vdbgi_free(ctx, samples);
    vdbgi_free(ctx, values);
    vdbgi_free(ctx, written);
    vdbgi_free(ctx, out);
    vdbgi_free(ctx, valid);
    vdbgi_free(ctx, near);
    return r;
}
