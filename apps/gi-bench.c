/* gi-bench: measure the bake against a bare Embree loop over the same rays. */
#define _DEFAULT_SOURCE     /* mkstemps */
#define VDBGI_BENCHMARK_API /* vdbgi_probes_trace_bare, vdbgi_lightmap_trace_bare, ... */
#include "bench_lights.h"
#include "bench_truth.h"
#include "cli.h"
#include "vdbgi.h"

#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

extern char **environ;

static void usage(void)
{
    printf("Usage: gi-bench bake SCENE [options]\n"
           "       gi-bench convert PROBES.vdb [options]\n"
           "       gi-bench sweep SCENE [options]\n"
           "       gi-bench memory SCENE [options]\n"
           "       gi-bench lightmap SCENE [options]\n"
           "       gi-bench truth SCENE [options]\n"
           "       gi-bench lights SCENE [options]\n"
           "\n"
           "bake: measure, in one run on one machine, the ray throughput of:\n"
           "  - a bare Embree loop that traces exactly the bake's rays (primary rays, then a\n"
           "    shadow ray from each hit that faces the sun) with no shading, for each query\n"
           "    shape (rtcIntersect1, 8- and 16-wide packets, rtcIntersect1M streams);\n"
           "  - the bake itself in-process (trace and shade), for each query shape;\n"
           "  - the whole gi-bake process (load, topology, trace, VDB write), run as a child.\n"
           "Each is run --repeat times and the fastest kept, as the machine is shared.\n"
           "Prints a Markdown table; ratios are against the fastest bare loop.\n"
           "\n"
           "convert: time reading the .vdb, then convert it with each\n"
           "criterion (range, interp) at eps 0, 0.01, 0.03, 0.1, 0.2, 0.4 in RGBM in the seed\n"
           "layout, and the defaults (compact layout) in RGBM and RGB9E5 and in the seed\n"
           "layout; print bytes against the dense RGBA8 grid, the error, and the conversion\n"
           "time against the read, each the fastest of --repeat.\n"
           "\n"
           "sweep: speed against accuracy on SCENE, as CSV files in --out: rays.csv (rays\n"
           "16..1024 per sampling, and adaptive targets, against a 4096-ray random bake of\n"
           "the same probes at 1 m), size.csv (bytes against error over eps, max level,\n"
           "criterion and encoding), spacing.csv (0.25..2 m: probes, time, bytes, and\n"
           "the error and bias at the surface receivers against the hemisphere truth (as\n"
           "truth below), under the default darkest fill, the mean fill and the compact\n"
           "layout).\n"
           "\n"
           "memory: memory against the error a player sees on SCENE, as --out/memory.csv:\n"
           "at 0.25, 0.5 and 1 m (--spacing S limits it to one), a dense grid of every\n"
           "probe (scalar RGBM, and with L2 terms), seed 000's brick layout and the compact\n"
           "one (scalar, and with L2 terms) at eps 0.05..0.4: VRAM, gzip'd bytes, RMSE at\n"
           "the probes, and RMSE and bias against the hemisphere truth (as truth below) at\n"
           "the surface receivers and the character layer, each read as the runtime reads\n"
           "it; probes within 2.5 m of a surface at every spacing.\n"
           "\n"
           "lightmap: gi-lightmap on SCENE. Throughput at its defaults (0.25 m texels, 64\n"
           "rays, 2 passes): a bare Embree loop over the same rays (nothing shaded nor\n"
           "dilated) against the bake, per pass, fastest of --repeat, and the whole\n"
           "gi-lightmap process. Packing: the charts' boxes of this unwrap and of seed\n"
           "004's coplanar islands, into --out/lightmap_boxes.json (tests/js/potpack.mjs\n"
           "packs them as seed 004 does). Error against memory, --out/lightmap.csv: texels\n"
           "of 1, 0.5, 0.25 and 0.125 m, each in the smallest power-of-two atlas that holds\n"
           "it, one pass, against 2048-ray estimates at 3000 points on the surfaces (only\n"
           "when --out is given).\n"
           "\n"
           "truth: what each method gives a surface, against the hemisphere estimator\n"
           "(2048 random rays over the receiver's own normal) at 3000 points on the\n"
           "surfaces and at 400 character points 0.5-2 m over walkable ground read facing\n"
           "up, the four horizontal directions and down: the scalar in bricks (today's\n"
           "runtime), the scalar, ambient cube and L2 probes read directly, and a one-pass\n"
           "lightmap at 0.25 m texels; at 0.5 and 0.25 m (--spacing S: that one only).\n"
           "Prints a Markdown table and writes --out/truth.csv. --model physical and\n"
           "--bounces N hold every method and the truth to that light (a lightmap takes a\n"
           "pass a bounce).\n"
           "\n"
           "lights: the scene's own light (its lights, a sky map written to --out, the\n"
           "physical model, bounces): each feature's bake time, probes/s and rays/s against\n"
           "seed 000's one-bounce bake at --spacing (0.25), fastest of --repeat; then the\n"
           "error at 400 valid probes of 1, 2, 3, 4 and 6 bounces at 32..2048 rays against\n"
           "8 bounces of 4096 rays (--out/lights.csv), and a sky with a small sun against a\n"
           "smooth one (the noise a sun leaves once taken out of the map as a lamp).\n"
           "\n"
           "Options:\n"
           "      --spacing M     probe spacing in metres (0.5)\n"
           "      --rays N        rays per probe (128)\n"
           "      --threads N     worker threads (all cores)\n"
           "      --repeat N      runs of each measurement, fastest kept (3)\n"
           "      --model M       truth: seed or physical (seed)\n"
           "      --bounces N     truth: bounces, 1..16 (1)\n"
           "      --gi-bake PATH  the gi-bake to time (the one beside gi-bench)\n"
           "      --out PATH      bake: where gi-bake writes its .vdb (a temporary file);\n"
           "                      sweep: the directory for the CSV files (build/chart)\n"
           "  -h, --help          print this help and exit\n"
           "      --version       print the version and exit\n"
           "\n"
           "Examples:\n"
           "  gi-bench bake data/world.glb\n"
           "  gi-bench bake world200.glb --repeat 1\n"
           "  gi-bench convert world.vdb\n"
           "  gi-bench sweep data/world.glb --out build/chart\n"
           "  gi-bench memory data/world.glb --out build/chart\n"
           "  gi-bench lightmap data/world.glb --out build/chart\n"
           "  gi-bench truth data/world.glb --out build/chart\n"
           "  gi-bench truth interior.glb --model physical --bounces 3\n"
           "  gi-bench lights interior.glb --out build/chart\n");
}

typedef struct options {
    const char *mode, *scene, *gi_bake, *out;
    double spacing;
    bool spacing_given;
    int rays, threads, repeat;
    bench_light light;
} options;

enum {
    OPT_SPACING = 256,
    OPT_RAYS,
    OPT_THREADS,
    OPT_REPEAT,
    OPT_GI_BAKE,
    OPT_OUT,
    OPT_MODEL,
    OPT_BOUNCES
};

static int parse_args(int argc, char **argv, options *o)
{
    static const struct option longs[] = {{"spacing", required_argument, NULL, OPT_SPACING},
                                          {"rays", required_argument, NULL, OPT_RAYS},
                                          {"threads", required_argument, NULL, OPT_THREADS},
                                          {"repeat", required_argument, NULL, OPT_REPEAT},
                                          {"gi-bake", required_argument, NULL, OPT_GI_BAKE},
                                          {"out", required_argument, NULL, OPT_OUT},
                                          {"model", required_argument, NULL, OPT_MODEL},
                                          {"bounces", required_argument, NULL, OPT_BOUNCES},
                                          {"help", no_argument, NULL, 'h'},
                                          {"version", no_argument, NULL, CLI_OPT_VERSION},
                                          {NULL, 0, NULL, 0}};
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, ":h", longs, NULL)) != -1) {
        double d;
        long long i;
        switch (c) {
        case OPT_SPACING:
            if (!cli_parse_double(optarg, &d) || !(d > 0.0))
                return cli_usage_error("--spacing must be a number > 0 (got '%s')", optarg);
            o->spacing = d;
            o->spacing_given = true;
            break;
        case OPT_RAYS:
            if (!cli_parse_int(optarg, &i) || i < 1 || i > 1000000)
                return cli_usage_error("--rays must be an integer in 1..1000000 (got '%s')",
                                       optarg);
            o->rays = (int)i;
            break;
        case OPT_THREADS:
            if (!cli_parse_int(optarg, &i) || i < 1 || i > 1024)
                return cli_usage_error("--threads must be an integer in 1..1024 (got '%s')",
                                       optarg);
            o->threads = (int)i;
            break;
        case OPT_REPEAT:
            if (!cli_parse_int(optarg, &i) || i < 1 || i > 100)
                return cli_usage_error("--repeat must be an integer in 1..100 (got '%s')", optarg);
            o->repeat = (int)i;
            break;
        case OPT_GI_BAKE: o->gi_bake = optarg; break;
        case OPT_OUT: o->out = optarg; break;
        case OPT_MODEL:
            if (strcmp(optarg, "seed") != 0 && strcmp(optarg, "physical") != 0)
                return cli_usage_error("--model must be seed or physical (got '%s')", optarg);
            o->light.model =
                strcmp(optarg, "physical") == 0 ? VDBGI_MODEL_PHYSICAL : VDBGI_MODEL_SEED;
            break;
        case OPT_BOUNCES:
            if (!cli_parse_int(optarg, &i) || i < 1 || i > 16)
                return cli_usage_error("--bounces must be an integer in 1..16 (got '%s')", optarg);
            o->light.bounces = (int)i;
            break;
        default: return cli_common_option(c, argv, usage);
        }
    }
    if (optind == argc ||
        (strcmp(argv[optind], "bake") != 0 && strcmp(argv[optind], "convert") != 0 &&
         strcmp(argv[optind], "sweep") != 0 && strcmp(argv[optind], "memory") != 0 &&
         strcmp(argv[optind], "lightmap") != 0 && strcmp(argv[optind], "truth") != 0 &&
         strcmp(argv[optind], "lights") != 0))
        return cli_usage_error("say which benchmark: gi-bench bake SCENE, convert PROBES.vdb, "
                               "sweep SCENE, memory SCENE, lightmap SCENE, truth SCENE or "
                               "lights SCENE");
    if (argc - optind != 2)
        return cli_usage_error("give one input: gi-bench %s FILE", argv[optind]);
    o->mode = argv[optind];
    o->scene = argv[optind + 1];
    return -1;
}

/* Wall seconds of running argv to completion, or -1 if it failed. */
static double time_process(char *const argv[])
{
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    const double t0 = cli_now();
    pid_t pid;
    const int spawned = posix_spawn(&pid, argv[0], &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (spawned != 0)
        return -1.0;
    int status = 0;
    if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return -1.0;
    return cli_now() - t0;
}

static const char *const method_names[] = {"auto", "rtcIntersect1", "packet 8", "packet 16",
                                           "stream 1M"};

/* A built volume's figures with its file's size: its file made (gzip happens on write). */
static void bench_info(const vdbgi_volume *v, vdbgi_volume_info *vi)
{
    vdbgi_volume_write_memory(v, NULL, 0);
    vdbgi_volume_get_info(v, vi);
}

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
        const vdbgi_result r = vdbgi_volume_build(ctx, p, d, &v);
        if (r != VDBGI_OK)
            return cli_fail(ctx, r);
        /* The conversion is the build and the file's bytes (gzip happens on write). */
        const double t0 = cli_now();
        vdbgi_volume_write_memory(v, NULL, 0);
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

static int bench_convert(const options *o)
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
    static const float eps[] = {VDBGI_ZERO, 0.01f, 0.03f, 0.1f, 0.2f, 0.4f};
    static const char *const eps_text[] = {"0", "0.01", "0.03", "0.1", "0.2", "0.4"};
    int code = CLI_OK;
    for (int c = VDBGI_CRITERION_RANGE; c <= VDBGI_CRITERION_INTERP && code == CLI_OK; c++)
        for (size_t e = 0; e < sizeof(eps) / sizeof(eps[0]) && code == CLI_OK; e++) {
            const vdbgi_convert_desc d = {.eps = eps[e], .criterion = (vdbgi_criterion)c};
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
    const vdbgi_convert_desc flat = {.layout = VDBGI_LAYOUT_COMPACT, .scalar_only = 1};
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

/* ---- sweep ------------------------------------------------------------------ */

typedef struct sweep {
    vdbgi_context *ctx;
    const options *o;
    vdbgi_scene *scene;
    FILE *csv;
} sweep;

static FILE *open_csv(const char *dir, const char *name, const char *header)
{
    char path[4096];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    FILE *const f = fopen(path, "w");
    if (f)
        fprintf(f, "%s\n", header);
    else
        cli_error("%s: cannot write", path);
    return f;
}

/* RMSE and mean of b against a over n RGB values, relative to a's mean. */
static void compare(const float *a, const float *b, size_t n, double *rmse_rel, double *p99_rel)
{
    double sq = 0.0, mean = 0.0;
    double *const e = calloc(n ? n : 1, sizeof(double));
    for (size_t i = 0; i < n; i++) {
        double worst = 0.0;
        for (int k = 0; k < 3; k++) {
            const double d = (double)b[3 * i + k] - a[3 * i + k];
            sq += d * d;
            mean += a[3 * i + k];
            worst = fabs(d) > worst ? fabs(d) : worst;
        }
        if (e)
            e[i] = worst;
    }
    mean /= 3.0 * (double)(n ? n : 1);
    *rmse_rel = sqrt(sq / (3.0 * (double)(n ? n : 1))) / mean;
    *p99_rel = 0.0;
    if (e && n) {
        for (size_t i = 1; i < n; i++) /* insertion sort is enough for a few thousand */
            for (size_t j = i; j > 0 && e[j - 1] > e[j]; j--) {
                const double t = e[j];
                e[j] = e[j - 1], e[j - 1] = t;
            }
        *p99_rel = e[(size_t)(0.99 * (double)(n - 1))] / mean;
    }
    free(e);
}

static int sweep_rays(sweep *w, const char *dir)
{
    vdbgi_context *const ctx = w->ctx;
    const vdbgi_place_desc pd = {.spacing = 1.0};
    vdbgi_probes *p = NULL;
    vdbgi_result r = vdbgi_probes_place(ctx, w->scene, &pd, &p);
    if (r != VDBGI_OK)
        return cli_fail(ctx, r);
    vdbgi_probes_info pi;
    vdbgi_probes_get_info(p, &pi);
    const size_t n = pi.probe_count;
    float *const ref = calloc(n * 3, sizeof(float)), *const got = calloc(n * 3, sizeof(float));
    const vdbgi_bake_desc rd = {.rays = 4096, .sampling = VDBGI_SAMPLING_RANDOM, .seed = 99};
    r = vdbgi_probes_bake(p, w->scene, &rd, NULL);
    /* Only probes that are valid in the reference count: the others are filled anyway. */
    size_t m = 0;
    unsigned char *const valid = calloc(n ? n : 1, 1);
    for (size_t i = 0; r == VDBGI_OK && i < n; i++) {
        float bf;
        vdbgi_probes_get(p, i, NULL, &ref[3 * m], &bf);
        valid[i] = bf <= pi.invalid_threshold;
        m += valid[i];
    }
    FILE *const f =
        open_csv(dir, "rays.csv", "sampling,rays,noise_target,seconds,rmse_rel,p99_rel");
    static const int rays[] = {16, 32, 64, 128, 256, 512, 1024};
    static const float targets[] = {0.1f, 0.05f, 0.02f, 0.01f};
    for (int sampling = 0; r == VDBGI_OK && f && sampling < 3; sampling++) {
        const int runs = sampling < 2 ? (int)(sizeof(rays) / sizeof(rays[0])) : 4;
        for (int k = 0; r == VDBGI_OK && k < runs; k++) {
            vdbgi_bake_desc d = {.rays = sampling < 2 ? rays[k] : VDBGI_RAYS_AUTO,
                                 .sampling = sampling == 0 ? VDBGI_SAMPLING_FIBONACCI
                                                           : VDBGI_SAMPLING_RANDOM,
                                 .noise = sampling == 2 ? targets[k] : 0.0f};
            vdbgi_bake_stats st;
            if ((r = vdbgi_probes_bake(p, w->scene, &d, &st)) != VDBGI_OK)
                break;
            size_t j = 0;
            for (size_t i = 0; i < n; i++)
                if (valid[i])
                    vdbgi_probes_get(p, i, NULL, &got[3 * j++], NULL);
            double rmse, p99;
            compare(ref, got, m, &rmse, &p99);
            fprintf(f, "%s,%.1f,%g,%.4f,%.6f,%.6f\n",
                    sampling == 0   ? "fibonacci"
                    : sampling == 1 ? "random"
                                    : "adaptive",
                    (double)st.primary_ray_count / (double)n,
                    sampling == 2 ? (double)targets[k] : 0.0, st.seconds, rmse, p99);
            fflush(f);
        }
    }
    if (f)
        fclose(f);
    free(ref);
    free(got);
    free(valid);
    vdbgi_probes_destroy(p);
    return r == VDBGI_OK && f ? CLI_OK : (r != VDBGI_OK ? cli_fail(ctx, r) : CLI_FAILED);
}

static int sweep_size(sweep *w, const char *dir)
{
    vdbgi_context *const ctx = w->ctx;
    vdbgi_probes *p = NULL;
    vdbgi_result r = vdbgi_probes_place(ctx, w->scene, NULL, &p);
    if (r == VDBGI_OK)
        r = vdbgi_probes_bake(p, w->scene, NULL, NULL);
    FILE *const f = r == VDBGI_OK ? open_csv(dir, "size.csv",
                                             "criterion,eps,max_level,encoding,raw_bytes,"
                                             "gzip_bytes,dense_bytes,rmse_rel,p99_rel")
                                  : NULL;
    static const float eps[] = {VDBGI_ZERO, 0.01f, 0.03f, 0.1f, 0.2f, 0.4f, 0.8f, 1.6f};
    static const char *const eps_text[] = {"0", "0.01", "0.03", "0.1", "0.2", "0.4", "0.8", "1.6"};
    for (int c = VDBGI_CRITERION_RANGE; f && r == VDBGI_OK && c <= VDBGI_CRITERION_INTERP; c++)
        for (int e = 0; r == VDBGI_OK && e < 2; e++)
            for (int max_level = 0; r == VDBGI_OK && max_level <= 3; max_level += 3)
                for (size_t i = 0; r == VDBGI_OK && i < sizeof(eps) / sizeof(eps[0]); i++) {
                    const vdbgi_convert_desc d = {.eps = eps[i],
                                                  .max_level = max_level ? max_level : VDBGI_ZERO,
                                                  .criterion = (vdbgi_criterion)c,
                                                  .encoding = (vdbgi_encoding)e};
                    vdbgi_volume *v = NULL;
                    if ((r = vdbgi_volume_build(ctx, p, &d, &v)) != VDBGI_OK)
                        break;
                    vdbgi_volume_info vi;
                    bench_info(v, &vi);
                    fprintf(f, "%s,%s,%d,%s,%zu,%zu,%zu,%.6f,%.6f\n",
                            c == VDBGI_CRITERION_RANGE ? "range" : "interp", eps_text[i], max_level,
                            e ? "rgb9e5" : "rgbm", vi.indirection_size + vi.atlas_size,
                            vi.file_size, vi.dense_rgba8_size, vi.rmse / vi.mean_irradiance,
                            vi.p99 / vi.mean_irradiance);
                    vdbgi_volume_destroy(v);
                }
    if (f)
        fclose(f);
    vdbgi_probes_destroy(p);
    return r == VDBGI_OK && f ? CLI_OK : (r != VDBGI_OK ? cli_fail(ctx, r) : CLI_FAILED);
}

static int sweep_spacing(sweep *w, const char *dir)
{
    vdbgi_context *const ctx = w->ctx;
    /* The surface receivers and their hemisphere truth (gi-bench truth's). */
    bench_receivers rv = {0};
    float *got = NULL;
    vdbgi_result r = bench_receivers_make(w->scene, NULL, &rv);
    if (r == VDBGI_OK && !(got = calloc(3 * rv.count + 3, sizeof(float))))
        r = VDBGI_ERR_OUT_OF_MEMORY;
    FILE *const f = r == VDBGI_OK ? open_csv(dir, "spacing.csv",
                                             "spacing,probes,bake_seconds,raw_bytes,gzip_bytes,"
                                             "dense_bytes,receivers,receiver_rmse_rel,"
                                             "receiver_bias,mean_fill_rmse_rel,"
                                             "mean_fill_bias,compact_raw_bytes,"
                                             "compact_gzip_bytes,compact_receiver_rmse_rel,"
                                             "compact_receiver_bias")
                                  : NULL;
    static const double spacing[] = {0.25, 0.5, 1.0, 2.0};
    for (int i = 0; f && r == VDBGI_OK && i < 4; i++) {
        const vdbgi_place_desc pd = {.spacing = spacing[i]};
        vdbgi_probes *p = NULL;
        vdbgi_volume *v = NULL;
        vdbgi_bake_stats st = {0};
        r = vdbgi_probes_place(ctx, w->scene, &pd, &p);
        if (r == VDBGI_OK)
            r = vdbgi_probes_bake(p, w->scene, NULL, &st);
        if (r == VDBGI_OK)
            r = vdbgi_volume_build(ctx, p, NULL, &v);
        /* The same probes under the mean fill: what the darkest fill costs in the open;
           and in the compact layout. */
        vdbgi_volume *mean = NULL, *compact = NULL;
        const vdbgi_convert_desc md = {.fill = VDBGI_FILL_MEAN};
        const vdbgi_convert_desc cd = {.layout = VDBGI_LAYOUT_COMPACT};
        if (r == VDBGI_OK)
            r = vdbgi_volume_build(ctx, p, &md, &mean);
        if (r == VDBGI_OK)
            r = vdbgi_volume_build(ctx, p, &cd, &compact);
        if (r == VDBGI_OK) {
            bench_error e[3];
            const vdbgi_volume *const vs[3] = {v, mean, compact};
            for (int k = 0; k < 3; k++) {
                bench_volume_reading(vs[k], &rv, got);
                e[k] = bench_error_of(&rv, got, -1);
            }
            vdbgi_volume_info vi, ci;
            bench_info(v, &vi);
            bench_info(compact, &ci);
            fprintf(f, "%g,%llu,%.4f,%zu,%zu,%zu,%zu,%.6f,%.6f,%.6f,%.6f,%zu,%zu,%.6f,%.6f\n",
                    spacing[i], (unsigned long long)st.probe_count, st.seconds,
                    vi.indirection_size + vi.atlas_size, vi.file_size, vi.dense_rgba8_size,
                    rv.surface, e[0].rmse, e[0].bias, e[1].rmse, e[1].bias,
                    ci.indirection_size + ci.atlas_size, ci.file_size, e[2].rmse, e[2].bias);
            fflush(f);
        }
        vdbgi_volume_destroy(compact);
        vdbgi_volume_destroy(mean);
        vdbgi_volume_destroy(v);
        vdbgi_probes_destroy(p);
    }
    if (f)
        fclose(f);
    free(got);
    bench_receivers_free(&rv);
    return r == VDBGI_OK && f ? CLI_OK : (r != VDBGI_OK ? cli_fail(ctx, r) : CLI_FAILED);
}

/* Bytes of a dense RGBM grid over the probes' box, gzip'd as the .gi is (level 6). */
static size_t dense_gzip_bytes(const vdbgi_volume *exact, const vdbgi_probes_info *pi)
{
    z_stream z = {0};
    if (deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        return 0;
    const int nx = pi->ijk_max[0] - pi->ijk_min[0] + 1;
    uint8_t *const row = malloc(4 * (size_t)nx);
    uint8_t out[1 << 16];
    size_t total = 0;
    vdbgi_volume_info vi;
    bench_info(exact, &vi);
    for (int z0 = pi->ijk_min[2]; row && z0 <= pi->ijk_max[2] + 1; z0++)
        for (int y = pi->ijk_min[1]; y <= pi->ijk_max[1]; y++) {
            const bool last = z0 > pi->ijk_max[2];
            if (!last)
                for (int x = 0; x < nx; x++) {
                    const int32_t ijk[3] = {pi->ijk_min[0] + x, y, z0};
                    float pos[3], rgb[3];
                    for (int k = 0; k < 3; k++)
                        pos[k] = (float)(pi->origin[k] + pi->spacing * ijk[k]);
                    vdbgi_volume_sample(exact, pos, rgb);
                    vdbgi_rgbm_encode(rgb, vi.rgbm_range, &row[4 * x]);
                }
            z.next_in = row;
            z.avail_in = last ? 0 : 4 * (unsigned)nx;
            do {
                z.next_out = out;
                z.avail_out = sizeof(out);
                deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
                total += sizeof(out) - z.avail_out;
            } while (z.avail_out == 0);
            if (last)
                break;
        }
    deflateEnd(&z);
    free(row);
    return total;
}

/*
 * One row of memory.csv: a volume's bytes, its error at the probes (against
 * the filled field, its own quantity) and what it gives the receivers
 * against the hemisphere truth, each read as the runtime reads it.
 */
static void memory_row(FILE *f, double spacing, const char *layout, const char *basis,
                       const char *eps, const vdbgi_volume *v, size_t vram, size_t file,
                       const bench_receivers *rv, float *got)
{
    vdbgi_volume_info vi;
    bench_info(v, &vi);
    bench_volume_reading(v, rv, got);
    const bench_error s = bench_error_of(rv, got, -1), c = bench_error_of(rv, got, 3);
    const double mean = vi.mean_irradiance > 0.0 ? vi.mean_irradiance : 1.0;
    fprintf(f, "%g,%s,%s,%s,%zu,%zu,%zu,%u,%u,%u,%u,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%zu,%zu\n",
            spacing, layout, basis, eps, vi.valid_count, vram, file, vi.bricks[0], vi.bricks[1],
            vi.bricks[2], vi.bricks[3], vi.rmse / mean, vi.p99 / mean, s.rmse, s.bias, c.rmse,
            c.bias, s.n, c.n);
    fflush(f);
}

static int bench_memory(const options *o, bool one_spacing)
{
    const char *const dir = o->out ? o->out : "build/chart";
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        cli_error("%s: cannot make directory: %s", dir, strerror(errno));
        return CLI_FAILED;
    }
    vdbgi_context *const ctx = cli_context();
    if (!ctx)
        return CLI_FAILED;
    vdbgi_scene *scene = NULL;
    bench_receivers rv = {0};
    float *got = NULL;
    vdbgi_result r = vdbgi_scene_load(ctx, o->scene, &scene);
    if (r == VDBGI_OK)
        r = bench_receivers_make(scene, NULL, &rv);
    if (r == VDBGI_OK && !(got = calloc(3 * rv.count + 3, sizeof(float))))
        r = VDBGI_ERR_OUT_OF_MEMORY;
    FILE *const f =
        r == VDBGI_OK
            ? open_csv(dir, "memory.csv",
                       "spacing,layout,basis,eps,valid_probes,vram_bytes,file_bytes,"
                       "bricks_l0,bricks_l1,bricks_l2,bricks_l3,probe_rmse_rel,probe_p99_rel,"
                       "surface_rmse_rel,surface_bias,character_rmse_rel,character_bias,"
                       "surface_points,character_points")
            : NULL;
    static const double spacings[] = {0.25, 0.5, 1.0};
    static const float eps[] = {0.05f, 0.1f, 0.2f, 0.4f};
    static const char *const eps_text[] = {"0.05", "0.1", "0.2", "0.4"};
    for (int i = 0; f && r == VDBGI_OK && i < 3; i++) {
        const double spacing = one_spacing ? o->spacing : spacings[i];
        if (one_spacing && i > 0)
            break;
        /* Probes up to 2.5 m from a surface at every spacing, so that a character's
           head (2 m) and the lattice step above it have probes (the default margin,
           4 spacings, is 1 m at 0.25 m). One L2 bake gives both bases: its L0 is
           the scalar bake, bit for bit. */
        const vdbgi_place_desc pd = {.spacing = spacing, .margin = 2.5};
        const vdbgi_bake_desc bd = {.rays = o->rays, .basis = VDBGI_BASIS_SH2};
        vdbgi_probes *p = NULL;
        r = vdbgi_probes_place(ctx, scene, &pd, &p);
        if (r == VDBGI_OK)
            r = vdbgi_probes_bake(p, scene, &bd, NULL);
        /* A dense grid holds every probe: the bricks at eps 0, level 0 (L2 terms rounded as
           by default), with the dense grid's bytes (RGBM; L2: 24 more a probe). */
        for (int b = 0; r == VDBGI_OK && b < 2; b++) {
            vdbgi_volume *exact = NULL;
            const vdbgi_convert_desc ed = {
                .eps = VDBGI_ZERO, .max_level = VDBGI_ZERO, .scalar_only = !b};
            if ((r = vdbgi_volume_build(ctx, p, &ed, &exact)) == VDBGI_OK) {
                vdbgi_probes_info pi;
                vdbgi_volume_info ei;
                vdbgi_probes_get_info(p, &pi);
                bench_info(exact, &ei);
                memory_row(f, spacing, "dense", b ? "L2" : "scalar", "0", exact,
                           ei.dense_rgba8_size * (b ? 7 : 1), b ? 0 : dense_gzip_bytes(exact, &pi),
                           &rv, got);
            }
            vdbgi_volume_destroy(exact);
        }
        /* Bricks: seed 000's layout (scalar only), the compact one scalar and with L2,
           its terms rounded as the default rounds them and with every bit kept. */
        static const char *const basis_text[] = {"scalar", "scalar", "L2", "L2-8bit"};
        for (int m = 0; r == VDBGI_OK && m < 4; m++)
            for (int e = 0; r == VDBGI_OK && e < 4; e++) {
                const vdbgi_convert_desc d = {.eps = eps[e],
                                              .layout =
                                                  m ? VDBGI_LAYOUT_COMPACT : VDBGI_LAYOUT_SEED,
                                              .scalar_only = m < 2,
                                              .term_bits = m == 3 ? 8 : 0};
                vdbgi_volume *v = NULL;
                r = vdbgi_volume_build(ctx, p, &d, &v);
                if (r == VDBGI_OK) {
                    vdbgi_volume_info vi;
                    bench_info(v, &vi);
                    memory_row(f, spacing, m ? "compact" : "seed", basis_text[m], eps_text[e], v,
                               vi.columns_size + vi.atlas_size + vi.sh_size, vi.file_size, &rv,
                               got);
                }
                vdbgi_volume_destroy(v);
            }
        vdbgi_probes_destroy(p);
    }
    if (f)
        fclose(f);
    if (r == VDBGI_OK && f)
        printf("memory: %s/memory.csv (%zu surface and %zu character receivers)\n", dir, rv.surface,
               rv.count - rv.surface);
    free(got);
    bench_receivers_free(&rv);
    vdbgi_scene_destroy(scene);
    const int code = r == VDBGI_OK && f ? CLI_OK : (r != VDBGI_OK ? cli_fail(ctx, r) : CLI_FAILED);
    vdbgi_context_destroy(ctx);
    return code;
}

static int bench_sweep(const options *o)
{
    const char *const dir = o->out ? o->out : "build/chart";
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        cli_error("%s: cannot make directory: %s", dir, strerror(errno));
        return CLI_FAILED;
    }
    sweep w = {.o = o};
    if (!(w.ctx = cli_context()))
        return CLI_FAILED;
    vdbgi_result r = vdbgi_scene_load(w.ctx, o->scene, &w.scene);
    int code = r == VDBGI_OK ? CLI_OK : cli_fail(w.ctx, r);
    if (code == CLI_OK)
        code = sweep_rays(&w, dir);
    if (code == CLI_OK)
        code = sweep_size(&w, dir);
    if (code == CLI_OK)
        code = sweep_spacing(&w, dir);
    if (code == CLI_OK)
        printf("sweep: rays.csv, size.csv and spacing.csv in %s\n", dir);
    vdbgi_scene_destroy(w.scene);
    vdbgi_context_destroy(w.ctx);
    return code;
}

/* ---- lightmap ---------------------------------------------------------------- */

/* A tool beside gi-bench (argv0's directory). */
static void beside(const char *argv0, const char *tool, char *out, size_t cap)
{
    const char *const slash = strrchr(argv0, '/');
    snprintf(out, cap, "%.*s%s", slash ? (int)(slash - argv0 + 1) : 0, argv0, tool);
}

/* The charts' boxes of one unwrap as a JSON object, and the area ours took (used rectangles). */
static double boxes_json(FILE *f, const char *name, const vdbgi_lightmap_result *r,
                         const vdbgi_lightmap_stats *st)
{
    const uint32_t *pages = NULL;
    size_t n = 0;
    const int32_t *const b = vdbgi_lightmap_result_boxes(r, &pages, &n);
    fprintf(
        f,
        "    {\"name\": \"%s\", \"charts\": %zu, \"samples\": %zu, \"atlases\": %zu, \"boxes\": [",
        name, n, st->samples, st->atlases);
    double area = 0.0;
    for (size_t p = 0; p < st->atlases; p++) {
        int32_t w = 0, h = 0;
        for (size_t c = 0; c < n; c++)
            if (pages[c] == p) {
                w = b[4 * c] + b[4 * c + 2] > w ? b[4 * c] + b[4 * c + 2] : w;
                h = b[4 * c + 1] + b[4 * c + 3] > h ? b[4 * c + 1] + b[4 * c + 3] : h;
            }
        area += (double)w * h;
    }
    for (size_t c = 0; c < n; c++)
        fprintf(f, "%s[%d, %d]", c ? ", " : "", b[4 * c + 2], b[4 * c + 3]);
    fprintf(f, "], \"used_area\": %.0f}", area);
    return area;
}

/* The fastest of repeated runs, pass by pass (the first run sets the counts). */
static void keep_fastest(vdbgi_lightmap_stats *best, const vdbgi_lightmap_stats *s, bool first)
{
    if (first) {
        *best = *s;
        return;
    }
    for (int p = 0; p < s->passes && p < 16; p++)
        best->pass_seconds[p] = fmin(best->pass_seconds[p], s->pass_seconds[p]);
}

/* Error of a lightmap at the receivers (triangle, barycentrics) against their estimates. */
static void lightmap_error(const vdbgi_lightmap_result *r, const uint32_t *prims, const float *uv,
                           const float *ref, float *got, int n, double *rmse, double *p99)
{
    for (int k = 0; k < n; k++)
        vdbgi_lightmap_result_sample(r, prims[k], uv[2 * k], uv[2 * k + 1], &got[3 * k]);
    compare(ref, got, (size_t)n, rmse, p99);
}

static int bench_lightmap(const options *o, const char *argv0)
{
    vdbgi_context *const ctx = cli_context();
    if (!ctx)
        return CLI_FAILED;
    vdbgi_scene *scene = NULL;
    vdbgi_lightmap_result *res = NULL;
    enum { RECEIVERS = 3000 };
    uint32_t *const prims = calloc(RECEIVERS, sizeof(uint32_t));
    float *const uv = calloc(2 * RECEIVERS, sizeof(float));
    float *const ref = calloc(3 * RECEIVERS, sizeof(float));
    float *const got = calloc(3 * RECEIVERS, sizeof(float));
    float *const bf = calloc(RECEIVERS, sizeof(float));
    FILE *csv = NULL, *json = NULL;
    char dir[PATH_MAX], path[PATH_MAX + 32], glb[PATH_MAX];
    snprintf(dir, sizeof(dir), "%s", o->out ? o->out : "build/chart");
    int code = CLI_FAILED;
    vdbgi_result r = prims && uv && ref && got && bf ? vdbgi_scene_load(ctx, o->scene, &scene)
                                                     : VDBGI_ERR_OUT_OF_MEMORY;
    if (r != VDBGI_OK) {
        code = cli_fail(ctx, r);
        goto done;
    }
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        cli_error("%s: cannot make directory: %s", dir, strerror(errno));
        goto done;
    }
    vdbgi_scene_info si;
    vdbgi_scene_get_info(scene, &si);

    /* Throughput: bare loop and bake, per pass, fastest of --repeat. */
    const vdbgi_lightmap_desc def = {.bake = {.threads = o->threads}};
    vdbgi_lightmap_stats bare = {0}, bake = {0};
    for (int rep = 0; rep < o->repeat; rep++) {
        vdbgi_lightmap_stats s;
        if ((r = vdbgi_lightmap_trace_bare(ctx, scene, &def, &s)) != VDBGI_OK)
            break;
        keep_fastest(&bare, &s, rep == 0);
        vdbgi_lightmap_destroy(res);
        res = NULL;
        if ((r = vdbgi_lightmap_bake_scene(ctx, scene, &def, &res, &s)) != VDBGI_OK)
            break;
        keep_fastest(&bake, &s, rep == 0);
    }
    if (r != VDBGI_OK) {
        code = cli_fail(ctx, r);
        goto done;
    }
    /* The whole gi-lightmap process, writing into a temporary .glb. */
    char tool[PATH_MAX], threads[32], q_flag[] = "-q", o_flag[] = "-o", t_flag[] = "--threads";
    beside(argv0, "gi-lightmap", tool, sizeof(tool));
    snprintf(glb, sizeof(glb), "/tmp/gi-bench-XXXXXX.glb");
    const int fd = mkstemps(glb, 4);
    if (fd < 0) {
        cli_error("cannot make a temporary file: %s", glb);
        goto done;
    }
    close(fd);
    unlink(glb); /* gi-lightmap refuses to replace what is not a glTF */
    snprintf(threads, sizeof(threads), "%d", o->threads);
    char scene_arg[PATH_MAX];
    snprintf(scene_arg, sizeof(scene_arg), "%s", o->scene);
    char *const lm_argv[] = {tool,    scene_arg, o_flag, glb, q_flag, o->threads ? t_flag : NULL,
                             threads, NULL};
    double process = -1.0;
    for (int rep = 0; rep < o->repeat; rep++) {
        const double t = time_process(lm_argv);
        if (t < 0.0) {
            cli_error("%s failed on %s", tool, o->scene);
            unlink(glb);
            goto done;
        }
        process = rep == 0 || t < process ? t : process;
    }
    unlink(glb);
    snprintf(path, sizeof(path), "%.*s.lightmap0.exr", (int)strlen(glb) - 4, glb);
    unlink(path);
    const double rays_per_pass = (double)bake.rays / bake.passes;
    printf("### %s: lightmap, %zu triangles, 0.25 m texels, 64 rays a texel, %d passes, "
           "%d threads\n\n",
           si.name, si.triangle_count, bake.passes,
           o->threads ? o->threads : (int)sysconf(_SC_NPROCESSORS_ONLN));
    printf("%zu charts, %zu atlas%s of 1024 texels, %zu samples (%zu invalid); about %.2fM rays a "
           "pass\n\n",
           bake.charts, bake.atlases, bake.atlases == 1 ? "" : "es", bake.samples, bake.invalid,
           rays_per_pass * 1e-6);
    printf("| pass | bare loop s | bake s | Mtexels/s | Mrays/s | bake vs bare loop |\n");
    printf("|---|---:|---:|---:|---:|---:|\n");
    double bare_total = 0.0, bake_total = 0.0;
    for (int p = 0; p < bake.passes; p++) {
        bare_total += bare.pass_seconds[p];
        bake_total += bake.pass_seconds[p];
        printf("| %d | %.3f | %.3f | %.3f | %.2f | %.3f |\n", p + 1, bare.pass_seconds[p],
               bake.pass_seconds[p], (double)bake.samples / bake.pass_seconds[p] * 1e-6,
               rays_per_pass / bake.pass_seconds[p] * 1e-6,
               bare.pass_seconds[p] / bake.pass_seconds[p]);
    }
    printf("| all passes | %.3f | %.3f | %.3f | %.2f | **%.3f** |\n", bare_total, bake_total,
           (double)bake.samples * bake.passes / bake_total * 1e-6,
           (double)bake.rays / bake_total * 1e-6, bare_total / bake_total);
    printf(
        "| gi-lightmap process (load, unwrap, texels, passes, write) | | %.3f | %.3f | %.2f | %.3f "
        "|\n\n",
        process, (double)bake.samples * bake.passes / process * 1e-6,
        (double)bake.rays / process * 1e-6, bare_total / process);

    /* Packing: this unwrap's boxes and seed 004's coplanar islands (within 0.5 degree). */
    snprintf(path, sizeof(path), "%s/lightmap_boxes.json", dir);
    if (!(json = fopen(path, "w"))) {
        cli_error("%s: cannot write: %s", path, strerror(errno));
        goto done;
    }
    fputs("{\n  \"scene\": ", json);
    cli_json_string(json, si.name);
    fputs(",\n  \"sets\": [\n", json);
    const double ours =
        boxes_json(json, "vdbgi: 15 degree charts, smallest boxes, stb_rect_pack", res, &bake);
    vdbgi_lightmap_destroy(res);
    res = NULL;
    vdbgi_lightmap_desc cop = {
        .chart_angle = 0.5f, .passes = 1, .bake = {.rays = 1, .threads = o->threads}};
    vdbgi_lightmap_stats cs;
    if ((r = vdbgi_lightmap_bake_scene(ctx, scene, &cop, &res, &cs)) != VDBGI_OK) {
        code = cli_fail(ctx, r);
        goto done;
    }
    fputs(",\n", json);
    boxes_json(json, "coplanar islands (seed 004), smallest boxes, stb_rect_pack", res, &cs);
    fputs("\n  ]\n}\n", json);
    vdbgi_lightmap_destroy(res);
    res = NULL;
    printf("Packing: %zu charts into %.0f texels of atlas, %.1f %% of it covered by triangles "
           "(%s; tests/js/potpack.mjs packs the same boxes as seed 004 does).\n\n",
           bake.charts, ours, 100.0 * (double)bake.samples / ours, path);

    /* Error against memory (only with --out: at 0.125 m a large world takes minutes). */
    if (!o->out) {
        code = CLI_OK;
        goto done;
    }
    /* Error against memory: one pass, texel sizes, the smallest atlas that holds each. */
    const vdbgi_bake_desc rd = {.rays = 2048, .sampling = VDBGI_SAMPLING_RANDOM, .seed = 5};
    if ((r = vdbgi_scene_sample_triangles(scene, RECEIVERS, 7, prims, uv)) == VDBGI_OK)
        r = vdbgi_scene_bake_surface(scene, &rd, prims, uv, RECEIVERS, ref, bf);
    int kept = 0;
    for (int k = 0; r == VDBGI_OK && k < RECEIVERS; k++)
        if (bf[k] <= 0.25f) { /* faces nobody sees are not receivers */
            prims[kept] = prims[k];
            memmove(&uv[2 * kept], &uv[2 * k], 2 * sizeof(float));
            memmove(&ref[3 * kept], &ref[3 * k], 3 * sizeof(float));
            kept++;
        }
    if (r != VDBGI_OK) {
        code = cli_fail(ctx, r);
        goto done;
    }
    snprintf(path, sizeof(path), "%s/lightmap.csv", dir);
    if (!(csv = fopen(path, "w"))) {
        cli_error("%s: cannot write: %s", path, strerror(errno));
        goto done;
    }
    fprintf(csv, "texel,size,atlases,vram_bytes,samples,receivers,receiver_rmse_rel,"
                 "receiver_p99_rel,bake_seconds\n");
    static const float texels[4] = {1.0f, 0.5f, 0.25f, 0.125f};
    for (int t = 0; t < 4; t++) {
        vdbgi_lightmap_stats ls = {0};
        /* From the atlas the boxes would fill at this density, up until one holds them. */
        const double area = ours * (0.25 / texels[t]) * (0.25 / texels[t]);
        int size = 64;
        while (size < 8192 && (double)size * size < area)
            size *= 2;
        for (; size <= 8192; size *= 2) {
            vdbgi_lightmap_destroy(res);
            res = NULL;
            const vdbgi_lightmap_desc d = {
                .texel = texels[t], .size = size, .passes = 1, .bake = {.threads = o->threads}};
            if ((r = vdbgi_lightmap_bake_scene(ctx, scene, &d, &res, &ls)) != VDBGI_OK)
                break;
            if (ls.atlases == 1)
                break;
        }
        if (r != VDBGI_OK) {
            code = cli_fail(ctx, r);
            goto done;
        }
        if (ls.atlases != 1) {
            cli_error("%g m texels do not fit one atlas of 8192", (double)texels[t]);
            goto done;
        }
        double rmse, p99;
        lightmap_error(res, prims, uv, ref, got, kept, &rmse, &p99);
        fprintf(csv, "%g,%d,%zu,%zu,%zu,%d,%.6f,%.6f,%.3f\n", (double)texels[t], size, ls.atlases,
                (size_t)size * (size_t)size * ls.atlases * 4, ls.samples, kept, rmse, p99,
                ls.seconds);
    }
    printf("lightmap: %s (%d surface receivers)\n", path, kept);
    code = CLI_OK;
done:
    if (csv)
        fclose(csv);
    if (json)
        fclose(json);
    vdbgi_lightmap_destroy(res);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
    free(prims);
    free(uv);
    free(ref);
    free(got);
    free(bf);
    return code;
}

int main(int argc, char **argv)
{
    cli_init("gi-bench");
    options o = {.spacing = 0.5, .rays = 128, .repeat = 3};
    const int parsed = parse_args(argc, argv, &o);
    if (parsed >= 0)
        return parsed;
    if (strcmp(o.mode, "convert") == 0)
        return bench_convert(&o);
    if (strcmp(o.mode, "sweep") == 0)
        return bench_sweep(&o);
    if (strcmp(o.mode, "memory") == 0)
        return bench_memory(&o, o.spacing_given);
    if (strcmp(o.mode, "lightmap") == 0)
        return bench_lightmap(&o, argv[0]);
    if (strcmp(o.mode, "truth") == 0)
        return bench_truth(o.scene, o.spacing, o.spacing_given, o.rays, o.threads, &o.light, o.out);
    if (strcmp(o.mode, "lights") == 0)
        return bench_lights(o.scene, o.spacing_given ? o.spacing : 0.25, o.threads, o.repeat,
                            o.out);

    /* gi-bake lives beside gi-bench unless told otherwise. */
    char gi_bake[PATH_MAX];
    if (o.gi_bake) {
        snprintf(gi_bake, sizeof(gi_bake), "%s", o.gi_bake);
    } else {
        const char *const slash = strrchr(argv[0], '/');
        snprintf(gi_bake, sizeof(gi_bake), "%.*sgi-bake", slash ? (int)(slash - argv[0] + 1) : 0,
                 argv[0]);
    }
    char out[PATH_MAX];
    snprintf(out, sizeof(out), "%s", o.out ? o.out : "/tmp/gi-bench-XXXXXX.vdb");
    if (!o.out) {
        const int fd = mkstemps(out, 4);
        if (fd < 0) {
            cli_error("cannot make a temporary file: %s", out);
            return CLI_FAILED;
        }
        close(fd);
    }

    vdbgi_context *const ctx = cli_context();
    vdbgi_scene *scene = NULL;
    vdbgi_probes *probes = NULL;
    if (!ctx)
        return CLI_FAILED;
    int code = CLI_FAILED;
    vdbgi_result r = vdbgi_scene_load(ctx, o.scene, &scene);
    const vdbgi_place_desc pd = {.spacing = o.spacing};
    if (r == VDBGI_OK)
        r = vdbgi_probes_place(ctx, scene, &pd, &probes);
    if (r != VDBGI_OK) {
        code = cli_fail(ctx, r);
        goto done;
    }
    vdbgi_scene_info si;
    vdbgi_probes_info pi;
    vdbgi_scene_get_info(scene, &si);
    vdbgi_probes_get_info(probes, &pi);

    /* Bare loops and in-process bakes for every query shape, best of --repeat. */
    double bare[5] = {0}, bake[5] = {0};
    vdbgi_bake_stats st = {0};
    for (int rep = 0; rep < o.repeat; rep++) {
        for (int m = VDBGI_TRACE_SINGLE; m <= VDBGI_TRACE_STREAM; m++) {
            const vdbgi_bake_desc bd = {
                .rays = o.rays, .threads = o.threads, .trace_method = (vdbgi_trace_method)m};
            vdbgi_bake_stats s;
            if ((r = vdbgi_probes_trace_bare(probes, scene, &bd, &s)) != VDBGI_OK ||
                (r = vdbgi_probes_bake(probes, scene, &bd, &st)) != VDBGI_OK) {
                code = cli_fail(ctx, r);
                goto done;
            }
            if (rep == 0 || s.seconds < bare[m])
                bare[m] = s.seconds;
            if (rep == 0 || st.seconds < bake[m])
                bake[m] = st.seconds;
        }
    }
    /* The directional bases on the default query shape, against the scalar bake beside them. */
    double scalar_auto = 0.0, cube_auto = 0.0, sh2_auto = 0.0;
    for (int rep = 0; rep < o.repeat; rep++) {
        vdbgi_bake_desc bd = {.rays = o.rays, .threads = o.threads};
        vdbgi_bake_stats s;
        if ((r = vdbgi_probes_bake(probes, scene, &bd, &s)) != VDBGI_OK) {
            code = cli_fail(ctx, r);
            goto done;
        }
        scalar_auto = rep == 0 || s.seconds < scalar_auto ? s.seconds : scalar_auto;
        bd.basis = VDBGI_BASIS_AMBIENT_CUBE;
        if ((r = vdbgi_probes_bake(probes, scene, &bd, &s)) != VDBGI_OK) {
            code = cli_fail(ctx, r);
            goto done;
        }
        cube_auto = rep == 0 || s.seconds < cube_auto ? s.seconds : cube_auto;
        bd.basis = VDBGI_BASIS_SH2;
        if ((r = vdbgi_probes_bake(probes, scene, &bd, &s)) != VDBGI_OK) {
            code = cli_fail(ctx, r);
            goto done;
        }
        sh2_auto = rep == 0 || s.seconds < sh2_auto ? s.seconds : sh2_auto;
    }
    int best = VDBGI_TRACE_SINGLE;
    for (int m = VDBGI_TRACE_SINGLE; m <= VDBGI_TRACE_STREAM; m++)
        best = bare[m] < bare[best] ? m : best;

    /* The whole gi-bake process with its default (auto) query shape. */
    char spacing[32], rays[32], threads[32];
    snprintf(spacing, sizeof(spacing), "%g", o.spacing);
    snprintf(rays, sizeof(rays), "%d", o.rays);
    snprintf(threads, sizeof(threads), "%d", o.threads);
    char scene_arg[PATH_MAX], o_flag[] = "-o", q_flag[] = "-q", spacing_flag[] = "--spacing",
                              rays_flag[] = "--rays", threads_flag[] = "--threads";
    snprintf(scene_arg, sizeof(scene_arg), "%s", o.scene);
    char *const bake_argv[] = {
        gi_bake,      scene_arg, o_flag,    out,  q_flag,
        spacing_flag, spacing,   rays_flag, rays, o.threads ? threads_flag : NULL,
        threads,      NULL};
    double process = -1.0;
    for (int rep = 0; rep < o.repeat; rep++) {
        const double t = time_process(bake_argv);
        if (t < 0.0) {
            cli_error("%s failed on %s", gi_bake, o.scene);
            goto done;
        }
        process = rep == 0 || t < process ? t : process;
    }

    vdbgi_probes_get_info(probes, &pi); /* now baked: invalid count known */
    const double nrays = (double)(st.primary_ray_count + st.shadow_ray_count);
    char buf[32];
    printf("### %s: %zu triangles, %g m spacing, %d rays per probe, %d threads\n\n", si.name,
           si.triangle_count, o.spacing, o.rays, st.threads);
    printf("%zu probes (%zu invalid); %.2fM primary + %.2fM shadow rays = %.2fM rays\n\n",
           pi.probe_count, pi.invalid_count, (double)st.primary_ray_count * 1e-6,
           (double)st.shadow_ray_count * 1e-6, nrays * 1e-6);
    printf("| run | seconds | Mrays/s | probes/s | vs best bare loop |\n");
    printf("|---|---:|---:|---:|---:|\n");
    for (int m = VDBGI_TRACE_SINGLE; m <= VDBGI_TRACE_STREAM; m++)
        printf("| bare loop, %s | %.3f | %.2f | %.0f | %.3f |\n", method_names[m], bare[m],
               nrays / bare[m] * 1e-6, (double)pi.probe_count / bare[m], bare[best] / bare[m]);
    for (int m = VDBGI_TRACE_SINGLE; m <= VDBGI_TRACE_STREAM; m++)
        printf("| bake in-process, %s | %.3f | %.2f | %.0f | %.3f |\n", method_names[m], bake[m],
               nrays / bake[m] * 1e-6, (double)pi.probe_count / bake[m], bare[best] / bake[m]);
    printf("| bake in-process, auto, scalar (paired with the next two rows) | %.3f | %.2f | %.0f | "
           "%.3f "
           "|\n",
           scalar_auto, nrays / scalar_auto * 1e-6, (double)pi.probe_count / scalar_auto,
           bare[best] / scalar_auto);
    printf("| bake in-process, auto, ambient cube | %.3f | %.2f | %.0f | %.3f |\n", cube_auto,
           nrays / cube_auto * 1e-6, (double)pi.probe_count / cube_auto, bare[best] / cube_auto);
    printf("| bake in-process, auto, L2 (sh2) | %.3f | %.2f | %.0f | %.3f |\n", sh2_auto,
           nrays / sh2_auto * 1e-6, (double)pi.probe_count / sh2_auto, bare[best] / sh2_auto);
    printf("| **gi-bake process** (load, topology, trace, write) | %.3f | %.2f | %.0f | **%.3f** "
           "|\n\n",
           process, nrays / process * 1e-6, (double)pi.probe_count / process, bare[best] / process);
    struct stat fs;
    printf("Fastest bare loop: %s. Ambient cubes cost %.1f%%, L2 terms %.1f%% of the scalar "
           "bake. gi-bake wrote a %s .vdb.\n\n",
           method_names[best], 100.0 * (cube_auto / scalar_auto - 1.0),
           100.0 * (sh2_auto / scalar_auto - 1.0),
           stat(out, &fs) == 0 ? cli_bytes((double)fs.st_size, buf, sizeof(buf)) : "?");
    code = CLI_OK;
done:
    if (!o.out)
        unlink(out);
    vdbgi_probes_destroy(probes);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
    return code;
}
