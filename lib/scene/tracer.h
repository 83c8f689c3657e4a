/* tracer.h: Embree behind a C interface: first hits and occlusion for batches of rays. */
#ifndef VDBGI_TRACER_H
#define VDBGI_TRACER_H

#include "context.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vdbgi_tracer vdbgi_tracer;

vdbgi_result vdbgi_tracer_create(vdbgi_context *ctx, const float *positions, size_t vertex_count,
                                 const uint32_t *indices, size_t triangle_count,
                                 vdbgi_tracer **out);
void vdbgi_tracer_destroy(vdbgi_tracer *tracer);

/*
 * A batch of rays sharing their extent. org and dir hold 3 floats per ray,
 * or one xyz for every ray when their stride is 0 (a probe's rays share an
 * origin; its shadow rays share the sun's direction).
 */
typedef struct vdbgi_ray_batch {
    const float *org;
    const float *dir;
    size_t org_stride, dir_stride; /* floats between rays: 3, or 0 for shared */
    float tnear, tfar;
    size_t count;
    const float *tfars; /* each ray's own tfar (shadow rays towards a lamp), or NULL */
} vdbgi_ray_batch;

/* First hits: t (INFINITY for a miss), primitive and barycentrics. */
typedef struct vdbgi_hit {
    float t, u, v;
    uint32_t prim;
} vdbgi_hit;

/* Thread-safe after creation. scratch must hold vdbgi_tracer_scratch_size(count) bytes. */
size_t vdbgi_tracer_scratch_size(size_t count);
void vdbgi_tracer_intersect(const vdbgi_tracer *tracer, vdbgi_trace_method method,
                            const vdbgi_ray_batch *rays, vdbgi_hit *hits, void *scratch);
/* occluded[i] = 1 if ray i hits anything in (tnear, tfar). */
void vdbgi_tracer_occluded(const vdbgi_tracer *tracer, vdbgi_trace_method method,
                           const vdbgi_ray_batch *rays, unsigned char *occluded, void *scratch);
/* The first Embree error since creation, or VDBGI_OK (message recorded on ctx). */
vdbgi_result vdbgi_tracer_check(vdbgi_tracer *tracer);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_TRACER_H */
