/*
 * lightmap.h: surface lightmaps (seed 004) from the probes' light model:
 * each texel's sample point gathers over its normal's hemisphere, pass after
 * pass, each pass shading the hits with the previous pass's map.
 */
#ifndef VDBGI_LIGHTMAP_H
#define VDBGI_LIGHTMAP_H

#include "estimate.h"
#include "texels.h"

typedef struct vdbgi_lightmap_params {
    int passes;  /* bounces: pass k lights the hits with pass k - 1's map; >= 1 */
    bool direct; /* add the texel's own sun (fully baked lighting); else bounced light only */
    int rings;   /* dilation rings after each pass (gutter + invalid texels) */
} vdbgi_lightmap_params;

typedef struct vdbgi_lightmap {
    vdbgi_context *ctx;
    size_t texel_count;   /* size x size x pages, as the texels */
    float *rgb;           /* 3 per texel: irradiance E, dilated into gutters and invalid texels */
    unsigned char *valid; /* per texel: a sample whose rays found no more back faces than allowed */
    size_t invalid_count; /* samples inside geometry or behind back faces */
    double pass_seconds[16];
    uint64_t rays;
} vdbgi_lightmap;

/*
 * Bake the map of tx (from scene and un) with bp's light model (rays,
 * sampling, ambient, sun, sky, falloff, ray length, invalid threshold,
 * threads). E is in the unit three.js takes for material.lightMap: a surface
 * of albedo rho shows rho E / pi. Each texel's random stream comes from its
 * coordinates and bp->seed, so the bytes do not depend on the threads.
 */
vdbgi_result vdbgi_lightmap_bake(vdbgi_context *ctx, const vdbgi_scene *scene,
                                 const vdbgi_bake_params *bp, const vdbgi_unwrap *un,
                                 const vdbgi_texels *tx, const vdbgi_lightmap_params *lp,
                                 vdbgi_lightmap *out);
void vdbgi_lightmap_free(vdbgi_lightmap *m);

/* The map's E at a triangle's barycentrics (Embree's u, v): bilinear, as a GPU filters it. */
void vdbgi_lightmap_at(const vdbgi_lightmap *m, const vdbgi_unwrap *un, const vdbgi_texels *tx,
                       uint32_t prim, float u, float v, float rgb[3]);

#endif /* VDBGI_LIGHTMAP_H */
