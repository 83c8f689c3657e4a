/*
 * params.c: a bake's settings resolved (defaults, ranges, the scene's
 * lights and sky taken in), and the sources as the estimator reads them: a
 * lamp's light at a point, the sky along a ray that meets nothing.
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
    bool scene_sun = false, scene_lit = false;
    for (size_t i = 0; i < count; i++) {
        scene_sun = scene_sun || lights[i].type == VDBGI_LIGHT_DIRECTIONAL;
        scene_lit = scene_lit || !is_zero3(lights[i].color);
    }
    /* The scene's own sun replaces the default one; a sun_dir given replaces the scene's.
       Under the physical model a scene whose own lamps light it (punctual lights of non-zero
       intensity; emitters do not count) is lit by them alone: a sun nobody put in the scene
       would light an interior's outer walls and come in at its windows. */
    const bool given = !is_zero3(desc->sun_dir);
    const bool asked = given || desc->sun_color_is_set || !is_zero3(desc->sun_color);
    const bool own_light = scene_lit && bp->model == VDBGI_MODEL_PHYSICAL && !asked;
    if ((scene_sun && !given) || own_light) {
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
    bp->adaptive = desc->adaptive != 0;
    VDBGI_FAIL_IF(ctx, bp->adaptive && desc->rays != 0, VDBGI_ERR_INVALID_ARG,
                  "an adaptive bake takes no fixed ray count (got %d; max rays caps it)",
                  desc->rays);
    bp->rays = desc->rays == 0 ? 128 : desc->rays;
    VDBGI_FAIL_IF(ctx, bp->rays < 1 || bp->rays > 1000000, VDBGI_ERR_INVALID_ARG,
                  "rays per probe must be in 1..1000000 (got %d)", desc->rays);
    bp->noise = desc->noise != 0.0f ? desc->noise : VDBGI_NOISE;
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
    bp->ambient = desc->ambient == 0.0f && !desc->ambient_is_set ? 0.15f : desc->ambient;
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

    const bool default_sun_color = is_zero3(desc->sun_color) && !desc->sun_color_is_set;
    for (int k = 0; k < 3; k++)
        bp->sun_color[k] = default_sun_color ? 1.0f : desc->sun_color[k];
    bp->sun_on = !is_zero3(bp->sun_color);
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
        VDBGI_FAIL_IF(ctx, desc->ambient != 0.0f, VDBGI_ERR_INVALID_ARG,
                      "the physical model has no ambient fill (got %g)", (double)desc->ambient);
        VDBGI_FAIL_IF(ctx, desc->falloff != 0.0f && !isinf(desc->falloff), VDBGI_ERR_INVALID_ARG,
                      "the physical model has no distance falloff (got %g)", (double)desc->falloff);
        bp->ambient = 0.0f;
        bp->falloff = INFINITY;
    }
    VDBGI_FAIL_IF(ctx, desc->lights != VDBGI_LIGHTS_SCENE && desc->lights != VDBGI_LIGHTS_OFF,
                  VDBGI_ERR_INVALID_ARG, "unknown lights setting %d", (int)desc->lights);
    bp->lights = desc->lights;
    /* The physical model bounces until converged unless told; the seed model's fill stands in
       for the bounces past its one. */
    VDBGI_FAIL_IF(ctx, desc->bounces < 0 || desc->bounces > VDBGI_MAX_BOUNCES,
                  VDBGI_ERR_INVALID_ARG, "bounces must be in 1..%d, or 0 until converged (got %d)",
                  VDBGI_MAX_BOUNCES, desc->bounces);
    const bool until = desc->bounces == 0 && bp->model == VDBGI_MODEL_PHYSICAL;
    VDBGI_FAIL_IF(ctx, desc->converge != 0.0f && !until, VDBGI_ERR_INVALID_ARG,
                  "a converged share is for bounces until converged, under the physical model "
                  "(got %g)",
                  (double)desc->converge);
    bp->bounces = until ? 0 : desc->bounces ? desc->bounces : 1;
    bp->converge = !until ? 0.0f : desc->converge == 0.0f ? VDBGI_CONVERGE : desc->converge;
    VDBGI_FAIL_IF(ctx, until && !(bp->converge > 0.0f && bp->converge < 1.0f),
                  VDBGI_ERR_INVALID_ARG, "the converged share must be in (0, 1) (got %g)",
                  (double)desc->converge);
    bp->tail[0] = bp->tail[1] = bp->tail[2] = 0.0f;
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
