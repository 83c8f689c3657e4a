/* gi-bench: measure vdbgi: the bake against a bare Embree loop over the same rays, the
   conversion, speed against accuracy, memory, lightmaps, the truth, lights (one file each). */
#define _DEFAULT_SOURCE /* posix_spawn, wait4 */
#include "bench.h"
#include "bench_lights.h"
#include "cli.h"
#include "vdbgi.h"
#include "vdbgi_bench.h"

#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <math.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <zlib.h>

extern char **environ;

static void usage(void)
{
    printf("Usage: gi-bench bake SCENE [options]\n"
           "       gi-bench convert PROBES.vdb [options]\n"
           "       gi-bench sweep SCENE [options]\n"
           "       gi-bench rays SCENE [options]\n"
           "       gi-bench texel-rays SCENE [options]\n"
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
           "sweep: speed against accuracy on SCENE, as CSV files in --out: rays.csv (as\n"
           "rays below, at 1 m), size.csv (bytes against error over eps, max level,\n"
           "criterion and encoding), spacing.csv (0.25..2 m: probes, time, bytes, and\n"
           "the error and bias at the surface receivers against the hemisphere truth (as\n"
           "truth below), under the default darkest fill, the mean fill and the compact\n"
           "layout).\n"
           "\n"
           "rays: error against time for each way of spending a probe's rays, on SCENE's\n"
           "probes at --spacing (1 m): the fixed Fibonacci set (seed 000's bake at 128)\n"
           "and a random rotation of it a probe at 16..1024 rays, and --rays auto at noise\n"
           "targets 0.14..0.018, each against a 16384-ray random bake of the same probes,\n"
           "under --model and --bounces; a Markdown table, and --out/rays.csv, with the\n"
           "fixed count that gives each row's RMSE.\n"
           "\n"
           "texel-rays: the same for a lightmap's texels, one pass at --spacing texels\n"
           "(0.5 m): the fixed hemisphere set, a random turn of it a texel, and --rays auto\n"
           "at targets 0.14..0.018, each map against a 16384-ray random map over the\n"
           "texels valid in both; --out/texel_rays.csv.\n"
           "\n"
           "memory: memory against the error a player sees on SCENE, as --out/memory.csv:\n"
           "at 0.25, 0.5 and 1 m (--spacing S limits it to one), a dense grid of every\n"
           "probe (scalar RGBM, and with L2 terms), seed 000's brick layout and the compact\n"
           "one (scalar, and with L2 terms) at eps 0.05..0.4: VRAM, gzip'd bytes, RMSE at\n"
           "the probes, and RMSE and bias against the hemisphere truth (as truth below) at\n"
           "the surface receivers and the character layer, each read as the runtime reads\n"
           "it; probes within 2.5 m of a surface at every spacing, and (compact-walkable)\n"
           "only those up to 2.5 m over walkable surfaces (gi-bake --walkable 2.5).\n"
           "\n"
           "lightmap: gi-lightmap on SCENE. Throughput at its defaults (0.25 m texels, 64\n"
           "rays, 2 passes): a bare Embree loop over the same rays (nothing shaded nor\n"
           "dilated) against the bake, per pass, fastest of --repeat, and the whole\n"
           "gi-lightmap process. Packing: the charts' boxes of this unwrap and of seed\n"
           "004's coplanar islands, into --out/lightmap_boxes.json (tests/js/potpack.mjs\n"
           "packs them as seed 004 does). Error against memory, --out/lightmap.csv: texels\n"
           "of 1, 0.5, 0.25 and 0.125 m, each in the atlases gi-lightmap takes by default,\n"
           "a pass a bounce, against 2048-ray estimates at 3000 points on the surfaces\n"
           "(only when --out is given; a texel past the lightmap's limits is skipped).\n"
           "\n"
           "truth: what each method gives a surface, against the hemisphere estimator\n"
           "(2048 random rays over the receiver's own normal) at 3000 points on the\n"
           "surfaces and at 400 character points 0.5-2 m over walkable ground read facing\n"
           "up, the four horizontal directions and down: the scalar and L2 bricks (the\n"
           "runtime; L2 also at other term bits, from a random rotation of the directions\n"
           "a probe and from half the rays), the scalar, ambient cube and L2 probes read\n"
           "directly, and a one-pass lightmap at 0.25 m texels; at 0.5 and 0.25 m\n"
           "(--spacing S: that one only).\n"
           "Prints a Markdown table and writes --out/truth.csv.\n"
           "For rays, memory, lightmap and truth, --model physical and --bounces N hold every\n"
           "method and the truth to that light (a lightmap takes a pass a bounce); the\n"
           "seed model, one bounce, by default.\n"
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

static int parse_args(int argc, char **argv, bench_options *o)
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
         strcmp(argv[optind], "sweep") != 0 && strcmp(argv[optind], "rays") != 0 &&
         strcmp(argv[optind], "texel-rays") != 0 && strcmp(argv[optind], "memory") != 0 &&
         strcmp(argv[optind], "lightmap") != 0 && strcmp(argv[optind], "truth") != 0 &&
         strcmp(argv[optind], "lights") != 0))
        return cli_usage_error("say which benchmark: gi-bench bake SCENE, convert PROBES.vdb, "
                               "sweep SCENE, rays SCENE, texel-rays SCENE, memory SCENE, lightmap "
                               "SCENE, truth SCENE or "
                               "lights SCENE");
    if (argc - optind != 2)
        return cli_usage_error("give one input: gi-bench %s FILE", argv[optind]);
    o->mode = argv[optind];
    o->scene = argv[optind + 1];
    return -1;
}

/* Wall seconds of running argv to completion, or -1 if it failed. */
double bench_time_process(char *const argv[], double *peak_mb)
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
    struct rusage ru;
    if (wait4(pid, &status, 0, &ru) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return -1.0;
    if (peak_mb)
        *peak_mb = (double)ru.ru_maxrss / 1024.0; /* Linux counts it in KiB */
    return cli_now() - t0;
}

/*
 * A built volume's figures with its file's size: its file made (gzip happens
 * on write). A file that cannot be made (out of memory) shows as 0 bytes.
 */
void bench_info(const vdbgi_volume *v, vdbgi_volume_info *vi)
{
    size_t size;
    (void)vdbgi_volume_write_memory(v, NULL, 0, &size);
    vdbgi_volume_get_info(v, vi);
}

const char *bench_out_dir(const bench_options *o)
{
    const char *const dir = o->out ? o->out : "build/chart";
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        cli_error("%s: cannot make directory: %s", dir, strerror(errno));
        return NULL;
    }
    return dir;
}

int bench_open_scene(const bench_options *o, const char **dir, vdbgi_context **ctx,
                     vdbgi_scene **scene)
{
    *ctx = NULL;
    *scene = NULL;
    if (!(*dir = bench_out_dir(o)) || !(*ctx = cli_context()))
        return CLI_FAILED;
    const vdbgi_result r = vdbgi_scene_load(*ctx, o->scene, scene);
    if (r == VDBGI_OK)
        return CLI_OK;
    const int code = cli_fail(*ctx, r);
    vdbgi_context_destroy(*ctx);
    *ctx = NULL;
    return code;
}

FILE *bench_open_csv(const char *dir, const char *name, const char *header)
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
void bench_compare(const float *a, const float *b, size_t n, double *rmse_rel, double *p99_rel)
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

/* A tool beside gi-bench (argv0's directory). */
void bench_beside(const char *argv0, const char *tool, char *out, size_t cap)
{
    const char *const slash = strrchr(argv0, '/');
    snprintf(out, cap, "%.*s%s", slash ? (int)(slash - argv0 + 1) : 0, argv0, tool);
}

int main(int argc, char **argv)
{
    cli_init("gi-bench");
    bench_options o = {.spacing = 0.5, .rays = 128, .repeat = 3};
    const int parsed = parse_args(argc, argv, &o);
    if (parsed >= 0)
        return parsed;
    if (strcmp(o.mode, "convert") == 0)
        return bench_convert(&o);
    if (strcmp(o.mode, "sweep") == 0)
        return bench_sweep(&o);
    if (strcmp(o.mode, "rays") == 0)
        return bench_rays(&o);
    if (strcmp(o.mode, "texel-rays") == 0)
        return bench_texel_rays(&o);
    if (strcmp(o.mode, "memory") == 0)
        return bench_memory(&o, o.spacing_given);
    if (strcmp(o.mode, "lightmap") == 0)
        return bench_lightmap(&o, argv[0]);
    if (strcmp(o.mode, "truth") == 0)
        return bench_truth(o.scene, o.spacing, o.spacing_given, o.rays, o.threads, &o.light, o.out);
    if (strcmp(o.mode, "lights") == 0)
        return bench_lights(o.scene, o.spacing_given ? o.spacing : 0.25, o.threads, o.repeat,
                            o.out);
    return bench_bake(&o, argv[0]);
}
