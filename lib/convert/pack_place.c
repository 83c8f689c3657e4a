/*
 * pack_place.c: where the converter puts the compact layout's bricks in the
 * atlas. Its own choice, not the format's: the file records each brick's
 * place (docs/format.md, "Version 5"), and readers only check it.
 */
#include "gifile.h"
#include "pack_common.h"

#include <stdlib.h>
#include <string.h>

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
vdbgi_result vdbgi_pack_place(vdbgi_context *ctx, vdbgi_pack_plan *pl, uint32_t dims[3])
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
    /* The reader's bound on the atlas (gifile.c's header checks): never met by this packer, but kept. */
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
