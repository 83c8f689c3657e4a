/* vdb-to-gi: convert baked probes (.vdb) into seed 000's bricked volume (.gi.gz). */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "vdbgi.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(void)
{
    printf("Usage: vdb-to-gi IN.vdb -o OUT.gi.gz [options]\n"
           "\n"
           "Convert the probes baked by gi-bake into what a game ships: adaptive bricks of\n"
           "4x4x4 probes (big where light is flat, small where it changes), packed into an\n"
           "atlas texture with a one-texel apron, an indirection texture pointing every\n"
           "2 m cell at its brick, both RGBM-encoded (or RGB9E5) and gzip'd into one file\n"
           "(docs/format.md). Invalid and absent probes are filled from valid neighbours\n"
           "first. Statistics go to stdout.\n"
           "\n"
           "Options:\n"
           "  -o, --output FILE     the .gi.gz to write (required; replaced only on success)\n"
           "      --eps E           coarsening tolerance, relative to the mean irradiance\n"
           "                        (0.1); 0 keeps every varying block fine\n"
           "      --max-level L     largest brick level, 0..3: a level-L brick spans 4*2^L\n"
           "                        probes (3)\n"
           "      --criterion C     interp: keep a coarse brick when its interpolation\n"
           "                        reproduces every probe it covers within eps; range: when\n"
           "                        its colour range is within eps, as seed 000 (interp)\n"
           "      --encoding E      rgbm (rgba8, range 8, as seed 000) or rgb9e5 (rgbm)\n"
           "      --slices DIR      write slice images (PNG and EXR) into DIR\n"
           "      --slice-axis A    x, y or z (y)\n"
           "      --slice-at M      world coordinate of the slice (the plane with most probes)\n"
           "      --exposure S      stops applied to the PNG slices (auto)\n"
           "      --stats FILE      also write the statistics as JSON\n"
           "  -q, --quiet           no statistics, errors only\n"
           "  -v, --verbose         more detail on stderr (-vv: timings of each step)\n"
           "  -h, --help            print this help and exit\n"
           "      --version         print the version and exit\n"
           "\n"
           "Examples:\n"
           "  vdb-to-gi world.vdb -o world.gi.gz\n"
           "  vdb-to-gi world.vdb -o world.gi.gz --eps 0.05 --slices slices --stats stats.json\n"
           "  vdb-to-gi world.vdb -o exact.gi.gz --eps 0 --max-level 0 --encoding rgb9e5\n");
}

enum {
    OPT_EPS = 256,
    OPT_MAX_LEVEL,
    OPT_CRITERION,
    OPT_ENCODING,
    OPT_SLICES,
    OPT_SLICE_AXIS,
    OPT_SLICE_AT,
    OPT_EXPOSURE,
    OPT_STATS,
    OPT_VERSION
};

typedef struct options {
    const char *input, *output, *slices, *stats;
    vdbgi_convert_desc convert;
    vdbgi_axis axis;
    double slice_at, exposure; /* NAN: automatic */
} options;

static int parse_args(int argc, char **argv, options *o)
{
    static const struct option longs[] = {{"output", required_argument, NULL, 'o'},
                                          {"eps", required_argument, NULL, OPT_EPS},
                                          {"max-level", required_argument, NULL, OPT_MAX_LEVEL},
                                          {"criterion", required_argument, NULL, OPT_CRITERION},
                                          {"encoding", required_argument, NULL, OPT_ENCODING},
                                          {"slices", required_argument, NULL, OPT_SLICES},
                                          {"slice-axis", required_argument, NULL, OPT_SLICE_AXIS},
                                          {"slice-at", required_argument, NULL, OPT_SLICE_AT},
                                          {"exposure", required_argument, NULL, OPT_EXPOSURE},
                                          {"stats", required_argument, NULL, OPT_STATS},
                                          {"quiet", no_argument, NULL, 'q'},
                                          {"verbose", no_argument, NULL, 'v'},
                                          {"help", no_argument, NULL, 'h'},
                                          {"version", no_argument, NULL, OPT_VERSION},
                                          {NULL, 0, NULL, 0}};
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, ":o:qvh", longs, NULL)) != -1) {
        double d;
        long long i;
        switch (c) {
        case 'o': o->output = optarg; break;
        case OPT_EPS:
            if (!cli_parse_double(optarg, &d) || !(d >= 0.0) || !isfinite(d))
                return cli_usage_error("--eps must be a number >= 0 (got '%s')", optarg);
            o->convert.eps = d == 0.0 ? VDBGI_NONE : (float)d;
            break;
        case OPT_MAX_LEVEL:
            if (!cli_parse_int(optarg, &i) || i < 0 || i > 3)
                return cli_usage_error("--max-level must be 0, 1, 2 or 3 (got '%s')", optarg);
            o->convert.levels = (int)i + 1;
            break;
        case OPT_CRITERION:
            if (strcmp(optarg, "range") == 0)
                o->convert.criterion = VDBGI_CRITERION_RANGE;
            else if (strcmp(optarg, "interp") == 0)
                o->convert.criterion = VDBGI_CRITERION_INTERP;
            else
                return cli_usage_error("--criterion must be range or interp (got '%s')", optarg);
            break;
        case OPT_ENCODING:
            if (strcmp(optarg, "rgbm") == 0)
                o->convert.encoding = VDBGI_ENCODING_RGBM;
            else if (strcmp(optarg, "rgb9e5") == 0)
                o->convert.encoding = VDBGI_ENCODING_RGB9E5;
            else
                return cli_usage_error("--encoding must be rgbm or rgb9e5 (got '%s')", optarg);
            break;
        case OPT_SLICES: o->slices = optarg; break;
        case OPT_SLICE_AXIS:
            if (strlen(optarg) != 1 || !strchr("xyz", optarg[0]))
                return cli_usage_error("--slice-axis must be x, y or z (got '%s')", optarg);
            o->axis = (vdbgi_axis)(optarg[0] - 'x');
            break;
        case OPT_SLICE_AT:
            if (!cli_parse_double(optarg, &d) || !isfinite(d))
                return cli_usage_error("--slice-at must be a number (got '%s')", optarg);
            o->slice_at = d;
            break;
        case OPT_EXPOSURE:
            if (!cli_parse_double(optarg, &d) || !isfinite(d) || fabs(d) > 64.0)
                return cli_usage_error("--exposure must be a number of stops (got '%s')", optarg);
            o->exposure = d;
            break;
        case OPT_STATS: o->stats = optarg; break;
        case 'q': cli_verbosity = 1; break;
        case 'v': cli_verbosity++; break;
        case 'h': usage(); return CLI_OK;
        case OPT_VERSION: printf("vdb-to-gi %s\n", vdbgi_version_string()); return CLI_OK;
        default: return cli_bad_option(c, argv);
        }
    }
    const int taken = cli_one_input(argc, argv, "input", &o->input);
    if (taken >= 0)
        return taken;
    if (!o->output)
        return cli_usage_error("no output given: use -o OUT.gi.gz");
    return -1;
}

/* The lattice plane across axis that holds the most probes, as a world coordinate. */
static double busiest_plane(const vdbgi_probes *p, vdbgi_axis axis)
{
    vdbgi_probes_info pi;
    vdbgi_probes_get_info(p, &pi);
    const int32_t lo = pi.ijk_min[axis], n = pi.ijk_max[axis] - lo + 1;
    size_t *const count = calloc((size_t)n, sizeof(size_t));
    int32_t best = lo;
    if (count) {
        for (size_t i = 0; i < pi.probe_count; i++) {
            int32_t ijk[3];
            float bf;
            vdbgi_probes_get(p, i, ijk, NULL, &bf);
            count[ijk[axis] - lo] += bf <= pi.invalid_threshold;
        }
        for (int32_t k = 0; k < n; k++)
            best = count[k] > count[best - lo] ? lo + k : best;
        free(count);
    }
    return pi.origin[axis] + pi.spacing * best;
}

/* A path as a JSON string body: quotes, backslashes and control characters escaped. */
static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        const unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

static void print_stats(FILE *f, const options *o, const vdbgi_volume_info *vi,
                        const vdbgi_probes_info *pi, double read_seconds, bool json)
{
    const double raw = (double)(vi->indirection_size + vi->atlas_size);
    const double mean = vi->mean_irradiance > 0.0 ? vi->mean_irradiance : 1.0;
    if (json) {
        fputs("{\n  \"input\": ", f);
        json_string(f, o->input);
        fputs(",\n  \"output\": ", f);
        json_string(f, o->output);
        fprintf(f,
                ",\n  \"probes\": %zu,\n"
                "  \"valid_probes\": %zu,\n  \"filled_points\": %zu,\n  \"unreached_points\": %zu,\n"
                "  \"fallback_texels\": %zu,\n  \"spacing\": %g,\n  \"max_level\": %u,\n"
                "  \"encoding\": \"%s\",\n  \"bricks_per_level\": [%u, %u, %u, %u],\n"
                "  \"bricks\": %u,\n  \"atlas_dims\": [%u, %u, %u],\n"
                "  \"indirection_dims\": [%u, %u, %u],\n  \"atlas_bytes\": %zu,\n"
                "  \"indirection_bytes\": %zu,\n  \"raw_bytes\": %.0f,\n  \"gzip_bytes\": %zu,\n"
                "  \"dense_rgba8_bytes\": %zu,\n  \"dense_over_raw\": %.3f,\n"
                "  \"dense_over_gzip\": %.3f,\n  \"clamped_texels\": %zu,\n"
                "  \"mean_irradiance\": %.6g,\n  \"rmse\": %.6g,\n  \"p99\": %.6g,\n"
                "  \"max_error\": %.6g,\n  \"rmse_relative\": %.6g,\n  \"p99_relative\": %.6g,\n"
                "  \"max_relative\": %.6g,\n  \"read_seconds\": %.4f,\n"
                "  \"convert_seconds\": %.4f,\n  \"convert_over_read\": %.3f\n}\n",
                vi->probe_count, vi->valid_count, vi->filled_count,
                vi->unreached_count, vi->fallback_count, (double)vi->spacing, vi->max_level,
                vi->encoding == VDBGI_ENCODING_RGB9E5 ? "rgb9e5" : "rgbm", vi->bricks[0],
                vi->bricks[1], vi->bricks[2], vi->bricks[3], vi->brick_count, vi->atlas_dims[0],
                vi->atlas_dims[1], vi->atlas_dims[2], vi->indirection_dims[0],
                vi->indirection_dims[1], vi->indirection_dims[2], vi->atlas_size,
                vi->indirection_size, raw, vi->file_size, vi->dense_rgba8_size,
                (double)vi->dense_rgba8_size / raw,
                (double)vi->dense_rgba8_size / (double)vi->file_size, vi->clamped_count,
                vi->mean_irradiance, vi->rmse, vi->p99, vi->max_error, vi->rmse / mean,
                vi->p99 / mean, vi->max_error / mean, read_seconds, vi->seconds,
                vi->seconds / read_seconds);
        return;
    }
    char a[32], b[32], c[32], d[32];
    fprintf(f, "input        %s: %zu probes (%zu valid) at %g m\n", o->input, pi->probe_count,
            vi->valid_count, pi->spacing);
    fprintf(f, "fill         %zu points hold a value (%zu unreached, %zu texels from block means)\n",
            vi->filled_count, vi->unreached_count, vi->fallback_count);
    fprintf(f, "bricks       %u: level 0 %u, level 1 %u, level 2 %u, level 3 %u\n",
            vi->brick_count, vi->bricks[0], vi->bricks[1], vi->bricks[2], vi->bricks[3]);
    fprintf(f, "atlas        %ux%ux%u texels, %s\n", vi->atlas_dims[0], vi->atlas_dims[1],
            vi->atlas_dims[2], cli_bytes((double)vi->atlas_size, a, sizeof(a)));
    fprintf(f, "indirection  %ux%ux%u cells, %s\n", vi->indirection_dims[0],
            vi->indirection_dims[1], vi->indirection_dims[2],
            cli_bytes((double)vi->indirection_size, b, sizeof(b)));
    fprintf(f, "file         %s: %s raw, %s gzip'd\n", o->output, cli_bytes(raw, c, sizeof(c)),
            cli_bytes((double)vi->file_size, d, sizeof(d)));
    fprintf(f, "dense        RGBA8 grid at %g m: %s, %.1fx the raw textures, %.1fx the file\n",
            pi->spacing, cli_bytes((double)vi->dense_rgba8_size, a, sizeof(a)),
            (double)vi->dense_rgba8_size / raw,
            (double)vi->dense_rgba8_size / (double)vi->file_size);
    fprintf(f, "error        RMSE %.3g%%, p99 %.3g%%, max %.3g%% of the mean irradiance %.4g\n",
            100.0 * vi->rmse / mean, 100.0 * vi->p99 / mean, 100.0 * vi->max_error / mean,
            vi->mean_irradiance);
    fprintf(f, "clamped      %zu texels above the RGBM range %g\n", vi->clamped_count,
            (double)vi->rgbm_range);
    fprintf(f, "time         convert %.3f s, %.2fx reading the .vdb (%.3f s)\n", vi->seconds,
            vi->seconds / read_seconds, read_seconds);
}

/* The JSON statistics, through a temporary name like every output. */
static bool write_json(const options *o, const vdbgi_volume_info *vi, const vdbgi_probes_info *pi,
                       double read_seconds)
{
    char tmp[4096];
    snprintf(tmp, sizeof(tmp), "%s.tmp-json", o->stats);
    FILE *const f = fopen(tmp, "w");
    if (!f)
        return false;
    print_stats(f, o, vi, pi, read_seconds, true);
    const bool written = !ferror(f);
    const bool ok = (fclose(f) == 0) & written && rename(tmp, o->stats) == 0;
    if (!ok)
        remove(tmp);
    return ok;
}

int main(int argc, char **argv)
{
    cli_init("vdb-to-gi");
    options o = {.axis = VDBGI_AXIS_Y, .slice_at = NAN, .exposure = NAN};
    const int parsed = parse_args(argc, argv, &o);
    if (parsed >= 0)
        return parsed;
    vdbgi_context *const ctx = cli_context();
    if (!ctx)
        return CLI_FAILED;
    vdbgi_probes *probes = NULL;
    vdbgi_volume *vol = NULL;
    int code = CLI_FAILED;
    vdbgi_result r = vdbgi_output_check(ctx, o.output);
    if (r == VDBGI_OK && o.stats)
        r = vdbgi_output_check(ctx, o.stats);
    const double t0 = cli_now();
    if (r == VDBGI_OK)
        r = vdbgi_probes_read(ctx, o.input, &probes);
    const double read_seconds = cli_now() - t0;
    if (r == VDBGI_OK)
        r = vdbgi_volume_build(ctx, probes, &o.convert, &vol);
    if (r == VDBGI_OK)
        r = vdbgi_volume_write(vol, o.output);
    vdbgi_volume_info vi;
    vdbgi_probes_info pi;
    if (r == VDBGI_OK) {
        vdbgi_volume_get_info(vol, &vi);
        vdbgi_probes_get_info(probes, &pi);
    }
    if (r == VDBGI_OK && o.slices) {
        const double at = isnan(o.slice_at) ? busiest_plane(probes, o.axis) : o.slice_at;
        /* Auto exposure puts the mean irradiance at 18% grey. */
        const double ev = isnan(o.exposure) && vi.mean_irradiance > 0.0
                              ? log2(0.18 / vi.mean_irradiance)
                              : (isnan(o.exposure) ? 0.0 : o.exposure);
        r = vdbgi_volume_write_slices(vol, probes, o.axis, at, (float)ev, o.slices);
    }
    if (r != VDBGI_OK) {
        code = cli_fail(ctx, r);
    } else {
        code = CLI_OK;
        if (cli_verbosity >= 2)
            print_stats(stdout, &o, &vi, &pi, read_seconds, false);
        if (o.stats && !write_json(&o, &vi, &pi, read_seconds)) {
            cli_error("%s: cannot write statistics", o.stats);
            code = CLI_FAILED;
        }
    }
    vdbgi_volume_destroy(vol);
    vdbgi_probes_destroy(probes);
    vdbgi_context_destroy(ctx);
    return code;
}
