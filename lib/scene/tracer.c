/* tracer.c: the Embree device and BVH; first-hit and occlusion queries. */
#include "tracer.h"

#include <embree3/rtcore.h>

#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>

struct vdbgi_tracer {
    vdbgi_context *ctx;
    RTCDevice device;
    RTCScene scene;
    atomic_int error; /* first RTCError seen, RTC_ERROR_NONE until then */
    char message[256];
};

/* Embree reports errors here, from whichever thread hit them: keep the first. */
static void on_embree_error(void *user, enum RTCError code, const char *str)
{
    vdbgi_tracer *const t = user;
    int expected = RTC_ERROR_NONE;
    if (atomic_compare_exchange_strong(&t->error, &expected, (int)code))
        snprintf(t->message, sizeof(t->message), "%s", str ? str : "no detail");
}

vdbgi_result vdbgi_tracer_check(vdbgi_tracer *t)
{
    const int code = atomic_load(&t->error);
    if (code == RTC_ERROR_NONE)
        return VDBGI_OK;
    return vdbgi_fail(t->ctx,
                      code == RTC_ERROR_OUT_OF_MEMORY ? VDBGI_ERR_OUT_OF_MEMORY : VDBGI_ERR_BACKEND,
                      "embree: error %d: %s", code, t->message);
}

void vdbgi_tracer_destroy(vdbgi_tracer *t)
{
    if (!t)
        return;
    if (t->scene)
        rtcReleaseScene(t->scene);
    if (t->device)
        rtcReleaseDevice(t->device);
    vdbgi_free(t->ctx, t);
}

vdbgi_result vdbgi_tracer_create(vdbgi_context *ctx, const float *positions, size_t vertex_count,
                                 const uint32_t *indices, size_t triangle_count, vdbgi_tracer **out)
{
    *out = NULL;
    vdbgi_tracer *const t = vdbgi_calloc(ctx, 1, sizeof(*t));
    if (!t)
        return VDBGI_ERR_OUT_OF_MEMORY;
    t->ctx = ctx;
    atomic_init(&t->error, RTC_ERROR_NONE);
    /*
     * AVX-512's kernels find a few hits a hair apart from AVX2's (the bundled
     * world converts to 1028 level-0 bricks, not 1026): capped at AVX2, a bake
     * gives the same bytes on every machine that has it.
     */
    t->device = rtcNewDevice("verbose=0,max_isa=avx2");
    if (!t->device) {
        const enum RTCError code = rtcGetDeviceError(NULL);
        vdbgi_free(ctx, t);
        return vdbgi_fail(ctx, VDBGI_ERR_BACKEND, "embree: cannot create device (error %d)",
                          (int)code);
    }
    rtcSetDeviceErrorFunction(t->device, on_embree_error, t);
    t->scene = rtcNewScene(t->device);
    if (t->scene) {
        /* Robust traversal: no rays slipping through shared edges of a closed mesh. */
        rtcSetSceneFlags(t->scene, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(t->scene, RTC_BUILD_QUALITY_HIGH);
        RTCGeometry g = rtcNewGeometry(t->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        if (g) {
            /* Shared, not copied: the scene owns the arrays (padded for 16-byte loads). */
            rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, positions,
                                       0, 3 * sizeof(float), vertex_count);
            rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices, 0,
                                       3 * sizeof(uint32_t), triangle_count);
            rtcCommitGeometry(g);
            rtcAttachGeometry(t->scene, g);
            rtcReleaseGeometry(g);
        }
        rtcCommitScene(t->scene);
    }
    const vdbgi_result r = vdbgi_tracer_check(t);
    if (r != VDBGI_OK || !t->scene) {
        vdbgi_tracer_destroy(t);
        return r != VDBGI_OK ? r : vdbgi_fail(ctx, VDBGI_ERR_BACKEND, "embree: no scene");
    }
    *out = t;
    return VDBGI_OK;
}

size_t vdbgi_tracer_scratch_size(size_t count)
{
    return count * sizeof(struct RTCRayHit) + 64;
}

static void *align64(void *p)
{
    return (void *)(((uintptr_t)p + 63) & ~(uintptr_t)63);
}

static void fill_ray(struct RTCRay *r, const vdbgi_ray_batch *b, size_t i)
{
    const float *const o = &b->org[b->org_stride * i];
    const float *const d = &b->dir[b->dir_stride * i];
    r->org_x = o[0];
    r->org_y = o[1];
    r->org_z = o[2];
    r->dir_x = d[0];
    r->dir_y = d[1];
    r->dir_z = d[2];
    r->tnear = b->tnear;
    r->tfar = b->tfars ? b->tfars[i] : b->tfar;
    r->time = 0.0f;
    r->mask = 0xFFFFFFFFu;
    r->id = (unsigned)i;
    r->flags = 0;
}

static void read_hit(const struct RTCRayHit *rh, vdbgi_hit *h)
{
    if (rh->hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        h->t = INFINITY;
        h->u = h->v = 0.0f;
        h->prim = 0;
    } else {
        h->t = rh->ray.tfar;
        h->u = rh->hit.u;
        h->v = rh->hit.v;
        h->prim = rh->hit.primID;
    }
}

/*
 * Packets are written once per width with a macro: RTCRayHit8 and RTCRayHit16
 * differ only in their lane count, and C has no templates.
 */
#define VDBGI_PACKET_INTERSECT(N)                                                                  \
    static void intersect##N(RTCScene scene, const vdbgi_ray_batch *b, vdbgi_hit *hits)            \
    {                                                                                              \
        struct RTCIntersectContext ic;                                                             \
        rtcInitIntersectContext(&ic);                                                              \
        for (size_t base = 0; base < b->count; base += N) {                                        \
            struct RTCRayHit##N rh;                                                                \
            _Alignas(4 * N) int valid[N]; /* Embree reads the mask with aligned vector loads */    \
            for (int l = 0; l < N; l++) {                                                          \
                const size_t i = base + (size_t)l < b->count ? base + (size_t)l : base;            \
                valid[l] = base + (size_t)l < b->count ? -1 : 0;                                   \
                const float *const o = &b->org[b->org_stride * i];                                 \
                const float *const d = &b->dir[b->dir_stride * i];                                 \
                rh.ray.org_x[l] = o[0], rh.ray.org_y[l] = o[1], rh.ray.org_z[l] = o[2];            \
                rh.ray.dir_x[l] = d[0], rh.ray.dir_y[l] = d[1], rh.ray.dir_z[l] = d[2];            \
                rh.ray.tnear[l] = b->tnear, rh.ray.tfar[l] = b->tfars ? b->tfars[i] : b->tfar;     \
                rh.ray.time[l] = 0.0f, rh.ray.mask[l] = 0xFFFFFFFFu;                               \
                rh.ray.id[l] = (unsigned)l, rh.ray.flags[l] = 0;                                   \
                rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;                                        \
                rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;                                     \
            }                                                                                      \
            rtcIntersect##N(valid, scene, &ic, &rh);                                               \
            for (int l = 0; l < N && base + (size_t)l < b->count; l++) {                           \
                vdbgi_hit *const h = &hits[base + (size_t)l];                                      \
                if (rh.hit.geomID[l] == RTC_INVALID_GEOMETRY_ID) {                                 \
                    h->t = INFINITY, h->u = h->v = 0.0f, h->prim = 0;                              \
                } else {                                                                           \
                    h->t = rh.ray.tfar[l], h->u = rh.hit.u[l], h->v = rh.hit.v[l];                 \
                    h->prim = rh.hit.primID[l];                                                    \
                }                                                                                  \
            }                                                                                      \
        }                                                                                          \
    }                                                                                              \
    static void occluded##N(RTCScene scene, const vdbgi_ray_batch *b, unsigned char *occ)          \
    {                                                                                              \
        struct RTCIntersectContext ic;                                                             \
        rtcInitIntersectContext(&ic);                                                              \
        for (size_t base = 0; base < b->count; base += N) {                                        \
            struct RTCRay##N r;                                                                    \
            _Alignas(4 * N) int valid[N];                                                          \
            for (int l = 0; l < N; l++) {                                                          \
                const size_t i = base + (size_t)l < b->count ? base + (size_t)l : base;            \
                valid[l] = base + (size_t)l < b->count ? -1 : 0;                                   \
                const float *const o = &b->org[b->org_stride * i];                                 \
                const float *const d = &b->dir[b->dir_stride * i];                                 \
                r.org_x[l] = o[0], r.org_y[l] = o[1], r.org_z[l] = o[2];                           \
                r.dir_x[l] = d[0], r.dir_y[l] = d[1], r.dir_z[l] = d[2];                           \
                r.tnear[l] = b->tnear, r.tfar[l] = b->tfars ? b->tfars[i] : b->tfar;               \
                r.time[l] = 0.0f, r.mask[l] = 0xFFFFFFFFu, r.id[l] = (unsigned)l, r.flags[l] = 0;  \
            }                                                                                      \
            rtcOccluded##N(valid, scene, &ic, &r);                                                 \
            for (int l = 0; l < N && base + (size_t)l < b->count; l++)                             \
                occ[base + (size_t)l] = r.tfar[l] < 0.0f;                                          \
        }                                                                                          \
    }

VDBGI_PACKET_INTERSECT(8)
VDBGI_PACKET_INTERSECT(16)

void vdbgi_tracer_intersect(const vdbgi_tracer *t, vdbgi_trace_method method,
                            const vdbgi_ray_batch *b, vdbgi_hit *hits, void *scratch)
{
    struct RTCIntersectContext ic;
    rtcInitIntersectContext(&ic);
    switch (method) {
    case VDBGI_TRACE_PACKET8: intersect8(t->scene, b, hits); return;
    case VDBGI_TRACE_PACKET16: intersect16(t->scene, b, hits); return;
    case VDBGI_TRACE_STREAM: {
        struct RTCRayHit *const rh = align64(scratch);
        for (size_t i = 0; i < b->count; i++) {
            fill_ray(&rh[i].ray, b, i);
            rh[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh[i].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect1M(t->scene, &ic, rh, (unsigned)b->count, sizeof(struct RTCRayHit));
        for (size_t i = 0; i < b->count; i++)
            read_hit(&rh[i], &hits[i]);
        return;
    }
    case VDBGI_TRACE_AUTO:
    case VDBGI_TRACE_SINGLE:
    default:
        for (size_t i = 0; i < b->count; i++) {
            struct RTCRayHit rh;
            fill_ray(&rh.ray, b, i);
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(t->scene, &ic, &rh);
            read_hit(&rh, &hits[i]);
        }
        return;
    }
}

void vdbgi_tracer_occluded(const vdbgi_tracer *t, vdbgi_trace_method method,
                           const vdbgi_ray_batch *b, unsigned char *occluded, void *scratch)
{
    struct RTCIntersectContext ic;
    rtcInitIntersectContext(&ic);
    switch (method) {
    case VDBGI_TRACE_PACKET8: occluded8(t->scene, b, occluded); return;
    case VDBGI_TRACE_PACKET16: occluded16(t->scene, b, occluded); return;
    case VDBGI_TRACE_STREAM: {
        struct RTCRay *const r = align64(scratch);
        for (size_t i = 0; i < b->count; i++)
            fill_ray(&r[i], b, i);
        rtcOccluded1M(t->scene, &ic, r, (unsigned)b->count, sizeof(struct RTCRay));
        for (size_t i = 0; i < b->count; i++)
            occluded[i] = r[i].tfar < 0.0f;
        return;
    }
    case VDBGI_TRACE_AUTO:
    case VDBGI_TRACE_SINGLE:
    default:
        for (size_t i = 0; i < b->count; i++) {
            struct RTCRay r;
            fill_ray(&r, b, i);
            rtcOccluded1(t->scene, &ic, &r);
            occluded[i] = r.tfar < 0.0f;
        }
        return;
    }
}
