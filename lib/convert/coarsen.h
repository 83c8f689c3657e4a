/* coarsen.h: the colour-range pyramid over the filled field and the choice of brick levels. */
#ifndef VDBGI_COARSEN_H
#define VDBGI_COARSEN_H

#include "field.h"
#include "probes.h"
#include "sampler.h" /* VDBGI_BRICK, VDBGI_BRICK_PADDED: the format's brick */

/* A kept brick: block coordinate key at its level (fine origin = key * 4 * 2^level). */
typedef struct vdbgi_brick {
    int32_t key[3];
    int level;
    float mean[3]; /* the block's mean, for points the fill did not reach */
} vdbgi_brick;

typedef struct vdbgi_coarsen_params {
    int max_level;             /* 0..3 */
    float tolerance;           /* eps * mean irradiance: absolute, per channel */
    float sigmas;              /* noise allowance: a probe may stray this many standard errors */
    vdbgi_criterion criterion; /* resolved: RANGE, INTERP or RMSE */
    float fallback[3];         /* mean of the valid probes: a block with no filled point */
    int threads;               /* >= 1 */
    vdbgi_layout layout;       /* where a coarse brick's probes stand */
} vdbgi_coarsen_params;

/*
 * Seed 000's top-down coarsening over the occupied level-0 cells (3 int32
 * each): one brick where a block is flat enough by cp's criterion, its
 * children elsewhere. *bricks (allocated through ctx) lists them in z, y, x
 * order of their root blocks, whatever the thread count.
 */
vdbgi_result vdbgi_coarsen(vdbgi_context *ctx, const vdbgi_field *filled,
                           const vdbgi_probes *probes, const int32_t *cells, size_t cell_count,
                           const vdbgi_coarsen_params *cp, vdbgi_brick **bricks,
                           size_t *brick_count);

/*
 * The values of a level-L brick at block key in the layout's slot (6^3 or
 * 5^3, x fastest), apron or border included, from the filled field; mean
 * stands in where the field holds nothing near. Returns how many texels took it.
 */
size_t vdbgi_brick_samples(const vdbgi_field *filled, const int32_t key[3], int level,
                           const float mean[3], vdbgi_layout layout, float out[][3]);

#endif /* VDBGI_COARSEN_H */
