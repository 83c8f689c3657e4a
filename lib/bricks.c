/*
 * bricks.c: from baked probes to seed 000's bricked volume: fill, colour-range
 * pyramid over the filled leaves, top-down coarsening, atlas packing with
 * aprons, indirection, encoding, and the error of the result.
 */
#include "bricks.h"
#include "encode.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* ---- a map from block coordinates to stats, one per pyramid level ---------- */

typedef struct block_stats {
    float lo[3], hi[3];
    double sum[3];
    uint32_t count; /* filled points summed */
    float noise;    /* largest standard error of a valid probe in the block */
} block_stats;

typedef struct level_map {
    int32_t (*keys)[3];
    block_stats *stats;
    size_t count, capacity;
    uint32_t *table; /* index + 1, 0 = empty */
    size_t table_size;
} level_map;

static size_t hash_key(const int32_t k[3])
{
    uint64_t h = (uint64_t)(uint32_t)k[0] * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)(uint32_t)k[1] * 0xC2B2AE3D27D4EB4Full;
    h ^= (uint64_t)(uint32_t)k[2] * 0x165667B19E3779F9ull;
    return (size_t)(h ^ (h >> 31));
}

static vdbgi_result map_init(vdbgi_context *ctx, level_map *m, size_t capacity)
{
    memset(m, 0, sizeof(*m));
    m->table_size = 16;
    while (m->table_size < 2 * capacity)
        m->table_size *= 2;
    m->capacity = capacity ? capacity : 1;
    m->keys = vdbgi_calloc(ctx, m->capacity, sizeof(*m->keys));
    m->stats = vdbgi_calloc(ctx, m->capacity, sizeof(*m->stats));
    m->table = vdbgi_calloc(ctx, m->table_size, sizeof(uint32_t));
    return m->keys && m->stats && m->table ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
}

static void map_free(vdbgi_context *ctx, level_map *m)
{
    vdbgi_free(ctx, m->keys);
    vdbgi_free(ctx, m->stats);
    vdbgi_free(ctx, m->table);
    memset(m, 0, sizeof(*m));
}

static long map_find(const level_map *m, const int32_t k[3])
{
    const size_t mask = m->table_size - 1;
    for (size_t s = hash_key(k) & mask; m->table[s]; s = (s + 1) & mask) {
        const int32_t *const q = m->keys[m->table[s] - 1];
        if (q[0] == k[0] && q[1] == k[1] && q[2] == k[2])
            return (long)m->table[s] - 1;
    }
    return -1;
}

/* Index of key, inserted with empty stats if new. The map never grows past capacity. */
static size_t map_insert(level_map *m, const int32_t k[3])
{
    const size_t mask = m->table_size - 1;
    size_t s = hash_key(k) & mask;
    for (; m->table[s]; s = (s + 1) & mask) {
        const int32_t *const q = m->keys[m->table[s] - 1];
        if (q[0] == k[0] && q[1] == k[1] && q[2] == k[2])
            return m->table[s] - 1;
    }
    const size_t i = m->count++;
    memcpy(m->keys[i], k, sizeof(m->keys[i]));
    block_stats *const st = &m->stats[i];
    for (int c = 0; c < 3; c++) {
        st->lo[c] = INFINITY;
        st->hi[c] = -INFINITY;
        st->sum[c] = 0.0;
    }
    st->count = 0;
    st->noise = 0.0f;
    m->table[s] = (uint32_t)i + 1;
    return i;
}

static void stats_merge(block_stats *into, const block_stats *from)
{
    for (int c = 0; c < 3; c++) {
        into->lo[c] = fminf(into->lo[c], from->lo[c]);
        into->hi[c] = fmaxf(into->hi[c], from->hi[c]);
        into->sum[c] += from->sum[c];
    }
    into->count += from->count;
    into->noise = fmaxf(into->noise, from->noise);
}

/* Largest channel range; 0 for a block with no filled point (it reads its fallback). */
static float stats_range(const block_stats *st)
{
    if (!st->count)
        return 0.0f;
    float r = 0.0f;
    for (int c = 0; c < 3; c++)
        r = fmaxf(r, st->hi[c] - st->lo[c]);
    return r;
}

/* ---- the build ------------------------------------------------------------- */

typedef struct kept_brick {
    int32_t key[3]; /* block coordinate at its level: fine origin = key * 4 * 2^level */
    int level;
} kept_brick;

typedef struct builder {
    vdbgi_context *ctx;
    const vdbgi_probes *probes;
    vdbgi_volume *vol;
    level_map levels[4];
    int max_level;
    float tolerance; /* eps * mean irradiance: absolute, per channel */
    float sigmas;    /* noise allowance: a probe may stray this many standard errors */
    vdbgi_criterion criterion;
    kept_brick *kept;
    size_t kept_count, kept_capacity;
    int threads;
} builder;

/*
 * The 6^3 values of a level-L brick: probe q (-1..4 per axis, -1 and 4 the
 * apron) stands at fine position origin + (q + 0.5) 2^L - 0.5, the centre of
 * its 2^L block (the shader's convention). Points the fill did not reach take
 * the block's mean, which is within the block's range of every filled point.
 */
static size_t brick_samples(const builder *b, const int32_t key[3], int level,
                            float out[VDBGI_BRICK_PADDED][VDBGI_BRICK_PADDED][VDBGI_BRICK_PADDED][3])
{
    size_t fallbacks = 0;
    const vdbgi_leaf *cache = NULL;
    const int span = 1 << level;
    const block_stats *const st = &b->levels[level].stats[map_find(&b->levels[level], key)];
    float mean[3];
    for (int c = 0; c < 3; c++)
        mean[c] = st->count ? (float)(st->sum[c] / st->count) : b->vol->mean_rgb[c];
    for (int z = 0; z < 6; z++)
        for (int y = 0; y < 6; y++)
            for (int x = 0; x < 6; x++) {
                const int q[3] = {x - 1, y - 1, z - 1};
                double pos[3];
                for (int k = 0; k < 3; k++)
                    pos[k] = (double)key[k] * VDBGI_BRICK * span + (q[k] + 0.5) * span - 0.5;
                if (!vdbgi_field_trilinear(&b->vol->filled, pos, out[z][y][x], &cache)) {
                    memcpy(out[z][y][x], mean, sizeof(mean));
                    fallbacks++;
                }
            }
    return fallbacks;
}

/* Trilinear reconstruction from a brick's 6^3 samples at fine position pos. */
static void brick_interpolate(float s[6][6][6][3], const int32_t key[3], int level,
                              const int32_t pos[3], float rgb[3])
{
    const float span = (float)(1 << level);
    int i0[3];
    float fr[3];
    for (int k = 0; k < 3; k++) {
        const float origin = (float)key[k] * VDBGI_BRICK * span;
        const float t = ((float)pos[k] - origin + 0.5f) / span - 0.5f + 1.0f; /* texel units */
        const float fl = floorf(t);
        i0[k] = (int)fl;
        fr[k] = t - fl;
        if (i0[k] > 4) { /* t <= 4.75 for a coarse block and the step past it: a guard */
            i0[k] = 4;
            fr[k] = 1.0f;
        }
    }
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    for (int c = 0; c < 8; c++) {
        const float w = (c & 1 ? fr[0] : 1.0f - fr[0]) * (c & 2 ? fr[1] : 1.0f - fr[1]) *
                        (c & 4 ? fr[2] : 1.0f - fr[2]);
        const float *const v = s[i0[2] + (c >> 2 & 1)][i0[1] + (c >> 1 & 1)][i0[0] + (c & 1)];
        for (int k = 0; k < 3; k++)
            rgb[k] += w * v[k];
    }
}

/*
 * Unreal's test: does the coarse brick reproduce every filled point it draws
 * within tolerance? The shader keeps a block's brick up to the next block's
 * first probe, so the probes one step past the block's far faces are tested
 * too: with both ends of that last step within tolerance, and the next
 * block's brick exact or within its own tolerance at that probe, the jump
 * where the bricks meet stays within the two tolerances (docs/stability.md,
 * level seams). The near faces need no extra points: the block's first probe
 * is its own.
 */
static bool interpolation_fits(builder *b, const int32_t key[3], int level, float noise)
{
    float s[6][6][6][3];
    brick_samples(b, key, level, s);
    const int span = 1 << level, n = VDBGI_BRICK * span;
    const level_map *const cells = &b->levels[0];
    const vdbgi_leaf *cache = NULL;
    for (int z = 0; z <= n; z++)
        for (int y = 0; y <= n; y++)
            for (int x = 0; x <= n; x++) {
                const int32_t p[3] = {key[0] * n + x, key[1] * n + y, key[2] * n + z};
                const int32_t cell[3] = {vdbgi_floor_div(p[0], VDBGI_BRICK),
                                         vdbgi_floor_div(p[1], VDBGI_BRICK),
                                         vdbgi_floor_div(p[2], VDBGI_BRICK)};
                if (map_find(cells, cell) < 0)
                    continue; /* no brick there: nothing is drawn */
                float got[3];
                const float *const want = vdbgi_field_at(&b->vol->filled, p, &cache);
                if (!want)
                    continue;
                brick_interpolate(s, key, level, p, got);
                for (int k = 0; k < 3; k++)
                    if (fabsf(got[k] - want[k]) > b->tolerance + noise)
                        return false;
            }
    return true;
}

/*
 * Kept bricks go into the region of b->kept reserved for their root block:
 * bricks are disjoint and each holds a cell, so a root never keeps more
 * bricks than it has cells, and the region is sized to that.
 */
static vdbgi_result keep(builder *b, const int32_t key[3], int level)
{
    if (b->kept_count == b->kept_capacity)
        return vdbgi_fail(b->ctx, VDBGI_ERR_BACKEND, "internal error: more bricks than cells");
    kept_brick *const k = &b->kept[b->kept_count++];
    memcpy(k->key, key, sizeof(k->key));
    k->level = level;
    return VDBGI_OK;
}

/* Seed 000's visit(): one coarse brick if flat enough, else the eight children that exist. */
static vdbgi_result visit(builder *b, const int32_t key[3], int level)
{
    const long i = map_find(&b->levels[level], key);
    if (i < 0)
        return VDBGI_OK; /* empty air: no brick */
    const block_stats *const st = &b->levels[level].stats[i];
    if (level == 0)
        return keep(b, key, level);
    /*
     * Sampling noise spreads a flat field over about +-sigmas standard errors,
     * so that much of the range (twice: both ends) is not the light's doing.
     */
    const float noise = b->sigmas * st->noise;
    /*
     * A flat block is not enough for the interpolation criterion: its brick's apron
     * reaches half a coarse texel into the neighbours, and a flat block beside a
     * shadow edge would draw the edge into its own probes (docs/stability.md).
     */
    const bool coarse = b->criterion == VDBGI_CRITERION_RANGE
                            ? stats_range(st) - 2.0f * noise <= b->tolerance
                            : interpolation_fits(b, key, level, noise);
    if (coarse)
        return keep(b, key, level);
    for (int c = 0; c < 8; c++) {
        const int32_t child[3] = {2 * key[0] + (c & 1), 2 * key[1] + (c >> 1 & 1),
                                  2 * key[2] + (c >> 2 & 1)};
        VDBGI_TRY(visit(b, child, level - 1));
    }
    return VDBGI_OK;
}

static int compare_keys(const void *a, const void *b)
{
    const int32_t *const x = a, *const y = b;
    for (int k = 2; k >= 0; k--)
        if (x[k] != y[k])
            return x[k] < y[k] ? -1 : 1;
    return 0;
}

/* Level-0 stats from the filled leaves (a leaf holds 2^3 cells), then coarser levels. */
static vdbgi_result build_pyramid(builder *b, const int32_t *cells, size_t cell_count)
{
    vdbgi_context *const ctx = b->ctx;
    for (int l = 0; l <= b->max_level; l++)
        VDBGI_TRY(map_init(ctx, &b->levels[l], cell_count));
    for (size_t c = 0; c < cell_count; c++)
        map_insert(&b->levels[0], &cells[3 * c]);
    const vdbgi_field *const f = &b->vol->filled;
    for (size_t li = 0; li < f->leaf_count; li++) {
        const vdbgi_leaf *const leaf = &f->leaves[li];
        for (int sub = 0; sub < 8; sub++) {
            const int ox = (sub & 1) * 4, oy = (sub >> 1 & 1) * 4, oz = (sub >> 2 & 1) * 4;
            /* Leaf origins are multiples of 8, so this division is exact. */
            const int32_t ck[3] = {(leaf->origin[0] + ox) / 4, (leaf->origin[1] + oy) / 4,
                                   (leaf->origin[2] + oz) / 4};
            const long ci = map_find(&b->levels[0], ck);
            if (ci < 0)
                continue; /* rim points: filled for filtering, not part of any cell */
            block_stats *const st = &b->levels[0].stats[ci];
            for (int x = ox; x < ox + 4; x++)
                for (int y = oy; y < oy + 4; y++)
                    for (int z = oz; z < oz + 4; z++) {
                        const unsigned n = (unsigned)(x << 6 | y << 3 | z);
                        if (!(leaf->mask[n >> 6] >> (n & 63) & 1))
                            continue;
                        const float *const v = leaf->values + 3 * n;
                        for (int k = 0; k < 3; k++) {
                            st->lo[k] = fminf(st->lo[k], v[k]);
                            st->hi[k] = fmaxf(st->hi[k], v[k]);
                            st->sum[k] += v[k];
                        }
                        st->count++;
                    }
        }
    }
    /* Each cell's noise: the largest standard error among its valid probes. */
    const vdbgi_probes *const p = b->probes;
    for (size_t n = 0; p->stderr_ && n < p->count; n++) {
        if (p->backface[n] > p->invalid_threshold)
            continue;
        const int32_t ck[3] = {vdbgi_floor_div(p->ijk[3 * n], 4), vdbgi_floor_div(p->ijk[3 * n + 1], 4),
                               vdbgi_floor_div(p->ijk[3 * n + 2], 4)};
        const long ci = map_find(&b->levels[0], ck);
        if (ci >= 0)
            b->levels[0].stats[ci].noise = fmaxf(b->levels[0].stats[ci].noise, p->stderr_[n]);
    }
    for (int l = 1; l <= b->max_level; l++) {
        const level_map *const fine = &b->levels[l - 1];
        for (size_t i = 0; i < fine->count; i++) {
            const int32_t parent[3] = {vdbgi_floor_div(fine->keys[i][0], 2),
                                       vdbgi_floor_div(fine->keys[i][1], 2),
                                       vdbgi_floor_div(fine->keys[i][2], 2)};
            const size_t pi = map_insert(&b->levels[l], parent);
            stats_merge(&b->levels[l].stats[pi], &fine->stats[i]);
        }
    }
    return VDBGI_OK;
}

/* ---- packing, encoding, error ---------------------------------------------- */

static vdbgi_result resolve_desc(vdbgi_context *ctx, const vdbgi_convert_desc *desc, float *eps,
                                 float *sigmas, int *max_level, vdbgi_criterion *criterion,
                                 vdbgi_encoding *encoding, int *threads)
{
    const vdbgi_convert_desc none = {0};
    if (!desc)
        desc = &none;
    *eps = desc->eps == 0.0f ? 0.1f : desc->eps == VDBGI_NONE ? 0.0f : desc->eps;
    VDBGI_FAIL_IF(ctx, !(*eps >= 0.0f) || !isfinite(*eps), VDBGI_ERR_INVALID_ARG,
                  "eps must be >= 0 and finite (got %g)", (double)desc->eps);
    *sigmas = desc->noise_sigmas == 0.0f ? 1.0f
              : desc->noise_sigmas == VDBGI_NONE ? 0.0f
                                                 : desc->noise_sigmas;
    VDBGI_FAIL_IF(ctx, !(*sigmas >= 0.0f) || !isfinite(*sigmas), VDBGI_ERR_INVALID_ARG,
                  "noise allowance must be >= 0 standard errors (got %g)", (double)desc->noise_sigmas);
    const int levels = desc->levels ? desc->levels : 4;
    VDBGI_FAIL_IF(ctx, levels < 1 || levels > 4, VDBGI_ERR_INVALID_ARG,
                  "max level must be in 0..3 (got %d)", levels - 1);
    *max_level = levels - 1;
    VDBGI_FAIL_IF(ctx, desc->criterion < VDBGI_CRITERION_AUTO || desc->criterion > VDBGI_CRITERION_INTERP,
                  VDBGI_ERR_INVALID_ARG, "unknown criterion %d", (int)desc->criterion);
    *criterion = desc->criterion == VDBGI_CRITERION_AUTO ? VDBGI_CRITERION_INTERP : desc->criterion;
    VDBGI_FAIL_IF(ctx, desc->encoding != VDBGI_ENCODING_RGBM && desc->encoding != VDBGI_ENCODING_RGB9E5,
                  VDBGI_ERR_INVALID_ARG, "unknown encoding %d", (int)desc->encoding);
    *encoding = desc->encoding;
    VDBGI_FAIL_IF(ctx, desc->fill < VDBGI_FILL_AUTO || desc->fill > VDBGI_FILL_DARKEST,
                  VDBGI_ERR_INVALID_ARG, "unknown fill %d", (int)desc->fill);
    VDBGI_FAIL_IF(ctx, desc->threads < 0, VDBGI_ERR_INVALID_ARG,
                  "thread count must be >= 0 (got %d)", desc->threads);
    *threads = desc->threads ? desc->threads : vdbgi_core_count();
    return VDBGI_OK;
}

vdbgi_volume_view vdbgi_volume_view_of(const vdbgi_volume *v)
{
    vdbgi_volume_view view;
    memset(&view, 0, sizeof(view));
    view.encoding = (uint32_t)v->info.encoding;
    view.rgbm_range = v->info.rgbm_range;
    for (int k = 0; k < 3; k++) {
        view.box_min[k] = v->info.box_min[k];
        view.box_max[k] = v->info.box_max[k];
        view.ind_dims[k] = v->info.indirection_dims[k];
        view.atlas_dims[k] = v->info.atlas_dims[k];
    }
    view.indirection = v->indirection;
    view.atlas = v->atlas;
    return view;
}

void vdbgi_volume_sample(const vdbgi_volume *v, const float pos[3], float rgb[3])
{
    const vdbgi_volume_view view = vdbgi_volume_view_of(v);
    vdbgi_sampler_sample(&view, pos, rgb);
}

void vdbgi_volume_get_info(const vdbgi_volume *v, vdbgi_volume_info *info)
{
    *info = v->info;
}

void vdbgi_volume_destroy(vdbgi_volume *v)
{
    if (!v)
        return;
    vdbgi_context *const ctx = v->ctx;
    vdbgi_free(ctx, v->raw);
    vdbgi_free(ctx, v->file);
    vdbgi_field_free(&v->filled);
    vdbgi_free(ctx, v);
}

/* Atlas slots per axis: near-cubic, each at most 256 (a slot coordinate is one byte). */
static vdbgi_result pack_atlas(vdbgi_context *ctx, size_t slots, uint32_t dims[3])
{
    uint32_t sx = (uint32_t)ceil(cbrt((double)slots));
    sx = sx > 256 ? 256 : sx;
    uint32_t sy = (uint32_t)ceil(sqrt((double)slots / sx));
    sy = sy > 256 ? 256 : sy;
    const uint64_t sz = (slots + (uint64_t)sx * sy - 1) / ((uint64_t)sx * sy);
    VDBGI_FAIL_IF(ctx, sz > 256, VDBGI_ERR_OUT_OF_MEMORY,
                  "%zu bricks do not fit an atlas of 256^3 slots (%d texels a side): raise eps or "
                  "the probe spacing",
                  slots, 256 * VDBGI_BRICK_PADDED);
    dims[0] = sx * VDBGI_BRICK_PADDED;
    dims[1] = sy * VDBGI_BRICK_PADDED;
    dims[2] = (uint32_t)sz * VDBGI_BRICK_PADDED;
    return VDBGI_OK;
}

/* k-th smallest of a (reorders a); deterministic quickselect. */
static double select_kth(double *a, size_t n, size_t k)
{
    size_t lo = 0, hi = n - 1;
    while (lo < hi) {
        const double pivot = a[lo + (hi - lo) / 2];
        size_t i = lo, j = hi;
        while (i <= j) {
            while (a[i] < pivot)
                i++;
            while (a[j] > pivot)
                j--;
            if (i <= j) {
                const double t = a[i];
                a[i] = a[j], a[j] = t;
                i++;
                if (j == 0)
                    break;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break;
    }
    return a[k];
}

/* The shader's view of every valid probe against its value (which the fill kept). */
static vdbgi_result measure_error(vdbgi_volume *v, const vdbgi_probes *p)
{
    vdbgi_volume_info *const info = &v->info;
    double *const err = vdbgi_calloc(v->ctx, info->valid_count ? info->valid_count : 1,
                                     sizeof(double));
    if (!err)
        return VDBGI_ERR_OUT_OF_MEMORY;
    const vdbgi_volume_view view = vdbgi_volume_view_of(v);
    double sq = 0.0, worst = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < p->count; i++) {
        if (p->backface[i] > p->invalid_threshold)
            continue;
        float pos[3], got[3];
        for (int k = 0; k < 3; k++)
            pos[k] = (float)(v->lattice_origin[k] + p->spacing * p->ijk[3 * i + k]);
        vdbgi_sampler_sample(&view, pos, got);
        double e = 0.0;
        for (int k = 0; k < 3; k++) {
            const double d = (double)got[k] - (double)p->rgb[3 * i + k];
            sq += d * d;
            e = fmax(e, fabs(d));
        }
        err[n++] = e;
        worst = fmax(worst, e);
    }
    info->rmse = n ? sqrt(sq / (3.0 * (double)n)) : 0.0;
    info->max_error = worst;
    info->p99 = n ? select_kth(err, n, (size_t)floor(0.99 * (double)(n - 1))) : 0.0;
    vdbgi_free(v->ctx, err);
    return VDBGI_OK;
}

/* Encode a brick into its atlas slot; returns how many texels clamped. */
static size_t encode_brick(const vdbgi_volume *v, float s[6][6][6][3], uint32_t slot)
{
    size_t clamped_count = 0;
    const uint32_t *const d = v->info.atlas_dims;
    const uint32_t sx = d[0] / VDBGI_BRICK_PADDED, sy = d[1] / VDBGI_BRICK_PADDED;
    const uint32_t base[3] = {(slot % sx) * VDBGI_BRICK_PADDED,
                              (slot / sx % sy) * VDBGI_BRICK_PADDED,
                              (slot / (sx * sy)) * VDBGI_BRICK_PADDED};
    for (uint32_t z = 0; z < 6; z++)
        for (uint32_t y = 0; y < 6; y++)
            for (uint32_t x = 0; x < 6; x++) {
                const size_t t = ((size_t)(base[2] + z) * d[1] + base[1] + y) * d[0] + base[0] + x;
                uint8_t *const out = &v->atlas[4 * t];
                bool clamped;
                if (v->info.encoding == VDBGI_ENCODING_RGB9E5) {
                    uint32_t w;
                    clamped = vdbgi_rgb9e5_encode(s[z][y][x], &w);
                    out[0] = (uint8_t)w, out[1] = (uint8_t)(w >> 8);
                    out[2] = (uint8_t)(w >> 16), out[3] = (uint8_t)(w >> 24);
                } else {
                    clamped = vdbgi_rgbm_encode(s[z][y][x], v->info.rgbm_range, out);
                }
                clamped_count += clamped;
            }
    return clamped_count;
}

/* Point every level-0 cell a brick covers at that brick's slot and level. */
static void mark_indirection(const vdbgi_volume *v, const kept_brick *k, uint32_t slot)
{
    const uint32_t *const d = v->info.indirection_dims;
    const uint32_t sx = v->info.atlas_dims[0] / VDBGI_BRICK_PADDED;
    const uint32_t sy = v->info.atlas_dims[1] / VDBGI_BRICK_PADDED;
    const uint8_t texel[4] = {(uint8_t)(slot % sx), (uint8_t)(slot / sx % sy),
                              (uint8_t)(slot / (sx * sy)), (uint8_t)(k->level + 1)};
    const int32_t span = 1 << k->level;
    int32_t lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = k->key[a] * span - v->origin_cell[a];
        hi[a] = lo[a] + span;
        lo[a] = lo[a] < 0 ? 0 : lo[a];
        hi[a] = hi[a] > (int32_t)d[a] ? (int32_t)d[a] : hi[a];
    }
    for (int32_t z = lo[2]; z < hi[2]; z++)
        for (int32_t y = lo[1]; y < hi[1]; y++)
            for (int32_t x = lo[0]; x < hi[0]; x++)
                memcpy(&v->indirection[4 * (((size_t)z * d[1] + (size_t)y) * d[0] + (size_t)x)],
                       texel, 4);
}

typedef struct atlas_job {
    const builder *b;
    size_t begin, end; /* kept bricks [begin, end) */
    size_t fallbacks, clamped;
} atlas_job;

static void *atlas_worker(void *arg)
{
    atlas_job *const job = arg;
    const builder *const b = job->b;
    for (size_t i = job->begin; i < job->end; i++) {
        const kept_brick *const k = &b->kept[i];
        float s[6][6][6][3];
        job->fallbacks += brick_samples(b, k->key, k->level, s);
        job->clamped += encode_brick(b->vol, s, (uint32_t)i + 1);
        mark_indirection(b->vol, k, (uint32_t)i + 1);
    }
    return NULL;
}

/*
 * Sample, encode and point at every kept brick, over all cores: bricks own
 * disjoint slots and cells, so the result does not depend on the split.
 */
static vdbgi_result fill_atlas(builder *b)
{
    enum { MAX_JOBS = 64 };
    atlas_job jobs[MAX_JOBS];
    int n = b->threads;
    n = n > MAX_JOBS ? MAX_JOBS : n;
    memset(jobs, 0, sizeof(jobs));
    for (int t = 0; t < n; t++) {
        jobs[t].b = b;
        jobs[t].begin = b->kept_count * (size_t)t / (size_t)n;
        jobs[t].end = b->kept_count * (size_t)(t + 1) / (size_t)n;
    }
    vdbgi_run_threads(n, atlas_worker, jobs, sizeof(jobs[0]));
    for (int t = 0; t < n; t++) {
        b->vol->info.fallback_count += jobs[t].fallbacks;
        b->vol->info.clamped_count += jobs[t].clamped;
    }
    return VDBGI_OK;
}

/*
 * Coarsen every root block over all cores. Roots are handed out one at a
 * time; each writes its bricks into its own region of b->kept, and the
 * regions are joined in z, y, x order of the roots afterwards, so the brick
 * order, hence the file, does not depend on the threads.
 */
typedef struct coarsen_job {
    const builder *b;
    const int32_t (*roots)[3];
    builder *parts; /* one per root: the builder with that root's region as kept */
    size_t count;
    atomic_size_t *next;
    vdbgi_result result;
} coarsen_job;

static void *coarsen_worker(void *arg)
{
    coarsen_job *const job = arg;
    for (size_t i; job->result == VDBGI_OK && (i = atomic_fetch_add(job->next, 1)) < job->count;)
        job->result = visit(&job->parts[i], job->roots[i], job->b->max_level);
    return NULL;
}

static vdbgi_result coarsen(builder *b)
{
    vdbgi_context *const ctx = b->ctx;
    const level_map *const top = &b->levels[b->max_level], *const cells = &b->levels[0];
    const size_t n = top->count;
    int32_t(*roots)[3] = vdbgi_calloc(ctx, n ? n : 1, sizeof(*roots));
    size_t *const cells_under = vdbgi_calloc(ctx, n ? n : 1, sizeof(size_t)); /* by top index */
    builder *const parts = vdbgi_calloc(ctx, n ? n : 1, sizeof(*parts));
    b->kept = vdbgi_calloc(ctx, cells->count ? cells->count : 1, sizeof(*b->kept));
    vdbgi_result r = VDBGI_OK;
    if (!roots || !cells_under || !parts || !b->kept) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto done;
    }
    /* Each root's region: as many bricks as it has level-0 cells, roots in z, y, x order. */
    memcpy(roots, top->keys, n * sizeof(*roots));
    qsort(roots, n, sizeof(*roots), compare_keys);
    for (size_t c = 0; c < cells->count; c++) {
        int32_t root[3];
        for (int k = 0; k < 3; k++)
            root[k] = vdbgi_floor_div(cells->keys[c][k], 1 << b->max_level);
        const long ti = map_find(top, root);
        if (ti >= 0) /* always: the pyramid holds every cell's ancestors */
            cells_under[ti]++;
    }
    size_t sum = 0;
    for (size_t i = 0; i < n; i++) {
        const size_t count = cells_under[map_find(top, roots[i])]; /* roots are top's keys */
        parts[i] = *b;
        parts[i].kept = b->kept + sum;
        parts[i].kept_count = 0;
        parts[i].kept_capacity = count;
        sum += count;
    }
    enum { MAX_JOBS = 64 };
    coarsen_job jobs[MAX_JOBS];
    atomic_size_t next = 0;
    int t_count = b->threads;
    t_count = t_count > MAX_JOBS ? MAX_JOBS : t_count;
    for (int t = 0; t < t_count; t++)
        jobs[t] = (coarsen_job){.b = b, .roots = (const int32_t(*)[3])roots, .parts = parts,
                                .count = n, .next = &next};
    vdbgi_run_threads(t_count, coarsen_worker, jobs, sizeof(jobs[0]));
    for (int t = 0; t < t_count && r == VDBGI_OK; t++)
        r = jobs[t].result;
    /* Join the regions in root order. */
    b->kept_count = 0;
    for (size_t i = 0; r == VDBGI_OK && i < n; i++) {
        memmove(b->kept + b->kept_count, parts[i].kept, parts[i].kept_count * sizeof(*b->kept));
        b->kept_count += parts[i].kept_count;
    }
done:
    vdbgi_free(ctx, roots);
    vdbgi_free(ctx, cells_under);
    vdbgi_free(ctx, parts);
    return r;
}

static int report(const vdbgi_convert_desc *desc, float done)
{
    return desc && desc->progress ? desc->progress(desc->progress_user, done) : 0;
}

vdbgi_result vdbgi_volume_build(vdbgi_context *ctx, const vdbgi_probes *probes,
                                const vdbgi_convert_desc *desc, vdbgi_volume **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_FAIL_IF(ctx, !probes, VDBGI_ERR_INVALID_ARG, "no probes given");
    const double t0 = vdbgi_now();
    builder b = {.ctx = ctx, .probes = probes};
    float eps = 0.0f;
    vdbgi_encoding encoding = VDBGI_ENCODING_RGBM;
    VDBGI_TRY(resolve_desc(ctx, desc, &eps, &b.sigmas, &b.max_level, &b.criterion, &encoding,
                         &b.threads));
    /*
     * A fixed Fibonacci set gives every probe the same directions: its error is a bias
     * shared by neighbours, not noise, and its standard error is no measure of it. The
     * default allowance applies to random and adaptive bakes only.
     */
    const vdbgi_meta *const sampling = vdbgi_meta_find(probes, "sampling");
    const vdbgi_meta *const rays_meta = vdbgi_meta_find(probes, "rays");
    const bool fixed_set = sampling && sampling->type == VDBGI_META_STRING &&
                           strcmp(sampling->text, "fibonacci") == 0 &&
                           !(rays_meta && rays_meta->type == VDBGI_META_INT &&
                             rays_meta->i == VDBGI_RAYS_AUTO);
    if (fixed_set && (!desc || desc->noise_sigmas == 0.0f))
        b.sigmas = 0.0f;
    VDBGI_FAIL_IF(ctx, !probes->rgb, VDBGI_ERR_FORMAT, "probes have no values: bake them first");
    VDBGI_FAIL_IF(ctx, probes->count == 0, VDBGI_ERR_FORMAT, "the grid holds no probes");

    vdbgi_volume *const v = vdbgi_calloc(ctx, 1, sizeof(*v));
    if (!v)
        return VDBGI_ERR_OUT_OF_MEMORY;
    v->ctx = ctx;
    vdbgi_volume_info *const info = &v->info;
    info->encoding = encoding;
    info->rgbm_range = VDBGI_RGBM_RANGE;
    info->spacing = (float)probes->spacing;
    info->max_level = (uint32_t)b.max_level;
    info->probe_count = probes->count;
    memcpy(v->lattice_origin, probes->origin, sizeof(v->lattice_origin));

    /* Mean irradiance of the valid probes: the scale of eps and of the error figures. */
    double sum[3] = {0.0, 0.0, 0.0};
    for (size_t i = 0; i < probes->count; i++) {
        if (probes->backface[i] > probes->invalid_threshold)
            continue;
        info->valid_count++;
        for (int k = 0; k < 3; k++)
            sum[k] += probes->rgb[3 * i + k];
    }
    for (int k = 0; k < 3; k++)
        v->mean_rgb[k] = info->valid_count ? (float)(sum[k] / (double)info->valid_count) : 0.0f;
    info->mean_irradiance = (v->mean_rgb[0] + v->mean_rgb[1] + v->mean_rgb[2]) / 3.0;
    b.tolerance = eps * (float)info->mean_irradiance;
    b.vol = v;

    int32_t *cells = NULL;
    size_t cell_count = 0;
    const vdbgi_fill_params fp =
        vdbgi_fill_params_default(probes->invalid_threshold, desc ? desc->fill : VDBGI_FILL_AUTO,
                                  b.threads);
    const vdbgi_fill_input in = {probes->count, probes->ijk, probes->rgb, probes->backface, 1};
    vdbgi_result r = vdbgi_field_fill(ctx, &in, &fp, &v->filled, &cells, &cell_count,
                                      &info->unreached_count);
    if (r != VDBGI_OK)
        goto fail;
    for (size_t li = 0; li < v->filled.leaf_count; li++)
        for (int w = 0; w < 8; w++)
            info->filled_count += (size_t)__builtin_popcountll(v->filled.leaves[li].mask[w]);
    double t1 = vdbgi_now();
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "fill: %zu points in %.3f s", info->filled_count, t1 - t0);
    if (report(desc, 0.3f)) {
        r = vdbgi_fail(ctx, VDBGI_ERR_CANCELLED, "conversion cancelled");
        goto fail;
    }

    /* The indirection covers the occupied cells from a corner aligned to level-3 blocks. */
    int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
    for (size_t c = 0; c < cell_count; c++)
        for (int k = 0; k < 3; k++) {
            lo[k] = cells[3 * c + k] < lo[k] ? cells[3 * c + k] : lo[k];
            hi[k] = cells[3 * c + k] > hi[k] ? cells[3 * c + k] : hi[k];
        }
    for (int k = 0; k < 3; k++) {
        v->origin_cell[k] = vdbgi_floor_div(lo[k], 8) * 8;
        const int64_t dim = (int64_t)hi[k] - v->origin_cell[k] + 1;
        if (dim > VDBGI_MAX_TEXTURE_DIM) {
            r = vdbgi_fail(ctx, VDBGI_ERR_OUT_OF_MEMORY,
                           "the indirection texture would be %lld cells along %c, above the "
                           "%d-texel limit of 3D textures: raise the probe spacing",
                           (long long)dim, "xyz"[k], VDBGI_MAX_TEXTURE_DIM);
            goto fail;
        }
        info->indirection_dims[k] = (uint32_t)dim;
        info->box_min[k] = (float)(v->lattice_origin[k] +
                                   probes->spacing * ((double)v->origin_cell[k] * VDBGI_BRICK - 0.5));
        info->box_max[k] = (float)(info->box_min[k] + probes->spacing * (double)dim * VDBGI_BRICK);
    }

    if ((r = build_pyramid(&b, cells, cell_count)) != VDBGI_OK)
        goto fail;
    if ((r = coarsen(&b)) != VDBGI_OK)
        goto fail;
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "pyramid and coarsening: %zu bricks in %.3f s", b.kept_count,
              vdbgi_now() - t1);
    t1 = vdbgi_now();
    if (report(desc, 0.6f)) {
        r = vdbgi_fail(ctx, VDBGI_ERR_CANCELLED, "conversion cancelled");
        goto fail;
    }

    /* Slot 0 is an all-zero brick: an empty cell (indirection 0,0,0,0) reads black from it. */
    const size_t slots = b.kept_count + 1;
    if ((r = pack_atlas(ctx, slots, info->atlas_dims)) != VDBGI_OK)
        goto fail;
    info->brick_count = (uint32_t)b.kept_count;
    info->indirection_size = 4 * (size_t)info->indirection_dims[0] * info->indirection_dims[1] *
                             info->indirection_dims[2];
    info->atlas_size =
        4 * (size_t)info->atlas_dims[0] * info->atlas_dims[1] * info->atlas_dims[2];
    if ((r = vdbgi_gifile_alloc(v)) != VDBGI_OK)
        goto fail;
    if ((r = fill_atlas(&b)) != VDBGI_OK)
        goto fail;
    for (size_t i = 0; i < b.kept_count; i++)
        info->bricks[b.kept[i].level]++;
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "sampling and encoding: %.3f s", vdbgi_now() - t1);
    t1 = vdbgi_now();
    if (report(desc, 0.8f)) {
        r = vdbgi_fail(ctx, VDBGI_ERR_CANCELLED, "conversion cancelled");
        goto fail;
    }

    /* A dense RGBA8 grid over the probes' box at the same spacing, for comparison. */
    {
        int32_t pmin[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, pmax[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
        for (size_t i = 0; i < probes->count; i++)
            for (int k = 0; k < 3; k++) {
                const int32_t c = probes->ijk[3 * i + k];
                pmin[k] = c < pmin[k] ? c : pmin[k];
                pmax[k] = c > pmax[k] ? c : pmax[k];
            }
        info->dense_rgba8_size = 4;
        for (int k = 0; k < 3; k++)
            info->dense_rgba8_size *= (size_t)(pmax[k] - pmin[k] + 1);
    }
    if ((r = measure_error(v, probes)) != VDBGI_OK)
        goto fail;
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "error measurement: %.3f s", vdbgi_now() - t1);
    t1 = vdbgi_now();
    if ((r = vdbgi_gifile_encode(v)) != VDBGI_OK)
        goto fail;
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "gzip: %zu bytes in %.3f s", info->file_size, vdbgi_now() - t1);
    info->seconds = vdbgi_now() - t0;
    report(desc, 1.0f);
fail:
    vdbgi_free(ctx, cells);
    for (int l = 0; l < 4; l++)
        map_free(ctx, &b.levels[l]);
    vdbgi_free(ctx, b.kept);
    if (r != VDBGI_OK) {
        vdbgi_volume_destroy(v);
        return r;
    }
    *out = v;
    return VDBGI_OK;
}
