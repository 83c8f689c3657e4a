/*
 * bake.c: the driver: sample points (lattice probes or given points) handed
 * out over threads in chunks, each through the estimator, with progress.
 */
#include "estimate.h"
#include "probes.h"
#include "util.h"

#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>

/* Points handed to a thread at a time: small enough to balance, big enough to amortise. */
#define CHUNK 32

typedef struct bake_shared {
    vdbgi_context *ctx;
    const vdbgi_bake_params *bp;
    vdbgi_estimator proto; /* scene, tracer, direction set: what every thread reads */
    /* Either a lattice (ijk + origin + spacing) or explicit points. */
    const int32_t *ijk;
    const float *points;
    double origin[3], spacing, margin;
    size_t count;
    float *rgb, *backface;
    float *stderr_;  /* per probe, or NULL */
    uint32_t *rays;  /* per probe, or NULL */
    float *cube;     /* 18 per probe, or NULL */
    float *sh;       /* 24 per point (L2 terms c1..c8), or NULL */
    uint16_t *terms; /* 24 per probe, as vdbgi_probes holds them (vdbgi_term_encode), or NULL */
    int (*progress)(void *user, float done);
    void *progress_user;
    /* Work distribution. */
    atomic_size_t next;
    atomic_size_t done;
    atomic_int cancel;
} bake_shared;

typedef struct bake_thread {
    bake_shared *sh;
    vdbgi_estimator est;
    bool reports; /* the caller's thread: it calls progress */
    uint64_t primary, shadow, hits_count, invalid;
} bake_thread;

static void bake_point(bake_thread *th, size_t index)
{
    const bake_shared *const sh = th->sh;
    float pos[3];
    uint64_t stream;
    if (sh->ijk) {
        const int32_t *const c = &sh->ijk[3 * index];
        for (int k = 0; k < 3; k++)
            pos[k] = (float)(sh->origin[k] + sh->spacing * c[k]);
        stream = vdbgi_point_stream(c[0], c[1], c[2], sh->bp->seed);
    } else {
        memcpy(pos, &sh->points[3 * index], sizeof(pos));
        stream = vdbgi_point_stream((int32_t)index, 0, 0, sh->bp->seed);
    }
    vdbgi_estimate e;
    vdbgi_estimate_point(&th->est, pos, stream, &e);
    th->primary += e.rays;
    th->shadow += e.shadow;
    th->hits_count += e.hits;
    th->invalid += e.backface > sh->bp->invalid_threshold;
    if (!th->est.shade)
        return;
    memcpy(&sh->rgb[3 * index], e.rgb, sizeof(e.rgb));
    sh->backface[index] = e.backface;
    if (sh->stderr_)
        sh->stderr_[index] = e.stderr_;
    if (sh->rays)
        sh->rays[index] = e.rays;
    if (sh->cube)
        memcpy(&sh->cube[18 * index], e.cube, sizeof(e.cube));
    if (sh->sh)
        memcpy(&sh->sh[24 * index], e.sh, sizeof(e.sh));
    if (sh->terms)
        vdbgi_terms_encode(e.sh, e.rgb, &sh->terms[24 * index]);
}

/* Take chunks until none are left; returns after the last one or on cancel. */
static void *run_chunks(void *arg)
{
    bake_thread *const th = arg;
    bake_shared *const sh = th->sh;
    size_t reported = 0; /* percent */
    for (;;) {
        if (atomic_load(&sh->cancel))
            return NULL;
        const size_t begin = atomic_fetch_add(&sh->next, CHUNK);
        if (begin >= sh->count)
            return NULL;
        const size_t end = begin + CHUNK < sh->count ? begin + CHUNK : sh->count;
        for (size_t i = begin; i < end; i++)
            bake_point(th, i);
        const size_t done = atomic_fetch_add(&sh->done, end - begin) + (end - begin);
        if (th->reports && sh->progress) {
            const size_t percent = done * 100 / sh->count;
            if (percent > reported) {
                reported = percent;
                if (sh->progress(sh->progress_user, (float)done / (float)sh->count))
                    atomic_store(&sh->cancel, 1);
            }
        }
    }
}

/* Run sh over bp->threads threads (the caller's included) and sum the counters; with noise,
   stats->noise too (vdbgi_bake_noise). */
static vdbgi_result bake_run(bake_shared *sh, const vdbgi_scene *scene, bool shade,
                             vdbgi_bake_stats *stats, bool noise)
{
    vdbgi_context *const ctx = sh->ctx;
    /* Loading a scene builds no BVH: a bake builds its own, outside its timing. */
    vdbgi_tracer *tracer = NULL;
    VDBGI_TRY(vdbgi_tracer_create(ctx, scene->positions, scene->vertex_count, scene->indices,
                                  scene->triangle_count, &tracer));
    const double t0 = vdbgi_now();
    /* Bounces left to convergence are counted first, on this copy the threads read. */
    vdbgi_bake_params run = *sh->bp;
    vdbgi_bounce_plan plan;
    vdbgi_result r = vdbgi_bounces_converge(ctx, scene, tracer, &run, &plan);
    const double lattice[5] = {sh->origin[0], sh->origin[1], sh->origin[2], sh->spacing,
                               sh->margin};
    if (r == VDBGI_OK && shade) /* and an adaptive bake's rays for its spread */
        r = vdbgi_adaptive_scale(ctx, scene, tracer, sh->ijk ? lattice : NULL, false, &run);
    const vdbgi_bake_params *const bp = sh->bp = &run;
    float *base_dirs = NULL;
    int set = 0;
    if (r == VDBGI_OK)
        r = vdbgi_estimator_directions(ctx, bp, false, &base_dirs, &set);
    sh->proto = (vdbgi_estimator){.scene = scene,
                                  .tracer = tracer,
                                  .bp = bp,
                                  .base_dirs = base_dirs,
                                  .shade = shade,
                                  .cube = sh->cube,
                                  .sh2 = sh->sh || sh->terms};
    atomic_init(&sh->next, 0);
    atomic_init(&sh->done, 0);
    atomic_init(&sh->cancel, 0);

    /* No more threads than chunks: idle threads would only cost their scratch. */
    const size_t chunks = (sh->count + CHUNK - 1) / CHUNK;
    const int nth = (size_t)bp->threads < chunks ? bp->threads : (chunks ? (int)chunks : 1);
    bake_thread *const ths = r == VDBGI_OK ? vdbgi_calloc(ctx, (size_t)nth, sizeof(*ths)) : NULL;
    if (r == VDBGI_OK && !ths)
        r = VDBGI_ERR_OUT_OF_MEMORY;
    for (int t = 0; r == VDBGI_OK && t < nth; t++) {
        ths[t].sh = sh;
        ths[t].est = sh->proto;
        ths[t].reports = t == 0;
        r = vdbgi_estimator_init(ctx, &ths[t].est, set);
    }
    int ran = 0;
    if (r == VDBGI_OK) {
        ran = vdbgi_run_threads(nth, run_chunks, ths, sizeof(*ths));
        if (atomic_load(&sh->cancel))
            r = vdbgi_fail(ctx, VDBGI_ERR_CANCELLED, "bake cancelled after %zu of %zu probes",
                           (size_t)atomic_load(&sh->done), sh->count);
        else
            r = vdbgi_tracer_check(tracer);
    }
    if (r == VDBGI_OK && stats) {
        memset(stats, 0, sizeof(*stats));
        stats->probe_count = sh->count;
        for (int t = 0; t < nth; t++) {
            stats->primary_ray_count += ths[t].primary;
            stats->shadow_ray_count += ths[t].shadow;
            stats->hit_count += ths[t].hits_count;
            stats->invalid_probe_count += ths[t].invalid;
        }
        stats->threads = ran;
        stats->seconds = vdbgi_now() - t0;
        stats->bounces = plan.bounces;
        stats->bounces_traced = plan.traced;
        stats->last_share = plan.last_share;
        stats->tail_share = plan.tail_share;
        /* Measured after the timing, when asked: a report on the bake, not a part of it. */
        if (noise)
            r = vdbgi_bake_noise(ctx, scene, tracer, sh->ijk ? lattice : NULL, false, bp,
                                 &stats->noise);
    }
    sh->bp = NULL; /* run is gone with this call */
    for (int t = 0; ths && t < nth; t++)
        vdbgi_estimator_free(ctx, &ths[t].est);
    vdbgi_free(ctx, ths);
    vdbgi_free(ctx, base_dirs);
    vdbgi_tracer_destroy(tracer);
    return r;
}

static const char *basis_name(vdbgi_basis b)
{
    return b == VDBGI_BASIS_AMBIENT_CUBE ? "ambient-cube" : b == VDBGI_BASIS_SH2 ? "sh2" : "scalar";
}

static const char *sampling_name(vdbgi_sampling s)
{
    return s == VDBGI_SAMPLING_RANDOM ? "random" : "fibonacci";
}

/* Every setting that shaped the values, so a .vdb says how it was made. */
static void record_settings(vdbgi_probes *p, const vdbgi_scene *scene, const vdbgi_bake_params *bp,
                            const vdbgi_bake_stats *st)
{
    const float origin[3] = {(float)p->origin[0], (float)p->origin[1], (float)p->origin[2]};
    vdbgi_meta_set_string(&p->meta, "vdbgi_version", vdbgi_version_string());
    vdbgi_meta_set_string(&p->meta, "scene", scene->name);
    vdbgi_meta_set_int(&p->meta, "triangles", (int64_t)scene->triangle_count);
    vdbgi_meta_set_int(&p->meta, "probes", (int64_t)p->count);
    vdbgi_meta_set_int(&p->meta, "invalid_probes", (int64_t)p->invalid_count);
    vdbgi_meta_set_double(&p->meta, "bake_seconds", st->seconds);
    vdbgi_meta_set_double(&p->meta, "spacing", p->spacing);
    vdbgi_meta_set_double(&p->meta, "margin", p->margin);
    vdbgi_meta_set_vec3(&p->meta, "origin", origin);
    vdbgi_meta_set_int(&p->meta, "rays", bp->adaptive ? VDBGI_META_RAYS_ADAPTIVE : bp->rays);
    if (bp->adaptive) {
        vdbgi_meta_set_double(&p->meta, "noise", bp->noise);
        vdbgi_meta_set_int(&p->meta, "max_rays", bp->max_rays);
    }
    vdbgi_meta_set_double(&p->meta, "ray_dist", bp->ray_dist);
    vdbgi_meta_set_double(&p->meta, "ambient", bp->ambient);
    vdbgi_meta_set_vec3(&p->meta, "sun_dir", bp->sun_dir);
    vdbgi_meta_set_vec3(&p->meta, "sun_color", bp->sun_color);
    vdbgi_meta_set_double(&p->meta, "falloff", bp->falloff);
    vdbgi_meta_set_vec3(&p->meta, "sky", bp->sky);
    vdbgi_meta_set_string(&p->meta, "sampling", sampling_name(bp->sampling));
    vdbgi_meta_set_int(&p->meta, "seed", (int64_t)bp->seed);
    vdbgi_meta_set_double(&p->meta, "invalid_threshold", bp->invalid_threshold);
    vdbgi_meta_set_double(&p->meta, "ray_offset", scene->ray_offset);
    vdbgi_meta_set_string(&p->meta, "basis", basis_name(bp->basis));
    if (p->tile_count > 1) {
        /* What gi-merge checks: which tile of how many, the range of i it holds, and the
           range all the tiles cover. */
        vdbgi_meta_set_int(&p->meta, "tile_index", p->tile_index);
        vdbgi_meta_set_int(&p->meta, "tile_count", p->tile_count);
        vdbgi_meta_set_int(&p->meta, "tile_x_begin", p->tile_x[0]);
        vdbgi_meta_set_int(&p->meta, "tile_x_end", p->tile_x[1]);
        vdbgi_meta_set_int(&p->meta, "tiles_x_begin", p->tile_span[0]);
        vdbgi_meta_set_int(&p->meta, "tiles_x_end", p->tile_span[1]);
    }
    vdbgi_meta_set_string(&p->meta, "model",
                          bp->model == VDBGI_MODEL_PHYSICAL ? "physical" : "seed");
    vdbgi_meta_set_int(&p->meta, "bounces", st->bounces);
    if (bp->converge > 0.0f) {
        vdbgi_meta_set_double(&p->meta, "converge", bp->converge);
        vdbgi_meta_set_int(&p->meta, "bounces_traced", st->bounces_traced);
        vdbgi_meta_set_double(&p->meta, "bounce_tail_share", st->tail_share);
    }
    vdbgi_meta_set_int(&p->meta, "scene_lights", bp->scene_lamps);
    if (bp->sky_map) {
        char hash[17];
        snprintf(hash, sizeof(hash), "%016llx", (unsigned long long)vdbgi_sky_hash(bp->sky_map));
        vdbgi_meta_set_string(&p->meta, "sky_map", hash);
    }
}

vdbgi_result vdbgi_probes_bake(vdbgi_probes *p, const vdbgi_scene *scene,
                               const vdbgi_bake_desc *desc, vdbgi_bake_stats *stats)
{
    vdbgi_context *const ctx = p->ctx;
    VDBGI_FAIL_IF(ctx, !scene, VDBGI_ERR_INVALID_ARG, "no scene given");
    vdbgi_bake_params bp;
    VDBGI_TRY(vdbgi_bake_params_resolve(ctx, desc, scene, &bp));
    const size_t n = p->count ? p->count : 1;
    /* The new values, kept apart until complete: old ones are replaced only then. */
    float *next[4] = {
        vdbgi_calloc(ctx, n, 3 * sizeof(float)), vdbgi_calloc(ctx, n, sizeof(float)),
        vdbgi_calloc(ctx, n, sizeof(float)),
        bp.basis == VDBGI_BASIS_AMBIENT_CUBE ? vdbgi_calloc(ctx, n, 18 * sizeof(float)) : NULL};
    uint16_t *terms =
        bp.basis == VDBGI_BASIS_SH2 ? vdbgi_calloc(ctx, n, 24 * sizeof(uint16_t)) : NULL;
    uint32_t *rays = bp.adaptive ? vdbgi_calloc(ctx, n, sizeof(uint32_t)) : NULL;
    float *const rgb = next[0], *const backface = next[1], *const stderr_ = next[2];
    float *const cube = next[3];
    if (!rgb || !backface || !stderr_ || (bp.basis == VDBGI_BASIS_AMBIENT_CUBE && !cube) ||
        (bp.basis == VDBGI_BASIS_SH2 && !terms) || (bp.adaptive && !rays)) {
        for (int a = 0; a < 4; a++)
            vdbgi_free(ctx, next[a]);
        vdbgi_free(ctx, terms);
        vdbgi_free(ctx, rays);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    bake_shared sh = {.ctx = ctx,
                      .bp = &bp,
                      .ijk = p->ijk,
                      .spacing = p->spacing,
                      .margin = p->margin,
                      .count = p->count,
                      .rgb = rgb,
                      .backface = backface,
                      .stderr_ = stderr_,
                      .rays = rays,
                      .cube = cube,
                      .terms = terms,
                      .progress = desc ? desc->progress : NULL,
                      .progress_user = desc ? desc->progress_user : NULL};
    memcpy(sh.origin, p->origin, sizeof(sh.origin));
    vdbgi_bake_stats st;
    const vdbgi_result r = bake_run(&sh, scene, true, &st, stats != NULL);
    if (r != VDBGI_OK) {
        for (int a = 0; a < 4; a++)
            vdbgi_free(ctx, next[a]);
        vdbgi_free(ctx, terms);
        vdbgi_free(ctx, rays);
        return r;
    }
    float **const cur[4] = {&p->rgb, &p->backface, &p->stderr_, &p->cube};
    for (int a = 0; a < 4; a++) {
        vdbgi_free(ctx, *cur[a]);
        *cur[a] = next[a];
    }
    vdbgi_free(ctx, p->sh);
    p->sh = terms;
    vdbgi_free(ctx, p->rays);
    p->rays = rays;
    p->invalid_threshold = bp.invalid_threshold;
    p->sampling = bp.sampling;
    p->adaptive = bp.adaptive;
    p->invalid_count = (size_t)st.invalid_probe_count;
    record_settings(p, scene, &bp, &st);
    /* A black bake is almost always a scene without light (a closed room with no lamp under the
       physical model), not what was wanted: say so rather than write darkness silently. */
    bool lit = false, valid = false;
    for (size_t i = 0; i < n && !lit; i++)
        if (!(p->backface[i] > bp.invalid_threshold)) {
            valid = true;
            lit = p->rgb[3 * i] > 0.0f || p->rgb[3 * i + 1] > 0.0f || p->rgb[3 * i + 2] > 0.0f;
        }
    if (valid && !lit)
        vdbgi_log(ctx, VDBGI_LOG_WARNING,
                  "no light reached any probe: no lamp, sun, sky or emitter lights what they "
                  "see%s",
                  bp.model == VDBGI_MODEL_PHYSICAL ? " (the seed model's ambient fill would)" : "");
    if (stats)
        *stats = st;
    return VDBGI_OK;
}

vdbgi_result vdbgi_probes_trace_bare(const vdbgi_probes *p, const vdbgi_scene *scene,
                                     const vdbgi_bake_desc *desc, vdbgi_bake_stats *stats)
{
    vdbgi_context *const ctx = p->ctx;
    VDBGI_FAIL_IF(ctx, !scene || !stats, VDBGI_ERR_INVALID_ARG, "no scene or stats given");
    vdbgi_bake_params bp;
    VDBGI_TRY(vdbgi_bake_params_resolve(ctx, desc, scene, &bp));
    VDBGI_FAIL_IF(ctx, bp.adaptive, VDBGI_ERR_INVALID_ARG,
                  "the bare loop needs a fixed ray count: an adaptive one depends on shading");
    bake_shared sh = {.ctx = ctx,
                      .bp = &bp,
                      .ijk = p->ijk,
                      .spacing = p->spacing,
                      .margin = p->margin,
                      .count = p->count,
                      .progress = desc ? desc->progress : NULL,
                      .progress_user = desc ? desc->progress_user : NULL};
    memcpy(sh.origin, p->origin, sizeof(sh.origin));
    return bake_run(&sh, scene, false, stats, false);
}

/* Points baked as given: rgb (3 floats each), backface (1, may be NULL) and, when terms is
   not NULL, the L2 terms c1..c8 (24 floats each). */
static vdbgi_result bake_points(const vdbgi_scene *scene, const vdbgi_bake_desc *desc,
                                const float *points, size_t point_count, float *rgb,
                                float *backface, float *terms)
{
    if (!scene)
        return VDBGI_ERR_INVALID_ARG;
    vdbgi_context *const ctx = scene->ctx;
    VDBGI_FAIL_IF(ctx, point_count && (!points || !rgb), VDBGI_ERR_INVALID_ARG,
                  "no points or output given");
    for (size_t i = 0; i < point_count * 3; i++)
        VDBGI_FAIL_IF(ctx, !isfinite(points[i]), VDBGI_ERR_INVALID_ARG, "point %zu is not finite",
                      i / 3);
    vdbgi_bake_params bp;
    VDBGI_TRY(vdbgi_bake_params_resolve(ctx, desc, scene, &bp));
    float *bf = backface;
    if (!bf && !(bf = vdbgi_calloc(ctx, point_count ? point_count : 1, sizeof(float))))
        return VDBGI_ERR_OUT_OF_MEMORY;
    bake_shared sh = {.ctx = ctx,
                      .bp = &bp,
                      .points = points,
                      .count = point_count,
                      .rgb = rgb,
                      .backface = bf,
                      .sh = terms,
                      .progress = desc ? desc->progress : NULL,
                      .progress_user = desc ? desc->progress_user : NULL};
    const vdbgi_result r = bake_run(&sh, scene, true, NULL, false);
    if (bf != backface)
        vdbgi_free(ctx, bf);
    return r;
}

vdbgi_result vdbgi_scene_bake_points(const vdbgi_scene *scene, const vdbgi_bake_desc *desc,
                                     const float *points, size_t point_count, float *rgb,
                                     float *backface)
{
    return bake_points(scene, desc, points, point_count, rgb, backface, NULL);
}

vdbgi_result vdbgi_scene_bake_points_sh2(const vdbgi_scene *scene, const vdbgi_bake_desc *desc,
                                         const float *points, size_t point_count, float *sh)
{
    if (!scene)
        return VDBGI_ERR_INVALID_ARG;
    const size_t n = point_count ? point_count : 1;
    float *const rgb = vdbgi_calloc(scene->ctx, n, 3 * sizeof(float));
    float *const terms = vdbgi_calloc(scene->ctx, n, 24 * sizeof(float));
    vdbgi_result r = rgb && terms ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK && point_count && !sh)
        r = vdbgi_fail(scene->ctx, VDBGI_ERR_INVALID_ARG, "no points or output given");
    if (r == VDBGI_OK)
        r = bake_points(scene, desc, points, point_count, rgb, NULL, terms);
    for (size_t i = 0; r == VDBGI_OK && i < point_count; i++) {
        memcpy(&sh[27 * i], &rgb[3 * i], 3 * sizeof(float));
        memcpy(&sh[27 * i + 3], &terms[24 * i], 24 * sizeof(float));
    }
    vdbgi_free(scene->ctx, rgb);
    vdbgi_free(scene->ctx, terms);
    return r;
}
