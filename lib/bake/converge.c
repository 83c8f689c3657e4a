/*
 * converge.c: how many bounces a scene's light needs. A pilot of receivers
 * spread over the surfaces by area is traced VDBGI_MAX_BOUNCES deep, each
 * bounce's light summed apart; the count is where the next bounce would add
 * less than the asked share. Only the first VDBGI_TRACED_BOUNCES are traced
 * at every probe: past them a bounce's light over a scene keeps its shape
 * and shrinks by a steady ratio, so the last traced one, scaled by what the
 * pilot saw of the rest, carries them (the "ambient term" of progressive
 * radiosity, measured rather than assumed).
 */
#include "band.h"
#include "estimate.h"
#include "util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Enough receivers that the sums settle to well under the share asked (docs/lights.md). */
#define PILOT_RECEIVERS 1024
#define PILOT_RAYS 32
#define DEPTHS (VDBGI_MAX_BOUNCES + 1)

typedef struct pilot_job {
    vdbgi_estimator est;
    const float *pos, *normal;
    size_t first, end;
    double *light; /* DEPTHS x RGB per receiver */
    uint64_t seed;
} pilot_job;

static void *run_pilot(void *arg)
{
    pilot_job *const j = arg;
    for (size_t i = j->first; i < j->end; i++) {
        j->est.depth_light = &j->light[3 * DEPTHS * i];
        vdbgi_estimate e;
        vdbgi_estimate_hemisphere(&j->est, &j->pos[3 * i], &j->normal[3 * i],
                                  vdbgi_point_stream((int32_t)i, -1, 0, j->seed), &e);
    }
    return NULL;
}

/*
 * Receiver i of n: on the triangle where (i + 1/2) / n falls in the area's
 * running sum, at a point its stream picks, lifted off the front face as a
 * texel's sample is; *placed false (and none placed) when the scene has no
 * area.
 */
static vdbgi_result place_receivers(vdbgi_context *ctx, const vdbgi_scene *scene, size_t n,
                                    uint64_t seed, float *pos, float *normal, bool *placed)
{
    const size_t tris = scene->triangle_count;
    double *const cdf = vdbgi_calloc(ctx, tris ? tris : 1, sizeof(double));
    if (!cdf)
        return VDBGI_ERR_OUT_OF_MEMORY;
    double area = 0.0;
    for (size_t t = 0; t < tris; t++)
        cdf[t] = area += vdbgi_scene_triangle_area(scene, t);
    *placed = area > 0.0;
    for (size_t i = 0; *placed && i < n; i++) {
        const double want = ((double)i + 0.5) / (double)n * cdf[tris - 1];
        size_t lo = 0, hi = tris - 1;
        while (lo < hi) {
            const size_t mid = lo + (hi - lo) / 2;
            if (cdf[mid] < want)
                lo = mid + 1;
            else
                hi = mid;
        }
        uint64_t st = vdbgi_point_stream((int32_t)i, -2, 0, seed);
        const double r1 = sqrt(vdbgi_uniform01(&st)), r2 = vdbgi_uniform01(&st);
        const float u = (float)(r1 * (1.0 - r2)), v = (float)(r1 * r2);
        const float *const nt = scene->tris[lo].normal;
        const float off = vdbgi_scene_hit_point(scene, (uint32_t)lo, u, v, &pos[3 * i]);
        for (int k = 0; k < 3; k++) {
            normal[3 * i + k] = nt[k];
            pos[3 * i + k] += off * nt[k];
        }
    }
    vdbgi_free(ctx, cdf);
    return VDBGI_OK;
}

/*
 * The count from the pilot's sums per bounce, B[k] (RGB) for k in
 * 0..VDBGI_MAX_BOUNCES: decided on the light over the channels, while the
 * tail is each channel's own (later bounces redden in a red room).
 */
static void plan_from(const double B[][3], float converge, vdbgi_bounce_plan *plan, float tail[3])
{
    double b[DEPTHS];
    for (int k = 0; k < DEPTHS; k++)
        b[k] = B[k][0] + B[k][1] + B[k][2];
    double light = b[0] + b[1];
    int n = 1;
    while (n < VDBGI_MAX_BOUNCES && b[n + 1] > converge * (light + b[n + 1]))
        light += b[++n];
    const int traced = n < VDBGI_TRACED_BOUNCES ? n : VDBGI_TRACED_BOUNCES;
    double rest = 0.0;
    for (int c = 0; c < 3; c++) {
        double part = 0.0;
        for (int k = traced + 1; k <= n; k++)
            part += B[k][c];
        tail[c] = B[traced][c] > 0.0 ? (float)(part / B[traced][c]) : 0.0f;
        rest += part;
    }
    plan->bounces = n;
    plan->traced = traced;
    plan->last_share = light > 0.0 ? b[n] / light : 0.0;
    plan->tail_share = light > 0.0 ? rest / light : 0.0;
}

vdbgi_result vdbgi_bounces_converge(vdbgi_context *ctx, const vdbgi_scene *scene,
                                    const vdbgi_tracer *tracer, vdbgi_bake_params *bp,
                                    vdbgi_bounce_plan *plan)
{
    memset(plan, 0, sizeof(*plan));
    if (bp->bounces > 0) {
        plan->bounces = plan->traced = bp->bounces;
        return VDBGI_OK;
    }
    const size_t n = PILOT_RECEIVERS;
    int nth = bp->threads < 1 ? 1 : bp->threads > 64 ? 64 : bp->threads;
    vdbgi_bake_params pilot = *bp;
    pilot.bounces = VDBGI_MAX_BOUNCES;
    pilot.rays = PILOT_RAYS;
    pilot.adaptive = false;
    pilot.tail[0] = pilot.tail[1] = pilot.tail[2] = 0.0f;
    float *const pos = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    float *const normal = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    double *const light = vdbgi_calloc(ctx, n, 3 * DEPTHS * sizeof(double));
    float *const dirs = vdbgi_calloc(ctx, PILOT_RAYS, 3 * sizeof(float));
    pilot_job *const jobs = vdbgi_calloc(ctx, (size_t)nth, sizeof(*jobs));
    vdbgi_result r = pos && normal && light && dirs && jobs ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    bool placed = false;
    if (r == VDBGI_OK)
        r = place_receivers(ctx, scene, n, bp->seed, pos, normal, &placed);
    if (r == VDBGI_OK && placed) {
        vdbgi_hemisphere_directions(PILOT_RAYS, dirs);
        for (int t = 0; t < nth && r == VDBGI_OK; t++) {
            jobs[t] = (pilot_job){.est = {.scene = scene,
                                          .tracer = tracer,
                                          .bp = &pilot,
                                          .base_dirs = dirs,
                                          .shade = true},
                                  .pos = pos,
                                  .normal = normal,
                                  .first = n * (size_t)t / (size_t)nth,
                                  .end = n * (size_t)(t + 1) / (size_t)nth,
                                  .light = light,
                                  .seed = bp->seed};
            r = vdbgi_estimator_init(ctx, &jobs[t].est, PILOT_RAYS);
            if (r != VDBGI_OK)
                nth = t; /* those before it are freed below */
        }
        if (r == VDBGI_OK)
            vdbgi_run_threads(nth, run_pilot, jobs, sizeof(*jobs));
    }
    if (r == VDBGI_OK) {
        /* Summed in receiver order, so the count is the same on any number of threads. */
        double B[DEPTHS][3] = {{0}};
        for (size_t i = 0; i < n; i++)
            for (int k = 0; k < DEPTHS; k++)
                for (int c = 0; c < 3; c++)
                    B[k][c] += light[3 * (DEPTHS * i + (size_t)k) + (size_t)c];
        plan_from(B, bp->converge, plan, bp->tail);
        bp->bounces = plan->traced;
    }
    for (int t = 0; jobs && t < nth; t++)
        vdbgi_estimator_free(ctx, &jobs[t].est);
    vdbgi_free(ctx, jobs);
    vdbgi_free(ctx, dirs);
    vdbgi_free(ctx, light);
    vdbgi_free(ctx, normal);
    vdbgi_free(ctx, pos);
    return r;
}

/* Points estimated as probes, each: its light per channel, the spread of its rays, and the
   share of them that met back faces. */
#define SPREAD_OUT 5
typedef struct spread_job {
    vdbgi_estimator est;
    const float *pos, *normal; /* normal: NULL for probes, else surface points' */
    size_t first, end;
    int32_t salt; /* which of a point's streams */
    double *out;  /* SPREAD_OUT a point: RGB, the rays' standard deviation, back faces */
    uint64_t seed;
} spread_job;

static void *run_spread(void *arg)
{
    spread_job *const j = arg;
    for (size_t i = j->first; i < j->end; i++) {
        vdbgi_estimate e;
        const uint64_t stream = vdbgi_point_stream((int32_t)i, j->salt, 0, j->seed);
        if (j->normal)
            vdbgi_estimate_hemisphere(&j->est, &j->pos[3 * i], &j->normal[3 * i], stream, &e);
        else
            vdbgi_estimate_point(&j->est, &j->pos[3 * i], stream, &e);
        double *const o = &j->out[SPREAD_OUT * i];
        for (int k = 0; k < 3; k++)
            o[k] = e.rgb[k];
        o[3] = (double)e.stderr_ * sqrt((double)e.rays);
        o[4] = e.backface;
    }
    return NULL;
}

/* The first n of pos estimated under bp (its own directions) with the points' salt streams,
   as probes, or given their normals as surface points; unshaded, only the back faces. */
static vdbgi_result trace_points(vdbgi_context *ctx, const vdbgi_scene *scene,
                                 const vdbgi_tracer *tracer, const vdbgi_bake_params *bp,
                                 const float *pos, const float *normal, size_t n, int32_t salt,
                                 bool shade, double *out)
{
    int nth = bp->threads < 1 ? 1 : bp->threads > 64 ? 64 : bp->threads;
    float *dirs = NULL;
    int set = 0;
    spread_job *const jobs = vdbgi_calloc(ctx, (size_t)nth, sizeof(*jobs));
    vdbgi_result r = jobs ? vdbgi_estimator_directions(ctx, bp, normal != NULL, &dirs, &set)
                          : VDBGI_ERR_OUT_OF_MEMORY;
    for (int t = 0; t < nth && r == VDBGI_OK; t++) {
        jobs[t] = (spread_job){
            .est = {.scene = scene, .tracer = tracer, .bp = bp, .base_dirs = dirs, .shade = shade},
            .pos = pos,
            .normal = normal,
            .first = n * (size_t)t / (size_t)nth,
            .end = n * (size_t)(t + 1) / (size_t)nth,
            .salt = salt,
            .out = out,
            .seed = bp->seed};
        r = vdbgi_estimator_init(ctx, &jobs[t].est, set);
        if (r != VDBGI_OK)
            nth = t;
    }
    if (r == VDBGI_OK)
        vdbgi_run_threads(nth, run_spread, jobs, sizeof(*jobs));
    for (int t = 0; jobs && t < nth; t++)
        vdbgi_estimator_free(ctx, &jobs[t].est);
    vdbgi_free(ctx, jobs);
    vdbgi_free(ctx, dirs);
    return r;
}

static vdbgi_result spread(vdbgi_context *ctx, const vdbgi_scene *scene, const vdbgi_tracer *tracer,
                           const vdbgi_bake_params *bp, const float *pos, const float *normal,
                           size_t n, int32_t salt, double *out)
{
    return trace_points(ctx, scene, tracer, bp, pos, normal, n, salt, true, out);
}

/*
 * The error bp gives the NOISE_POINTS points pos holds, over their mean light:
 * each estimated twice under streams of its own, the RMS of the two's
 * difference over sqrt 2 (one estimate's error), summed in point order.
 * A bake with no random rotation of its own is measured under one.
 */
#define NOISE_POINTS 256

static vdbgi_result measure_noise(vdbgi_context *ctx, const vdbgi_scene *scene,
                                  const vdbgi_tracer *tracer, const vdbgi_bake_params *bp,
                                  const float *pos, const float *normal, int32_t salt,
                                  double *noise)
{
    vdbgi_bake_params b = *bp;
    if (!b.adaptive)
        b.sampling = VDBGI_SAMPLING_RANDOM;
    double *const est = vdbgi_calloc(ctx, 2 * NOISE_POINTS, SPREAD_OUT * sizeof(double));
    vdbgi_result r = est ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK)
        r = spread(ctx, scene, tracer, &b, pos, normal, NOISE_POINTS, salt, est);
    double *const again = est ? &est[SPREAD_OUT * NOISE_POINTS] : NULL;
    if (r == VDBGI_OK)
        r = spread(ctx, scene, tracer, &b, pos, normal, NOISE_POINTS, salt - 1, again);
    double sq = 0.0, light = 0.0;
    size_t valid = 0;
    for (size_t i = 0; r == VDBGI_OK && i < NOISE_POINTS; i++) {
        const double *const x = &est[SPREAD_OUT * i], *const y = &again[SPREAD_OUT * i];
        if (!(x[4] <= bp->invalid_threshold && y[4] <= bp->invalid_threshold))
            continue; /* filled, not baked, as the bake's invalid probes are */
        for (size_t k = 0; k < 3; k++) {
            sq += (x[k] - y[k]) * (x[k] - y[k]) / 2.0;
            light += (x[k] + y[k]) / 2.0;
        }
        valid++;
    }
    *noise = light > 0.0 ? sqrt(sq / (3.0 * (double)valid)) / (light / (3.0 * (double)valid)) : 0.0;
    vdbgi_free(ctx, est);
    return r;
}

/* A band point: its fine ijk and the hash that picks it. */
typedef struct band_pick {
    uint64_t hash;
    int32_t ijk[3];
} band_pick;

static int by_hash(const void *a, const void *b)
{
    const band_pick *const x = a, *const y = b;
    if (x->hash != y->hash)
        return x->hash < y->hash ? -1 : 1;
    return memcmp(x->ijk, y->ijk, sizeof(x->ijk));
}

/*
 * The band's points on k lattices k times coarser than lattice's, each
 * shifted by o (0..k-1) fine steps on every axis, so that every layer of
 * the fine lattice along every axis is reached (one coarse lattice alone
 * keeps one layer in k: over a plane, one height), into *out (fine ijk,
 * hashed by the fine point's stream), *count of them. About 1/k^2 of the
 * fine lattice's points.
 */
static vdbgi_result band_candidates(vdbgi_context *ctx, const vdbgi_scene *scene,
                                    const double lattice[5], int k, uint64_t seed, int threads,
                                    band_pick **out, size_t *count)
{
    int32_t *ijk[4] = {NULL, NULL, NULL, NULL};
    size_t m[4] = {0, 0, 0, 0}, total = 0;
    vdbgi_result r = VDBGI_OK;
    for (int o = 0; o < k && r == VDBGI_OK; o++) {
        vdbgi_band_desc band = {.positions = scene->positions,
                                .indices = scene->indices,
                                .triangle_count = scene->triangle_count,
                                .spacing = k * lattice[3],
                                .margin = lattice[4],
                                .x_range = {INT64_MIN, INT64_MAX},
                                .max_count = UINT64_MAX,
                                .threads = threads};
        for (int c = 0; c < 3; c++)
            band.origin[c] = lattice[c] + o * lattice[3];
        r = vdbgi_band_points(ctx, &band, &ijk[o], &m[o]);
        total += m[o];
    }
    *count = 0;
    *out = r == VDBGI_OK && total ? vdbgi_calloc(ctx, total, sizeof(band_pick)) : NULL;
    if (r == VDBGI_OK && total && !*out)
        r = VDBGI_ERR_OUT_OF_MEMORY;
    for (int o = 0; o < k && *out; o++)
        for (size_t i = 0; i < m[o]; i++) {
            band_pick *const b = &(*out)[(*count)++];
            for (int c = 0; c < 3; c++)
                b->ijk[c] = k * ijk[o][3 * i + c] + o;
            b->hash = vdbgi_point_stream(b->ijk[0], b->ijk[1], b->ijk[2], seed);
        }
    for (int o = 0; o < k; o++)
        vdbgi_free(ctx, ijk[o]);
    return r;
}

/*
 * n of the lattice's own valid probes (lattice: origin xyz, spacing, margin
 * > 0), spread over the band as the bake's are, into pos: the band's points
 * on lattices k = 4, else 2, else 1 times coarser (band_candidates), found
 * as the bake places its probes (band.c) but over the whole scene, so the
 * same in every tile; taken in the order their streams hash to, those whose
 * 32 primary rays meet few enough back faces, until n are found (at the
 * finest k tried, as many as the band has, cycled; no finer k past
 * CANDIDATES_MOST points, where each halving of k quadruples them).
 * Surface points lifted along their normals stood as probes do over a
 * plane but not round a building's edges or in a corner: at 1 m probes
 * (a 4 m margin) on the bundled world the noise measured there was 0.75
 * of the error against a 16,384-ray bake, on 2,048 points, with the
 * estimators alike.
 */
#define CHECK_SALT (-9)
#define CANDIDATES_MOST ((size_t)1 << 22)

static vdbgi_result band_sample(vdbgi_context *ctx, const vdbgi_scene *scene,
                                const vdbgi_tracer *tracer, const vdbgi_bake_params *bp,
                                const double lattice[5], size_t n, float *pos, bool *placed)
{
    /* Only the back faces count: primary rays, no lamp, no bounce. */
    vdbgi_bake_params check = *bp;
    check.rays = VDBGI_ADAPTIVE_BATCH;
    check.adaptive = false;
    check.sampling = VDBGI_SAMPLING_RANDOM;
    check.model = VDBGI_MODEL_SEED;
    check.bounces = 1;
    check.lamp_count = 0;
    float *const at = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    double *const out = vdbgi_calloc(ctx, n, SPREAD_OUT * sizeof(double));
    vdbgi_result r = at && out ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    size_t kept = 0, count = 0;
    for (int k = 4; r == VDBGI_OK && kept < n && k >= 1 && count <= CANDIDATES_MOST; k /= 2) {
        band_pick *pick = NULL;
        r = band_candidates(ctx, scene, lattice, k, bp->seed, bp->threads, &pick, &count);
        if (pick)
            qsort(pick, count, sizeof(*pick), by_hash);
        kept = 0; /* a finer k holds the coarser points again: start afresh */
        for (size_t from = 0; r == VDBGI_OK && from < count && kept < n; from += n) {
            const size_t m = count - from < n ? count - from : n;
            for (size_t i = 0; i < m; i++)
                for (int c = 0; c < 3; c++)
                    at[3 * i + c] =
                        (float)(lattice[c] + lattice[3] * (double)pick[from + i].ijk[c]);
            r = trace_points(ctx, scene, tracer, &check, at, NULL, m, CHECK_SALT, false, out);
            for (size_t i = 0; r == VDBGI_OK && i < m && kept < n; i++)
                if (out[SPREAD_OUT * i + 4] <= bp->invalid_threshold)
                    memcpy(&pos[3 * kept++], &at[3 * i], 3 * sizeof(float));
        }
        vdbgi_free(ctx, pick);
    }
    *placed = r == VDBGI_OK && kept > 0;
    for (size_t i = kept; *placed && i < n; i++)
        memcpy(&pos[3 * i], &pos[3 * (i % kept)], 3 * sizeof(float));
    vdbgi_free(ctx, out);
    vdbgi_free(ctx, at);
    return r;
}

/*
 * n points for a pilot or the noise, into pos; *placed false when the scene
 * has none. Given a lattice with its margin, the bake's own probes
 * (band_sample). Else spread over the scene's surfaces by area
 * (place_receivers): with normal (n of them) left on the surfaces, as
 * texels' samples stand; without, lifted off them as points stand (one on
 * the surface would see a plain half below it and little of the spread a
 * probe sees), up to PILOT_LIFT, at most half way to what the normal meets,
 * and given a lattice (probes read from a file that never said their
 * margin), moved to its nearest point.
 */
#define PILOT_LIFT 2.0f

static vdbgi_result pilot_points(vdbgi_context *ctx, const vdbgi_scene *scene,
                                 const vdbgi_tracer *tracer, const double lattice[5],
                                 const vdbgi_bake_params *bp, size_t n, float *pos,
                                 float *surface_normal, bool *placed)
{
    if (lattice && lattice[4] > 0.0 && !surface_normal)
        return band_sample(ctx, scene, tracer, bp, lattice, n, pos, placed);
    const uint64_t seed = bp->seed;
    float *const normal = surface_normal ? surface_normal : vdbgi_calloc(ctx, n, 3 * sizeof(float));
    *placed = false;
    if (!normal)
        return VDBGI_ERR_OUT_OF_MEMORY;
    vdbgi_result r = place_receivers(ctx, scene, n, seed, pos, normal, placed);
    if (surface_normal || r != VDBGI_OK || !*placed) {
        if (!surface_normal)
            vdbgi_free(ctx, normal);
        return r;
    }
    vdbgi_hit *const hits = vdbgi_calloc(ctx, n, sizeof(vdbgi_hit));
    void *const scratch = vdbgi_alloc(ctx, vdbgi_tracer_scratch_size(n));
    if (!hits || !scratch)
        r = VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK) {
        const vdbgi_ray_batch up = {pos, normal, 3, 3, 0.0f, 2.0f * PILOT_LIFT, n, NULL};
        vdbgi_tracer_intersect(tracer, VDBGI_TRACE_SINGLE, &up, hits, scratch);
        for (size_t i = 0; i < n; i++) {
            uint64_t st = vdbgi_point_stream((int32_t)i, -6, 0, seed);
            const float room = hits[i].t < INFINITY ? 0.5f * hits[i].t : PILOT_LIFT;
            const float lift = (float)vdbgi_uniform01(&st) * fminf(room, PILOT_LIFT);
            for (int k = 0; k < 3; k++) {
                pos[3 * i + k] += lift * normal[3 * i + k];
                if (lattice)
                    pos[3 * i + k] =
                        (float)(lattice[k] +
                                lattice[3] * round((pos[3 * i + k] - lattice[k]) / lattice[3]));
            }
        }
    }
    vdbgi_free(ctx, scratch);
    vdbgi_free(ctx, hits);
    vdbgi_free(ctx, normal);
    return r;
}

#define SURFACE_FLOOR 0.25
#define PROBE_FLOOR 0.05

/*
 * From the scale independent rays would need, the one whose noise, measured
 * as vdbgi_bake_noise measures it (the same points, under rotations of
 * their own, so the noise a bake reports is not the fit's own sample),
 * meets bp->noise: a Fibonacci set's error falls faster than independent
 * rays', by how much depends on the scene (0.4-0.55 of the target on the
 * bundled world, 0.23 in a lamp-lit room). The error goes as a power of the
 * scale, fitted from the last two measurements (the first step assumes
 * 0.75), until a scale over the target and one within it bracket it; then
 * log-log between them (the measure is itself noisy: a little more scale
 * can measure a little more noise). At most CALIBRATE measurements,
 * stopping within 15 % under the target. The least scale measured within
 * the target stands, else (past what max_rays allows) the largest
 * measured. The points and their streams are fixed, so the same in every
 * tile and on any thread count.
 */
#define CALIBRATE 6
#define CALIBRATE_SALT (-7) /* its own streams: the noise printed is measured apart */

static vdbgi_result calibrate(vdbgi_context *ctx, const vdbgi_scene *scene,
                              const vdbgi_tracer *tracer, const float *pos, const float *normal,
                              vdbgi_bake_params *bp)
{
    const double target = (double)bp->noise, aim = 0.95 * target;
    /* The bracket: the largest scale measured over the target, the least within it. */
    double over = 0.0, over_e = 0.0, within = 0.0, within_e = 0.0, power = 0.75;
    double prev = 0.0, prev_e = 0.0;
    for (int m = 0; m < CALIBRATE; m++) {
        const double scale = bp->adaptive_scale;
        double e;
        VDBGI_TRY(measure_noise(ctx, scene, tracer, bp, pos, normal, CALIBRATE_SALT, &e));
        vdbgi_log(ctx, VDBGI_LOG_DEBUG, "auto: scale %.4g gives noise %.2f %% (target %.2f %%)",
                  scale, 100.0 * e, 100.0 * target);
        if (!(e > 0.0)) /* no noise at all: any scale does */
            return VDBGI_OK;
        if (e > target && scale > over)
            over = scale, over_e = e;
        if (e <= target && (within == 0.0 || scale < within))
            within = scale, within_e = e;
        if (e <= target && e > 0.85 * target)
            break; /* close under the target */
        if (prev > 0.0 && prev_e > 0.0 && prev != scale) {
            const double p = -log(e / prev_e) / log(scale / prev);
            power = fmin(fmax(p, 0.25), 1.5); /* flat (the cap near): the boldest step */
        }
        prev = scale, prev_e = e;
        double next;
        if (over > 0.0 && within > 0.0) {
            if (within / over < 1.1)
                break; /* bracketed as closely as the measure's own noise allows */
            /* Inside the bracket, log-log between its ends (its middle where they disagree). */
            const double t = over_e > within_e ? log(over_e / aim) / log(over_e / within_e) : 0.5;
            next = over * pow(within / over, fmin(fmax(t, 0.1), 0.9));
        } else {
            /* Not yet bracketed: the power law, by at most 16 times. */
            next = scale * fmin(fmax(pow(e / aim, 1.0 / power), 1.0 / 16.0), 16.0);
        }
        bp->adaptive_scale = next;
    }
    /* The least scale measured within the target; else (past what max_rays allows) the most. */
    bp->adaptive_scale = within > 0.0 ? within : over;
    return VDBGI_OK;
}

/*
 * The NOISE_POINTS points the noise is measured at, placed as the pilot's
 * (with their normals on surfaces) into *pos and *normal, which the caller
 * frees; *placed false when the scene has no area.
 */
static vdbgi_result noise_points(vdbgi_context *ctx, const vdbgi_scene *scene,
                                 const vdbgi_tracer *tracer, const double lattice[5], bool surface,
                                 const vdbgi_bake_params *bp, float **pos, float **normal,
                                 bool *placed)
{
    *pos = vdbgi_calloc(ctx, NOISE_POINTS, 3 * sizeof(float));
    *normal = surface ? vdbgi_calloc(ctx, NOISE_POINTS, 3 * sizeof(float)) : NULL;
    *placed = false;
    return *pos && (*normal || !surface)
               ? pilot_points(ctx, scene, tracer, lattice, bp, NOISE_POINTS, *pos, *normal, placed)
               : VDBGI_ERR_OUT_OF_MEMORY;
}

vdbgi_result vdbgi_adaptive_scale(vdbgi_context *ctx, const vdbgi_scene *scene,
                                  const vdbgi_tracer *tracer, const double lattice[5], bool surface,
                                  vdbgi_bake_params *bp)
{
    bp->adaptive_scale = bp->adaptive_floor = 0.0;
    if (!bp->adaptive)
        return VDBGI_OK;
    const size_t n = PILOT_RECEIVERS;
    float *const pos = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    float *const normal = surface ? vdbgi_calloc(ctx, n, 3 * sizeof(float)) : NULL;
    double *const first = vdbgi_calloc(ctx, n, SPREAD_OUT * sizeof(double));
    bool placed = false;
    vdbgi_result r = pos && first && (normal || !surface)
                         ? pilot_points(ctx, scene, tracer, lattice, bp, n, pos, normal, &placed)
                         : VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK && placed) {
        vdbgi_bake_params pilot = *bp;
        pilot.rays = VDBGI_ADAPTIVE_BATCH;
        pilot.adaptive = false;
        pilot.sampling = VDBGI_SAMPLING_RANDOM;
        r = spread(ctx, scene, tracer, &pilot, pos, normal, n, -3, first);
    }
    if (r == VDBGI_OK && placed) {
        /*
         * Independent rays would spend best in proportion to each point's
         * spread sigma (Lagrange: the least summed variance sigma^2 / n for
         * the rays); a 32-ray pilot's sigma says less than that about a
         * Fibonacci set's error, and n ~ sqrt(sigma) measured better (docs/
         * performance.md, "Rays where they pay"). The first scale gives
         * the pilot points noise times their mean light as independent rays
         * would, sqrt(mean(sigma^1.5) / scale); a Fibonacci set does better,
         * by a share calibrate measures. A floor under the spread (more
         * on surfaces): a pilot that saw none may have missed a small
         * bright patch, and without it auto's error stopped falling (at
         * 3.8 % on the bundled world's texels).
         */
        double light = 0.0, mean = 0.0, sigma = 0.0;
        size_t valid = 0;
        for (size_t i = 0; i < n; i++) {
            const double *const o = &first[SPREAD_OUT * i];
            if (o[4] <= bp->invalid_threshold)
                light += (o[0] + o[1] + o[2]) / 3.0, mean += o[3], valid++;
        }
        light /= (double)(valid ? valid : 1), mean /= (double)(valid ? valid : 1);
        const double f = bp->adaptive_floor = (surface ? SURFACE_FLOOR : PROBE_FLOOR) * mean;
        for (size_t i = 0; i < n; i++) {
            const double *const o = &first[SPREAD_OUT * i];
            if (o[4] <= bp->invalid_threshold)
                sigma += o[3] > 0.0 ? o[3] * o[3] / sqrt(o[3] + f) : 0.0;
        }
        sigma /= (double)(valid ? valid : 1);
        const double t = (double)bp->noise * light;
        bp->adaptive_scale = t > 0.0 ? sigma / (t * t) : 0.0;
    }
    vdbgi_free(ctx, first);
    vdbgi_free(ctx, normal);
    vdbgi_free(ctx, pos);
    if (r == VDBGI_OK && placed && bp->adaptive_scale > 0.0) {
        float *at = NULL, *at_normal = NULL; /* the noise points, placed once for the fit */
        r = noise_points(ctx, scene, tracer, lattice, surface, bp, &at, &at_normal, &placed);
        if (r == VDBGI_OK && placed)
            r = calibrate(ctx, scene, tracer, at, at_normal, bp);
        vdbgi_free(ctx, at_normal);
        vdbgi_free(ctx, at);
    }
    return r;
}

vdbgi_result vdbgi_bake_noise(vdbgi_context *ctx, const vdbgi_scene *scene,
                              const vdbgi_tracer *tracer, const double lattice[5], bool surface,
                              const vdbgi_bake_params *bp, double *noise)
{
    *noise = 0.0;
    float *pos = NULL, *normal = NULL;
    bool placed = false;
    vdbgi_result r = noise_points(ctx, scene, tracer, lattice, surface, bp, &pos, &normal, &placed);
    if (r == VDBGI_OK && placed)
        r = measure_noise(ctx, scene, tracer, bp, pos, normal, -4, noise);
    vdbgi_free(ctx, normal);
    vdbgi_free(ctx, pos);
    return r;
}
