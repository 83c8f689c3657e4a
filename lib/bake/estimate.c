/*
 * estimate.c: seed 000's irradiance estimator for one sample point: its
 * direction set, the rays, the sun's shadow rays, validity (the back-face
 * fraction), the standard error and the ambient-cube sides.
 */
#include "estimate.h"
#include "util.h"

#include <math.h>
#include <string.h>

#define PI_F 3.14159265358979f

/* The query shape VDBGI_TRACE_AUTO picks: the fastest in docs/performance.md. */
#define VDBGI_TRACE_BEST VDBGI_TRACE_PACKET16

static bool is_zero3(const float v[3])
{
    return v[0] == 0.0f && v[1] == 0.0f && v[2] == 0.0f;
}

/*
 * The brightest light a setting may ask for, as emission's cap (scene.h):
 * 3e38 would overflow every sum into Inf and NaN, and a half-float map long
 * before.
 */
#define MAX_LIGHT VDBGI_MAX_EMISSION

static bool in_light_range3(const float v[3])
{
    for (int k = 0; k < 3; k++)
        if (!(v[k] >= 0.0f && v[k] <= MAX_LIGHT))
            return false;
    return true;
}

/* A scene light as a lamp; false when it cannot light anything. */
static bool lamp_from_light(const vdbgi_light *in, vdbgi_lamp *l)
{
    memset(l, 0, sizeof(*l));
    l->type = in->type;
    memcpy(l->pos, in->position, sizeof(l->pos));
    for (int k = 0; k < 3; k++) {
        l->to_light[k] = -in->direction[k];
        l->axis[k] = in->direction[k];
        l->rgb[k] = in->color[k] / PI_F; /* E, as the estimator's E / pi */
    }
    const double r = in->range;
    l->inv_range4 = r > 0.0 ? (float)(1.0 / (r * r * r * r)) : 0.0f;
    if (in->type == VDBGI_LIGHT_SPOT) {
        l->cos_outer = cosf(in->outer_cone);
        l->cone_scale = 1.0f / fmaxf(0.001f, cosf(in->inner_cone) - l->cos_outer);
    }
    return !is_zero3(l->rgb);
}

/* The lamps: the sun when on, then the scene's lights as bp->lights says. */
static void resolve_lamps(const vdbgi_bake_desc *desc, const vdbgi_scene *scene,
                          vdbgi_bake_params *bp)
{
    const vdbgi_light *lights = NULL;
    const size_t count =
        scene && bp->lights == VDBGI_LIGHTS_SCENE ? vdbgi_scene_get_lights(scene, &lights) : 0;
    bool scene_sun = false;
    for (size_t i = 0; i < count; i++)
        scene_sun = scene_sun || lights[i].type == VDBGI_LIGHT_DIRECTIONAL;
    /* The scene's own sun replaces the default one; a sun_dir given replaces the scene's. */
    const bool given = !is_zero3(desc->sun_dir);
    if (scene_sun && !given) {
        bp->sun_on = false;
        memset(bp->sun_color, 0, sizeof(bp->sun_color));
    }
    if (bp->sun_on) {
        vdbgi_lamp *const l = &bp->lamps[bp->lamp_count++];
        memset(l, 0, sizeof(*l));
        l->type = VDBGI_LIGHT_DIRECTIONAL;
        l->is_sun = true;
        memcpy(l->to_light, bp->sun_dir, sizeof(l->to_light));
        memcpy(l->rgb, bp->sun_color, sizeof(l->rgb));
    }
    float dir[3], e[3];
    if (bp->sky_map && vdbgi_sky_sun(bp->sky_map, dir, e)) {
        vdbgi_lamp *const l = &bp->lamps[bp->lamp_count++];
        memset(l, 0, sizeof(*l));
        l->type = VDBGI_LIGHT_DIRECTIONAL;
        l->is_sky = true;
        memcpy(l->to_light, dir, sizeof(l->to_light));
        for (int k = 0; k < 3; k++)
            l->rgb[k] = e[k] / PI_F;
    }
    for (size_t i = 0; i < count && bp->lamp_count < VDBGI_MAX_LIGHTS + 2; i++)
        if (!(given && lights[i].type == VDBGI_LIGHT_DIRECTIONAL) &&
            lamp_from_light(&lights[i], &bp->lamps[bp->lamp_count])) {
            bp->lamp_count++;
            bp->scene_lamps++;
        }
}

vdbgi_result vdbgi_bake_params_resolve(vdbgi_context *ctx, const vdbgi_bake_desc *desc,
                                       const vdbgi_scene *scene, vdbgi_bake_params *bp)
{
    const vdbgi_bake_desc none = {0};
    if (!desc)
        desc = &none;
    memset(bp, 0, sizeof(*bp));
    bp->adaptive = desc->rays == VDBGI_RAYS_AUTO;
    bp->rays = desc->rays == 0 || bp->adaptive ? 128 : desc->rays;
    VDBGI_FAIL_IF(ctx, bp->rays < 1 || bp->rays > 1000000, VDBGI_ERR_INVALID_ARG,
                  "rays per probe must be in 1..1000000 (got %d)", desc->rays);
    bp->noise = desc->noise != 0.0f ? desc->noise : 0.02f;
    VDBGI_FAIL_IF(ctx, !(bp->noise > 0.0f) || !isfinite(bp->noise), VDBGI_ERR_INVALID_ARG,
                  "noise target must be > 0 (got %g)", (double)desc->noise);
    bp->max_rays = desc->max_rays ? desc->max_rays : 1024;
    VDBGI_FAIL_IF(ctx,
                  bp->max_rays < 2 * VDBGI_ADAPTIVE_BATCH || bp->max_rays > (1 << 20) ||
                      (bp->max_rays & (bp->max_rays - 1)),
                  VDBGI_ERR_INVALID_ARG, "max rays must be a power of two in %d..%d (got %d)",
                  2 * VDBGI_ADAPTIVE_BATCH, 1 << 20, desc->max_rays);
    bp->ray_dist = desc->ray_dist != 0.0f ? desc->ray_dist : 40.0f;
    VDBGI_FAIL_IF(ctx, !(bp->ray_dist > 0.0f) || !isfinite(bp->ray_dist), VDBGI_ERR_INVALID_ARG,
                  "ray distance must be > 0 and finite (got %g)", (double)desc->ray_dist);
    bp->ambient = desc->ambient == 0.0f         ? 0.15f
                  : desc->ambient == VDBGI_ZERO ? 0.0f
                                                : desc->ambient;
    VDBGI_FAIL_IF(ctx, !(bp->ambient >= 0.0f && bp->ambient <= MAX_LIGHT), VDBGI_ERR_INVALID_ARG,
                  "ambient must be in 0..%g (got %g)", (double)MAX_LIGHT, (double)desc->ambient);

    static const float default_sun[3] = {0.4f, 0.8f, 0.3f};
    const float *const sd = is_zero3(desc->sun_dir) ? default_sun : desc->sun_dir;
    const float len = sqrtf(sd[0] * sd[0] + sd[1] * sd[1] + sd[2] * sd[2]);
    VDBGI_FAIL_IF(ctx, !(len > 0.0f) || !isfinite(len), VDBGI_ERR_INVALID_ARG,
                  "sun direction must be finite and non-zero (got %g,%g,%g)", (double)sd[0],
                  (double)sd[1], (double)sd[2]);
    for (int k = 0; k < 3; k++)
        bp->sun_dir[k] = sd[k] / len;

    bp->sun_on = !(desc->sun_color[0] == VDBGI_ZERO && desc->sun_color[1] == VDBGI_ZERO &&
                   desc->sun_color[2] == VDBGI_ZERO);
    for (int k = 0; k < 3; k++)
        bp->sun_color[k] = !bp->sun_on                 ? 0.0f
                           : is_zero3(desc->sun_color) ? 1.0f
                                                       : desc->sun_color[k];
    VDBGI_FAIL_IF(ctx, !in_light_range3(bp->sun_color), VDBGI_ERR_INVALID_ARG,
                  "sun colour must be in 0..%g (got %g,%g,%g)", (double)MAX_LIGHT,
                  (double)desc->sun_color[0], (double)desc->sun_color[1],
                  (double)desc->sun_color[2]);
    bp->sun_on = bp->sun_on && !is_zero3(bp->sun_color);

    bp->falloff = desc->falloff != 0.0f ? desc->falloff : 4.0f;
    VDBGI_FAIL_IF(ctx, !(bp->falloff > 0.0f), VDBGI_ERR_INVALID_ARG,
                  "falloff must be > 0 or inf (got %g)", (double)desc->falloff);
    memcpy(bp->sky, desc->sky, sizeof(bp->sky));
    VDBGI_FAIL_IF(ctx, !in_light_range3(bp->sky), VDBGI_ERR_INVALID_ARG,
                  "sky colour must be in 0..%g (got %g,%g,%g)", (double)MAX_LIGHT,
                  (double)desc->sky[0], (double)desc->sky[1], (double)desc->sky[2]);
    VDBGI_FAIL_IF(
        ctx, desc->sampling != VDBGI_SAMPLING_FIBONACCI && desc->sampling != VDBGI_SAMPLING_RANDOM,
        VDBGI_ERR_INVALID_ARG, "unknown sampling method %d", (int)desc->sampling);
    bp->sampling = desc->sampling;
    bp->seed = desc->seed;
    VDBGI_FAIL_IF(ctx, desc->threads < 0 || desc->threads > 1024, VDBGI_ERR_INVALID_ARG,
                  "threads must be in 0..1024 (got %d)", desc->threads);
    bp->threads = desc->threads ? desc->threads : vdbgi_core_count();
    bp->invalid_threshold = desc->invalid_threshold != 0.0f ? desc->invalid_threshold : 0.25f;
    VDBGI_FAIL_IF(ctx, !(bp->invalid_threshold > 0.0f && bp->invalid_threshold <= 1.0f),
                  VDBGI_ERR_INVALID_ARG, "invalid threshold must be in (0, 1] (got %g)",
                  (double)desc->invalid_threshold);
    VDBGI_FAIL_IF(ctx,
                  desc->trace_method < VDBGI_TRACE_AUTO || desc->trace_method > VDBGI_TRACE_STREAM,
                  VDBGI_ERR_INVALID_ARG, "unknown trace method %d", (int)desc->trace_method);
    bp->method = desc->trace_method == VDBGI_TRACE_AUTO ? VDBGI_TRACE_BEST : desc->trace_method;
    VDBGI_FAIL_IF(ctx, desc->basis < VDBGI_BASIS_SCALAR || desc->basis > VDBGI_BASIS_SH2,
                  VDBGI_ERR_INVALID_ARG, "unknown basis %d", (int)desc->basis);
    bp->basis = desc->basis;
    VDBGI_FAIL_IF(ctx, desc->model != VDBGI_MODEL_SEED && desc->model != VDBGI_MODEL_PHYSICAL,
                  VDBGI_ERR_INVALID_ARG, "unknown light model %d", (int)desc->model);
    bp->model = desc->model;
    if (bp->model == VDBGI_MODEL_PHYSICAL) {
        /* Physical light needs neither stand-in: bounces replace the fill, 1/d^2 is in E. */
        VDBGI_FAIL_IF(ctx, desc->ambient != 0.0f && desc->ambient != VDBGI_ZERO,
                      VDBGI_ERR_INVALID_ARG, "the physical model has no ambient fill (got %g)",
                      (double)desc->ambient);
        VDBGI_FAIL_IF(ctx, desc->falloff != 0.0f && !isinf(desc->falloff), VDBGI_ERR_INVALID_ARG,
                      "the physical model has no distance falloff (got %g)", (double)desc->falloff);
        bp->ambient = 0.0f;
        bp->falloff = INFINITY;
    }
    VDBGI_FAIL_IF(ctx, desc->lights != VDBGI_LIGHTS_SCENE && desc->lights != VDBGI_LIGHTS_OFF,
                  VDBGI_ERR_INVALID_ARG, "unknown lights setting %d", (int)desc->lights);
    bp->lights = desc->lights;
    bp->bounces = desc->bounces ? desc->bounces : 1;
    VDBGI_FAIL_IF(ctx, bp->bounces < 1 || bp->bounces > VDBGI_MAX_BOUNCES, VDBGI_ERR_INVALID_ARG,
                  "bounces must be in 1..%d (got %d)", VDBGI_MAX_BOUNCES, desc->bounces);
    bp->sky_map = desc->sky_map;
    VDBGI_FAIL_IF(ctx, bp->sky_map && !is_zero3(bp->sky), VDBGI_ERR_INVALID_ARG,
                  "a sky map and a sky colour: give one");
    resolve_lamps(desc, scene, bp);
    return VDBGI_OK;
}

bool vdbgi_lamp_light(const vdbgi_lamp *l, const float p[3], const float n[3], float *f,
                      float dir[3], float *dist)
{
    float scale = 1.0f;
    if (l->type == VDBGI_LIGHT_DIRECTIONAL) {
        memcpy(dir, l->to_light, 3 * sizeof(float));
        *dist = INFINITY;
    } else {
        const float d[3] = {l->pos[0] - p[0], l->pos[1] - p[1], l->pos[2] - p[2]};
        const float d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (!(d2 > 0.0f))
            return false;
        const float r = sqrtf(d2);
        for (int k = 0; k < 3; k++)
            dir[k] = d[k] / r;
        *dist = r;
        scale = 1.0f / d2;
        if (l->inv_range4 > 0.0f) {
            const float q = d2 * d2 * l->inv_range4; /* (d / range)^4 */
            if (q >= 1.0f)
                return false;
            scale *= 1.0f - q;
        }
        if (l->type == VDBGI_LIGHT_SPOT) {
            const float c = -(dir[0] * l->axis[0] + dir[1] * l->axis[1] + dir[2] * l->axis[2]);
            const float a = fminf((c - l->cos_outer) * l->cone_scale, 1.0f);
            if (!(a > 0.0f))
                return false;
            scale *= a * a;
        }
    }
    const float cosn = n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2];
    if (!(cosn > 0.0f))
        return false;
    *f = l->type == VDBGI_LIGHT_DIRECTIONAL ? cosn : scale * cosn;
    return true;
}

void vdbgi_miss_radiance(const vdbgi_bake_params *bp, const float d[3], float rgb[3])
{
    if (bp->sky_map)
        vdbgi_sky_radiance(bp->sky_map, d, rgb);
    else
        memcpy(rgb, bp->sky, 3 * sizeof(float));
}

/* ---- directions ------------------------------------------------------------ */

/*
 * Spherical Fibonacci set: z evenly spaced in (-1, 1), azimuth advancing by
 * the golden angle, so every direction stands for the same solid angle.
 */
void vdbgi_fibonacci_directions(int n, float *dirs)
{
    const double golden = PI_F * (3.0 - sqrt(5.0));
    for (int i = 0; i < n; i++) {
        const double z = 1.0 - (2.0 * i + 1.0) / n;
        const double r = sqrt(1.0 - z * z);
        const double phi = golden * i;
        dirs[3 * i + 0] = (float)(r * cos(phi));
        dirs[3 * i + 1] = (float)z;
        dirs[3 * i + 2] = (float)(r * sin(phi));
    }
}

/*
 * Reorder a set of n (a power of two) directions so that entry k holds the
 * one at the bit-reversed index: the first 2^j entries are every (n/2^j)-th
 * direction of the set, so any prefix of whole batches covers the sphere
 * about as evenly as a set of its own size.
 */
static void bit_reverse_order(float *dirs, int n)
{
    int bits = 0;
    while ((1 << bits) < n)
        bits++;
    for (int k = 0; k < n; k++) {
        int r = 0;
        for (int b = 0; b < bits; b++)
            r |= (k >> b & 1) << (bits - 1 - b);
        if (r > k)
            for (int c = 0; c < 3; c++) {
                const float t = dirs[3 * k + c];
                dirs[3 * k + c] = dirs[3 * r + c], dirs[3 * r + c] = t;
            }
    }
}

uint64_t vdbgi_point_stream(int32_t i, int32_t j, int32_t k, uint64_t seed)
{
    uint64_t s = seed ^ ((uint64_t)(uint32_t)i * 0x8CB92BA72F3D8DD7ull) ^
                 ((uint64_t)(uint32_t)j * 0xAB8F3B2A1F7C5D93ull) ^
                 ((uint64_t)(uint32_t)k * 0xD1B54A32D192ED03ull);
    return vdbgi_splitmix64(&s);
}

/* Uniformly random rotation (Shoemake's quaternion from three uniforms). */
static void random_rotation(uint64_t stream, float m[9])
{
    const double u1 = vdbgi_uniform01(&stream), u2 = vdbgi_uniform01(&stream),
                 u3 = vdbgi_uniform01(&stream);
    const double a = sqrt(1.0 - u1), b = sqrt(u1);
    const double x = a * sin(2.0 * PI_F * u2), y = a * cos(2.0 * PI_F * u2);
    const double z = b * sin(2.0 * PI_F * u3), w = b * cos(2.0 * PI_F * u3);
    m[0] = (float)(1 - 2 * (y * y + z * z)), m[1] = (float)(2 * (x * y - z * w));
    m[2] = (float)(2 * (x * z + y * w)), m[3] = (float)(2 * (x * y + z * w));
    m[4] = (float)(1 - 2 * (x * x + z * z)), m[5] = (float)(2 * (y * z - x * w));
    m[6] = (float)(2 * (x * z - y * w)), m[7] = (float)(2 * (y * z + x * w));
    m[8] = (float)(1 - 2 * (x * x + y * y));
}

/* What a probe's rays add up to, batch after batch. */
typedef struct probe_sums {
    double sum[3]; /* radiance, per channel */
    double sum_sq; /* squares of the per-ray mean over channels, for the standard error */
    double cube[6][3], cube_w[6];
    double sh[8][3]; /* radiance times each L2 term, per channel */
    size_t rays, hits, back, shadow;
} probe_sums;

/*
 * Light from the lamps at count surface points: the shadow ray of each lamp
 * from each point that it can light (org: the point one ray offset off its
 * surface; n: facing normal), and for the open ones radiance[ray[i]] +=
 * weight[i] x f x the lamp's colour. Returns the shadow rays traced.
 */
static size_t light_points(vdbgi_estimator *th, const float *org, const float *n,
                           const float *weight, const uint32_t *ray, size_t count)
{
    const vdbgi_bake_params *const bp = th->bp;
    const float off = th->scene->ray_offset;
    size_t traced = 0;
    for (int li = 0; li < bp->lamp_count; li++) {
        const vdbgi_lamp *const l = &bp->lamps[li];
        size_t m = 0;
        for (size_t i = 0; i < count; i++) {
            float f, dist;
            if (!vdbgi_lamp_light(l, &org[3 * i], &n[3 * i], &f, &th->sdir[3 * m], &dist))
                continue;
            memcpy(&th->sorg[3 * m], &org[3 * i], 3 * sizeof(float));
            th->sdist[m] = dist - off; /* stop short of a lamp on a surface */
            for (int k = 0; k < 3; k++)
                th->sun_weight[3 * m + k] = weight[3 * i + k] * f * l->rgb[k];
            th->shadow_ray[m] = ray[i];
            m++;
        }
        if (!m)
            continue;
        const vdbgi_ray_batch shadow = {th->sorg, th->sdir, 3, 3, 0.0f, INFINITY, m, th->sdist};
        vdbgi_tracer_occluded(th->tracer, bp->method, &shadow, th->occluded, th->scratch);
        traced += m;
        if (th->shade)
            for (size_t s = 0; s < m; s++)
                if (!th->occluded[s])
                    for (int k = 0; k < 3; k++)
                        th->radiance[3 * th->shadow_ray[s] + k] += th->sun_weight[3 * s + k];
    }
    return traced;
}

/* Unit t and b completing unit n to a right-handed frame (t, b, n). */
static void frame_about(const float n[3], float t[3], float b[3])
{
    const float a[3] = {fabsf(n[0]) < 0.9f ? 1.0f : 0.0f, fabsf(n[0]) < 0.9f ? 0.0f : 1.0f, 0.0f};
    t[0] = a[1] * n[2] - a[2] * n[1], t[1] = a[2] * n[0] - a[0] * n[2];
    t[2] = a[0] * n[1] - a[1] * n[0];
    const float l = sqrtf(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (int k = 0; k < 3; k++)
        t[k] /= l;
    b[0] = n[1] * t[2] - n[2] * t[1], b[1] = n[2] * t[0] - n[0] * t[2];
    b[2] = n[0] * t[1] - n[1] * t[0];
}

/*
 * The radiance hit h's emitter sends back along the ray into e: from its
 * front (both sides when double-sided), when bp's emission takes its
 * material. False, e untouched, when it sends none.
 */
static bool hit_emission(const vdbgi_bake_params *bp, const vdbgi_scene *scene, const vdbgi_hit *h,
                         bool front, float e[3])
{
    const vdbgi_tri *const tri = &scene->tris[h->prim];
    if (!(tri->flags & VDBGI_TRI_EMISSIVE) || !(front || tri->flags & VDBGI_TRI_DOUBLE_SIDED) ||
        !(bp->emission == 0 || bp->emission == tri->material + 1))
        return false;
    vdbgi_scene_emission(scene, h->prim, h->u, h->v, e);
    return true;
}

/* A cosine-weighted direction about unit n from two uniforms. */
static void cosine_direction(const float n[3], double u1, double u2, float out[3])
{
    float t[3], b[3];
    frame_about(n, t, b);
    const float r = (float)sqrt(u1), phi = (float)(2.0 * 3.14159265358979323846 * u2);
    const float x = r * cosf(phi), y = r * sinf(phi), z = sqrtf(fmaxf(0.0f, 1.0f - r * r));
    for (int k = 0; k < 3; k++)
        out[k] = x * t[k] + y * b[k] + z * n[k];
}

/*
 * Bounces 2..bp->bounces of the paths that left count hits (th->porg, pnorm,
 * pweight, pray): one cosine-weighted ray each per bounce, its own random
 * numbers from the point's stream, the ray's index and the bounce. A miss
 * brings the sky; a hit its emission and its lamps, times the path's
 * throughput; then the path goes on from there with its albedo. Returns
 * the rays traced (paths and shadows).
 */
static size_t trace_bounces(vdbgi_estimator *th, size_t count, size_t first_ray)
{
    const vdbgi_bake_params *const bp = th->bp;
    const vdbgi_scene *const scene = th->scene;
    const float off = scene->ray_offset;
    size_t traced = 0;
    for (int b = 2; b <= bp->bounces && count; b++) {
        for (size_t i = 0; i < count; i++) {
            uint64_t st = th->stream ^
                          ((uint64_t)(first_ray + th->pray[i]) * 0x9E3779B97F4A7C15ull) ^
                          ((uint64_t)b * 0xC2B2AE3D27D4EB4Full);
            vdbgi_splitmix64(&st);
            const double u1 = vdbgi_uniform01(&st), u2 = vdbgi_uniform01(&st);
            cosine_direction(&th->pnorm[3 * i], u1, u2, &th->dir[3 * i]);
        }
        const vdbgi_ray_batch rays = {th->porg, th->dir, 3, 3, 0.0f, bp->ray_dist, count, NULL};
        vdbgi_tracer_intersect(th->tracer, bp->method, &rays, th->hits, th->scratch);
        traced += count;
        size_t live = 0;
        for (size_t i = 0; i < count; i++) {
            const vdbgi_hit *const h = &th->hits[i];
            const float *const d = &th->dir[3 * i];
            float *const L = &th->radiance[3 * th->pray[i]];
            const float *const w = &th->pweight[3 * i];
            if (!(h->t < INFINITY)) {
                float sky[3];
                vdbgi_miss_radiance(bp, d, sky);
                for (int k = 0; k < 3; k++)
                    L[k] += w[k] * sky[k];
                continue;
            }
            const vdbgi_tri *const tri = &scene->tris[h->prim];
            const float *const tn = tri->normal;
            const float facing = tn[0] * d[0] + tn[1] * d[1] + tn[2] * d[2];
            const float flip = facing > 0.0f ? -1.0f : 1.0f;
            float albedo[3], e[3];
            vdbgi_scene_albedo(scene, h->prim, h->u, h->v, albedo);
            if (hit_emission(bp, scene, h, flip > 0.0f, e))
                for (int k = 0; k < 3; k++)
                    L[k] += w[k] * e[k];
            /* The path goes on from this hit (compacted in place: live <= i). */
            const float *const o = &th->porg[3 * i];
            for (int k = 0; k < 3; k++) {
                th->pnorm[3 * live + k] = tn[k] * flip;
                th->porg[3 * live + k] = o[k] + h->t * d[k] + off * tn[k] * flip;
                th->pweight[3 * live + k] = w[k] * albedo[k];
            }
            th->pray[live] = th->pray[i];
            live++;
        }
        traced += light_points(th, th->porg, th->pnorm, th->pweight, th->pray, live);
        count = live;
    }
    return traced;
}

/*
 * Trace n rays from pos along dirs and add what they bring back to *sums:
 * seed 000's sum, the squares for the standard error, the ambient-cube sides
 * (each side weights a ray by its cosine to the side's normal and keeps the sum
 * of weights, so uniform radiance gives itself exactly) and the counts.
 * Without shading (the bare loop) only the rays and the counts. Kept whole
 * (about 90 lines): the passes share the per-ray buffers in order.
 */
static void trace_batch(vdbgi_estimator *th, const float pos[3], const float *dirs, int n,
                        probe_sums *sums)
{
    const vdbgi_bake_params *const bp = th->bp;
    const vdbgi_scene *const scene = th->scene;
    const vdbgi_ray_batch primary = {pos, dirs, 0, 3, 0.0f, bp->ray_dist, (size_t)n, NULL};
    vdbgi_tracer_intersect(th->tracer, bp->method, &primary, th->hits, th->scratch);

    size_t hit_count = 0;
    const float off = scene->ray_offset;
    for (int i = 0; i < n; i++) {
        const vdbgi_hit *const h = &th->hits[i];
        float *const L = &th->radiance[3 * i];
        const float *const d = &dirs[3 * i];
        if (!(h->t < INFINITY)) {
            vdbgi_miss_radiance(bp, d, L);
            continue;
        }
        sums->hits++;
        const vdbgi_tri *const tri = &scene->tris[h->prim];
        const float *const tn = tri->normal;
        const float facing = tn[0] * d[0] + tn[1] * d[1] + tn[2] * d[2];
        /* The ray arrives from the side the normal points away from: a back face. */
        const float flip = facing > 0.0f ? -1.0f : 1.0f;
        if (facing > 0.0f && !(tri->flags & VDBGI_TRI_DOUBLE_SIDED))
            sums->back++;
        float *const albedo_w = &th->pweight[3 * hit_count];
        albedo_w[0] = albedo_w[1] = albedo_w[2] = 0.0f;
        L[0] = L[1] = L[2] = 0.0f;
        if (th->shade) {
            float albedo[3], extra[3] = {0.0f, 0.0f, 0.0f};
            vdbgi_scene_albedo(scene, h->prim, h->u, h->v, albedo);
            if (th->hit_light)
                th->hit_light(th->hit_user, h, facing > 0.0f, extra);
            const float q = h->t / bp->falloff;
            const float w = 1.0f / (1.0f + q * q); /* q = 0 when falloff is infinite */
            for (int k = 0; k < 3; k++) {
                albedo_w[k] = albedo[k] * w;
                L[k] = albedo_w[k] * (bp->ambient + extra[k]);
            }
            float e[3];
            if (hit_emission(bp, scene, h, flip > 0.0f, e))
                for (int k = 0; k < 3; k++)
                    L[k] += w * e[k];
        }
        /* The hit's point one ray offset off its lit side, and that side's normal. */
        for (int k = 0; k < 3; k++) {
            th->pnorm[3 * hit_count + k] = tn[k] * flip;
            th->porg[3 * hit_count + k] = pos[k] + h->t * d[k] + off * tn[k] * flip;
        }
        th->pray[hit_count++] = (uint32_t)i;
    }
    size_t shadow_count = light_points(th, th->porg, th->pnorm, th->pweight, th->pray, hit_count);
    if (bp->bounces > 1)
        shadow_count += trace_bounces(th, hit_count, sums->rays);
    sums->rays += (size_t)n;
    sums->shadow += shadow_count;
    if (!th->shade)
        return;
    for (int i = 0; i < n; i++) {
        const float *const L = &th->radiance[3 * i];
        for (int k = 0; k < 3; k++)
            sums->sum[k] += L[k];
        const double l = ((double)L[0] + L[1] + L[2]) / 3.0;
        sums->sum_sq += l * l;
    }
    if (th->cube)
        for (int i = 0; i < n; i++) {
            const float *const d = &dirs[3 * i];
            const float *const L = &th->radiance[3 * i];
            /* Misses under a black sky carry nothing: only their weight counts. */
            const bool dark = L[0] == 0.0f && L[1] == 0.0f && L[2] == 0.0f;
            for (int a = 0; a < 3; a++) {
                const int side = 2 * a + (d[a] < 0.0f); /* +a is even, -a odd */
                const double w = fabs((double)d[a]);
                sums->cube_w[side] += w;
                if (!dark)
                    for (int k = 0; k < 3; k++)
                        sums->cube[side][k] += w * (double)L[k];
            }
        }
    if (th->sh2)
        for (int i = 0; i < n; i++) {
            const float *const L = &th->radiance[3 * i];
            if (L[0] == 0.0f && L[1] == 0.0f && L[2] == 0.0f)
                continue;
            float p[8];
            vdbgi_sh2_terms(&dirs[3 * i], p);
            for (int t = 0; t < 8; t++)
                for (int k = 0; k < 3; k++)
                    sums->sh[t][k] += (double)p[t] * L[k];
        }
}

/* c_k = w_k * mean(L p_k(d)): 4 pi Y_k^2 (the band's constant squared) times A_l / pi. */
const float vdbgi_sh2_weights[8] = {2.0f, 2.0f, 2.0f, 3.75f, 3.75f, 0.3125f, 3.75f, 0.9375f};

void vdbgi_sh2_terms(const float d[3], float p[8])
{
    const float x = d[0], y = d[1], z = d[2];
    p[0] = x, p[1] = y, p[2] = z;
    p[3] = x * y, p[4] = y * z, p[5] = 3.0f * z * z - 1.0f, p[6] = x * z, p[7] = x * x - y * y;
}

/* Standard error of a probe's value (the mean over channels), from its sums. */
static double standard_error(const probe_sums *s)
{
    if (s->rays < 2)
        return 0.0;
    const double n = (double)s->rays;
    const double mean = (s->sum[0] + s->sum[1] + s->sum[2]) / 3.0 / n;
    const double var = (s->sum_sq - n * mean * mean) / (n - 1.0);
    return var > 0.0 ? sqrt(var / n) : 0.0;
}

static void rotate_dirs(uint64_t stream, const float *base, int n, float *out)
{
    float m[9];
    random_rotation(stream, m);
    for (int i = 0; i < n; i++) {
        const float *const d = &base[3 * i];
        for (int r = 0; r < 3; r++)
            out[3 * i + r] = m[3 * r] * d[0] + m[3 * r + 1] * d[1] + m[3 * r + 2] * d[2];
    }
}

/* What a point's sums say: the counts, the validity, and when shading, the values. */
static void report(const vdbgi_estimator *th, const probe_sums *sums, vdbgi_estimate *out)
{
    memset(out, 0, sizeof(*out));
    out->rays = (uint32_t)sums->rays;
    out->shadow = sums->shadow;
    out->hits = sums->hits;
    out->backface = sums->hits ? (float)sums->back / (float)sums->hits : 0.0f;
    if (!th->shade)
        return;
    for (int k = 0; k < 3; k++)
        out->rgb[k] = (float)(sums->sum[k] / (double)sums->rays);
    out->stderr_ = (float)standard_error(sums);
    if (th->cube)
        for (int side = 0; side < 6; side++)
            for (int k = 0; k < 3; k++)
                out->cube[3 * side + k] = sums->cube_w[side] > 0.0
                                              ? (float)(sums->cube[side][k] / sums->cube_w[side])
                                              : 0.0f;
    if (th->sh2)
        for (int t = 0; t < 8; t++)
            for (int k = 0; k < 3; k++)
                out->sh[3 * t + k] =
                    (float)(vdbgi_sh2_weights[t] * sums->sh[t][k] / (double)sums->rays);
}

void vdbgi_estimate_point(vdbgi_estimator *th, const float pos[3], uint64_t stream,
                          vdbgi_estimate *out)
{
    const vdbgi_bake_params *const bp = th->bp;
    probe_sums sums;
    memset(&sums, 0, sizeof(sums));
    th->stream = stream;
    if (bp->adaptive) {
        /*
         * One Fibonacci set of max_rays directions under a random rotation, traced in
         * batches in bit-reversed order (every prefix is itself evenly spread), until
         * the standard error falls below the target (relative to the probe's value,
         * with a floor for dark probes) or the set is used up.
         */
        rotate_dirs(stream, th->base_dirs, bp->max_rays, th->dir);
        for (;;) {
            trace_batch(th, pos, &th->dir[3 * sums.rays], VDBGI_ADAPTIVE_BATCH, &sums);
            if (sums.rays + VDBGI_ADAPTIVE_BATCH > (size_t)bp->max_rays)
                break;
            if (sums.rays >= 2 * VDBGI_ADAPTIVE_BATCH) {
                const double mean =
                    (sums.sum[0] + sums.sum[1] + sums.sum[2]) / 3.0 / (double)sums.rays;
                if (standard_error(&sums) <= bp->noise * fmax(mean, 1e-3))
                    break;
            }
        }
    } else if (bp->sampling == VDBGI_SAMPLING_RANDOM) {
        rotate_dirs(stream, th->base_dirs, bp->rays, th->dir);
        trace_batch(th, pos, th->dir, bp->rays, &sums);
    } else {
        trace_batch(th, pos, th->base_dirs, bp->rays, &sums);
    }
    report(th, &sums, out);
}

void vdbgi_hemisphere_turn(const float *base, int count, const float n[3], uint64_t stream,
                           bool random, float *out)
{
    /* A frame (t, b, n); random sampling turns the set about n by an angle of its own. */
    float t[3], b[3];
    frame_about(n, t, b);
    float c = 1.0f, s = 0.0f;
    if (random) {
        const float turn = 2.0f * PI_F * (float)(vdbgi_splitmix64(&stream) >> 40) / 16777216.0f;
        c = cosf(turn), s = sinf(turn);
    }
    for (int i = 0; i < count; i++) {
        const float *const d = &base[3 * i];
        const float x = c * d[0] - s * d[1], y = s * d[0] + c * d[1];
        for (int k = 0; k < 3; k++)
            out[3 * i + k] = x * t[k] + y * b[k] + d[2] * n[k];
    }
}

void vdbgi_estimate_hemisphere(vdbgi_estimator *th, const float pos[3], const float n[3],
                               uint64_t stream, vdbgi_estimate *out)
{
    const vdbgi_bake_params *const bp = th->bp;
    vdbgi_hemisphere_turn(th->base_dirs, bp->rays, n, stream, bp->sampling == VDBGI_SAMPLING_RANDOM,
                          th->dir);
    probe_sums sums;
    memset(&sums, 0, sizeof(sums));
    th->stream = stream;
    trace_batch(th, pos, th->dir, bp->rays, &sums);
    report(th, &sums, out);
}

void vdbgi_hemisphere_directions(int n, float *dirs)
{
    const double golden = 3.14159265358979323846 * (3.0 - sqrt(5.0));
    for (int i = 0; i < n; i++) {
        const double r = sqrt((i + 0.5) / n), phi = golden * i;
        dirs[3 * i] = (float)(r * cos(phi));
        dirs[3 * i + 1] = (float)(r * sin(phi));
        dirs[3 * i + 2] = (float)sqrt(fmax(0.0, 1.0 - r * r));
    }
}

vdbgi_result vdbgi_estimator_directions(vdbgi_context *ctx, const vdbgi_bake_params *bp,
                                        float **dirs, int *count)
{
    /* All the rays of a point, or the adaptive cap in bit-reversed order. */
    const int set = bp->adaptive ? bp->max_rays : bp->rays;
    float *const d = vdbgi_calloc(ctx, (size_t)set, 3 * sizeof(float));
    if (!d)
        return VDBGI_ERR_OUT_OF_MEMORY;
    vdbgi_fibonacci_directions(set, d);
    if (bp->adaptive)
        bit_reverse_order(d, set);
    *dirs = d;
    *count = set;
    return VDBGI_OK;
}

vdbgi_result vdbgi_estimator_init(vdbgi_context *ctx, vdbgi_estimator *e, int set_count)
{
    const size_t n = (size_t)set_count; /* a whole set (adaptive: the cap) */
    e->dir = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->sorg = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->sun_weight = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->shadow_ray = vdbgi_calloc(ctx, n, sizeof(uint32_t));
    e->radiance = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->hits = vdbgi_calloc(ctx, n, sizeof(vdbgi_hit));
    e->occluded = vdbgi_calloc(ctx, n, 1);
    e->sdir = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->sdist = vdbgi_calloc(ctx, n, sizeof(float));
    e->porg = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->pnorm = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->pweight = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->pray = vdbgi_calloc(ctx, n, sizeof(uint32_t));
    e->scratch = vdbgi_alloc(ctx, vdbgi_tracer_scratch_size(n));
    if (!e->dir || !e->sorg || !e->sun_weight || !e->shadow_ray || !e->radiance || !e->hits ||
        !e->occluded || !e->sdir || !e->sdist || !e->porg || !e->pnorm || !e->pweight || !e->pray ||
        !e->scratch) {
        vdbgi_estimator_free(ctx, e);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    return VDBGI_OK;
}

void vdbgi_estimator_free(vdbgi_context *ctx, vdbgi_estimator *e)
{
    vdbgi_free(ctx, e->dir);
    vdbgi_free(ctx, e->sorg);
    vdbgi_free(ctx, e->sun_weight);
    vdbgi_free(ctx, e->radiance);
    vdbgi_free(ctx, e->shadow_ray);
    vdbgi_free(ctx, e->hits);
    vdbgi_free(ctx, e->occluded);
    vdbgi_free(ctx, e->scratch);
    vdbgi_free(ctx, e->sdir);
    vdbgi_free(ctx, e->sdist);
    vdbgi_free(ctx, e->porg);
    vdbgi_free(ctx, e->pnorm);
    vdbgi_free(ctx, e->pweight);
    vdbgi_free(ctx, e->pray);
    e->sdir = e->sdist = e->porg = e->pnorm = e->pweight = NULL;
    e->pray = NULL;
    e->dir = e->sorg = e->sun_weight = e->radiance = NULL;
    e->shadow_ray = NULL;
    e->hits = NULL;
    e->occluded = NULL;
    e->scratch = NULL;
}
