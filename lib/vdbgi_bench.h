/*
 * vdbgi_bench.h: calls for measuring vdbgi itself (gi-bench, the tests): the
 * bake's and the lightmapper's rays with nothing shaded, and the estimators
 * at given points, the truth every method's error is measured against. Not
 * installed; the same rules as vdbgi.h.
 */
#ifndef VDBGI_BENCH_H_
#define VDBGI_BENCH_H_

#include "vdbgi.h"

#ifdef __cplusplus
extern "C" {
#endif

/*
 * For benchmarks: vdbgi_scene_bake_points's estimate with the L2 basis,
 * VDBGI_SH2_TERMS colours (27 floats) a point into sh: the best a probe
 * standing exactly there could give.
 */
VDBGI_API vdbgi_result vdbgi_scene_bake_points_sh2(const vdbgi_scene *scene,
                                                   const vdbgi_bake_desc *desc, const float *points,
                                                   size_t point_count, float *sh);

/*
 * For benchmarks: trace exactly the rays the bake would (primary rays, then a
 * shadow ray from each hit whose facing normal sees the sun) with no shading,
 * on desc's threads and trace_method. Fills stats; no probe value changes.
 * An adaptive ray count (desc->adaptive) depends on the shading, so it is
 * refused with VDBGI_ERR_INVALID_ARG.
 */
VDBGI_API vdbgi_result vdbgi_probes_trace_bare(const vdbgi_probes *probes, const vdbgi_scene *scene,
                                               const vdbgi_bake_desc *desc,
                                               vdbgi_bake_stats *stats);

/*
 * For benchmarks: a lightmap bake's rays, pass after pass, with nothing
 * shaded (no albedo, no previous map at the hits) nor dilated; stats as
 * the bake's.
 */
VDBGI_API vdbgi_result vdbgi_lightmap_trace_bare(vdbgi_context *ctx, const vdbgi_scene *scene,
                                                 const vdbgi_lightmap_desc *desc,
                                                 vdbgi_lightmap_stats *stats);
/*
 * Receivers on the surfaces, for lightmap error: count points spread by
 * area as vdbgi_scene_sample_surface spreads them (same seed, same points
 * at offset 0), each as its triangle prims[i] and barycentrics uv[2 i],
 * uv[2 i + 1] (p = (1-u-v) v0 + u v1 + v v2).
 */
VDBGI_API vdbgi_result vdbgi_scene_sample_triangles(const vdbgi_scene *scene, size_t count,
                                                    uint64_t seed, uint32_t *prims, float *uv);
/*
 * The lightmap estimator at those receivers (one ray offset off the front
 * face, over its cosine-weighted hemisphere; one bounce: the bake's first
 * pass): E into 3 floats each, the back-face fraction into backface.
 */
VDBGI_API vdbgi_result vdbgi_scene_bake_surface(const vdbgi_scene *scene,
                                                const vdbgi_bake_desc *desc, const uint32_t *prims,
                                                const float *uv, size_t count, float *rgb,
                                                float *backface);
/*
 * The same estimator at count points (3 floats each) with unit normals
 * (3 floats each), each used as given: E into rgb, the back-face fraction
 * into backface (may be NULL). The truth a volume's reading is held to.
 */
VDBGI_API vdbgi_result vdbgi_scene_bake_hemispheres(const vdbgi_scene *scene,
                                                    const vdbgi_bake_desc *desc,
                                                    const float *points, const float *normals,
                                                    size_t count, float *rgb, float *backface);
/* A lightmap's E (map 0, bilinear as a GPU filters it) at triangle prim, barycentrics u, v. */
VDBGI_API void vdbgi_lightmap_result_sample(const vdbgi_lightmap_result *result, uint32_t prim,
                                            float u, float v, float rgb[3]);
/*
 * A lightmap's map 0 texel by texel: E (3 floats a texel, dilated), and in
 * *valid per texel non-zero where a valid sample was baked; *count texels.
 * Owned by result.
 */
VDBGI_API const float *vdbgi_lightmap_result_texels(const vdbgi_lightmap_result *result,
                                                    const unsigned char **valid, size_t *count);
/*
 * The charts' boxes as packed, gutters included: 4 ints per chart (x, y, w,
 * h), each in atlas (*pages)[chart], *count charts; owned by result.
 */
VDBGI_API const int32_t *vdbgi_lightmap_result_boxes(const vdbgi_lightmap_result *result,
                                                     const uint32_t **pages, size_t *count);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_BENCH_H_ */
