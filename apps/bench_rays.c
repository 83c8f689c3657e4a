/* bench_rays.c: gi-bench rays: error against time for each way of spending a probe's rays. */
#include "bench.h"
#include "cli.h"
#include "vdbgi.h"
#include "vdbgi_bench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The reference: random rotations, so its own error is noise and not a pattern it shares. */
#define REFERENCE_RAYS 16384

typedef struct rays_row {
    const char *sampling;
    double rays, noise, seconds, rmse, p99;
    double printed; /* the noise the bake measured and printed (vdbgi_bake_stats.noise) */
} rays_row;

/*
 * The ways both tables measure, each a run of rows: the fixed set at each
 * count, its random turn a point at each count, auto at each target.
 */
enum { WAYS = 3 };
static const int counts[] = {16, 32, 64, 128, 256, 512, 1024};
static const float targets[] = {0.14f, 0.1f, 0.07f, 0.05f, 0.035f, 0.025f, 0.018f};
enum { FIXED = sizeof(counts) / sizeof(counts[0]), TARGETS = sizeof(targets) / sizeof(targets[0]) };

static int way_runs(int way)
{
    return way < 2 ? FIXED : TARGETS;
}

/*
 * Whether way's row k adds to each point's cost for the oracle: the random
 * rotation at 64..512 rays, whose error goes as 1/rays.
 */
static bool costs_run(int way, int k)
{
    return way == 1 && counts[k] >= 64 && counts[k] <= 512;
}

/* Way way's row k: its sampling under light, and its name and target into row. */
static vdbgi_bake_desc way_row(int way, int k, const bench_light *light, rays_row *row)
{
    row->sampling = way == 0 ? "fibonacci" : way == 1 ? "random" : "adaptive";
    row->noise = way == 2 ? (double)targets[k] : 0.0;
    return bench_lit(
        (vdbgi_bake_desc){.rays = way < 2 ? counts[k] : 0,
                          .adaptive = way == 2,
                          .sampling = way == 0 ? VDBGI_SAMPLING_FIBONACCI : VDBGI_SAMPLING_RANDOM,
                          .noise = way == 2 ? targets[k] : 0.0f},
        light);
}

/*
 * The fixed Fibonacci count that gives rmse, read off the fixed rows in
 * log-log (the error falls as a power of the count between two of them);
 * 0 when rmse is outside their range.
 */
static double fixed_rays_for(const rays_row *rows, size_t n, double rmse)
{
    for (size_t i = 0; i + 1 < n; i++) {
        const rays_row *const a = &rows[i], *const b = &rows[i + 1];
        if (strcmp(a->sampling, "fibonacci") != 0 || strcmp(b->sampling, "fibonacci") != 0)
            continue;
        if (rmse <= a->rmse && rmse >= b->rmse && a->rmse > b->rmse) {
            const double t = log(a->rmse / rmse) / log(a->rmse / b->rmse);
            return exp(log(a->rays) + t * log(b->rays / a->rays));
        }
    }
    return 0.0;
}

/*
 * The most any choice of rays a point could gain: point i's error goes as
 * cost_i / n_i, and for a given sum of rays the summed error is least at
 * n_i ~ sqrt(cost_i) (Lagrange), where it is mean(sqrt(cost))^2 / mean(cost)
 * of an even split's. The oracle's row: the rays that reach the random
 * rotation's 128-ray RMSE so (its costs are measured, so noisy: the gain is
 * if anything overstated). n points, each costed by the same runs.
 */
static void oracle_row(rays_row *rows, size_t *rows_n, const double *cost, size_t n)
{
    double mean = 0.0, root = 0.0;
    for (size_t i = 0; i < n; i++)
        mean += cost[i], root += sqrt(cost[i]);
    if (n == 0 || !(mean > 0.0))
        return;
    mean /= (double)n, root /= (double)n;
    const rays_row *const random128 = &rows[FIXED + 3];
    rows[(*rows_n)++] = (rays_row){
        "oracle", 128.0 * root * root / mean, 0.0, 0.0, random128->rmse, random128->p99, 0.0};
}

/* The rows as a Markdown table and dir/csv; n points (probes or texels), each a "what". */
static bool write_rows(const rays_row *rows, size_t rows_n, size_t n, const char *what,
                       const char *dir, const char *csv)
{
    char header[160];
    snprintf(header, sizeof(header),
             "sampling,rays,noise_target,seconds,rmse_rel,p99_rel,%ss_per_s,fixed_rays_same_rmse,"
             "noise_printed",
             what);
    FILE *const f = bench_open_csv(dir, csv, header);
    if (!f)
        return false;
    printf("| sampling | noise target | rays a %s | seconds | %ss/s | RMSE | "
           "noise printed | fixed Fibonacci rays for that RMSE |\n"
           "|---|---:|---:|---:|---:|---:|---:|---:|\n",
           what, what);
    for (size_t i = 0; i < rows_n; i++) {
        const rays_row *const w = &rows[i];
        const double same = fixed_rays_for(rows, rows_n, w->rmse);
        const double per_s = w->seconds > 0.0 ? (double)n / w->seconds : 0.0;
        fprintf(f, "%s,%.1f,%g,%.4f,%.6f,%.6f,%.0f,%.1f,%.6f\n", w->sampling, w->rays, w->noise,
                w->seconds, w->rmse, w->p99, per_s, same, w->printed);
        printf("| %s | %g | %.1f | %.2f | %.0f | %.2f %% | %.2f %% | %.0f |\n", w->sampling,
               w->noise, w->rays, w->seconds, per_s, 100.0 * w->rmse, 100.0 * w->printed, same);
    }
    return fclose(f) == 0;
}

int bench_rays_table(vdbgi_context *ctx, const vdbgi_scene *scene, double spacing,
                     const bench_light *light, const char *dir)
{
    const vdbgi_place_desc pd = {.spacing = spacing};
    vdbgi_probes *p = NULL;
    vdbgi_result r = vdbgi_probes_place(ctx, scene, &pd, &p);
    if (r != VDBGI_OK)
        return cli_fail(ctx, r);
    vdbgi_probes_info pi;
    vdbgi_probes_get_info(p, &pi);
    const size_t n = pi.probe_count;
    float *const ref = calloc(n * 3 + 1, sizeof(float)), *const got =
                                                             calloc(n * 3 + 1, sizeof(float));
    unsigned char *const valid = calloc(n + 1, 1);
    double *const cost = calloc(n + 1, sizeof(double)); /* per probe: error^2 x rays */
    rays_row rows[2 * FIXED + TARGETS + 1];
    size_t rows_n = 0;
    if (!ref || !got || !valid || !cost)
        r = VDBGI_ERR_OUT_OF_MEMORY;
    fprintf(stderr, "rays: %zu probes at %g m, the %d-ray reference\n", n, spacing, REFERENCE_RAYS);
    const vdbgi_bake_desc rd = bench_lit(
        (vdbgi_bake_desc){.rays = REFERENCE_RAYS, .sampling = VDBGI_SAMPLING_RANDOM, .seed = 99},
        light);
    if (r == VDBGI_OK)
        r = vdbgi_probes_bake(p, scene, &rd, NULL);
    /* Only probes valid in the reference count: the others are filled anyway. */
    size_t m = 0;
    for (size_t i = 0; r == VDBGI_OK && i < n; i++) {
        float bf;
        vdbgi_probes_get(p, i, NULL, &ref[3 * m], &bf);
        valid[i] = bf <= pi.invalid_threshold;
        m += valid[i];
    }
    /* Ways: the fixed set, its random rotation a probe, auto. */
    for (int way = 0; r == VDBGI_OK && way < WAYS; way++) {
        for (int k = 0; r == VDBGI_OK && k < way_runs(way); k++) {
            rays_row *const row = &rows[rows_n];
            const vdbgi_bake_desc d = way_row(way, k, light, row);
            vdbgi_bake_stats st;
            if ((r = vdbgi_probes_bake(p, scene, &d, &st)) != VDBGI_OK)
                break;
            size_t j = 0;
            for (size_t i = 0; i < n; i++)
                if (valid[i])
                    vdbgi_probes_get(p, i, NULL, &got[3 * j++], NULL);
            /* A random rotation's error at 64..512 rays, times the rays: each probe's cost. */
            if (costs_run(way, k))
                for (size_t i = 0; i < m; i++)
                    for (int c = 0; c < 3; c++) {
                        const double e = (double)got[3 * i + c] - ref[3 * i + c];
                        cost[i] += e * e * counts[k];
                    }
            rows_n++;
            row->rays = (double)st.primary_ray_count / (double)n;
            row->seconds = st.seconds;
            row->printed = st.noise;
            bench_compare(ref, got, m, &row->rmse, &row->p99);
            fprintf(stderr, "rays: %s %.1f rays: %.2f %% in %.2f s\n", row->sampling, row->rays,
                    100.0 * row->rmse, row->seconds);
        }
    }
    if (r == VDBGI_OK)
        oracle_row(rows, &rows_n, cost, m);
    const bool wrote = r == VDBGI_OK && write_rows(rows, rows_n, n, "probe", dir, "rays.csv");
    free(ref);
    free(got);
    free(valid);
    free(cost);
    vdbgi_probes_destroy(p);
    return r == VDBGI_OK && wrote ? CLI_OK : (r != VDBGI_OK ? cli_fail(ctx, r) : CLI_FAILED);
}

int bench_rays(const bench_options *o)
{
    const char *dir = NULL;
    vdbgi_context *ctx = NULL;
    vdbgi_scene *scene = NULL;
    int code = bench_open_scene(o, &dir, &ctx, &scene);
    if (code != CLI_OK)
        return code;
    code = bench_rays_table(ctx, scene, o->spacing_given ? o->spacing : 1.0, &o->light, dir);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
    return code;
}

/* A lightmap of one pass (its first gather) baked as bake says, or NULL (said on stderr). */
static vdbgi_lightmap_result *texel_map(vdbgi_context *ctx, const vdbgi_scene *scene, double texel,
                                        vdbgi_bake_desc bake, vdbgi_lightmap_stats *st)
{
    const vdbgi_lightmap_desc d = {.texel = (float)texel, .passes = 1, .bake = bake};
    vdbgi_lightmap_result *res = NULL;
    const vdbgi_result r = vdbgi_lightmap_bake_scene(ctx, scene, &d, &res, st);
    if (r != VDBGI_OK)
        cli_fail(ctx, r);
    return res;
}

/*
 * gi-bench texel-rays: the table of gi-bench rays for a lightmap's texels,
 * one pass of texel-sized texels (the same unwrap every run), each way's map
 * against a reference map, over the texels valid in both.
 */
int bench_texel_rays(const bench_options *o)
{
    const char *dir = NULL;
    vdbgi_context *ctx = NULL;
    vdbgi_scene *scene = NULL;
    const int opened = bench_open_scene(o, &dir, &ctx, &scene);
    if (opened != CLI_OK)
        return opened;
    const double texel = o->spacing_given ? o->spacing : 0.5;
    rays_row rows[2 * FIXED + TARGETS + 1];
    size_t rows_n = 0, n = 0, texels = 0;
    vdbgi_lightmap_stats st;
    fprintf(stderr, "texel-rays: %g m texels, the %d-ray reference\n", texel, REFERENCE_RAYS);
    vdbgi_lightmap_result *const ref =
        texel_map(ctx, scene, texel,
                  bench_lit((vdbgi_bake_desc){.rays = REFERENCE_RAYS,
                                              .sampling = VDBGI_SAMPLING_RANDOM,
                                              .seed = 99},
                            &o->light),
                  &st);
    const unsigned char *ref_valid = NULL;
    const float *const ref_rgb =
        ref ? vdbgi_lightmap_result_texels(ref, &ref_valid, &texels) : NULL;
    float *const a = calloc(3 * texels + 1, sizeof(float)), *const b = calloc(3 * texels + 1,
                                                                              sizeof(float));
    double *const cost = calloc(texels + 1, sizeof(double)); /* per texel: error^2 x rays */
    unsigned char *const costs = calloc(texels + 1, 1);      /* runs that costed it */
    bool ok = ref && a && b && cost && costs;
    for (int way = 0; ok && way < WAYS; way++) {
        for (int k = 0; ok && k < way_runs(way); k++) {
            rays_row *const row = &rows[rows_n];
            const vdbgi_bake_desc d = way_row(way, k, &o->light, row);
            vdbgi_lightmap_result *const got = texel_map(ctx, scene, texel, d, &st);
            if (!(ok = got != NULL))
                break;
            const unsigned char *valid = NULL;
            size_t count = 0;
            const float *const rgb = vdbgi_lightmap_result_texels(got, &valid, &count);
            n = 0;
            const bool costed = costs_run(way, k); /* as gi-bench rays's, texel by texel */
            for (size_t i = 0; i < texels && count == texels; i++)
                if (ref_valid[i] && valid[i]) {
                    memcpy(&a[3 * n], &ref_rgb[3 * i], 3 * sizeof(float));
                    memcpy(&b[3 * n], &rgb[3 * i], 3 * sizeof(float));
                    for (int c = 0; costed && c < 3; c++) {
                        const double e = (double)rgb[3 * i + c] - ref_rgb[3 * i + c];
                        cost[i] += e * e * counts[k];
                    }
                    costs[i] += costed;
                    n++;
                }
            rows_n++;
            row->rays = st.gather_rays;
            row->seconds = st.pass_seconds[0];
            row->printed = st.noise;
            bench_compare(a, b, n, &row->rmse, &row->p99);
            fprintf(stderr, "texel-rays: %s %.1f rays: %.2f %% in %.2f s (noise printed %.2f %%)\n",
                    row->sampling, row->rays, 100.0 * row->rmse, row->seconds, 100.0 * st.noise);
            vdbgi_lightmap_result_destroy(got);
        }
    }
    /* The oracle over the texels valid in every run that costs (gutters never are). */
    int costed_runs = 0;
    for (int k = 0; k < FIXED; k++)
        costed_runs += costs_run(1, k);
    size_t kept = 0;
    for (size_t i = 0; ok && i < texels; i++)
        if (costs[i] == costed_runs)
            cost[kept++] = cost[i];
    if (ok)
        oracle_row(rows, &rows_n, cost, kept);
    ok = ok && write_rows(rows, rows_n, st.samples, "texel", dir, "texel_rays.csv");
    free(a);
    free(b);
    free(cost);
    free(costs);
    vdbgi_lightmap_result_destroy(ref);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
    return ok ? CLI_OK : CLI_FAILED;
}
