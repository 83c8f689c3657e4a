/*
 * bench_lights.c: gi-bench lights: what the scene's own light costs against
 * the one-bounce bake of seed 000's model, and what bounces and rays buy
 * against a reference of many of both. A sky map is written beside the
 * CSV: a smooth one (zenith blue to a bright horizon), and the same with a
 * small sun, for the noise it leaves once taken out of the map as a lamp.
 */
#define _POSIX_C_SOURCE 200809L
#include "bench_lights.h"
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define PI 3.14159265358979323846

/* Radiance of the bench's sky towards elevation e (radians), with a sun or without. */
static void sky_texel(double e, double az, bool sun, float rgb[3])
{
    const double up = e > 0.0 ? sin(e) : 0.0;
    const float horizon[3] = {1.0f, 0.95f, 0.85f}, zenith[3] = {0.25f, 0.45f, 0.9f};
    for (int k = 0; k < 3; k++)
        rgb[k] = e < 0.0 ? 0.2f : (float)((1.0 - up) * horizon[k] + up * zenith[k]);
    /* A sun 30 degrees up, 2 degrees across: 0.1 % of the sky, about half its light. */
    if (sun && fabs(e - PI / 6.0) < PI / 180.0 && fabs(az) < PI / 180.0 / cos(PI / 6.0))
        for (int k = 0; k < 3; k++)
            rgb[k] += 4000.0f;
}

/* A flat Radiance .hdr (RGBE, no run-length coding) of the bench's sky, 2:1. */
static bool write_sky(const char *path, int h, bool sun)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return false;
    const int w = 2 * h;
    fprintf(f, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n", h, w);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const double e = PI / 2.0 - (y + 0.5) / h * PI, az = (x + 0.5) / w * 2.0 * PI - PI;
            float c[3];
            sky_texel(e, az, sun, c);
            const float m = fmaxf(c[0], fmaxf(c[1], c[2]));
            int ex = 0;
            const double mant = frexp(m, &ex); /* m = mant 2^ex, mant in [0.5, 1) */
            const double scale = m > 1e-32f ? mant * 256.0 / m : 0.0;
            const unsigned char px[4] = {
                (unsigned char)(c[0] * scale), (unsigned char)(c[1] * scale),
                (unsigned char)(c[2] * scale), (unsigned char)(m > 1e-32f ? ex + 128 : 0)};
            fwrite(px, 1, 4, f);
        }
    return fclose(f) == 0;
}

/* Mean of three channels at each of n points: RMSE over the reference's mean, and bias. */
static void error_of(const float *got, const float *ref, size_t n, double *rmse, double *bias)
{
    double se = 0.0, sg = 0.0, sr = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double g = (got[3 * i] + got[3 * i + 1] + got[3 * i + 2]) / 3.0;
        const double r = (ref[3 * i] + ref[3 * i + 1] + ref[3 * i + 2]) / 3.0;
        se += (g - r) * (g - r), sg += g, sr += r;
    }
    *rmse = sr > 0.0 ? sqrt(se / (double)n) / (sr / (double)n) : 0.0;
    *bias = sr > 0.0 ? sg / sr : 0.0;
}

typedef struct cost_row {
    const char *name;
    vdbgi_bake_desc bd;
} cost_row;

/* The bake of every probe for each row: fastest of repeat; ratios against the first row. */
static vdbgi_result costs(vdbgi_context *ctx, const vdbgi_scene *scene, vdbgi_probes *p,
                          const cost_row *rows, int n, int repeat)
{
    printf("| bake | seconds | probes/s | Mrays/s | rays a probe | time against seed 000's "
           "bake |\n|---|---:|---:|---:|---:|---:|\n");
    double base = 0.0;
    for (int i = 0; i < n; i++) {
        vdbgi_bake_stats best = {0};
        for (int k = 0; k < repeat; k++) {
            vdbgi_bake_stats st;
            const vdbgi_result r = vdbgi_probes_bake(p, scene, &rows[i].bd, &st);
            if (r != VDBGI_OK)
                return r;
            if (k == 0 || st.seconds < best.seconds)
                best = st;
        }
        const double rays = (double)(best.primary_ray_count + best.shadow_ray_count);
        if (i == 0)
            base = best.seconds;
        printf("| %s | %.3f | %.0f | %.1f | %.0f | %.2f |\n", rows[i].name, best.seconds,
               (double)best.probe_count / best.seconds, rays / best.seconds * 1e-6,
               rays / (double)best.probe_count, best.seconds / base);
    }
    (void)ctx;
    return VDBGI_OK;
}

/* Every tenth valid probe's position, at most cap of them, into *pts. */
static size_t probe_points(const vdbgi_probes *p, size_t cap, float **pts)
{
    vdbgi_probes_info pi;
    vdbgi_probes_get_info(p, &pi);
    int32_t *const ijk = malloc(pi.probe_count * 3 * sizeof(int32_t) + 12);
    float *const rgb = malloc(pi.probe_count * 3 * sizeof(float) + 12);
    float *const bf = malloc(pi.probe_count * sizeof(float) + 4);
    *pts = malloc(cap * 3 * sizeof(float) + 12);
    size_t n = 0;
    if (ijk && rgb && bf && *pts &&
        vdbgi_probes_copy(p, ijk, rgb, bf, pi.probe_count) == pi.probe_count)
        for (size_t i = 0; i < pi.probe_count && n < cap; i += 10)
            if (bf[i] <= 0.25f) {
                for (int k = 0; k < 3; k++)
                    (*pts)[3 * n + k] = (float)(pi.origin[k] + ijk[3 * i + k] * pi.spacing);
                n++;
            }
    free(ijk);
    free(rgb);
    free(bf);
    return n;
}

int bench_lights(const char *scene_path, double spacing, int threads, int repeat, const char *out)
{
    const char *const dir = out ? out : "build/chart";
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        cli_error("%s: cannot make directory: %s", dir, strerror(errno));
        return CLI_FAILED;
    }
    char sky_path[4096], sun_path[4096], csv_path[4096];
    snprintf(sky_path, sizeof(sky_path), "%s/sky.hdr", dir);
    snprintf(sun_path, sizeof(sun_path), "%s/sky_sun.hdr", dir);
    snprintf(csv_path, sizeof(csv_path), "%s/lights.csv", dir);
    if (!write_sky(sky_path, 256, false) || !write_sky(sun_path, 512, true)) {
        cli_error("%s: cannot write the sky maps", dir);
        return CLI_FAILED;
    }
    vdbgi_context *const ctx = cli_context();
    if (!ctx)
        return CLI_FAILED;
    vdbgi_scene *scene = NULL;
    vdbgi_probes *p = NULL;
    vdbgi_sky *sky = NULL, *sun = NULL;
    float *pts = NULL, *ref = NULL, *got = NULL;
    FILE *csv = NULL;
    vdbgi_result r = vdbgi_scene_load(ctx, scene_path, &scene);
    if (r == VDBGI_OK)
        r = vdbgi_sky_load(ctx, sky_path, 1.0f, 0.0f, &sky);
    if (r == VDBGI_OK)
        r = vdbgi_sky_load(ctx, sun_path, 1.0f, 0.0f, &sun);
    const vdbgi_place_desc pd = {.spacing = spacing};
    if (r == VDBGI_OK)
        r = vdbgi_probes_place(ctx, scene, &pd, &p);
    if (r == VDBGI_OK) {
        vdbgi_scene_info si;
        vdbgi_probes_info pi;
        vdbgi_scene_get_info(scene, &si);
        vdbgi_probes_get_info(p, &pi);
        printf("### %s: the scene's own light, %zu probes at %g m, 128 rays, %d threads\n\n",
               si.name, pi.probe_count, spacing, threads ? threads : 0);
        printf("Cost of each feature against seed 000's one-bounce bake (its default sun, no "
               "scene lights), fastest of %d; the sky map is %s.\n\n",
               repeat, sky_path);
        const vdbgi_bake_desc seed = {.threads = threads, .lights = VDBGI_LIGHTS_OFF};
        vdbgi_bake_desc lights = {.threads = threads};
        vdbgi_bake_desc phys = {.threads = threads, .model = VDBGI_MODEL_PHYSICAL, .bounces = 1};
        vdbgi_bake_desc skyd = phys;
        skyd.sky_map = sky;
        cost_row rows[8] = {{"seed 000: sun, fill, falloff, one bounce", seed},
                            {"+ the scene's lights", lights},
                            {"physical: lights, no fill or falloff", phys},
                            {"physical + sky map", skyd}};
        int n = 4;
        for (int b = 2; b <= 4; b++, n++) {
            static const char *names[] = {"physical + sky map, 2 bounces",
                                          "physical + sky map, 3 bounces",
                                          "physical + sky map, 4 bounces"};
            rows[n].name = names[b - 2];
            rows[n].bd = skyd;
            rows[n].bd.bounces = b;
        }
        rows[n].name = "physical + sky map, until converged (the default)";
        rows[n].bd = skyd;
        rows[n++].bd.bounces = 0;
        r = costs(ctx, scene, p, rows, n, repeat);
    }
    /* Error against bounces and rays, at valid probes, against 8 bounces of 4096 rays. */
    const size_t n = r == VDBGI_OK ? probe_points(p, 400, &pts) : 0;
    if (r == VDBGI_OK && !(ref = calloc(3 * n + 3, sizeof(float))))
        r = VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK && !(got = calloc(3 * n + 3, sizeof(float))))
        r = VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK && !(csv = fopen(csv_path, "w"))) {
        cli_error("%s: cannot write: %s", csv_path, strerror(errno));
        r = VDBGI_ERR_IO;
    }
    vdbgi_bake_desc bd = {.threads = threads,
                          .model = VDBGI_MODEL_PHYSICAL,
                          .sky_map = sky,
                          .sampling = VDBGI_SAMPLING_RANDOM,
                          .rays = 4096,
                          .bounces = 8,
                          .seed = 1};
    if (r == VDBGI_OK)
        r = vdbgi_scene_bake_points(scene, &bd, pts, n, ref, NULL);
    static const int bounces[5] = {1, 2, 3, 4, 6}, rays[4] = {32, 128, 512, 2048};
    if (r == VDBGI_OK) {
        printf("\nError of the physical bake (lights, sky map) at %zu valid probes, against 8 "
               "bounces of 4096 random rays: RMSE over the mean / mean bias.\n\n",
               n);
        printf("| bounces | 32 rays | 128 rays | 512 rays | 2048 rays "
               "|\n|---:|---:|---:|---:|---:|\n");
        fprintf(csv, "bounces,rays,rmse_rel,bias,seconds\n");
    }
    bd.seed = 2;
    for (int b = 0; r == VDBGI_OK && b < 5; b++) {
        printf("| %d |", bounces[b]);
        for (int k = 0; r == VDBGI_OK && k < 4; k++) {
            bd.bounces = bounces[b];
            bd.rays = rays[k];
            const double t0 = cli_now();
            r = vdbgi_scene_bake_points(scene, &bd, pts, n, got, NULL);
            const double t = cli_now() - t0;
            double rmse = 0.0, bias = 0.0;
            error_of(got, ref, n, &rmse, &bias);
            printf(" %.1f %% / %.3f |", 100.0 * rmse, bias);
            fprintf(csv, "%d,%d,%.5f,%.5f,%.4f\n", bounces[b], rays[k], rmse, bias, t);
        }
        printf("\n");
    }
    /* The sky's noise: the same bake under a sky with a small bright sun, 2 bounces. */
    if (r == VDBGI_OK) {
        printf("\nA sky with a sun (taken out of the map as a lamp with a shadow ray): RMSE "
               "against 4096 rays, 2 bounces.\n\n"
               "| sky | 128 rays | 512 rays |\n|---|---:|---:|\n");
        const vdbgi_sky *const skies[2] = {sky, sun};
        for (int s = 0; r == VDBGI_OK && s < 2; s++) {
            bd.sky_map = skies[s];
            bd.bounces = 2;
            bd.rays = 4096;
            bd.seed = 1;
            r = vdbgi_scene_bake_points(scene, &bd, pts, n, ref, NULL);
            printf("| %s |", s ? "with a 2-degree sun (half its light)" : "smooth");
            for (int k = 1; r == VDBGI_OK && k < 3; k++) {
                bd.rays = rays[k];
                bd.seed = 2;
                r = vdbgi_scene_bake_points(scene, &bd, pts, n, got, NULL);
                double rmse = 0.0, bias = 0.0;
                error_of(got, ref, n, &rmse, &bias);
                printf(" %.1f %% |", 100.0 * rmse);
            }
            printf("\n");
        }
    }
    if (csv)
        fclose(csv);
    if (r == VDBGI_OK)
        printf("\nlights: %s\n", csv_path);
    free(pts);
    free(ref);
    free(got);
    vdbgi_probes_destroy(p);
    vdbgi_sky_destroy(sky);
    vdbgi_sky_destroy(sun);
    vdbgi_scene_destroy(scene);
    const int code = r == VDBGI_OK ? CLI_OK : cli_fail(ctx, r);
    vdbgi_context_destroy(ctx);
    return code;
}
