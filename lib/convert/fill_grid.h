/* fill_grid.h: the fill's sparse grid of 8^3 leaves, which fill.c builds and reads and
   fill_rings.c spreads values over. Only those two include it. */
#ifndef VDBGI_FILL_GRID_H
#define VDBGI_FILL_GRID_H

#include "field.h"

#include <stdbool.h>

/* A leaf of the grid being filled: which points are to be filled, which are. */
typedef struct vdbgi_fill_leaf {
    int32_t origin[3];
    uint64_t target[8];  /* points the fill should reach */
    uint64_t filled[8];  /* points holding a value */
    uint64_t invalid[8]; /* invalid probes (for the darkest choice) */
    int32_t nb[27];      /* the 3^3 leaves around this one, -1 where none */
} vdbgi_fill_leaf;

typedef struct vdbgi_fill_grid {
    vdbgi_context *ctx;
    int channels;
    int judged;    /* leading channels the darkest choice sums */
    vdbgi_map map; /* origin -> leaf */
    vdbgi_fill_leaf *leaves;
    size_t leaf_capacity;
    float *values; /* 512 * 3 * channels a leaf, allocated once the leaves are known */
} vdbgi_fill_grid;

/* A point of the grid: leaf index and point number. */
typedef struct vdbgi_fill_point {
    uint32_t leaf, n;
} vdbgi_fill_point;

static inline bool fill_bit(const uint64_t m[8], unsigned n)
{
    return m[n >> 6] >> (n & 63) & 1;
}

static inline void fill_set_bit(uint64_t m[8], unsigned n)
{
    m[n >> 6] |= 1ull << (n & 63);
}

static inline size_t fill_popcount512(const uint64_t m[8])
{
    size_t c = 0;
    for (int w = 0; w < 8; w++)
        c += (size_t)__builtin_popcountll(m[w]);
    return c;
}

static inline float *fill_grid_value(const vdbgi_fill_grid *g, size_t leaf, unsigned n)
{
    return g->values + ((size_t)leaf * VDBGI_LEAF_VOXELS + n) * 3 * (size_t)g->channels;
}

/*
 * Spread ring by ring from the filled points until every target point holds
 * a value, a ring finds nothing, or fp->max_iterations rings have run. A
 * ring is the target points next to a filled one, found by dilating the
 * leaves' masks; a point's value reads only points filled before its ring,
 * so the order a ring is listed in changes nothing.
 */
vdbgi_result vdbgi_fill_spread(vdbgi_fill_grid *g, const vdbgi_fill_params *fp, size_t *unreached);

#endif /* VDBGI_FILL_GRID_H */
