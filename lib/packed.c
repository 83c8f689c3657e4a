/*
 * packed.c: the compact layout's file, version 5 (docs/format.md, "Version
 * 5"), and where the converter puts its bricks in the atlas. The runtime atlas repeats a
 * brick's border plane wherever its neighbour lies elsewhere, and holds
 * stitched values any reader can recompute; the file keeps neither. It
 * stores one level byte a cell, each brick's first atlas texel, then each
 * lattice point some brick reads unstitched, once, in owner-cell order, as
 * four planes of residuals against a prediction from its neighbours.
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

/* Threads a pass runs on: what was asked, 1 to MAX_JOBS (vdbgi_run_threads' bound). */
enum { MAX_JOBS = 64 };
static int job_count(int threads)
{
    return threads > MAX_JOBS ? MAX_JOBS : threads < 1 ? 1 : threads;
}

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
 * Cell c of the up to eight that touch lattice point p: the cell holding p,
 * one down along axis k where bit k of c is set. False where p does not
 * touch it (p is not on that cell face) or it lies below cell 0.
 */
static bool touching_cell(const int32_t p[3], int c, int32_t cell[3])
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
static bool coarser_brick_at(const vdbgi_pack_plan *pl, const int32_t p[3], int level,
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
static bool stitched(const vdbgi_pack_plan *pl, size_t b, int t, size_t *coarse, int *coarse_level)
{
    if (!(pl->stitch[b][t >> 5] >> (t & 31) & 1u))
        return false;
    int32_t p[3];
    texel_point(pl, b, t, p);
    return coarser_brick_at(pl, p, pl->level[b], coarse, coarse_level);
}

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
        uint8_t *const t = &v->indirection[4 * c];
        t[0] = (uint8_t)(o[0] >> 2);
        t[1] = (uint8_t)(o[1] >> 2);
        t[2] = (uint8_t)(o[2] >> 2);
        t[3] = (uint8_t)(pl->level[b] | (o[0] & 3) << 2 | (o[1] & 3) << 4 | (o[2] & 3) << 6);
    }
}

/* ---- placement: slabs of neighbours sharing borders, packed in layers ------------------ */

/*
 * Same-level neighbours along x and z go into one slab, (4 kx + 1) x 5 x
 * (4 kz + 1) texels for kx x kz bricks: a brick's + border is its
 * neighbour's first plane, stored once. Slabs are packed into layers 5
 * texels tall, each a skyline over x (vdb-to-gi's choice; the file records it): within
 * 2-3 % of their own texels on the worlds of docs/converter.md.
 */
enum { SLAB_MAX = 8, ATLAS_MAX = 1024, LAYERS_MAX = ATLAS_MAX / N };

typedef struct slab {
    uint32_t first;  /* its brick at -x, -z */
    uint16_t w, d;   /* texels along x and z */
    uint16_t pos[3]; /* its first texel */
} slab;

/* The brick whose level-`level` block is `key`, or -1. */
static int32_t brick_with_key(const vdbgi_pack_plan *pl, const int32_t key[3], int level)
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

/* The brick at (i, 0, j) bricks from slab s's first, if it is free (or, with taken NULL, any). */
static int32_t slab_brick(const vdbgi_pack_plan *pl, const slab *s, int i, int j,
                          const uint8_t *taken)
{
    const int32_t *const k = pl->key[s->first];
    const int32_t key[3] = {k[0] + i, k[1], k[2] + j};
    const int32_t b = brick_with_key(pl, key, pl->level[s->first]);
    return b >= 0 && (!taken || !taken[b]) ? b : -1;
}

/* Grow a slab from each brick, in scan order, not in one yet: along +x, then whole rows along +z. */
static size_t make_slabs(const vdbgi_pack_plan *pl, uint8_t *taken, slab *out)
{
    size_t n = 0;
    for (size_t b = 0; b < pl->brick_count; b++) {
        if (taken[b])
            continue;
        slab s = {.first = (uint32_t)b};
        int kx = 1, kz = 1;
        while (kx < SLAB_MAX && slab_brick(pl, &s, kx, 0, taken) >= 0)
            kx++;
        for (bool row = true; row && kz < SLAB_MAX; kz += row) {
            for (int i = 0; i < kx && row; i++)
                row = slab_brick(pl, &s, i, kz, taken) >= 0;
        }
        for (int j = 0; j < kz; j++)
            for (int i = 0; i < kx; i++)
                taken[slab_brick(pl, &s, i, j, NULL)] = 1;
        s.w = (uint16_t)(4 * kx + 1);
        s.d = (uint16_t)(4 * kz + 1);
        out[n++] = s;
    }
    return n;
}

/* Deepest first, then widest, then in the order grown. */
static int slab_order(const void *pa, const void *pb)
{
    const slab *a = pa, *b = pb;
    if (a->d != b->d)
        return a->d > b->d ? -1 : 1;
    if (a->w != b->w)
        return a->w > b->w ? -1 : 1;
    return a->first < b->first ? -1 : a->first > b->first;
}

/* Where a w-wide slab lies lowest on skyline h (S wide, lowest point low): the leftmost such x; its z. */
static int lowest_fit(const uint16_t *h, int S, int w, int low, int *x)
{
    int queue[ATLAS_MAX], head = 0, tail = 0, best = INT32_MAX;
    /* A sliding maximum: queue holds the window's candidates, highest first. No
       window lies below the skyline's lowest point, so the first there is the answer. */
    for (int i = 0; i < S && best > low; i++) {
        while (tail > head && h[queue[tail - 1]] <= h[i])
            tail--;
        queue[tail++] = i;
        if (queue[head] <= i - w)
            head++;
        if (i >= w - 1 && h[queue[head]] < best) {
            best = h[queue[head]];
            *x = i - w + 1;
        }
    }
    return best;
}

/*
 * Pack the slabs (sorted) into `layers` layers S texels wide along x, each
 * with a skyline over x: each slab goes where it lies lowest (its z), the
 * first such layer, the leftmost x there. Layer 0 starts with the block of
 * zeros at its corner. False if the atlas would pass ATLAS_MAX along z.
 */
static bool pack_layers(slab *slabs, size_t n, int S, int layers, uint16_t *h, uint32_t dims[3])
{
    int low[LAYERS_MAX] = {0}; /* each skyline's lowest point */
    memset(h, 0, sizeof(*h) * (size_t)S * (size_t)layers);
    for (int i = 0; i < N; i++)
        h[i] = N;
    uint32_t x_end = N, z_end = N;
    for (size_t i = 0; i < n; i++) {
        slab *const s = &slabs[i];
        int best_l = 0, best_x = 0, best_z = INT32_MAX;
        for (int l = 0; l < layers; l++) {
            if (low[l] >= best_z)
                continue; /* it cannot lie lower there */
            int x = 0;
            const int z = lowest_fit(&h[(size_t)l * S], S, s->w, low[l], &x);
            if (z < best_z)
                best_z = z, best_x = x, best_l = l;
        }
        if (best_z + s->d > ATLAS_MAX)
            return false;
        uint16_t *const row = &h[(size_t)best_l * S];
        for (int k = best_x; k < best_x + s->w; k++)
            row[k] = (uint16_t)(best_z + s->d);
        low[best_l] = INT32_MAX;
        for (int k = 0; k < S; k++)
            low[best_l] = row[k] < low[best_l] ? row[k] : low[best_l];
        s->pos[0] = (uint16_t)best_x;
        s->pos[1] = (uint16_t)(N * best_l);
        s->pos[2] = (uint16_t)best_z;
        x_end = (uint32_t)(best_x + s->w) > x_end ? (uint32_t)(best_x + s->w) : x_end;
        z_end = (uint32_t)(best_z + s->d) > z_end ? (uint32_t)(best_z + s->d) : z_end;
    }
    dims[0] = x_end;
    dims[1] = (uint32_t)(N * layers);
    dims[2] = z_end;
    return true;
}

/* Layers enough to hold area texels (x by z) at S x S each, at most LAYERS_MAX. */
static int layers_for(uint64_t area, uint64_t S)
{
    const uint64_t l = (area + S * S - 1) / (S * S);
    return l < 1 ? 1 : l > LAYERS_MAX ? LAYERS_MAX : (int)l;
}

/*
 * Every brick's atlas texel, and the atlas's size: S is the cube root of the
 * slabs' texels (at least the widest slab), the layers as many as their area
 * fills at S x S; if that passes 1024 texels along z, S = 1024.
 */
static vdbgi_result place_bricks(vdbgi_context *ctx, vdbgi_pack_plan *pl, uint32_t dims[3])
{
    const size_t count = pl->brick_count;
    uint8_t *const taken = vdbgi_calloc(ctx, count ? count : 1, 1);
    slab *const slabs = vdbgi_alloc(ctx, (count ? count : 1) * sizeof(*slabs));
    uint16_t *const h = vdbgi_alloc(ctx, sizeof(*h) * ATLAS_MAX * LAYERS_MAX);
    vdbgi_result r = VDBGI_OK;
    if (!taken || !slabs || !h) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto done;
    }
    const size_t n = make_slabs(pl, taken, slabs);
    uint64_t area = N * N, S = N; /* the block of zeros, then the slabs */
    for (size_t i = 0; i < n; i++) {
        area += (uint64_t)slabs[i].w * slabs[i].d;
        S = slabs[i].w > S ? slabs[i].w : S;
    }
    uint64_t root = 1;
    while (root * root * root < N * area) /* in integers, as a reader must */
        root++;
    S = root > S ? root : S;
    S = S > ATLAS_MAX ? ATLAS_MAX : S;
    qsort(slabs, n, sizeof(*slabs), slab_order);
    bool fits = pack_layers(slabs, n, (int)S, layers_for(area, S), h, dims);
    if (!fits && S < ATLAS_MAX)
        fits = pack_layers(slabs, n, ATLAS_MAX, layers_for(area, ATLAS_MAX), h, dims);
    if (!fits) {
        r = vdbgi_fail(ctx, VDBGI_ERR_OUT_OF_MEMORY,
                       "%zu bricks do not fit an atlas of %d^3 texels: raise eps or the probe "
                       "spacing",
                       count, ATLAS_MAX);
        goto done;
    }
    /* The reader's bound on the atlas (read_placement): never met by this packer, but kept. */
    if ((uint64_t)dims[0] * dims[1] * dims[2] >
        VDBGI_ATLAS_TEXELS_PER_BRICK * ((uint64_t)count + 1)) {
        r = vdbgi_fail(ctx, VDBGI_ERR_BACKEND,
                       "%zu bricks packed into a %ux%ux%u atlas, past the "
                       "format's %d texels a brick",
                       count, dims[0], dims[1], dims[2], VDBGI_ATLAS_TEXELS_PER_BRICK);
        goto done;
    }
    for (size_t i = 0; i < n; i++) {
        const slab *const s = &slabs[i];
        for (int j = 0; j < (s->d - 1) / 4; j++)
            for (int k = 0; k < (s->w - 1) / 4; k++) {
                const int32_t b = slab_brick(pl, s, k, j, NULL);
                pl->origin[b][0] = (uint16_t)(s->pos[0] + 4 * k);
                pl->origin[b][1] = s->pos[1];
                pl->origin[b][2] = (uint16_t)(s->pos[2] + 4 * j);
            }
    }
done:
    vdbgi_free(ctx, taken);
    vdbgi_free(ctx, slabs);
    vdbgi_free(ctx, h);
    return r;
}

/* ---- a reader's placement: the file's table, checked ---------------------------------------- */

/*
 * Each brick's first texel from the file's table (three arrays of u16: x of
 * every brick, then y, then z). A brick lies inside the atlas, in a layer
 * (its y a multiple of 5), and the atlas holds no more texels than
 * VDBGI_ATLAS_TEXELS_PER_BRICK per brick: the bound that keeps a small file
 * from asking for a large atlas.
 */
static vdbgi_result read_placement(vdbgi_context *ctx, vdbgi_pack_plan *pl, const uint8_t *table,
                                   const uint32_t dims[3], const char *name)
{
    const size_t n = pl->brick_count;
    const uint64_t texels = (uint64_t)dims[0] * dims[1] * dims[2];
    VDBGI_FAIL_IF(ctx, texels > VDBGI_ATLAS_TEXELS_PER_BRICK * ((uint64_t)n + 1), VDBGI_ERR_FORMAT,
                  "%s: a %ux%ux%u atlas for %zu bricks (at most %d texels a brick)", name, dims[0],
                  dims[1], dims[2], n, VDBGI_ATLAS_TEXELS_PER_BRICK);
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
        pl->dims[k] = info->indirection_dims[k];
        pl->grid[k] = pl->dims[k] + PAD;
        grid_cells *= pl->grid[k];
        cells *= pl->dims[k];
    }
    /* Count, check, then list: the bricks' arrays are sized by what the levels hold. */
    VDBGI_TRY(scan_bricks(ctx, pl->dims, levels, info->max_level, name, pl));
    const size_t count = pl->brick_count;
    /* A reader's header must count these bricks before anything is allocated for them. */
    VDBGI_FAIL_IF(ctx, expect && memcmp(expect->bricks, pl->per_level, sizeof(pl->per_level)) != 0,
                  VDBGI_ERR_FORMAT, "%s: the level bytes hold other bricks than the header counts",
                  name);
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
                               : place_bricks(ctx, pl, info->atlas_dims);
    info->atlas_size = 4 * (size_t)info->atlas_dims[0] * info->atlas_dims[1] * info->atlas_dims[2];
    if (r == VDBGI_OK)
        r = vdbgi_gifile_alloc(v);
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

static uint8_t *atlas_texel(const vdbgi_volume *v, const vdbgi_pack_plan *pl, size_t b, int t)
{
    const uint32_t *const d = v->info.atlas_dims;
    const uint16_t *const o = pl->origin[b];
    const size_t x = o[0] + (size_t)(t % N), y = o[1] + (size_t)(t / N % N),
                 z = o[2] + (size_t)(t / (N * N));
    return &v->atlas[4 * ((z * d[1] + y) * d[0] + x)];
}

/* One thread's share of the rebuild: the bricks whose first texel lies in rows y_begin..y_end. */
typedef struct rebuild_job {
    const vdbgi_volume *v;
    const vdbgi_pack_plan *pl;
    const uint8_t *values;
    float (*fs)[TEXELS][3]; /* coarse bricks' samples, by cidx */
    const int32_t *cidx;
    int level; /* the coarse level whose samples to compute, or -1: write the atlas */
    uint32_t y_begin, y_end;
    size_t clamped;
} rebuild_job;

static void *rebuild_worker(void *arg)
{
    rebuild_job *const job = arg;
    const vdbgi_pack_plan *const pl = job->pl;
    float(*const fs)[TEXELS][3] = job->fs;
    const int32_t *const cidx = job->cidx;
    for (size_t b = 0; b < pl->brick_count; b++) {
        if (pl->origin[b][1] < job->y_begin || pl->origin[b][1] >= job->y_end ||
            (job->level >= 0 && pl->level[b] != job->level))
            continue;
        for (int t = 0; t < TEXELS; t++) {
            size_t j;
            int cl;
            int32_t p[3];
            texel_point(pl, b, t, p);
            const bool stitch = stitched(pl, b, t, &j, &cl);
            const double pos[3] = {p[0], p[1], p[2]};
            if (job->level >= 0) { /* a coarse brick's samples */
                if (stitch) {
                    vdbgi_brick_interpolate((const float(*)[3])fs[cidx[j]], VDBGI_LAYOUT_COMPACT,
                                            pl->key[j], cl, pos, fs[cidx[b]][t]);
                } else {
                    const int64_t i = point_index(pl, p);
                    static const uint8_t zero[4];
                    decode_texel(job->v, i >= 0 ? &job->values[4 * i] : zero, fs[cidx[b]][t]);
                }
                continue;
            }
            uint8_t *const out = atlas_texel(job->v, pl, b, t);
            if (!stitch) {
                const int64_t i = point_index(pl, p);
                if (i >= 0)
                    memcpy(out, &job->values[4 * i], 4);
                continue;
            }
            float rgb[3];
            if (cidx[b] >= 0)
                memcpy(rgb, fs[cidx[b]][t], sizeof(rgb));
            else
                vdbgi_brick_interpolate((const float(*)[3])fs[cidx[j]], VDBGI_LAYOUT_COMPACT,
                                        pl->key[j], cl, pos, rgb);
            job->clamped += encode_texel(job->v, rgb, out);
        }
    }
    return NULL;
}

/*
 * The atlas from the stored values (4 bytes a point, interleaved). Coarse
 * bricks' samples are kept as floats, coarsest level first, so a stitched
 * texel interpolates exactly what the converter's stitching always did:
 * the coarser brick's values, its own stitched ones unrounded. Threads take
 * whole layers of the atlas: bricks that share texels lie in one layer, and
 * write the same bytes there.
 */
static vdbgi_result rebuild(vdbgi_volume *v, const vdbgi_pack_plan *pl, const uint8_t *values,
                            int threads, size_t *clamped_out)
{
    vdbgi_context *const ctx = v->ctx;
    const size_t count = pl->brick_count;
    size_t coarse = 0;
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
    rebuild_job jobs[MAX_JOBS];
    const uint32_t layers = v->info.atlas_dims[1] / N;
    int nt = job_count(threads);
    nt = (uint32_t)nt > layers ? (int)layers : nt;
    *clamped_out = 0;
    for (int level = (int)v->info.max_level; level >= -1; level--) {
        if (level == 0)
            continue;
        for (int t = 0; t < nt; t++)
            jobs[t] = (rebuild_job){.v = v,
                                    .pl = pl,
                                    .values = values,
                                    .fs = fs,
                                    .cidx = cidx,
                                    .level = level,
                                    .y_begin = N * (uint32_t)((uint64_t)layers * t / nt),
                                    .y_end = N * (uint32_t)((uint64_t)layers * (t + 1) / nt)};
        vdbgi_run_threads(nt, rebuild_worker, jobs, sizeof(jobs[0]));
        for (int t = 0; t < nt; t++)
            *clamped_out += jobs[t].clamped;
    }
    vdbgi_free(ctx, fs);
    vdbgi_free(ctx, cidx);
    return VDBGI_OK;
}

/*
 * The predictor (docs/format.md, "Version 5"). Its neighbours: the stored
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

vdbgi_result vdbgi_pack_rebuild(vdbgi_volume *v, const vdbgi_pack_plan *pl, const uint8_t *planes,
                                int threads, size_t *clamped)
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
    const vdbgi_result r = rebuild(v, pl, values, threads, clamped);
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

/*
 * The first brick (in brick order) whose unstitched texel stands at stored
 * point p. Its block holds one of the cells that touch p (a brick's +
 * border lies in the next cell), which may lie past the indirection when a
 * coarse block does: each such cell is looked up at each level's block.
 */
static size_t first_reader(const vdbgi_pack_plan *pl, const int32_t p[3])
{
    size_t first = SIZE_MAX;
    for (int c = 0; c < 8; c++) {
        int32_t cell[3];
        if (!touching_cell(p, c, cell))
            continue;
        for (int level = 0; level < 4; level++) {
            const int32_t key[3] = {cell[0] >> level, cell[1] >> level, cell[2] >> level};
            const int32_t b = brick_with_key(pl, key, level);
            if (b < 0 || (size_t)b >= first)
                continue;
            const int32_t span = 1 << level;
            bool on = true;
            int t = 0;
            for (int k = 2; k >= 0 && on; k--) {
                const int32_t q = p[k] - key[k] * VDBGI_BRICK * span;
                on = q % span == 0 && q >= 0 && q <= VDBGI_BRICK * span;
                t = t * N + q / span;
            }
            size_t j;
            int cl;
            if (on && !stitched(pl, (size_t)b, t, &j, &cl))
                first = (size_t)b;
        }
    }
    return first;
}

/*
 * A band of owner-cell planes z0 <= cz < z1 for one thread of the converter's
 * passes over the stored points; i0 is its first point's index. The points
 * of a band are written by its thread alone, so the bytes do not depend on
 * the threads.
 */
typedef struct band_job {
    const vdbgi_volume *v;
    const vdbgi_pack_plan *pl;
    const vdbgi_brick *bricks;
    size_t count;
    uint8_t *values; /* 4 bytes a point */
    uint8_t *out;    /* the residual planes */
    int32_t z0, z1;
    size_t i0;
    size_t clamped, fallback;
} band_job;

/* Each point's value: the filled field at its lattice point or, where the
 * fill left none, the block mean of the first brick (in brick order) that
 * reads it. Storage order keeps the field's leaves at hand. */
static void *values_worker(void *arg)
{
    band_job *const job = arg;
    const vdbgi_volume *const v = job->v;
    const vdbgi_leaf *cache = NULL;
    FOR_EACH_POINT_IN(job->pl, job->z0, job->z1, job->i0, p, i, {
        const int32_t at[3] = {p[0] + VDBGI_BRICK * v->origin_cell[0],
                               p[1] + VDBGI_BRICK * v->origin_cell[1],
                               p[2] + VDBGI_BRICK * v->origin_cell[2]};
        const float *f = vdbgi_field_at(&v->filled, at, &cache);
        if (!f) { /* every stored point has a reader: the plan stored it for one */
            static const float none[3];
            const size_t b = first_reader(job->pl, p);
            f = b < job->count ? job->bricks[b].mean : none;
            job->fallback++;
        }
        job->clamped += encode_texel(v, f, &job->values[4 * i]);
    });
    return NULL;
}

/* Each point's residual against its prediction from values that are final. */
static void *residual_worker(void *arg)
{
    band_job *const job = arg;
    const size_t n = job->pl->points;
    const bool rgbm = job->v->info.encoding == VDBGI_ENCODING_RGBM;
    FOR_EACH_POINT_IN(job->pl, job->z0, job->z1, job->i0, p, i, {
        int64_t nb[4];
        neighbours(job->pl, p, nb);
        for (int o = 0; o < 4; o++) {
            const int k = byte_order[!rgbm][o];
            const uint8_t pred = predict(job->values, nb, k, rgbm && k < 3, job->values[4 * i + 3]);
            job->out[k * n + i] = (uint8_t)(job->values[4 * i + k] - pred);
        }
    });
    return NULL;
}

/*
 * Bands of about equal numbers of points, one a thread (at most MAX_JOBS),
 * into jobs; returns how many. The plan's offset of a plane's first owner
 * cell is the number of points before that plane.
 */
static int split_bands(const vdbgi_pack_plan *pl, int threads, band_job *jobs,
                       const band_job *proto)
{
    const int32_t planes = (int32_t)pl->grid[2];
    const size_t plane_cells = (size_t)pl->grid[0] * pl->grid[1];
    int nt = job_count(threads);
    nt = nt > planes ? (planes > 0 ? planes : 1) : nt;
    int32_t z = 0;
    for (int t = 0; t < nt; t++) {
        jobs[t] = *proto;
        jobs[t].z0 = z;
        jobs[t].i0 = z < planes ? pl->offset[(size_t)z * plane_cells] : pl->points;
        const size_t until = pl->points * (size_t)(t + 1) / (size_t)nt;
        while (z < planes && (t == nt - 1 || pl->offset[(size_t)z * plane_cells] < until))
            z++;
        jobs[t].z1 = z;
    }
    return nt;
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
    uint8_t *values = NULL, *coarse_read = NULL, *out = NULL;
    uint64_t *valid = NULL, *near = NULL;
    vdbgi_result r = vdbgi_pack_plan_make(v, levels, NULL, NULL, "converter", threads, &pl);
    if (r != VDBGI_OK) {
        vdbgi_free(ctx, levels);
        return r;
    }
    const size_t n = pl.points;
    values = vdbgi_calloc(ctx, 4 * (n ? n : 1), 1);
    coarse_read = vdbgi_calloc(ctx, n ? n : 1, 1); /* 1: a coarse brick reads the point */
    const size_t table = VDBGI_PLACEMENT_BYTES * count;
    out = vdbgi_alloc(ctx, cells + table + 4 * n);
    valid = valid_bits(v, &pl, probes);
    const size_t grid_cells = (size_t)pl.grid[0] * pl.grid[1] * pl.grid[2];
    near = vdbgi_alloc(ctx, grid_cells * sizeof(*near));
    if (!values || !coarse_read || !out || !valid || !near) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto done;
    }
    band_job jobs[MAX_JOBS];
    const band_job proto = {.v = v,
                            .pl = &pl,
                            .bricks = bricks,
                            .count = count,
                            .values = values,
                            .out = out + cells + table};
    const int bands = split_bands(&pl, threads, jobs, &proto);
    vdbgi_run_threads(bands, values_worker, jobs, sizeof(jobs[0]));
    size_t clamped = 0;
    for (int t = 0; t < bands; t++) {
        clamped += jobs[t].clamped;
        v->info.fallback_count += jobs[t].fallback;
    }
    for (size_t b = 0; b < count; b++)
        for (int t = 0; pl.level[b] && t < TEXELS; t++) {
            size_t j;
            int cl;
            int32_t p[3];
            texel_point(&pl, b, t, p);
            const int64_t i = stitched(&pl, b, t, &j, &cl) ? -1 : point_index(&pl, p);
            if (i >= 0)
                coarse_read[i] = 1;
        }
    /*
     * A point no receiver reads takes the prediction itself: its residual is
     * zero, which gzip all but drops. Its prediction depends on the points
     * before it, so these go in storage order, on one thread; then every
     * residual, from final values, in bands.
     */
    /* Points with a valid probe among their 26 neighbours, or themselves valid. */
    grow(&pl, valid, near, 0);
    grow(&pl, near, valid, 1);
    grow(&pl, valid, near, 2);
    memcpy(out, levels, cells);
    for (size_t b = 0; b < count; b++)
        for (int k = 0; k < 3; k++)
            vdbgi_put_u16(out + cells + 2 * (k * count + b), pl.origin[b][k]);
    const bool rgbm = v->info.encoding == VDBGI_ENCODING_RGBM;
    size_t unread = 0;
    FOR_EACH_POINT(&pl, p, i, {
        size_t c;
        int own;
        grid_slot(&pl, p, &c, &own); /* every stored point is in the grid */
        if (!coarse_read[i] && !(near[c] >> own & 1u)) {
            unread++;
            int64_t nb[4];
            neighbours(&pl, p, nb);
            for (int o = 0; o < 4; o++) {
                const int k = byte_order[!rgbm][o];
                values[4 * i + k] = predict(values, nb, k, rgbm && k < 3, values[4 * i + 3]);
            }
        }
    });
    vdbgi_run_threads(bands, residual_worker, jobs, sizeof(jobs[0]));
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "%zu stored points, %zu of them read by no receiver", n,
              unread);
    size_t stitched_clamps = 0;
    if ((r = rebuild(v, &pl, values, threads, &stitched_clamps)) != VDBGI_OK)
        goto done;
    v->info.clamped_count += clamped + stitched_clamps;
    v->info.stored_points = n;
    *payload = out;
    *payload_size = cells + table + 4 * n;
    out = NULL;
done:
    vdbgi_pack_plan_free(ctx, &pl);
    vdbgi_free(ctx, levels);
    vdbgi_free(ctx, values);
    vdbgi_free(ctx, coarse_read);
    vdbgi_free(ctx, out);
    vdbgi_free(ctx, valid);
    vdbgi_free(ctx, near);
    return r;
}
