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
    int passes;     /* reflections: pass k lights the hits with pass k - 1's map; >= 1, or 0:
                      until the next would add less than converge of the light
                      (vdbgi_bounces_converge: at most three passes, the last carrying the
                      rest) */
    float converge; /* with passes 0: that share, in (0, 1) */
    bool direct;    /* add the texel's own sun (fully baked lighting); else bounced light only */
    int rings;      /* dilation rings after each pass (gutter + invalid texels) */
    float ao_dist;  /* > 0: ambient occlusion instead (seed 004's AO mode): the fraction of the
                      cosine-weighted hemisphere open for this many metres, in every channel */
    bool bare;      /* the same rays, nothing shaded nor dilated (the benchmark's bare loop) */
    bool noise;     /* measure the noise a pass's gather leaves into the map's noise */
} vdbgi_lightmap_params;

typedef struct vdbgi_lightmap {
    vdbgi_context *ctx;
    size_t texel_count;   /* size x size x pages, as the texels */
    float *rgb;           /* 3 per texel: irradiance E, dilated into gutters and invalid texels */
    unsigned char *valid; /* per texel: a sample whose rays found no more back faces than allowed */
    size_t invalid_count; /* samples inside geometry or behind back faces */
    double pass_seconds[16];
    int passes;        /* done */
    double last_share; /* of the map's light (its valid samples, all channels), the last pass's;
                          until converged, the pilot's for the last of the bounces */
    int bounces;       /* until converged: the bounces the light needs (0 otherwise) */
    double tail_share; /* of them, the share the passes not swept carry */
    uint64_t rays;
    uint64_t gathers, gathered; /* a sample's gathers over its hemisphere, every pass's, and
                                   their rays (no AO) */
    double noise;               /* with the params' noise: vdbgi_lightmap_noise's figure */
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
/*
 * The noise bp's gather leaves in a pass of a lightmap of scene: the first
 * pass's error at 256 points on the surfaces (vdbgi_bake_noise), over their
 * mean light; an adaptive bp's scale found as the bake finds it. What a
 * bake measures with the params' noise, apart from one (for layers, whose
 * bakes each take a light of bp's).
 */
vdbgi_result vdbgi_lightmap_noise(vdbgi_context *ctx, const vdbgi_scene *scene,
                                  const vdbgi_bake_params *bp, double *noise);

/* A bake's files: the .glb (scene, second UV set, maps) and each map's HDR form (EXR). */
typedef struct vdbgi_lightmap_files {
    uint8_t *glb;
    size_t glb_size;
    uint8_t **exr; /* map l of page p at l x pages + p: the map, then each layer */
    size_t *exr_size;
    size_t exr_count; /* pages x (1 + layers); none for AO */
    float scale;      /* E = the map's 8 bits (linear, after sRGB decoding) x scale */
} vdbgi_lightmap_files;

/* Per-light maps (seed 004's layers) beside the map they add up to. */
typedef struct vdbgi_lightmap_layers {
    const vdbgi_lightmap *maps;
    const char (*names)[32]; /* "sun", "ambient", "sky", "emissive<material>" */
    size_t count;
} vdbgi_lightmap_layers;

/*
 * Encode m: per page an 8-bit PNG (sRGB, E / scale with scale the largest E;
 * AO: linear) and a half-float EXR of E, the same for each layer of ly (may
 * be NULL), and the scene as a .glb whose materials carry the maps on
 * TEXCOORD_1 (docs/lightmap.md). Base colour and emissive textures go in as
 * sRGB PNGs on TEXCOORD_0.
 */
vdbgi_result vdbgi_lightmap_encode(vdbgi_context *ctx, const vdbgi_scene *scene,
                                   const vdbgi_unwrap *un, const vdbgi_texels *tx,
                                   const vdbgi_lightmap *m, bool ao,
                                   const vdbgi_lightmap_layers *ly, vdbgi_lightmap_files *out);
void vdbgi_lightmap_files_free(vdbgi_context *ctx, vdbgi_lightmap_files *f);

/*
 * What a vdbgi_lightmap_bake_scene result holds (for tests and tools): map
 * 0 is the map, 1.. its layers (NULL past them), with the layer's name.
 */
const vdbgi_lightmap *vdbgi_lightmap_result_map(const vdbgi_lightmap_result *r, size_t i,
                                                const char **name);

/* The map's E at a triangle's barycentrics (Embree's u, v): bilinear, as a GPU filters it. */
void vdbgi_lightmap_at(const vdbgi_lightmap *m, const vdbgi_unwrap *un, const vdbgi_texels *tx,
                       uint32_t prim, float u, float v, float rgb[3]);

#endif /* VDBGI_LIGHTMAP_H */
