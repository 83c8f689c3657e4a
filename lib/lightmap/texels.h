/*
 * texels.h: the lightmap's sample points. Every triangle is rasterised into
 * its chart's texels conservatively: a texel the triangle touches at all
 * gets a sample point inside the triangle, lifted off the surface, so no
 * sliver is left without one. Then dilation, which spreads finished texel
 * values into the gutters so bilinear filtering never reads black.
 */
#ifndef VDBGI_TEXELS_H
#define VDBGI_TEXELS_H

#include "unwrap.h"

typedef struct vdbgi_texels {
    vdbgi_context *ctx;
    int size;          /* atlas edge, texels */
    size_t page_count; /* texel (p, x, y) is number (p * size + y) * size + x */
    int32_t *tri;      /* per texel: the triangle it samples, or -1 (a gutter) */
    float *pos;        /* per texel, 3: the sample point on its triangle (rays leave it lifted) */
    size_t sample_count;
    size_t centre_count; /* samples at the texel's centre (the rest: its nearest point inside) */
} vdbgi_texels;

/*
 * Each texel a triangle touches samples the triangle that covers its centre,
 * else the one whose nearest point lies closest to its centre (ties: the
 * lower triangle), at that point. Deterministic; no threads.
 */
vdbgi_result vdbgi_texels_build(vdbgi_context *ctx, const vdbgi_scene *scene,
                                const vdbgi_unwrap *unwrap, vdbgi_texels *out);
void vdbgi_texels_free(vdbgi_texels *t);

/*
 * Spread values (channels floats a texel) from the texels whose keep[] is set
 * into the others, ring by ring, each new texel the mean of its kept or
 * already filled 8 neighbours on the same page, for at most rings rings.
 * keep[] is updated to mark what was filled.
 */
vdbgi_result vdbgi_texels_dilate(const vdbgi_texels *t, float *values, int channels,
                                 unsigned char *keep, int rings);

#endif /* VDBGI_TEXELS_H */
