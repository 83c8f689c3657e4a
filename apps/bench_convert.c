/* bench_convert.c: gi-bench convert: conversion size, error and time against reading the .vdb. */
#include "bench.h"
#include "bench_lights.h"
#include "cli.h"
#include "vdbgi.h"
#include "vdbgi_bench.h"

/* One row of the convert table: the fastest of `repeat` builds, timed as the read is
   (into *fastest if not NULL). */
static int convert_row(vdbgi_context *ctx, const vdbgi_probes *p, const vdbgi_convert_desc *d,
                       const char *label, double read_seconds, int repeat, double *fastest)
{
    vdbgi_volume *v = NULL;
    double seconds = 0.0;
    for (int rep = 0; rep < repeat; rep++) {
        vdbgi_volume_destroy(v);
        v = NULL;
        vdbgi_result r = vdbgi_volume_build(ctx, p, d, &v);
        /* The conversion is the build and the file's bytes (gzip happens on write). */
        const double t0 = cli_now();
        size_t size;
        if (r == VDBGI_OK)
            r = vdbgi_volume_write_memory(v, NULL, 0, &size);
        if (r != VDBGI_OK) {
            vdbgi_volume_destroy(v);
            return cli_fail(ctx, r);
        }
        vdbgi_volume_info run;
        vdbgi_volume_get_info(v, &run);
        run.seconds += cli_now() - t0;
        seconds = rep == 0 || run.seconds < seconds ? run.seconds : seconds;
    }
    vdbgi_volume_info vi;
    bench_info(v, &vi);
    const double raw = (double)(vi.indirection_size + vi.atlas_size);
    const double mean = vi.mean_irradiance > 0.0 ? vi.mean_irradiance : 1.0;
    printf("| %s | %u / %u / %u / %u | %.2f | %.2f | %.2f | %.2f | %.3f | %.3f | %.2f | %.3f | "
           "%.2f |\n",
           label, vi.bricks[0], vi.bricks[1], vi.bricks[2], vi.bricks[3], raw * 1e-6,
           (double)vi.file_size * 1e-6, (double)vi.dense_rgba8_size / raw,
           (double)vi.dense_rgba8_size / (double)vi.file_size, 100.0 * vi.rmse / mean,
           100.0 * vi.p99 / mean, 100.0 * vi.max_error / mean, seconds, seconds / read_seconds);
    vdbgi_volume_destroy(v);
    if (fastest)
        *fastest = seconds;
    return CLI_OK;
}

int bench_convert(const bench_options *o)
{
    vdbgi_context *const ctx = cli_context();
    if (!ctx)
        return CLI_FAILED;
    vdbgi_probes *p = NULL;
    double read_seconds = 0.0;
    for (int rep = 0; rep < o->repeat; rep++) {
        vdbgi_probes_destroy(p);
        p = NULL;
        const double t0 = cli_now();
        const vdbgi_result r = vdbgi_probes_read(ctx, o->scene, &p);
        const double t = cli_now() - t0;
        if (r != VDBGI_OK) {
            const int code = cli_fail(ctx, r);
            vdbgi_context_destroy(ctx);
            return code;
        }
        read_seconds = rep == 0 || t < read_seconds ? t : read_seconds;
    }
    vdbgi_probes_info pi;
    vdbgi_probes_get_info(p, &pi);
    char dense[32];
    const double box = (double)(pi.ijk_max[0] - pi.ijk_min[0] + 1) *
                       (pi.ijk_max[1] - pi.ijk_min[1] + 1) * (pi.ijk_max[2] - pi.ijk_min[2] + 1);
    printf("### %s: %zu probes (%zu invalid) at %g m; reading it takes %.3f s\n\n", o->scene,
           pi.probe_count, pi.invalid_count, pi.spacing, read_seconds);
    printf(
        "Dense RGBA8 grid over the probes' box: %s (%.0f%% of its lattice points are probes).\n\n",
        cli_bytes(4.0 * box, dense, sizeof(dense)), 100.0 * (double)pi.probe_count / box);
    printf("| criterion, eps, encoding | bricks L0 / L1 / L2 / L3 | raw MB | gzip MB | dense/raw "
           "| dense/gzip | RMSE %% | p99 %% | max %% | convert s | convert/read |\n");
    printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    static const float eps[] = {0.0f, 0.01f, 0.03f, 0.1f, 0.2f, 0.4f};
    static const char *const eps_text[] = {"0", "0.01", "0.03", "0.1", "0.2", "0.4"};
    int code = CLI_OK;
    for (int c = VDBGI_CRITERION_RANGE; c <= VDBGI_CRITERION_INTERP && code == CLI_OK; c++)
        for (size_t e = 0; e < sizeof(eps) / sizeof(eps[0]) && code == CLI_OK; e++) {
            const vdbgi_convert_desc d = {
                .eps = eps[e], .eps_is_set = 1, .criterion = (vdbgi_criterion)c};
            char label[64];
            snprintf(label, sizeof(label), "%s, %s, rgbm, seed layout",
                     c == VDBGI_CRITERION_RANGE ? "range" : "interp", eps_text[e]);
            code = convert_row(ctx, p, &d, label, read_seconds, o->repeat, NULL);
        }
    /* vdb-to-gi's default, the compact layout (the library's zero value), and seed 000's layout. */
    const vdbgi_convert_desc compact = {.layout = VDBGI_LAYOUT_COMPACT},
                             e9 = {.layout = VDBGI_LAYOUT_COMPACT,
                                   .encoding = VDBGI_ENCODING_RGB9E5},
                             seed = {.layout = VDBGI_LAYOUT_SEED};
    const bool terms = pi.basis == VDBGI_BASIS_SH2;
    double with_terms = 0.0, scalar = 0.0;
    if (code == CLI_OK)
        code = convert_row(ctx, p, &compact,
                           terms ? "**default** (compact), rgbm, L2 terms (6 bits)"
                                 : "**default** (compact), rgbm",
                           read_seconds, o->repeat, &with_terms);
    if (code == CLI_OK)
        code =
            convert_row(ctx, p, &e9,
                        terms ? "default (compact), rgb9e5, L2 terms" : "default (compact), rgb9e5",
                        read_seconds, o->repeat, NULL);
    if (code == CLI_OK)
        code =
            convert_row(ctx, p, &seed, "default, rgbm, seed layout", read_seconds, o->repeat, NULL);
    /* Probes with L2 terms: the same conversion without them, for what the terms cost. */
    const vdbgi_convert_desc flat = {.layout = VDBGI_LAYOUT_COMPACT, .terms = VDBGI_TERMS_DROP};
    if (code == CLI_OK && terms)
        code = convert_row(ctx, p, &flat, "default (compact), rgbm, scalar only", read_seconds,
                           o->repeat, &scalar);
    printf("\n");
    if (code == CLI_OK && terms && scalar > 0.0)
        printf("The L2 terms take the default conversion %.2fx the scalar's time (%.3f against "
               "%.3f s, fastest of %d each).\n\n",
               with_terms / scalar, with_terms, scalar, o->repeat);
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
    return code;
}
