/*
 * bench_truth.c: gi-bench truth: every way of lighting a surface, held to the
 * same truth: the hemisphere estimator (2048 random rays) at each receiver,
 * over the receiver's own normal.
 */
#include "bench_truth.h"
#include "cli.h"
#include "vdbgi_bench.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define PI 3.14159265358979
#define SURFACE_POINTS 3000
#define CHARACTER_POINTS 400
/* A character's sides: up, the four horizontal, down. */
static const float character_normals[6][3] = {{0, 1, 0}, {1, 0, 0},  {-1, 0, 0},
                                              {0, 0, 1}, {0, 0, -1}, {0, -1, 0}};

void bench_receivers_free(bench_receivers *r)
{
    free(r->pos);
    free(r->normal);
    free(r->truth);
    free(r->prim);
    free(r->uv);
    free(r->kind);
}

/*
 * Points on the surfaces spread by area, each with its triangle's front
 * normal and E there; then points 0.5-2 m above walkable ones, each read by
 * six normals. Receivers whose rays mostly meet back faces (inside solids)
 * are dropped.
 */
vdbgi_bake_desc bench_lit(vdbgi_bake_desc d, const bench_light *light)
{
    if (light) {
        d.model = light->model;
        d.bounces = light->bounces ? light->bounces : 1; /* the truth at a count, never auto */
    }
    return d;
}

vdbgi_result bench_receivers_make(const vdbgi_scene *scene, const bench_light *light,
                                  bench_receivers *rv)
{
    const size_t n = SURFACE_POINTS, most = n + 6 * CHARACTER_POINTS;
    memset(rv, 0, sizeof(*rv));
    rv->pos = calloc(3 * most, sizeof(float));
    rv->normal = calloc(3 * most, sizeof(float));
    rv->truth = calloc(3 * most, sizeof(float));
    rv->prim = calloc(n, sizeof(uint32_t));
    rv->uv = calloc(2 * n, sizeof(float));
    rv->kind = calloc(most, 1);
    float *const lifted = calloc(3 * n, sizeof(float));
    float *const bf = calloc(most, sizeof(float));
    if (!rv->pos || !rv->normal || !rv->truth || !rv->prim || !rv->uv || !rv->kind || !lifted ||
        !bf) {
        free(lifted);
        free(bf);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    const vdbgi_bake_desc truth = bench_lit(
        (vdbgi_bake_desc){.rays = 2048, .sampling = VDBGI_SAMPLING_RANDOM, .seed = 5}, light);
    vdbgi_result r = vdbgi_scene_sample_triangles(scene, n, 7, rv->prim, rv->uv);
    if (r == VDBGI_OK) /* the same points, on the surface and 10 cm off it: the normal */
        r = vdbgi_scene_sample_surface(scene, n, 0.0f, 7, rv->pos);
    if (r == VDBGI_OK)
        r = vdbgi_scene_sample_surface(scene, n, 0.1f, 7, lifted);
    if (r == VDBGI_OK)
        r = vdbgi_scene_bake_surface(scene, &truth, rv->prim, rv->uv, n, rv->truth, bf);
    size_t kept = 0;
    for (size_t i = 0; r == VDBGI_OK && i < n; i++) {
        if (bf[i] > 0.25f)
            continue; /* a face nobody sees */
        float *const nrm = &rv->normal[3 * kept];
        for (int k = 0; k < 3; k++)
            nrm[k] = (lifted[3 * i + k] - rv->pos[3 * i + k]) / 0.1f;
        memmove(&rv->pos[3 * kept], &rv->pos[3 * i], 3 * sizeof(float));
        memmove(&rv->truth[3 * kept], &rv->truth[3 * i], 3 * sizeof(float));
        rv->prim[kept] = rv->prim[i];
        memmove(&rv->uv[2 * kept], &rv->uv[2 * i], 2 * sizeof(float));
        rv->kind[kept] = nrm[1] > 0.7f ? 0 : fabsf(nrm[1]) < 0.3f ? 1 : 2;
        kept++;
    }
    rv->surface = kept;
    /* Characters: over every walkable receiver in turn, until there are enough. */
    size_t c = 0;
    for (size_t i = 0; r == VDBGI_OK && i < rv->surface && c < CHARACTER_POINTS; i++) {
        if (rv->kind[i] != 0)
            continue;
        const unsigned h = (unsigned)i * 2654435761u;
        const float lift = 0.5f + 1.5f * (float)(h >> 8) / 16777216.0f;
        for (int s = 0; s < 6; s++) {
            const size_t at = kept + 6 * c + (size_t)s;
            memcpy(&rv->pos[3 * at], &rv->pos[3 * i], 3 * sizeof(float));
            rv->pos[3 * at + 1] += lift;
            memcpy(&rv->normal[3 * at], character_normals[s], 3 * sizeof(float));
            rv->kind[at] = 3;
        }
        c++;
    }
    if (r == VDBGI_OK)
        r = vdbgi_scene_bake_hemispheres(scene, &truth, &rv->pos[3 * kept], &rv->normal[3 * kept],
                                         6 * c, &rv->truth[3 * kept], &bf[kept]);
    size_t total = kept;
    for (size_t i = kept; r == VDBGI_OK && i < kept + 6 * c; i += 6) {
        bool inside = false; /* a point inside a solid is no character: drop its six together */
        for (int s = 0; s < 6; s++)
            inside = inside || bf[i + (size_t)s] > 0.25f;
        if (inside)
            continue;
        memmove(&rv->pos[3 * total], &rv->pos[3 * i], 18 * sizeof(float));
        memmove(&rv->normal[3 * total], &rv->normal[3 * i], 18 * sizeof(float));
        memmove(&rv->truth[3 * total], &rv->truth[3 * i], 18 * sizeof(float));
        memmove(&rv->kind[total], &rv->kind[i], 6);
        total += 6;
    }
    rv->count = total;
    free(lifted);
    free(bf);
    return r;
}

bench_error bench_error_of(const bench_receivers *rv, const float *got, int kind)
{
    double se = 0.0, sum_got = 0.0, sum_ref = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < rv->count; i++) {
        const bool in = kind < 0 ? rv->kind[i] != 3 : rv->kind[i] == kind;
        if (!in)
            continue;
        for (int k = 0; k < 3; k++) {
            const double d = (double)got[3 * i + k] - rv->truth[3 * i + k];
            se += d * d;
            sum_got += got[3 * i + k];
            sum_ref += rv->truth[3 * i + k];
        }
        n++;
    }
    const double mean = n ? sum_ref / (3.0 * (double)n) : 0.0;
    bench_error e = {0.0, 0.0, n};
    if (n && mean > 0.0) {
        e.rmse = sqrt(se / (3.0 * (double)n)) / mean;
        e.bias = sum_got / sum_ref;
    }
    return e;
}

static void print_row(FILE *csv, double spacing, const char *method, const bench_receivers *rv,
                      const float *got)
{
    const bench_error all = bench_error_of(rv, got, -1), floors = bench_error_of(rv, got, 0),
                      walls = bench_error_of(rv, got, 1), chars = bench_error_of(rv, got, 3);
    char at[32] = "-";
    if (spacing > 0.0)
        snprintf(at, sizeof(at), "%g m", spacing);
    printf("| %s | %s | %.1f %% | %.2f | %.2f | %.2f |", at, method, 100.0 * all.rmse, all.bias,
           floors.bias, walls.bias);
    if (chars.n)
        printf(" %.1f %% | %.2f |\n", 100.0 * chars.rmse, chars.bias);
    else
        printf(" | |\n");
    fprintf(csv, "%g,%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%zu,%zu\n", spacing, method, all.rmse,
            all.bias, floors.bias, walls.bias, chars.rmse, chars.bias, all.n, chars.n);
}

/*
 * The probes' reading at every receiver (E, not E / pi), with or without the
 * normal; with it, a surface's point moved a quarter spacing off the surface
 * first, a character's where it is.
 */
static vdbgi_result probes_reading(const vdbgi_probes *p, const bench_receivers *rv, bool normal,
                                   float *got)
{
    vdbgi_probes_info pi;
    vdbgi_probes_get_info(p, &pi);
    const float bias = 0.25f * (float)pi.spacing;
    vdbgi_result r = vdbgi_probes_sample_points(p, rv->surface, rv->pos, normal ? rv->normal : NULL,
                                                bias, got, NULL);
    if (r == VDBGI_OK)
        r = vdbgi_probes_sample_points(p, rv->count - rv->surface, &rv->pos[3 * rv->surface],
                                       normal ? &rv->normal[3 * rv->surface] : NULL, 0.0f,
                                       &got[3 * rv->surface], NULL);
    for (size_t i = 0; i < 3 * rv->count; i++)
        got[i] *= (float)PI;
    return r;
}

void bench_volume_reading(const vdbgi_volume *v, const bench_receivers *rv, float *got)
{
    vdbgi_volume_info vi;
    vdbgi_volume_get_info(v, &vi);
    const bool l2 = vi.basis == VDBGI_BASIS_SH2;
    const float off = 0.5f * vi.spacing;
    for (size_t i = 0; i < rv->count; i++) {
        const float *const n = &rv->normal[3 * i];
        float at[3];
        for (int k = 0; k < 3; k++)
            at[k] = rv->pos[3 * i + k] + (l2 && i < rv->surface ? off * n[k] : 0.0f);
        vdbgi_volume_sample_normal(v, at, n, &got[3 * i]);
        for (int k = 0; k < 3; k++)
            got[3 * i + k] *= (float)PI;
    }
}

/* One spacing: bake both bases, read every method at every receiver, a row each. */
static vdbgi_result truth_at_spacing(vdbgi_context *ctx, const vdbgi_scene *scene,
                                     const bench_receivers *rv, double spacing, int rays,
                                     int threads, const bench_light *light, FILE *csv, float *got)
{
    const vdbgi_place_desc pd = {.spacing = spacing, .margin = 2.5};
    vdbgi_probes *p = NULL, *cube = NULL;
    vdbgi_volume *v = NULL;
    vdbgi_result r = vdbgi_probes_place(ctx, scene, &pd, &p);
    if (r == VDBGI_OK)
        r = vdbgi_probes_place(ctx, scene, &pd, &cube);
    vdbgi_bake_desc bd = bench_lit(
        (vdbgi_bake_desc){.rays = rays, .threads = threads, .basis = VDBGI_BASIS_SH2}, light);
    if (r == VDBGI_OK)
        r = vdbgi_probes_bake(p, scene, &bd, NULL);
    bd.basis = VDBGI_BASIS_AMBIENT_CUBE;
    if (r == VDBGI_OK)
        r = vdbgi_probes_bake(cube, scene, &bd, NULL);
    /* Today's runtime: the scalar in bricks at the converter's defaults. */
    const vdbgi_convert_desc cd = {.threads = threads, .terms = VDBGI_TERMS_DROP};
    if (r == VDBGI_OK)
        r = vdbgi_volume_build(ctx, p, &cd, &v);
    if (r == VDBGI_OK) {
        bench_volume_reading(v, rv, got);
        print_row(csv, spacing, "scalar, bricks (defaults)", rv, got);
    }
    /* The directional runtime: the same bricks carrying L2 terms, read with the normal half
       a spacing off a surface, as the shaders read them. */
    vdbgi_volume_destroy(v);
    v = NULL;
    if (r == VDBGI_OK)
        r = vdbgi_volume_build(ctx, p, &(vdbgi_convert_desc){.threads = threads}, &v);
    if (r == VDBGI_OK) {
        bench_volume_reading(v, rv, got);
        print_row(csv, spacing, "L2, bricks (defaults)", rv, got);
    }
    /* What the luminance second band costs: the same bricks as version 8 (14 term bytes a
       texel) and as version 7 (24, every term in colour), whichever the default chose. */
    for (int version = 8; r == VDBGI_OK && version >= 7; version--) {
        vdbgi_volume_destroy(v);
        v = NULL;
        r = vdbgi_volume_build(
            ctx, p, &(vdbgi_convert_desc){.threads = threads, .gi_version = version}, &v);
        if (r == VDBGI_OK) {
            bench_volume_reading(v, rv, got);
            print_row(csv, spacing,
                      version == 8 ? "L2, bricks, version 8 (the second band in luminance)"
                                   : "L2, bricks, version 7 (every term in colour)",
                      rv, got);
        }
    }
    /* What the rounding of the terms costs: every bit kept, and fewer than the default. */
    static const int bits[] = {8, 7, 5, 4};
    for (int b = 0; r == VDBGI_OK && b < 4; b++) {
        vdbgi_volume_destroy(v);
        v = NULL;
        r = vdbgi_volume_build(ctx, p,
                               &(vdbgi_convert_desc){.threads = threads, .term_bits = bits[b]}, &v);
        if (r == VDBGI_OK) {
            char name[64];
            snprintf(name, sizeof(name), "L2, bricks, terms %d bits", bits[b]);
            bench_volume_reading(v, rv, got);
            print_row(csv, spacing, name, rv, got);
        }
    }
    if (r == VDBGI_OK && (r = probes_reading(p, rv, false, got)) == VDBGI_OK)
        print_row(csv, spacing, "scalar, every probe", rv, got);
    if (r == VDBGI_OK && (r = probes_reading(cube, rv, true, got)) == VDBGI_OK)
        print_row(csv, spacing, "ambient cube, every probe", rv, got);
    if (r == VDBGI_OK && (r = probes_reading(p, rv, true, got)) == VDBGI_OK)
        print_row(csv, spacing, "L2, every probe", rv, got);
    /* The directions (issue 41): the same bricks from each probe's own random rotation of
       the set, and from half the rays, against the one Fibonacci set every probe shares. */
    static const struct {
        vdbgi_sampling sampling;
        int halve;
        const char *name;
    } sets[3] = {
        {VDBGI_SAMPLING_RANDOM, 0, "L2, bricks, a random rotation a probe"},
        {VDBGI_SAMPLING_FIBONACCI, 1, "L2, bricks, half the rays"},
        {VDBGI_SAMPLING_RANDOM, 1, "L2, bricks, half the rays, a random rotation a probe"}};
    for (int d = 0; r == VDBGI_OK && d < 3; d++) {
        vdbgi_bake_desc dd = bd;
        dd.basis = VDBGI_BASIS_SH2;
        dd.sampling = sets[d].sampling;
        dd.rays = rays > 1 ? rays >> sets[d].halve : rays;
        vdbgi_volume_destroy(v);
        v = NULL;
        if ((r = vdbgi_probes_bake(p, scene, &dd, NULL)) == VDBGI_OK &&
            (r = vdbgi_volume_build(ctx, p, &(vdbgi_convert_desc){.threads = threads}, &v)) ==
                VDBGI_OK) {
            bench_volume_reading(v, rv, got);
            print_row(csv, spacing, sets[d].name, rv, got);
        }
    }
    /* Under the physical truth, the apps' defaults (issue 45): the physical model with its
       bounces counted until converged, and the seed model's defaults it replaced. */
    static const struct {
        const char *name;
        vdbgi_model model;
    } apps[2] = {{"scalar, bricks: the apps' default (physical, converged)", VDBGI_MODEL_PHYSICAL},
                 {"scalar, bricks: the seed model (the default before)", VDBGI_MODEL_SEED}};
    for (int a = 0; r == VDBGI_OK && light && light->model == VDBGI_MODEL_PHYSICAL && a < 2; a++) {
        const vdbgi_bake_desc dd = {.rays = rays, .threads = threads, .model = apps[a].model};
        vdbgi_volume_destroy(v);
        v = NULL;
        if ((r = vdbgi_probes_bake(p, scene, &dd, NULL)) == VDBGI_OK &&
            (r = vdbgi_volume_build(ctx, p, &cd, &v)) == VDBGI_OK) {
            bench_volume_reading(v, rv, got);
            print_row(csv, spacing, apps[a].name, rv, got);
        }
    }
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(cube);
    vdbgi_probes_destroy(p);
    return r;
}

/*
 * The best any L2 probe could do: one baked exactly at each receiver, moved
 * off a surface by `off` metres along its normal (characters where they are).
 */
static vdbgi_result truth_of_perfect_probes(const vdbgi_scene *scene, const bench_receivers *rv,
                                            float off, int rays, int threads,
                                            const bench_light *light, FILE *csv, float *got)
{
    float *const at = calloc(3 * rv->count + 3, sizeof(float));
    float *const sh = calloc(27 * rv->count + 27, sizeof(float));
    vdbgi_result r = at && sh ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; r == VDBGI_OK && i < rv->count; i++)
        for (int k = 0; k < 3; k++)
            at[3 * i + k] =
                rv->pos[3 * i + k] + (i < rv->surface ? off * rv->normal[3 * i + k] : 0.0f);
    const vdbgi_bake_desc bd = bench_lit(
        (vdbgi_bake_desc){.rays = rays, .threads = threads, .basis = VDBGI_BASIS_SH2}, light);
    if (r == VDBGI_OK)
        r = vdbgi_scene_bake_points_sh2(scene, &bd, at, rv->count, sh);
    for (size_t i = 0; r == VDBGI_OK && i < rv->count; i++) {
        vdbgi_sh2_eval((const float(*)[3]) & sh[27 * i], &rv->normal[3 * i], &got[3 * i]);
        for (int k = 0; k < 3; k++)
            got[3 * i + k] *= (float)PI;
    }
    if (r == VDBGI_OK) {
        char name[64];
        snprintf(name, sizeof(name), "L2, a probe at each receiver, %g m off", (double)off);
        print_row(csv, 0.0, name, rv, got);
    }
    free(at);
    free(sh);
    return r;
}

/* The lightmap at 0.25 m texels, a pass per bounce of the truth's, at the surface receivers. */
static vdbgi_result truth_of_lightmap(vdbgi_context *ctx, const vdbgi_scene *scene,
                                      const bench_receivers *rv, int threads,
                                      const bench_light *light, FILE *csv, float *got)
{
    vdbgi_lightmap_result *res = NULL;
    const int passes = light && light->bounces > 1 ? light->bounces : 1;
    vdbgi_bake_desc bake = bench_lit((vdbgi_bake_desc){.threads = threads}, light);
    bake.bounces = 0; /* a lightmap bounces by its passes */
    const vdbgi_lightmap_desc d = {.texel = 0.25f, .passes = passes, .bake = bake};
    const vdbgi_result r = vdbgi_lightmap_bake_scene(ctx, scene, &d, &res, NULL);
    if (r == VDBGI_OK) {
        const bench_receivers surface = {.surface = rv->surface,
                                         .count = rv->surface,
                                         .pos = rv->pos,
                                         .normal = rv->normal,
                                         .truth = rv->truth,
                                         .kind = rv->kind};
        for (size_t i = 0; i < rv->surface; i++)
            vdbgi_lightmap_result_sample(res, rv->prim[i], rv->uv[2 * i], rv->uv[2 * i + 1],
                                         &got[3 * i]);
        print_row(csv, 0.25, passes == 1 ? "lightmap, one pass" : "lightmap, a pass a bounce",
                  &surface, got);
    }
    vdbgi_lightmap_result_destroy(res);
    return r;
}

int bench_truth(const char *scene_path, double spacing, bool spacing_given, int rays, int threads,
                const bench_light *light, const char *out)
{
    const char *const dir = out ? out : "build/chart";
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        cli_error("%s: cannot make directory: %s", dir, strerror(errno));
        return CLI_FAILED;
    }
    char path[4096];
    snprintf(path, sizeof(path), "%s/truth.csv", dir);
    vdbgi_context *const ctx = cli_context();
    if (!ctx)
        return CLI_FAILED;
    vdbgi_scene *scene = NULL;
    bench_receivers rv = {0};
    FILE *csv = NULL;
    float *got = NULL;
    vdbgi_result r = vdbgi_scene_load(ctx, scene_path, &scene);
    if (r == VDBGI_OK)
        r = bench_receivers_make(scene, light, &rv);
    if (r == VDBGI_OK && !(got = calloc(3 * rv.count + 3, sizeof(float))))
        r = VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK && !(csv = fopen(path, "w"))) {
        cli_error("%s: cannot write: %s", path, strerror(errno));
        bench_receivers_free(&rv);
        vdbgi_scene_destroy(scene);
        vdbgi_context_destroy(ctx);
        return CLI_FAILED;
    }
    if (r == VDBGI_OK) {
        vdbgi_scene_info si;
        vdbgi_scene_get_info(scene, &si);
        printf("### %s: what a surface receives, against the hemisphere estimator (2048 rays)\n\n"
               "%zu surface receivers (floors, walls, the rest) and %zu character ones (%zu "
               "points 0.5-2 m over walkable ground, each read facing up, the four horizontal "
               "directions and down); probes of %d rays within 2.5 m of a surface. RMSE over "
               "the truth's mean; bias: mean read over mean truth.\n\n",
               si.name, rv.surface, rv.count - rv.surface, (rv.count - rv.surface) / 6, rays);
        printf("| spacing | method | surface RMSE | bias | floors | walls | character RMSE | "
               "bias |\n|---|---|---:|---:|---:|---:|---:|---:|\n");
        fprintf(csv, "spacing,method,surface_rmse_rel,surface_bias,floor_bias,wall_bias,"
                     "character_rmse_rel,character_bias,surface_points,character_points\n");
    }
    static const double spacings[2] = {0.5, 0.25};
    for (int s = 0; r == VDBGI_OK && s < (spacing_given ? 1 : 2); s++)
        r = truth_at_spacing(ctx, scene, &rv, spacing_given ? spacing : spacings[s], rays, threads,
                             light, csv, got);
    static const float offsets[4] = {0.02f, 0.0625f, 0.125f, 0.25f};
    for (int o = 0; r == VDBGI_OK && o < 4; o++)
        r = truth_of_perfect_probes(scene, &rv, offsets[o], rays, threads, light, csv, got);
    if (r == VDBGI_OK)
        r = truth_of_lightmap(ctx, scene, &rv, threads, light, csv, got);
    if (csv)
        fclose(csv);
    if (r == VDBGI_OK)
        printf("\ntruth: %s\n", path);
    free(got);
    bench_receivers_free(&rv);
    vdbgi_scene_destroy(scene);
    const int code = r == VDBGI_OK ? CLI_OK : cli_fail(ctx, r);
    vdbgi_context_destroy(ctx);
    return code;
}
