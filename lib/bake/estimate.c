/*
 * estimate.c: seed 000's irradiance estimator for one sample point: the
 * rays and their bounces, the lamps' shadow rays, validity (the back-face
 * fraction), the standard error, the ambient-cube sides and the L2 terms.
 * Its direction sets are directions.c's; its settings and sources params.c's.
 */
#include "estimate.h"
#include "util.h"

#include <math.h>
#include <string.h>

#define PI_F 3.14159265358979f

/* What a probe's rays add up to, batch after batch. */
typedef struct probe_sums {
    double sum[3]; /* radiance, per channel */
    double sum_sq; /* squares of the per-ray mean over channels, for the standard error */
    double cube[6][3], cube_w[6];
    double sh[8][3]; /* radiance times each L2 term, per channel */
    size_t rays, hits, back, shadow;
} probe_sums;

/* Light l of a path's depth-th increment (see vdbgi_estimator.depth_light), when counted. */
static void count_depth(vdbgi_estimator *th, int depth, const float l[3])
{
    if (th->depth_light)
        for (int k = 0; k < 3; k++)
            th->depth_light[3 * depth + k] += l[k];
}

/*
 * Light from the lamps at the count path hits in th (phit, porg, poff,
 * pnorm, pweight, pray), the depth-th hits of their paths: each lamp is read
 * at the hit itself, and its shadow ray starts at the hit's origin, one
 * offset off the surface; for the open ones radiance[ray[i]] += weight[i] x
 * f x the lamp's colour. Returns the shadow rays traced.
 */
static size_t light_points(vdbgi_estimator *th, size_t count, int depth)
{
    const vdbgi_bake_params *const bp = th->bp;
    size_t traced = 0;
    for (int li = 0; li < bp->lamp_count; li++) {
        const vdbgi_lamp *const l = &bp->lamps[li];
        size_t m = 0;
        for (size_t i = 0; i < count; i++) {
            float f, dist;
            if (!vdbgi_lamp_light(l, &th->phit[3 * i], &th->pnorm[3 * i], &f, &th->sdir[3 * m],
                                  &dist))
                continue;
            memcpy(&th->sorg[3 * m], &th->porg[3 * i], 3 * sizeof(float));
            th->sdist[m] = dist - th->poff[i]; /* stop short of a lamp on a surface */
            for (int k = 0; k < 3; k++)
                th->sun_weight[3 * m + k] = th->pweight[3 * i + k] * f * l->rgb[k];
            th->shadow_ray[m] = th->pray[i];
            m++;
        }
        if (!m)
            continue;
        const vdbgi_ray_batch shadow = {th->sorg, th->sdir, 3, 3, 0.0f, INFINITY, m, th->sdist};
        vdbgi_tracer_occluded(th->tracer, bp->method, &shadow, th->occluded, th->scratch);
        traced += m;
        if (th->shade)
            for (size_t s = 0; s < m; s++)
                if (!th->occluded[s]) {
                    for (int k = 0; k < 3; k++)
                        th->radiance[3 * th->shadow_ray[s] + k] += th->sun_weight[3 * s + k];
                    count_depth(th, depth, &th->sun_weight[3 * s]);
                }
    }
    return traced;
}

/*
 * Path slot i becomes hit h of a ray along d: the point on the surface, the
 * origin one offset off its side facing the ray, that side's normal, and
 * throughput w.
 */
static void set_path_hit(vdbgi_estimator *th, size_t i, const vdbgi_hit *h, const float d[3],
                         const float w[3])
{
    const float *const tn = th->scene->tris[h->prim].normal;
    const float flip = tn[0] * d[0] + tn[1] * d[1] + tn[2] * d[2] > 0.0f ? -1.0f : 1.0f;
    float p[3];
    const float off = vdbgi_scene_hit_point(th->scene, h->prim, h->u, h->v, p);
    for (int k = 0; k < 3; k++) {
        th->phit[3 * i + k] = p[k];
        th->pnorm[3 * i + k] = tn[k] * flip;
        th->porg[3 * i + k] = p[k] + off * tn[k] * flip;
        th->pweight[3 * i + k] = w[k];
    }
    th->poff[i] = off;
}

/*
 * The longest path, in surface hits, that still brings light to the point.
 * Lamps are read at each of a path's bounces hits; the physical model lets
 * the path go one ray further for what is met by looking, the sky and
 * emitters, so that N bounces carry every source over N reflections. The seed
 * model keeps seed 000's count; a previous pass's map (hit_light) already
 * holds what the first hit sees.
 */
static int path_rays(const vdbgi_estimator *th)
{
    const vdbgi_bake_params *const bp = th->bp;
    return bp->bounces + (bp->model == VDBGI_MODEL_PHYSICAL && !th->hit_light);
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
 * Rays 2..path_rays of the paths that left count hits (th's path arrays):
 * one cosine-weighted ray each, its own random numbers from the point's
 * stream, the ray's index and the bounce. A miss brings the sky, a hit its
 * emission, times the path's throughput; within the bounces the hit's lamps
 * are read and the path goes on from there with its albedo. Returns the rays
 * traced (paths and shadows).
 */
static size_t trace_bounces(vdbgi_estimator *th, size_t count, size_t first_ray)
{
    const vdbgi_bake_params *const bp = th->bp;
    const vdbgi_scene *const scene = th->scene;
    const int last = path_rays(th);
    size_t traced = 0;
    for (int b = 2; b <= last && count; b++) {
        for (size_t i = 0; i < count; i++) {
            uint64_t st = th->stream ^
                          ((uint64_t)(first_ray + th->pray[i]) * 0x9E3779B97F4A7C15ull) ^
                          ((uint64_t)b * 0xC2B2AE3D27D4EB4Full);
            vdbgi_splitmix64(&st);
            const double u1 = vdbgi_uniform01(&st), u2 = vdbgi_uniform01(&st);
            cosine_direction(&th->pnorm[3 * i], u1, u2, &th->bdir[3 * i]);
        }
        const vdbgi_ray_batch rays = {th->porg, th->bdir, 3, 3, 0.0f, bp->ray_dist, count, NULL};
        vdbgi_tracer_intersect(th->tracer, bp->method, &rays, th->hits, th->scratch);
        traced += count;
        const bool goes_on = b <= bp->bounces;
        size_t live = 0;
        for (size_t i = 0; i < count; i++) {
            const vdbgi_hit *const h = &th->hits[i];
            const float *const d = &th->bdir[3 * i];
            float *const L = &th->radiance[3 * th->pray[i]];
            const float *const w = &th->pweight[3 * i];
            if (!(h->t < INFINITY)) {
                float sky[3];
                vdbgi_miss_radiance(bp, d, sky);
                for (int k = 0; k < 3; k++)
                    L[k] += sky[k] *= w[k];
                count_depth(th, b - 1, sky);
                continue;
            }
            const float *const tn = scene->tris[h->prim].normal;
            const bool front = tn[0] * d[0] + tn[1] * d[1] + tn[2] * d[2] <= 0.0f;
            float e[3];
            if (hit_emission(bp, scene, h, front, e)) {
                for (int k = 0; k < 3; k++)
                    L[k] += e[k] *= w[k];
                count_depth(th, b - 1, e);
            }
            if (!goes_on)
                continue;
            /* The path goes on from this hit (compacted in place: live <= i). */
            float albedo[3], wa[3];
            vdbgi_scene_albedo(scene, h->prim, h->u, h->v, albedo);
            const bool final = b == bp->bounces;
            for (int k = 0; k < 3; k++)
                wa[k] = w[k] * albedo[k] * (final ? 1.0f + bp->tail[k] : 1.0f);
            th->pray[live] = th->pray[i];
            set_path_hit(th, live++, h, d, wa);
        }
        if (goes_on)
            traced += light_points(th, live, b);
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
        if (facing > 0.0f && !(tri->flags & VDBGI_TRI_DOUBLE_SIDED))
            sums->back++;
        float albedo_w[3] = {0.0f, 0.0f, 0.0f};
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
            if (hit_emission(bp, scene, h, facing <= 0.0f, e))
                for (int k = 0; k < 3; k++)
                    L[k] += w * e[k];
        }
        /* The last bounce traced carries the bounces past it (bp->tail). */
        if (bp->bounces == 1)
            for (int k = 0; k < 3; k++)
                albedo_w[k] *= 1.0f + bp->tail[k];
        th->pray[hit_count] = (uint32_t)i;
        set_path_hit(th, hit_count++, h, d, albedo_w);
    }
    if (th->depth_light)
        for (int i = 0; i < n; i++)
            count_depth(th, 0, &th->radiance[3 * i]);
    size_t shadow_count = light_points(th, hit_count, 1);
    if (path_rays(th) > 1)
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

/*
 * Two sets' sums as one: each set's means weighted as the inverse of its
 * variance, which falls as n^-1.5 for a Fibonacci set over smooth light (an
 * even split of rays would weigh the pilot's coarser set too much); then
 * scaled back to sums over both sets' rays. The counts add.
 */
static void blend(probe_sums *a, const probe_sums *b)
{
    const double na = (double)a->rays, nb = (double)b->rays, n = na + nb;
    const double wa = pow(na, 1.5), wb = pow(nb, 1.5);
    const double sa = wa / (wa + wb) * n / na, sb = wb / (wa + wb) * n / nb;
    for (int k = 0; k < 3; k++)
        a->sum[k] = a->sum[k] * sa + b->sum[k] * sb;
    for (int side = 0; side < 6; side++) {
        a->cube_w[side] = a->cube_w[side] * sa + b->cube_w[side] * sb;
        for (int k = 0; k < 3; k++)
            a->cube[side][k] = a->cube[side][k] * sa + b->cube[side][k] * sb;
    }
    for (int t = 0; t < 8; t++)
        for (int k = 0; k < 3; k++)
            a->sh[t][k] = a->sh[t][k] * sa + b->sh[t][k] * sb;
    a->sum_sq += b->sum_sq; /* the spread of the rays, as if alike */
    a->rays += b->rays, a->hits += b->hits, a->back += b->back, a->shadow += b->shadow;
}

/* count of base's directions under a turn of stream's into th->dir: about the unit normal
   when there is one (a texel's hemisphere), else a whole rotation (a probe's sphere). */
static void turn_set(vdbgi_estimator *th, const float *normal, const float *base, int count,
                     uint64_t stream)
{
    if (normal)
        vdbgi_hemisphere_turn(base, count, normal, stream, true, th->dir);
    else
        vdbgi_directions_rotate(stream, base, count, th->dir);
}

/*
 * An adaptive point: a pilot set under its turn, then, when its spread (the
 * rays' standard deviation) asks for more, one more set of the ladder under
 * a turn of its own; the estimate is both sets' (blend).
 */
static void trace_adaptive(vdbgi_estimator *th, const float pos[3], const float *normal,
                           uint64_t stream, probe_sums *sums)
{
    const vdbgi_bake_params *const bp = th->bp;
    const int B = VDBGI_ADAPTIVE_BATCH;
    turn_set(th, normal, th->base_dirs, B, stream);
    trace_batch(th, pos, th->dir, B, sums);
    const double want = ceil(bp->adaptive_scale *
                             sqrt(standard_error(sums) * sqrt((double)B) + bp->adaptive_floor));
    if (want <= B)
        return;
    int offset;
    const int rest =
        vdbgi_adaptive_set((int)fmin(want, (double)bp->max_rays) - B, bp->max_rays, &offset);
    uint64_t turn = stream ^ 0x9E3779B97F4A7C15ull;
    turn_set(th, normal, &th->base_dirs[3 * offset], rest, vdbgi_splitmix64(&turn));
    probe_sums more;
    memset(&more, 0, sizeof(more));
    more.rays = (size_t)B; /* the bounces' random numbers go on from the pilot's */
    trace_batch(th, pos, th->dir, rest, &more);
    more.rays -= (size_t)B;
    blend(sums, &more);
}

void vdbgi_estimate_point(vdbgi_estimator *th, const float pos[3], uint64_t stream,
                          vdbgi_estimate *out)
{
    const vdbgi_bake_params *const bp = th->bp;
    probe_sums sums;
    memset(&sums, 0, sizeof(sums));
    th->stream = stream;
    if (bp->adaptive) {
        trace_adaptive(th, pos, NULL, stream, &sums);
    } else if (bp->sampling == VDBGI_SAMPLING_RANDOM) {
        vdbgi_directions_rotate(stream, th->base_dirs, bp->rays, th->dir);
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
    probe_sums sums;
    memset(&sums, 0, sizeof(sums));
    th->stream = stream;
    if (bp->adaptive) {
        trace_adaptive(th, pos, n, stream, &sums);
    } else {
        vdbgi_hemisphere_turn(th->base_dirs, bp->rays, n, stream,
                              bp->sampling == VDBGI_SAMPLING_RANDOM, th->dir);
        trace_batch(th, pos, th->dir, bp->rays, &sums);
    }
    report(th, &sums, out);
}

vdbgi_result vdbgi_estimator_init(vdbgi_context *ctx, vdbgi_estimator *e, int set_count)
{
    const size_t n = (size_t)set_count; /* the most rays a point traces at once */
    e->dir = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->bdir = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->sorg = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->sun_weight = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->shadow_ray = vdbgi_calloc(ctx, n, sizeof(uint32_t));
    e->radiance = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->hits = vdbgi_calloc(ctx, n, sizeof(vdbgi_hit));
    e->occluded = vdbgi_calloc(ctx, n, 1);
    e->sdir = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->sdist = vdbgi_calloc(ctx, n, sizeof(float));
    e->phit = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->porg = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->poff = vdbgi_calloc(ctx, n, sizeof(float));
    e->pnorm = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->pweight = vdbgi_calloc(ctx, n, 3 * sizeof(float));
    e->pray = vdbgi_calloc(ctx, n, sizeof(uint32_t));
    e->scratch = vdbgi_alloc(ctx, vdbgi_tracer_scratch_size(n));
    if (!e->dir || !e->bdir || !e->sorg || !e->sun_weight || !e->shadow_ray || !e->radiance ||
        !e->hits || !e->occluded || !e->sdir || !e->sdist || !e->phit || !e->porg || !e->poff ||
        !e->pnorm || !e->pweight || !e->pray || !e->scratch) {
        vdbgi_estimator_free(ctx, e);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    return VDBGI_OK;
}

void vdbgi_estimator_free(vdbgi_context *ctx, vdbgi_estimator *e)
{
    vdbgi_free(ctx, e->dir);
    vdbgi_free(ctx, e->bdir);
    vdbgi_free(ctx, e->sorg);
    vdbgi_free(ctx, e->sun_weight);
    vdbgi_free(ctx, e->radiance);
    vdbgi_free(ctx, e->shadow_ray);
    vdbgi_free(ctx, e->hits);
    vdbgi_free(ctx, e->occluded);
    vdbgi_free(ctx, e->scratch);
    vdbgi_free(ctx, e->sdir);
    vdbgi_free(ctx, e->sdist);
    vdbgi_free(ctx, e->phit);
    vdbgi_free(ctx, e->porg);
    vdbgi_free(ctx, e->poff);
    vdbgi_free(ctx, e->pnorm);
    vdbgi_free(ctx, e->pweight);
    vdbgi_free(ctx, e->pray);
    e->sdir = e->sdist = e->phit = e->porg = e->poff = e->pnorm = e->pweight = NULL;
    e->pray = NULL;
    e->dir = e->bdir = e->sorg = e->sun_weight = e->radiance = NULL;
    e->shadow_ray = NULL;
    e->hits = NULL;
    e->occluded = NULL;
    e->scratch = NULL;
}
