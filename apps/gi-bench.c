/* gi-bench: measure the bake against a bare Embree loop over the same rays. */
#define _DEFAULT_SOURCE /* mkstemps */
#include "cli.h"
#include "vdbgi.h"

#include <fcntl.h>
#include <getopt.h>
#include <limits.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

static void usage(void)
{
    printf("Usage: gi-bench bake SCENE [options]\n"
           "       gi-bench convert PROBES.vdb [options]\n"
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
           "convert: time reading the .vdb (fastest of --repeat), then convert it with each\n"
           "criterion (range, interp) at eps 0, 0.01, 0.03, 0.1, 0.2, 0.4 in RGBM, and the\n"
           "default in RGB9E5; print bytes against the dense RGBA8 grid, the error, and the\n"
           "conversion time against the read.\n"
           "\n"
           "Options:\n"
           "      --spacing M     probe spacing in metres (0.5)\n"
           "      --rays N        rays per probe (128)\n"
           "      --threads N     worker threads (all cores)\n"
           "      --repeat N      runs of each measurement, fastest kept (3)\n"
           "      --gi-bake PATH  the gi-bake to time (the one beside gi-bench)\n"
           "      --out FILE      where gi-bake writes its .vdb (a temporary file)\n"
           "  -h, --help          print this help and exit\n"
           "      --version       print the version and exit\n"
           "\n"
           "Examples:\n"
           "  gi-bench bake data/world.glb\n"
           "  gi-bench bake world200.glb --repeat 1\n"
           "  gi-bench convert world.vdb\n");
}

typedef struct options {
    const char *mode, *scene, *gi_bake, *out;
    double spacing;
    int rays, threads, repeat;
} options;

enum { OPT_SPACING = 256, OPT_RAYS, OPT_THREADS, OPT_REPEAT, OPT_GI_BAKE, OPT_OUT, OPT_VERSION };

static int parse_args(int argc, char **argv, options *o)
{
    static const struct option longs[] = {{"spacing", required_argument, NULL, OPT_SPACING},
                                          {"rays", required_argument, NULL, OPT_RAYS},
                                          {"threads", required_argument, NULL, OPT_THREADS},
                                          {"repeat", required_argument, NULL, OPT_REPEAT},
                                          {"gi-bake", required_argument, NULL, OPT_GI_BAKE},
                                          {"out", required_argument, NULL, OPT_OUT},
                                          {"help", no_argument, NULL, 'h'},
                                          {"version", no_argument, NULL, OPT_VERSION},
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
        case 'h': usage(); return CLI_OK;
        case OPT_VERSION: printf("gi-bench %s\n", vdbgi_version_string()); return CLI_OK;
        default: return cli_bad_option(c, argv);
        }
    }
    if (optind == argc ||
        (strcmp(argv[optind], "bake") != 0 && strcmp(argv[optind], "convert") != 0))
        return cli_usage_error("say which benchmark: gi-bench bake SCENE, or gi-bench convert PROBES.vdb");
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

/* One conversion of the sweep, as a table row. */
static int convert_row(vdbgi_context *ctx, const vdbgi_probes *p, const vdbgi_convert_desc *d,
                       const char *label, double read_seconds)
{
    vdbgi_volume *v = NULL;
    const vdbgi_result r = vdbgi_volume_build(ctx, p, d, &v);
    if (r != VDBGI_OK)
        return cli_fail(ctx, r);
    vdbgi_volume_info vi;
    vdbgi_volume_get_info(v, &vi);
    const double raw = (double)(vi.indirection_size + vi.atlas_size);
    const double mean = vi.mean_irradiance > 0.0 ? vi.mean_irradiance : 1.0;
    printf("| %s | %u / %u / %u / %u | %.2f | %.2f | %.2f | %.2f | %.3f | %.3f | %.2f | %.3f | "
           "%.2f |\n",
           label, vi.bricks[0], vi.bricks[1], vi.bricks[2], vi.bricks[3], raw * 1e-6,
           (double)vi.file_size * 1e-6, (double)vi.dense_rgba8_size / raw,
           (double)vi.dense_rgba8_size / (double)vi.file_size, 100.0 * vi.rmse / mean,
           100.0 * vi.p99 / mean, 100.0 * vi.max_error / mean, vi.seconds,
           vi.seconds / read_seconds);
    vdbgi_volume_destroy(v);
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
    printf("Dense RGBA8 grid over the probes' box: %s (%.0f%% of its lattice points are probes).\n\n",
           cli_bytes(4.0 * box, dense, sizeof(dense)), 100.0 * (double)pi.probe_count / box);
    printf("| criterion, eps, encoding | bricks L0 / L1 / L2 / L3 | raw MB | gzip MB | dense/raw "
           "| dense/gzip | RMSE %% | p99 %% | max %% | convert s | convert/read |\n");
    printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    static const float eps[] = {VDBGI_NONE, 0.01f, 0.03f, 0.1f, 0.2f, 0.4f};
    static const char *const eps_text[] = {"0", "0.01", "0.03", "0.1", "0.2", "0.4"};
    int code = CLI_OK;
    for (int c = VDBGI_CRITERION_RANGE; c <= VDBGI_CRITERION_INTERP && code == CLI_OK; c++)
        for (size_t e = 0; e < sizeof(eps) / sizeof(eps[0]) && code == CLI_OK; e++) {
            const vdbgi_convert_desc d = {.eps = eps[e], .criterion = (vdbgi_criterion)c};
            char label[64];
            snprintf(label, sizeof(label), "%s, %s, rgbm", c == VDBGI_CRITERION_RANGE ? "range" : "interp",
                     eps_text[e]);
            code = convert_row(ctx, p, &d, label, read_seconds);
        }
    const vdbgi_convert_desc defaults = {0}, e9 = {.encoding = VDBGI_ENCODING_RGB9E5};
    if (code == CLI_OK)
        code = convert_row(ctx, p, &defaults, "**default**, rgbm", read_seconds);
    if (code == CLI_OK)
        code = convert_row(ctx, p, &e9, "default, rgb9e5", read_seconds);
    printf("\n");
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
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

    /* gi-bake lives beside gi-bench unless told otherwise. */
    char gi_bake[PATH_MAX];
    if (o.gi_bake) {
        snprintf(gi_bake, sizeof(gi_bake), "%s", o.gi_bake);
    } else {
        const char *const slash = strrchr(argv[0], '/');
        snprintf(gi_bake, sizeof(gi_bake), "%.*sgi-bake",
                 slash ? (int)(slash - argv[0] + 1) : 0, argv[0]);
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
            const vdbgi_bake_desc bd = {.rays = o.rays, .threads = o.threads,
                                        .trace_method = (vdbgi_trace_method)m};
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
    /* The ambient-cube basis on the default query shape, against the scalar bake beside it. */
    double scalar_auto = 0.0, cube_auto = 0.0;
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
    char *const bake_argv[] = {gi_bake,      scene_arg, o_flag,     out,
                               q_flag,       spacing_flag, spacing, rays_flag,
                               rays,         o.threads ? threads_flag : NULL, threads, NULL};
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
    printf("| bake in-process, auto, scalar (paired with the next row) | %.3f | %.2f | %.0f | %.3f |\n",
           scalar_auto, nrays / scalar_auto * 1e-6, (double)pi.probe_count / scalar_auto,
           bare[best] / scalar_auto);
    printf("| bake in-process, auto, ambient cube | %.3f | %.2f | %.0f | %.3f |\n", cube_auto,
           nrays / cube_auto * 1e-6, (double)pi.probe_count / cube_auto, bare[best] / cube_auto);
    printf("| **gi-bake process** (load, topology, trace, write) | %.3f | %.2f | %.0f | **%.3f** "
           "|\n\n",
           process, nrays / process * 1e-6, (double)pi.probe_count / process,
           bare[best] / process);
    struct stat fs;
    printf("Fastest bare loop: %s. Ambient cubes cost %.1f%% of the scalar bake. gi-bake wrote "
           "a %s .vdb.\n\n",
           method_names[best], 100.0 * (cube_auto / scalar_auto - 1.0),
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
