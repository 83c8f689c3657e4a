/*
 * lightmap.c: the passes of a lightmap bake over threads. Each pass gathers
 * every sample texel's hemisphere with the probes' estimator, its hits lit
 * by the fill, the sun and the previous pass's map; the map is dilated
 * after each pass so the next one, and a GPU's filter, never read a gutter.
 */
#include "lightmap.h"
#include "util.h"
#include "vdbgi_bench.h"

#include <math.h>
#include <string.h>

#define PI_F 3.14159265358979f

void vdbgi_lightmap_free(vdbgi_lightmap *m)
{
    if (!m || !m->ctx)
        return;
    vdbgi_free(m->ctx, m->rgb);
    vdbgi_free(m->ctx, m->valid);
    memset(m, 0, sizeof(*m));
}

void vdbgi_lightmap_at(const vdbgi_lightmap *m, const vdbgi_unwrap *un, const vdbgi_texels *tx,
                       uint32_t prim, float u, float v, float rgb[3])
{
    const float *const uv = &un->uv[6 * (size_t)prim];
    const float w = 1.0f - u - v;
    /* Texel centres stand at half-integers: filter from the one below and left. */
    const float x = w * uv[0] + u * uv[2] + v * uv[4] - 0.5f,
                y = w * uv[1] + u * uv[3] + v * uv[5] - 0.5f;
    const int size = tx->size;
    const size_t page = (size_t)un->page[un->chart[prim]] * (size_t)size * (size_t)size;
    const float fx = floorf(x), fy = floorf(y);
    const float ax = x - fx, ay = y - fy;
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    for (int c = 0; c < 4; c++) {
        int xi = (int)fx + (c & 1), yi = (int)fy + (c >> 1);
        xi = xi < 0 ? 0 : xi >= size ? size - 1 : xi;
        yi = yi < 0 ? 0 : yi >= size ? size - 1 : yi;
        const float wt = (c & 1 ? ax : 1.0f - ax) * (c >> 1 ? ay : 1.0f - ay);
        const float *const e = &m->rgb[3 * (page + (size_t)yi * (size_t)size + (size_t)xi)];
        for (int k = 0; k < 3; k++)
            rgb[k] += wt * e[k];
    }
}

typedef struct pass_shared {
    const vdbgi_scene *scene;
    const vdbgi_unwrap *un;
    const vdbgi_texels *tx;
    const vdbgi_bake_params *bp;
    const vdbgi_lightmap *prev; /* NULL in the first pass */
    const uint32_t *samples;    /* texel indices that sample a triangle */
    size_t sample_count;
    int pass;
    bool direct;      /* add the texel's own lamps to what it gathers */
    bool direct_only; /* only add them, to the map out already holds */
    float ao_dist;
    float *out;           /* 3 per texel */
    unsigned char *valid; /* per texel, written in the first pass */
} pass_shared;

typedef struct pass_thread {
    pass_shared *sh;
    vdbgi_estimator est;
    size_t begin, end;
    uint64_t rays, gathers, gathered;
} pass_thread;

/*
 * What the previous pass's map lights a hit with: its E / pi, as the
 * estimator adds light. The map holds the front face's light (its samples
 * stand in front): a back face gets none of it, double-sided or not.
 */
static void previous_light(const void *user, const vdbgi_hit *h, bool back, float rgb[3])
{
    const pass_shared *const sh = user;
    if (back) {
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
        return;
    }
    vdbgi_lightmap_at(sh->prev, sh->un, sh->tx, h->prim, h->u, h->v, rgb);
    for (int k = 0; k < 3; k++)
        rgb[k] /= PI_F;
}

static void *run_pass(void *arg)
{
    pass_thread *const th = arg;
    const pass_shared *const sh = th->sh;
    const vdbgi_bake_params *const bp = sh->bp;
    const size_t size = (size_t)sh->tx->size;
    for (size_t s = th->begin; s < th->end; s++) {
        const size_t i = sh->samples[s];
        const int32_t tri = sh->tx->tri[i];
        const float *const n = sh->scene->tris[tri].normal;
        /* The texel's point on its triangle, and the rays' origin one offset in front. */
        const float *const pos = &sh->tx->pos[3 * i];
        const float off = vdbgi_scene_offset(sh->scene, (uint32_t)tri);
        const float org[3] = {pos[0] + off * n[0], pos[1] + off * n[1], pos[2] + off * n[2]};
        const uint64_t stream = vdbgi_point_stream((int32_t)(i % size), (int32_t)(i / size % size),
                                                   (int32_t)(i / (size * size)), bp->seed);
        if (sh->ao_dist > 0.0f) {
            /* Ambient occlusion: the open part of the cosine-weighted hemisphere. */
            vdbgi_hemisphere_turn(th->est.base_dirs, bp->rays, n, stream,
                                  bp->sampling == VDBGI_SAMPLING_RANDOM, th->est.dir);
            const vdbgi_ray_batch rays = {org,         th->est.dir,      0,   3, 0.0f,
                                          sh->ao_dist, (size_t)bp->rays, NULL};
            vdbgi_tracer_occluded(th->est.tracer, bp->method, &rays, th->est.occluded,
                                  th->est.scratch);
            int open = 0;
            for (int r = 0; r < bp->rays; r++)
                open += !th->est.occluded[r];
            th->rays += (uint64_t)bp->rays;
            sh->valid[i] = 1;
            for (int k = 0; k < 3; k++)
                sh->out[3 * i + (size_t)k] = (float)open / (float)bp->rays;
            continue;
        }
        float *const o = &sh->out[3 * i];
        if (!sh->direct_only) {
            vdbgi_estimate e;
            vdbgi_estimate_hemisphere(&th->est, org, n, stream, &e);
            th->rays += e.rays + e.shadow;
            th->gathers++, th->gathered += e.rays;
            if (sh->pass == 0)
                sh->valid[i] = e.backface <= bp->invalid_threshold;
            if (!sh->valid[i])
                continue;
            for (int k = 0; k < 3; k++)
                o[k] = PI_F * e.rgb[k];
        } else if (!sh->valid[i]) {
            continue;
        }
        /* Fully baked: the texel's own lamps, E = pi f rgb (the lamps' light is E / pi). */
        for (int li = 0; (sh->direct || sh->direct_only) && li < bp->lamp_count; li++) {
            const vdbgi_lamp *const l = &bp->lamps[li];
            float f, dir[3], dist;
            if (!vdbgi_lamp_light(l, pos, n, &f, dir, &dist))
                continue;
            unsigned char blocked = 0;
            const vdbgi_ray_batch ray = {org, dir, 0, 0, 0.0f, dist - off, 1, NULL};
            vdbgi_tracer_occluded(th->est.tracer, bp->method, &ray, &blocked, th->est.scratch);
            th->rays++;
            if (!blocked)
                for (int k = 0; k < 3; k++)
                    o[k] += PI_F * f * l->rgb[k];
        }
    }
    return NULL;
}

/*
 * One sweep of the threads over the samples into *cur (zeroed first, or for
 * the lamps alone a copy of the map), dilated; then *cur becomes the map and
 * the map the previous one (a swap of the buffers).
 */
static vdbgi_result sweep(pass_shared *sh, pass_thread *ths, int nth, vdbgi_tracer *tracer,
                          const vdbgi_lightmap_params *lp, unsigned char *keep, float **cur,
                          vdbgi_lightmap *out, vdbgi_lightmap *prev)
{
    const size_t texels = out->texel_count, n = sh->sample_count;
    if (sh->direct_only)
        memcpy(*cur, out->rgb, texels * 3 * sizeof(float));
    else
        memset(*cur, 0, texels * 3 * sizeof(float));
    sh->prev = sh->pass ? prev : NULL;
    sh->out = *cur;
    for (int t = 0; t < nth; t++) {
        ths[t].est.hit_light = sh->pass ? previous_light : NULL;
        ths[t].begin = n * (size_t)t / (size_t)nth;
        ths[t].end = n * (size_t)(t + 1) / (size_t)nth;
    }
    vdbgi_run_threads(nth, run_pass, ths, sizeof(*ths));
    VDBGI_TRY(vdbgi_tracer_check(tracer));
    memcpy(keep, out->valid, texels);
    if (!lp->bare)
        VDBGI_TRY(vdbgi_texels_dilate(sh->tx, *cur, 3, keep, lp->rings));
    float *const done_map = *cur;
    *cur = out->rgb;
    out->rgb = done_map;
    prev->rgb = out->rgb;
    prev->texel_count = texels;
    return VDBGI_OK;
}

/* The map's light: the sum over its valid samples and channels, in order (the same bits). */
static double map_light(const vdbgi_lightmap *m, const uint32_t *samples, size_t n)
{
    double light = 0.0;
    for (size_t s = 0; s < n; s++)
        if (m->valid[samples[s]])
            for (int k = 0; k < 3; k++)
                light += m->rgb[3 * (size_t)samples[s] + (size_t)k];
    return light;
}

/*
 * The passes over one set of buffers (about 90 lines, kept whole): each
 * pass's map becomes the next one's light by a swap of buffers this
 * function owns, and one cleanup frees them on every path.
 */
vdbgi_result vdbgi_lightmap_bake(vdbgi_context *ctx, const vdbgi_scene *scene,
                                 const vdbgi_bake_params *bp, const vdbgi_unwrap *un,
                                 const vdbgi_texels *tx, const vdbgi_lightmap_params *lp,
                                 vdbgi_lightmap *out)
{
    memset(out, 0, sizeof(*out));
    /* Each pass is one bounce: the passes converge, not the paths. */
    vdbgi_bake_params one = *bp;
    if (one.bounces == 0)
        one.bounces = 1, one.converge = 0.0f;
    bp = &one;
    VDBGI_FAIL_IF(ctx, lp->passes < 0 || lp->passes > VDBGI_LIGHTMAP_MAX_PASSES,
                  VDBGI_ERR_INVALID_ARG, "passes must be 1..%d, or 0 until converged (got %d)",
                  VDBGI_LIGHTMAP_MAX_PASSES, lp->passes);
    VDBGI_FAIL_IF(ctx, lp->passes == 0 && !(lp->converge > 0.0f && lp->converge < 1.0f),
                  VDBGI_ERR_INVALID_ARG, "the converged share must be in (0, 1) (got %g)",
                  (double)lp->converge);
    VDBGI_FAIL_IF(ctx, bp->adaptive && lp->ao_dist > 0.0f, VDBGI_ERR_INVALID_ARG,
                  "an AO map takes a fixed ray count, not --rays auto");
    VDBGI_FAIL_IF(ctx, bp->adaptive && lp->bare, VDBGI_ERR_INVALID_ARG,
                  "the bare loop takes a fixed ray count (unshaded, auto sees no spread)");
    VDBGI_FAIL_IF(ctx, !(lp->ao_dist >= 0.0f) || !isfinite(lp->ao_dist), VDBGI_ERR_INVALID_ARG,
                  "AO distance must be >= 0 and finite (got %g)", (double)lp->ao_dist);
    const size_t texels = (size_t)tx->size * (size_t)tx->size * tx->page_count;
    out->ctx = ctx;
    out->texel_count = texels;
    vdbgi_tracer *tracer = NULL;
    float *dirs = NULL, *cur = NULL;
    int set = 0;
    uint32_t *samples = NULL;
    pass_thread *ths = NULL;
    unsigned char *keep = NULL;
    vdbgi_lightmap prev = {0};
    int nth = bp->threads < 1 ? 1 : bp->threads > 64 ? 64 : bp->threads;
    out->rgb = vdbgi_calloc(ctx, texels, 3 * sizeof(float));
    out->valid = vdbgi_calloc(ctx, texels, 1);
    cur = vdbgi_calloc(ctx, texels, 3 * sizeof(float));
    keep = vdbgi_alloc(ctx, texels);
    samples = vdbgi_alloc(ctx, (tx->sample_count ? tx->sample_count : 1) * sizeof(*samples));
    ths = vdbgi_calloc(ctx, (size_t)nth, sizeof(*ths));
    vdbgi_result r = out->rgb && out->valid && cur && keep && samples && ths
                         ? VDBGI_OK
                         : VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK)
        r = vdbgi_estimator_directions(ctx, bp, true, &dirs, &set);
    if (r == VDBGI_OK)
        r = vdbgi_tracer_create(ctx, scene->positions, scene->vertex_count, scene->indices,
                                scene->triangle_count, &tracer);
    /* An adaptive texel's rays by its pilot's spread: the scale from points on the surfaces,
       lit as the first pass lights them (before the threads read one), timed with that pass. */
    const double scale_t0 = vdbgi_now();
    if (r == VDBGI_OK)
        r = vdbgi_adaptive_scale(ctx, scene, tracer, NULL, true, &one);
    const double scale_seconds = vdbgi_now() - scale_t0;
    if (r != VDBGI_OK)
        goto done;
    size_t n = 0;
    for (size_t i = 0; i < texels; i++)
        if (tx->tri[i] >= 0)
            samples[n++] = (uint32_t)i;
    pass_shared sh = {.scene = scene,
                      .un = un,
                      .tx = tx,
                      .bp = bp,
                      .samples = samples,
                      .sample_count = n,
                      .ao_dist = lp->ao_dist,
                      .out = cur,
                      .valid = out->valid};
    for (int t = 0; t < nth && r == VDBGI_OK; t++) {
        ths[t].sh = &sh;
        ths[t].est = (vdbgi_estimator){.scene = scene,
                                       .tracer = tracer,
                                       .bp = bp,
                                       .base_dirs = dirs,
                                       .shade = !lp->bare,
                                       .hit_user = &sh};
        r = vdbgi_estimator_init(ctx, &ths[t].est, set);
    }
    /*
     * AO bounces nothing. Until converged, the probes' pilot says how many passes the light
     * needs; at most VDBGI_TRACED_BOUNCES are swept and the last one's increment carries the
     * rest, as a probe's third bounce does. The texels' own lamps come after.
     */
    const bool until = lp->ao_dist <= 0.0f && lp->passes == 0;
    vdbgi_bounce_plan plan = {.traced = lp->passes};
    vdbgi_bake_params pilot = *bp;
    pilot.bounces = 0;
    pilot.converge = lp->converge;
    if (r == VDBGI_OK && until)
        r = vdbgi_bounces_converge(ctx, scene, tracer, &pilot, &plan);
    const int most = lp->ao_dist > 0.0f ? 1 : plan.traced;
    double light_before = 0.0;
    for (int pass = 0; r == VDBGI_OK && pass < most; pass++) {
        sh.pass = pass;
        sh.direct = lp->direct && !until && pass == most - 1;
        const double t0 = vdbgi_now();
        if ((r = sweep(&sh, ths, nth, tracer, lp, keep, &cur, out, &prev)) != VDBGI_OK)
            break;
        if (pass < (int)(sizeof(out->pass_seconds) / sizeof(out->pass_seconds[0])))
            out->pass_seconds[pass] = vdbgi_now() - t0 + (pass == 0 ? scale_seconds : 0.0);
        out->passes = pass + 1;
        const double light = map_light(out, samples, n);
        out->last_share = light > 0.0 ? (light - light_before) / light : 0.0;
        light_before = light;
    }
    if (r == VDBGI_OK && until) {
        /* cur holds the map before the last pass: what that pass added, scaled, is the rest. */
        for (size_t i = 0; i < 3 * texels; i++)
            out->rgb[i] += pilot.tail[i % 3] * (out->rgb[i] - cur[i]);
        out->bounces = plan.bounces;
        out->last_share = plan.last_share;
        out->tail_share = plan.tail_share;
    }
    if (r == VDBGI_OK && until && lp->direct) {
        sh.direct_only = true;
        r = sweep(&sh, ths, nth, tracer, lp, keep, &cur, out, &prev);
    }
    for (int t = 0; t < nth; t++)
        out->rays += ths[t].rays, out->gathers += ths[t].gathers, out->gathered += ths[t].gathered;
    /* After the passes' timing: a report on the map, not a part of it. */
    if (r == VDBGI_OK && lp->noise && lp->ao_dist <= 0.0f)
        r = vdbgi_bake_noise(ctx, scene, tracer, NULL, true, &one, &out->noise);
    for (size_t s = 0; s < n; s++)
        out->invalid_count += !out->valid[samples[s]];
done:
    for (int t = 0; ths && t < nth; t++)
        vdbgi_estimator_free(ctx, &ths[t].est);
    vdbgi_free(ctx, ths);
    vdbgi_free(ctx, dirs);
    vdbgi_free(ctx, samples);
    vdbgi_free(ctx, keep);
    vdbgi_free(ctx, cur);
    vdbgi_tracer_destroy(tracer);
    if (r != VDBGI_OK)
        vdbgi_lightmap_free(out);
    return r;
}

vdbgi_result vdbgi_lightmap_noise(vdbgi_context *ctx, const vdbgi_scene *scene,
                                  const vdbgi_bake_params *bp, double *noise)
{
    *noise = 0.0;
    vdbgi_bake_params one = *bp; /* as the bake's passes gather */
    if (one.bounces == 0)
        one.bounces = 1, one.converge = 0.0f;
    vdbgi_tracer *tracer = NULL;
    VDBGI_TRY(vdbgi_tracer_create(ctx, scene->positions, scene->vertex_count, scene->indices,
                                  scene->triangle_count, &tracer));
    vdbgi_result r = vdbgi_adaptive_scale(ctx, scene, tracer, NULL, true, &one);
    if (r == VDBGI_OK)
        r = vdbgi_bake_noise(ctx, scene, tracer, NULL, true, &one, noise);
    if (r == VDBGI_OK)
        r = vdbgi_tracer_check(tracer);
    vdbgi_tracer_destroy(tracer);
    return r;
}

/*
 * The hemisphere estimator at count receivers, each at the position and
 * unit normal place() gives for it (one thread: receivers for error charts
 * are a few thousand). E, not E / pi, into rgb.
 */
typedef void (*place_fn)(const vdbgi_scene *s, const void *user, size_t i, float pos[3],
                         float n[3]);

static vdbgi_result bake_hemispheres(const vdbgi_scene *scene, const vdbgi_bake_desc *desc,
                                     place_fn place, const void *user, size_t count, float *rgb,
                                     float *backface)
{
    vdbgi_context *const ctx = scene->ctx;
    vdbgi_bake_params bp;
    VDBGI_TRY(vdbgi_bake_params_resolve(ctx, desc, scene, &bp));
    VDBGI_FAIL_IF(ctx, bp.adaptive, VDBGI_ERR_INVALID_ARG, "a fixed ray count, not auto");
    vdbgi_tracer *tracer = NULL;
    float *const dirs = vdbgi_calloc(ctx, (size_t)bp.rays, 3 * sizeof(float));
    vdbgi_estimator e = {.scene = scene, .bp = &bp, .base_dirs = dirs, .shade = true};
    vdbgi_result r = dirs ? vdbgi_estimator_init(ctx, &e, bp.rays) : VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK)
        r = vdbgi_tracer_create(ctx, scene->positions, scene->vertex_count, scene->indices,
                                scene->triangle_count, &tracer);
    vdbgi_bounce_plan plan;
    if (r == VDBGI_OK)
        r = vdbgi_bounces_converge(ctx, scene, tracer, &bp, &plan);
    if (r == VDBGI_OK) {
        e.tracer = tracer;
        vdbgi_hemisphere_directions(bp.rays, dirs);
    }
    for (size_t i = 0; r == VDBGI_OK && i < count; i++) {
        float pos[3], n[3];
        place(scene, user, i, pos, n);
        vdbgi_estimate est;
        vdbgi_estimate_hemisphere(&e, pos, n, vdbgi_point_stream((int32_t)i, 0, 0, bp.seed), &est);
        for (int k = 0; k < 3; k++)
            rgb[3 * i + (size_t)k] = PI_F * est.rgb[k];
        if (backface)
            backface[i] = est.backface;
    }
    if (r == VDBGI_OK)
        r = vdbgi_tracer_check(tracer);
    vdbgi_estimator_free(ctx, &e);
    vdbgi_tracer_destroy(tracer);
    vdbgi_free(ctx, dirs);
    return r;
}

typedef struct on_triangles {
    const uint32_t *prims;
    const float *uv;
} on_triangles;

/* On the triangle, lifted off its front face as a texel's sample is. */
static void place_on_triangle(const vdbgi_scene *scene, const void *user, size_t i, float pos[3],
                              float n[3])
{
    const on_triangles *const t = user;
    memcpy(n, scene->tris[t->prims[i]].normal, 3 * sizeof(float));
    const float off =
        vdbgi_scene_hit_point(scene, t->prims[i], t->uv[2 * i], t->uv[2 * i + 1], pos);
    for (int k = 0; k < 3; k++)
        pos[k] += off * n[k];
}

vdbgi_result vdbgi_scene_bake_surface(const vdbgi_scene *scene, const vdbgi_bake_desc *desc,
                                      const uint32_t *prims, const float *uv, size_t count,
                                      float *rgb, float *backface)
{
    vdbgi_context *const ctx = scene->ctx;
    VDBGI_FAIL_IF(ctx, count && (!prims || !uv || !rgb), VDBGI_ERR_INVALID_ARG,
                  "no receivers or output given");
    for (size_t i = 0; i < count; i++)
        VDBGI_FAIL_IF(ctx, prims[i] >= scene->triangle_count, VDBGI_ERR_INVALID_ARG,
                      "receiver %zu: no triangle %u", i, prims[i]);
    const on_triangles t = {prims, uv};
    return bake_hemispheres(scene, desc, place_on_triangle, &t, count, rgb, backface);
}

typedef struct at_points {
    const float *points, *normals;
} at_points;

static void place_at_point(const vdbgi_scene *scene, const void *user, size_t i, float pos[3],
                           float n[3])
{
    (void)scene;
    const at_points *const a = user;
    memcpy(pos, &a->points[3 * i], 3 * sizeof(float));
    memcpy(n, &a->normals[3 * i], 3 * sizeof(float));
}

vdbgi_result vdbgi_scene_bake_hemispheres(const vdbgi_scene *scene, const vdbgi_bake_desc *desc,
                                          const float *points, const float *normals, size_t count,
                                          float *rgb, float *backface)
{
    vdbgi_context *const ctx = scene->ctx;
    VDBGI_FAIL_IF(ctx, count && (!points || !normals || !rgb), VDBGI_ERR_INVALID_ARG,
                  "no receivers or output given");
    for (size_t i = 0; i < count; i++) {
        const float *const n = &normals[3 * i];
        const float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        VDBGI_FAIL_IF(ctx, !(fabsf(len2 - 1.0f) < 1e-3f), VDBGI_ERR_INVALID_ARG,
                      "receiver %zu: the normal is not a unit vector", i);
        for (int k = 0; k < 3; k++)
            VDBGI_FAIL_IF(ctx, !isfinite(points[3 * i + k]), VDBGI_ERR_INVALID_ARG,
                          "receiver %zu is not finite", i);
    }
    const at_points a = {points, normals};
    return bake_hemispheres(scene, desc, place_at_point, &a, count, rgb, backface);
}
