/*
 * packed.c: the compact layout's file, version 5 (docs/format.md, "Version
 * 5"), and where the converter puts its bricks in the atlas. The runtime atlas repeats a
 * brick's border plane wherever its neighbour lies elsewhere, and holds
 * stitched values any reader can recompute; the file keeps neither. It
 * stores one level byte a cell, each brick's first atlas texel, then each
 * lattice point some brick reads unstitched, once, in owner-cell order, as
 * four planes of residuals against a prediction from its neighbours.
 * This file makes the plan: the placement read (and checked) or made, the
 * stitches; pack_rebuild.c fills the atlas by it. The converter builds its
 * own textures through the reader's code, so what it measures is what a
 * reader gets.
 */
#include "gifile.h"
#include "pack_common.h"
#include "util.h"

#include <string.h>

/* Could any face of brick b touch a coarser brick? Not if no cell around its block is coarser. */
static bool near_coarser(const vdbgi_pack_plan *pl, size_t b)
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
                const int32_t j = pl->cell_brick[cell_index(d, c)];
                if (j >= 0 && pl->level[j] > pl->level[b])
                    return true;
            }
    return false;
}

static void find_stitches(vdbgi_pack_plan *pl, size_t b)
{
    memset(pl->stitch[b], 0, sizeof(pl->stitch[b]));
    if (!near_coarser(pl, b))
        return;
    for (int t = 0; t < TEXELS; t++) {
        const int q[3] = {t % N, t / N % N, t / (N * N)};
        if (q[0] % 4 && q[1] % 4 && q[2] % 4)
            continue; /* inside: only faces meet other bricks */
        int32_t p[3];
        size_t j;
        int cl;
        texel_point(pl, b, t, p);
        if (coarser_brick_at(pl, p, pl->level[b], &j, &cl))
            pl->stitch[b][t >> 5] |= 1u << (t & 31);
    }
}

void vdbgi_pack_plan_free(vdbgi_context *ctx, vdbgi_pack_plan *pl)
{
    vdbgi_free(ctx, pl->key);
    vdbgi_free(ctx, pl->level);
    vdbgi_free(ctx, pl->origin);
    vdbgi_free(ctx, pl->cell_brick);
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

/* The cells a brick covers, clipped to the indirection. */
static void brick_cells(const vdbgi_pack_plan *pl, size_t b, int32_t lo[3], int32_t hi[3])
{
    const int32_t span = 1 << pl->level[b];
    for (int k = 0; k < 3; k++) {
        lo[k] = pl->key[b][k] * span;
        hi[k] = lo[k] + span < (int32_t)pl->dims[k] ? lo[k] + span : (int32_t)pl->dims[k];
    }
}

/*
 * Point every cell a brick covers at the brick's atlas texel and level: r, g, b the
 * texel / 4 per axis, a the level in bits 0-1 and texel mod 4 per axis in
 * bits 2-3 (x), 4-5 (y), 6-7 (z). An empty cell stays 0, 0, 0, 0: level 0
 * at the atlas's corner, where a block of zeros lies.
 */
static void mark_indirection(vdbgi_volume *v, const vdbgi_pack_plan *pl, size_t cells)
{
    for (size_t c = 0; c < cells; c++) {
        const int32_t b = pl->cell_brick[c];
        if (b < 0)
            continue;
        const uint16_t *const o = pl->origin[b];
        uint8_t *const t = &v->tex.indirection[4 * c];
        t[0] = (uint8_t)(o[0] >> 2);
        t[1] = (uint8_t)(o[1] >> 2);
        t[2] = (uint8_t)(o[2] >> 2);
        t[3] = (uint8_t)(pl->level[b] | (o[0] & 3) << 2 | (o[1] & 3) << 4 | (o[2] & 3) << 6);
    }
}

/* ---- a reader's placement: the file's table, checked ---------------------------------------- */

/*
 * Each brick's first texel from the file's table (three arrays of u16: x of
 * every brick, then y, then z). A brick lies inside the atlas, in a layer
 * (its y a multiple of 5). The atlas's own bound, VDBGI_ATLAS_TEXELS_PER_BRICK
 * texels a brick, is the header's (gifile.c), checked before this is reached.
 */
static vdbgi_result read_placement(vdbgi_context *ctx, vdbgi_pack_plan *pl, const uint8_t *table,
                                   const uint32_t dims[3], const char *name)
{
    const size_t n = pl->brick_count;
    for (size_t b = 0; b < n; b++) {
        for (int k = 0; k < 3; k++)
            pl->origin[b][k] = (uint16_t)vdbgi_get_u16(table + 2 * (k * n + b));
        const uint16_t *const o = pl->origin[b];
        VDBGI_FAIL_IF(ctx,
                      o[0] + N > (int64_t)dims[0] || o[1] + N > (int64_t)dims[1] ||
                          o[2] + N > (int64_t)dims[2] || o[1] % N,
                      VDBGI_ERR_FORMAT,
                      "%s: brick %zu at texel %u,%u,%u is not in a layer of the %ux%ux%u atlas",
                      name, b, o[0], o[1], o[2], dims[0], dims[1], dims[2]);
    }
    return VDBGI_OK;
}

/*
 * Two bricks may share texels only where they hold the same lattice points:
 * both of one level, at the same offset from their block index (origin - 4
 * key). None covers the block of zeros that empty cells read. Bricks of
 * different layers share nothing, so each layer is checked on its own, in a
 * map of its texels holding the first brick to claim each; threads take
 * runs of layers.
 */
typedef struct overlap_job {
    const vdbgi_pack_plan *pl;
    const uint32_t *dims, *by_layer, *layer_first; /* bricks in layer order; layer l's first */
    uint32_t l0, l1;
    uint32_t *owner; /* one layer's texels; NULL: out of memory */
    size_t bad;      /* the first brick (in layer order) that overlaps wrongly, or SIZE_MAX */
    int texel;       /* and its texel */
} overlap_job;

static void *overlap_worker(void *arg)
{
    overlap_job *const job = arg;
    const vdbgi_pack_plan *const pl = job->pl;
    const uint32_t *const d = job->dims;
    const size_t layer_texels = (size_t)d[0] * N * d[2];
    for (uint32_t l = job->l0; l < job->l1 && job->bad == SIZE_MAX && job->owner; l++) {
        memset(job->owner, 0, layer_texels * sizeof(*job->owner));
        for (int t = 0; l == 0 && t < TEXELS; t++) /* the block of zeros */
            job->owner[((size_t)(t / (N * N)) * N + t / N % N) * d[0] + t % N] = UINT32_MAX;
        for (uint32_t n = job->layer_first[l]; n < job->layer_first[l + 1]; n++) {
            const uint32_t b = job->by_layer[n];
            const uint16_t *const o = pl->origin[b];
            for (int t = 0; t < TEXELS && job->bad == SIZE_MAX; t++) {
                uint32_t *const w =
                    &job->owner[((size_t)(o[2] + t / (N * N)) * N + t / N % N) * d[0] + o[0] +
                                t % N];
                const uint32_t j = *w ? *w - 1 : b;
                bool same = j != UINT32_MAX - 1 && pl->level[j] == pl->level[b];
                for (int k = 0; k < 3 && same; k++)
                    same = pl->origin[j][k] - 4 * pl->key[j][k] == o[k] - 4 * pl->key[b][k];
                *w = *w ? *w : b + 1;
                if (!same)
                    job->bad = b, job->texel = t;
            }
            if (job->bad != SIZE_MAX)
                break;
        }
    }
    return NULL;
}

static vdbgi_result check_overlaps(vdbgi_context *ctx, const vdbgi_pack_plan *pl,
                                   const uint32_t dims[3], const char *name, int threads)
{
    const uint32_t layers = dims[1] / N;
    uint32_t *const first = vdbgi_calloc(ctx, (size_t)layers + 1, sizeof(*first));
    uint32_t *const by_layer = vdbgi_alloc(ctx, (pl->brick_count + 1) * sizeof(*by_layer));
    overlap_job jobs[MAX_JOBS];
    int nt = job_count(threads);
    nt = (uint32_t)nt > layers ? (int)layers : nt;
    vdbgi_result r = first && by_layer ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    for (int t = 0; t < nt; t++) {
        jobs[t] = (overlap_job){.pl = pl,
                                .dims = dims,
                                .by_layer = by_layer,
                                .layer_first = first,
                                .l0 = (uint32_t)((uint64_t)layers * t / nt),
                                .l1 = (uint32_t)((uint64_t)layers * (t + 1) / nt),
                                .bad = SIZE_MAX};
        jobs[t].owner = vdbgi_alloc(ctx, (size_t)dims[0] * N * dims[2] * sizeof(uint32_t));
        r = jobs[t].owner ? r : VDBGI_ERR_OUT_OF_MEMORY;
    }
    if (r == VDBGI_OK) { /* a counting sort by layer, in brick order within one */
        for (size_t b = 0; b < pl->brick_count; b++)
            first[pl->origin[b][1] / N + 1]++;
        for (uint32_t l = 0; l < layers; l++)
            first[l + 1] += first[l];
        for (size_t b = 0; b < pl->brick_count; b++)
            by_layer[first[pl->origin[b][1] / N]++] = (uint32_t)b;
        for (uint32_t l = layers; l > 0; l--)
            first[l] = first[l - 1];
        first[0] = 0;
        vdbgi_run_threads(nt, overlap_worker, jobs, sizeof(jobs[0]));
    }
    for (int t = 0; t < nt; t++) {
        const overlap_job *const job = &jobs[t];
        if (r == VDBGI_OK && job->bad != SIZE_MAX) {
            const uint16_t *const o = pl->origin[job->bad];
            const int q = job->texel;
            const size_t i =
                ((size_t)(o[2] + q / (N * N)) * N + q / N % N) * dims[0] + o[0] + q % N;
            r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: brick %zu overlaps %s at texel %u,%u,%u",
                           name, job->bad,
                           job->owner[i] == UINT32_MAX ? "the block of zeros"
                                                       : "another brick's points",
                           o[0] + q % N, o[1] + q / N % N, o[2] + q / (N * N));
        }
        vdbgi_free(ctx, job->owner);
    }
    vdbgi_free(ctx, first);
    vdbgi_free(ctx, by_layer);
    return r;
}

/* Bricks b0 <= b < b1: their stitched texels, then their stored points in the mask. */
typedef struct points_job {
    vdbgi_pack_plan *pl;
    size_t b0, b1;
} points_job;

static void *points_worker(void *arg)
{
    const points_job *const job = arg;
    vdbgi_pack_plan *const pl = job->pl;
    for (size_t b = job->b0; b < job->b1; b++) {
        find_stitches(pl, b);
        for (int t = 0; t < TEXELS; t++) {
            size_t j;
            int cl;
            if (stitched(pl, b, t, &j, &cl))
                continue;
            int32_t p[3];
            size_t c;
            int bit;
            texel_point(pl, b, t, p);
            /* Neighbouring bricks share points, and cells: OR the bit in atomically. */
            if (grid_slot(pl, p, &c, &bit))
                __atomic_fetch_or(&pl->mask[c], UINT64_C(1) << bit, __ATOMIC_RELAXED);
        }
    }
    return NULL;
}

vdbgi_result vdbgi_pack_plan_make(vdbgi_volume *v, const uint8_t *levels, const uint8_t *placement,
                                  const vdbgi_volume_info *expect, const char *name, int threads,
                                  vdbgi_pack_plan *pl)
{
    vdbgi_context *const ctx = v->ctx;
    vdbgi_volume_info *const info = &v->info;
    memset(pl, 0, sizeof(*pl));
    size_t grid_cells = 1, cells = 1;
    for (int k = 0; k < 3; k++) {
        pl->dims[k] = info->ind_dims[k];
        pl->grid[k] = pl->dims[k] + PAD;
        grid_cells *= pl->grid[k];
        cells *= pl->dims[k];
    }
    /* Count, check, then list: the bricks' arrays are sized by what the levels hold. */
    VDBGI_TRY(scan_bricks(ctx, pl->dims, levels, info->max_level, name, pl));
    const size_t count = pl->brick_count;
    /* A reader's header must count these bricks before anything is allocated for them. */
    for (int l = 0; expect && l < 4; l++)
        VDBGI_FAIL_IF(ctx, expect->bricks[l] != pl->per_level[l], VDBGI_ERR_FORMAT,
                      "%s: bricks[%d] says %u, the level bytes hold %u", name, l, expect->bricks[l],
                      pl->per_level[l]);
    pl->key = vdbgi_alloc(ctx, (count ? count : 1) * sizeof(*pl->key));
    pl->level = vdbgi_alloc(ctx, count ? count : 1);
    pl->origin = vdbgi_alloc(ctx, (count ? count : 1) * sizeof(*pl->origin));
    pl->cell_brick = vdbgi_alloc(ctx, cells * sizeof(*pl->cell_brick));
    pl->stitch = vdbgi_alloc(ctx, (count ? count : 1) * sizeof(*pl->stitch));
    pl->mask = vdbgi_calloc(ctx, grid_cells, sizeof(*pl->mask));
    pl->offset = vdbgi_alloc(ctx, grid_cells * sizeof(*pl->offset));
    if (!pl->key || !pl->level || !pl->origin || !pl->cell_brick || !pl->stitch || !pl->mask ||
        !pl->offset) {
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
    for (size_t c = 0; c < cells; c++)
        pl->cell_brick[c] = -1;
    for (size_t b = 0; b < count; b++) {
        int32_t lo[3], hi[3];
        brick_cells(pl, b, lo, hi);
        for (int32_t z = lo[2]; z < hi[2]; z++)
            for (int32_t y = lo[1]; y < hi[1]; y++)
                for (int32_t x = lo[0]; x < hi[0]; x++) {
                    const int32_t c[3] = {x, y, z};
                    pl->cell_brick[cell_index(pl->dims, c)] = (int32_t)b;
                }
    }
    vdbgi_result r = placement ? read_placement(ctx, pl, placement, info->atlas_dims, name)
                               : vdbgi_pack_place(ctx, pl, info->atlas_dims);
    info->atlas_size = 4 * (size_t)info->atlas_dims[0] * info->atlas_dims[1] * info->atlas_dims[2];
    if (r == VDBGI_OK)
        r = vdbgi_textures_alloc(ctx, &v->tex, info->ind_dims, info->atlas_dims);
    if (r == VDBGI_OK && placement)
        r = check_overlaps(ctx, pl, info->atlas_dims, name, threads);
    if (r != VDBGI_OK) {
        vdbgi_pack_plan_free(ctx, pl);
        return r;
    }
    mark_indirection(v, pl, cells);
    /* The stored points: every texel no stitching overwrites, over ranges of bricks. */
    points_job jobs[MAX_JOBS];
    const int nt = job_count(threads);
    for (int t = 0; t < nt; t++)
        jobs[t] = (points_job){.pl = pl,
                               .b0 = count * (size_t)t / (size_t)nt,
                               .b1 = count * (size_t)(t + 1) / (size_t)nt};
    vdbgi_run_threads(nt, points_worker, jobs, sizeof(jobs[0]));
    size_t sum = 0;
    for (size_t c = 0; c < grid_cells; c++) {
        pl->offset[c] = (uint32_t)sum;
        sum += (size_t)__builtin_popcountll(pl->mask[c]);
    }
    pl->points = sum;
    return VDBGI_OK;
}
