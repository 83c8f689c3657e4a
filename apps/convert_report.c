/*
 * convert_report.c: what vdb-to-gi says of a conversion: the statistics (as
 * text, and as JSON for --stats) and the Bevy volume's figures.
 */
#include "convert_report.h"
#include "budget.h"
#include "cli.h"

#include <math.h>
#include <string.h>

void print_stats(FILE *f, const options *o, const vdbgi_volume_info *vi,
                 const vdbgi_probes_info *pi, double read_seconds, bool json)
{
    const double raw = (double)(vi->indirection_size + vi->atlas_size);
    const double mean = vi->mean_irradiance > 0.0 ? vi->mean_irradiance : 1.0;
    if (json) {
        fputs("{\n  \"input\": ", f);
        cli_json_string(f, o->input);
        fputs(",\n  \"output\": ", f);
        cli_json_string(f, o->output);
        fprintf(
            f,
            ",\n  \"probes\": %zu,\n"
            "  \"valid_probes\": %zu,\n  \"filled_points\": %zu,\n  \"unreached_points\": %zu,\n"
            "  \"fallback_values\": %zu,\n  \"spacing\": %g,\n  \"max_level\": %u,\n"
            "  \"encoding\": \"%s\",\n  \"layout\": \"%s\",\n  \"basis\": \"%s\",\n"
            "  \"bricks_per_level\": [%u, %u, %u, %u],\n"
            "  \"bricks\": %u,\n  \"atlas_dims\": [%u, %u, %u],\n"
            "  \"indirection_dims\": [%u, %u, %u],\n  \"atlas_bytes\": %zu,\n"
            "  \"indirection_bytes\": %zu,\n  \"raw_bytes\": %.0f,\n"
            "  \"columns_dims\": [%u, %u],\n  \"columns_bytes\": %zu,\n  \"vram_bytes\": %zu,\n"
            "  \"gzip_bytes\": %zu,\n"
            "  \"dense_rgba8_bytes\": %zu,\n  \"dense_over_raw\": %.3f,\n"
            "  \"dense_over_gzip\": %.3f,\n  \"clamped_texels\": %zu,\n"
            "  \"mean_irradiance\": %.6g,\n  \"rmse\": %.6g,\n  \"p99\": %.6g,\n"
            "  \"max_error\": %.6g,\n  \"rmse_relative\": %.6g,\n  \"p99_relative\": %.6g,\n"
            "  \"max_relative\": %.6g,\n  \"read_seconds\": %.4f,\n"
            "  \"convert_seconds\": %.4f,\n  \"convert_over_read\": %.3f,\n"
            "  \"stored_points\": %zu,\n  \"term_bits\": %d,\n  \"term_bytes\": %zu,\n"
            "  \"luma2_error\": %.6g,\n  \"memory_peak_bytes\": %zu",
            vi->probe_count, vi->valid_count, vi->filled_count, vi->unreached_count,
            vi->fallback_count, (double)vi->spacing, vi->max_level,
            vi->encoding == VDBGI_ENCODING_RGB9E5 ? "rgb9e5" : "rgbm",
            vi->layout == VDBGI_LAYOUT_COMPACT ? "compact" : "seed",
            vi->basis == VDBGI_BASIS_SH2 ? "sh2" : "scalar", vi->bricks[0], vi->bricks[1],
            vi->bricks[2], vi->bricks[3], vi->brick_count, vi->atlas_dims[0], vi->atlas_dims[1],
            vi->atlas_dims[2], vi->ind_dims[0], vi->ind_dims[1], vi->ind_dims[2], vi->atlas_size,
            vi->indirection_size, raw, vi->columns_dims[0], vi->columns_dims[1], vi->columns_size,
            vi->columns_size + vi->atlas_size + vi->sh_size, vi->file_size, vi->dense_rgba8_size,
            (double)vi->dense_rgba8_size / raw,
            (double)vi->dense_rgba8_size / (double)vi->file_size, vi->clamped_count,
            vi->mean_irradiance, vi->rmse, vi->p99, vi->max_error, vi->rmse / mean, vi->p99 / mean,
            vi->max_error / mean, read_seconds, vi->seconds, vi->seconds / read_seconds,
            vi->stored_points, vi->term_bits, cli_term_bytes(vi), vi->luma2_error, o->memory_peak);
        if (o->budget > 0.0)
            fprintf(f,
                    ",\n  \"budget_bytes\": %.0f,\n  \"budget_eps\": %g,\n  \"budget_terms\": %s,\n"
                    "  \"budget_tries\": %d",
                    o->budget, (double)o->budget_eps, o->budget_terms ? "true" : "false",
                    o->budget_tries);
        fputs("\n}\n", f);
        return;
    }
    char a[32], b[32], c[32], d[32];
    fprintf(f, "input        %s: %zu probes (%zu valid) at %g m\n", o->input, pi->probe_count,
            vi->valid_count, pi->spacing);
    fprintf(f, "fill         %zu points hold a value (%zu unreached, %zu %s from block means)\n",
            vi->filled_count, vi->unreached_count, vi->fallback_count,
            vi->layout == VDBGI_LAYOUT_COMPACT ? "stored values" : "texels");
    fprintf(f, "bricks       %u: level 0 %u, level 1 %u, level 2 %u, level 3 %u\n", vi->brick_count,
            vi->bricks[0], vi->bricks[1], vi->bricks[2], vi->bricks[3]);
    fprintf(f, "atlas        %ux%ux%u texels%s, %s\n", vi->atlas_dims[0], vi->atlas_dims[1],
            vi->atlas_dims[2],
            vi->layout == VDBGI_LAYOUT_COMPACT ? " (compact: 5^3 bricks sharing borders)" : "",
            cli_bytes((double)vi->atlas_size, a, sizeof(a)));
    fprintf(f, "indirection  %ux%ux%u cells, %s\n", vi->ind_dims[0], vi->ind_dims[1],
            vi->ind_dims[2], cli_bytes((double)vi->indirection_size, b, sizeof(b)));
    if (vi->basis == VDBGI_BASIS_SH2)
        fprintf(f,
                "basis        L2: eight terms a texel beside the atlas (signed ratios to L0, %d "
                "bits kept; %s), %s; the second band in luminance moves a reading by %.2f%%\n",
                vi->term_bits, cli_term_form(vi), cli_bytes((double)vi->sh_size, d, sizeof(d)),
                100.0 * vi->luma2_error);
    cli_print_runtime(f, vi);
    if (o->budget > 0.0) {
        char e[320];
        if (vi->layout != VDBGI_LAYOUT_COMPACT)
            snprintf(e, sizeof(e), "no measured curve for the seed layout");
        else
            budget_expected(pi->spacing, o->budget_terms, o->budget_eps, e, sizeof(e));
        const size_t n = strlen(e);
        if (o->budget_terms && vi->term_bits != VDBGI_TERM_BITS && n < sizeof(e))
            snprintf(e + n, sizeof(e) - n, " (the curves' terms kept %d bits, these %d)",
                     VDBGI_TERM_BITS, vi->term_bits);
        const size_t m = strlen(e);
        if (o->budget_terms && cli_terms_luma2(vi) && m < sizeof(e))
            snprintf(e + m, sizeof(e) - m,
                     " (the curves' terms were in colour; the second band in luminance adds "
                     "1-2 points on characters, docs/directional.md)");
        fprintf(f, "budget       %g MB of GPU memory: eps %g, %s (conversions tried: %d); %s\n",
                o->budget / 1e6, (double)o->budget_eps,
                o->budget_terms ? "the L2 terms kept" : "scalar", o->budget_tries, e);
    }
    if (vi->stored_points)
        fprintf(f, "file         %s: %s gzip'd, %zu probe values each stored once (textures %s)\n",
                o->output, cli_bytes((double)vi->file_size, d, sizeof(d)), vi->stored_points,
                cli_bytes(raw, c, sizeof(c)));
    else
        fprintf(f, "file         %s: %s raw, %s gzip'd\n", o->output, cli_bytes(raw, c, sizeof(c)),
                cli_bytes((double)vi->file_size, d, sizeof(d)));
    fprintf(f, "dense        RGBA8 grid at %g m: %s, %.1fx the VRAM, %.1fx the file\n", pi->spacing,
            cli_bytes((double)vi->dense_rgba8_size, a, sizeof(a)),
            (double)vi->dense_rgba8_size / (double)(vi->columns_size + vi->atlas_size),
            (double)vi->dense_rgba8_size / (double)vi->file_size);
    fprintf(f, "error        RMSE %.3g%%, p99 %.3g%%, max %.3g%% of the mean irradiance %.4g\n",
            100.0 * vi->rmse / mean, 100.0 * vi->p99 / mean, 100.0 * vi->max_error / mean,
            vi->mean_irradiance);
    fprintf(f, "clamped      %zu texels above the RGBM range %g\n", vi->clamped_count,
            (double)vi->rgbm_range);
    fprintf(f, "time         convert %.3f s, %.2fx reading the .vdb (%.3f s)\n", vi->seconds,
            vi->seconds / read_seconds, read_seconds);
    fprintf(f,
            "memory       peak %.1f MiB held (vdbgi's arrays and the grids read: what "
            "--memory-limit counts)\n",
            (double)o->memory_peak / 1048576.0);
}

void print_bevy(const vdbgi_bevy *b, const options *o)
{
    vdbgi_bevy_info bi;
    vdbgi_bevy_get_info(b, &bi);
    printf("bevy         %dx%dx%d voxels over %g,%g,%g .. %g,%g,%g m\n", bi.resolution[0],
           bi.resolution[1], bi.resolution[2], bi.box_min[0], bi.box_min[1], bi.box_min[2],
           bi.box_max[0], bi.box_max[1], bi.box_max[2]);
    if (o->bevy)
        printf("bevy         %s: %dx%dx%d %s texels, %s\n", o->bevy, bi.resolution[0],
               2 * bi.resolution[1], 3 * bi.resolution[2],
               o->bevy_format == VDBGI_BEVY_RGB9E5 ? "rgb9e5" : "rgba16f", "KTX2");
    if (o->bevy_baked_gi)
        printf("bevy         %s: %dx%d RGBA8 texels of 3x2 cells\n", o->bevy_baked_gi,
               3 * bi.resolution[0], 2 * bi.resolution[1] * bi.resolution[2]);
    printf("bevy         LightProbe Transform: translation %g,%g,%g, scale %g,%g,%g\n",
           bi.center[0], bi.center[1], bi.center[2], bi.size[0], bi.size[1], bi.size[2]);
}

void print_json(FILE *f, const void *arg)
{
    const stats_args *const a = arg;
    print_stats(f, a->o, a->vi, a->pi, a->read_seconds, true);
}
