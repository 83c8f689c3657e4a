/*
 * unwrap.h: lightmap UVs for a triangle soup (seed 004's unwrap, and
 * better): triangles grouped into near-planar charts, each projected to its
 * plane and turned to its smallest bounding box, and the boxes packed into
 * one or more square atlases at a texel size in metres.
 */
#ifndef VDBGI_UNWRAP_H
#define VDBGI_UNWRAP_H

#include "scene.h"

/* An atlas made to fit its charts is a multiple of this many texels on a side. */
#define VDBGI_ATLAS_STEP 32

typedef struct vdbgi_unwrap_params {
    float texel;     /* metres a texel edge; 0 = 0.25 */
    int size;        /* atlas edge in texels; 0: the smallest multiple of VDBGI_ATLAS_STEP
                        that holds every chart on one atlas, else 1024 */
    float max_angle; /* degrees a chart's triangles may turn from its first; 0 = 15 */
    int gutter;      /* empty texels around each chart's footprint; 0 = 2 */
} vdbgi_unwrap_params;

typedef struct vdbgi_unwrap {
    vdbgi_context *ctx;
    size_t triangle_count;
    float *uv;       /* 6 per triangle: its corners in atlas texels (0..size), x right, y down */
    uint32_t *chart; /* per triangle */
    uint32_t *page;  /* per chart: which atlas */
    float *density;  /* per chart: texels a metre it got (1 / texel unless it had to shrink) */
    int32_t *rect;   /* 4 per chart: x, y, w, h of its box in its atlas, gutters included */
    size_t chart_count, page_count;
    int size;
    float texel, gutter;
    double chart_texels; /* texels inside the charts' rectangles, gutters excluded */
} vdbgi_unwrap;

/*
 * Unwrap every triangle of scene. Charts grow from the lowest unassigned
 * triangle across edges shared by exactly two triangles whose normals lie
 * within max_angle of the seed's; a chart that still folds over itself on
 * its plane (a spiral ramp) is split. The result depends only on the scene. A chart larger than an atlas
 * is scaled down to fit one, alone. VDBGI_ERR_INVALID_ARG for absurd
 * parameters.
 */
vdbgi_result vdbgi_unwrap_build(vdbgi_context *ctx, const vdbgi_scene *scene,
                                const vdbgi_unwrap_params *params, vdbgi_unwrap *out);
void vdbgi_unwrap_free(vdbgi_unwrap *u);

/*
 * The scene's own second UV set as the unwrap, one chart in one atlas of
 * params->size texels, if it is usable: every vertex has one, every corner
 * is finite and inside [0, 1], every triangle covers some area, and no texel
 * centre lies inside two triangles. *usable says whether it was; when not,
 * *why says what failed (for a message) and out is left empty. Its v runs
 * up the image, as assimp gives it (row 0 at v = 1).
 */
vdbgi_result vdbgi_unwrap_from_uv1(vdbgi_context *ctx, const vdbgi_scene *scene,
                                   const vdbgi_unwrap_params *params, vdbgi_unwrap *out,
                                   bool *usable, const char **why);

#endif /* VDBGI_UNWRAP_H */
