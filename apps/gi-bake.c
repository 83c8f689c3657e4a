/* gi-bake: bake bounced irradiance into light probes near a scene's surfaces, as .vdb. */
#define _POSIX_C_SOURCE 200809L
#include "budget.h"
#include "cli.h"
#include "vdbgi.h"

#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static void usage(void)
{
    printf("Usage: gi-bake SCENE -o OUT.vdb [options]\n"
           "\n"
           "Bake the bounced irradiance of SCENE (any format assimp reads: .glb,\n"
           ".gltf, .obj, .fbx, ...) into light probes on a regular lattice, keeping only\n"
           "probes near surfaces, and write them to an OpenVDB file: a Vec3s grid\n"
           "\"irradiance\" (linear RGB) and a float grid \"validity\" (back-face fraction).\n"
           "\n"
           "Options:\n"
           "  -o, --output FILE        the .vdb to write (required; replaced only on success)\n"
           "      --spacing M          probe spacing in metres (0.5)\n"
           "      --margin M           keep probes within M metres of a surface (4 x spacing)\n"
           "      --budget MB          GPU memory the converted volume may take (decimal MB):\n"
           "                           8-ray previews from 4 m, halving while one takes under\n"
           "                           half of it, and the finest that fits; with the L2 terms\n"
           "                           unless --basis says otherwise; give vdb-to-gi the same\n"
           "                           --budget\n"
           "      --max-probes N       refuse lattices of more than N probes (50000000)\n"
           "      --walkable H         keep only the probes over walkable surfaces (facing up\n"
           "                           within 45 degrees) up to H metres: the space what\n"
           "                           moves uses, when statics take a lightmap\n"
           "      --keep-box X0,Y0,Z0,X1,Y1,Z1|scene\n"
           "                           keep the probes in this box too (repeatable; alone,\n"
           "                           only theirs); scene: the boxes of the scene's nodes\n"
           "                           named vdbgi_keep* (no geometry: a balcony, a shaft)\n"
           "      --tile I/N           bake tile I of N only (slabs across x of about as many\n"
           "                           probes each); gi-merge joins the N files into the\n"
           "                           whole bake, probe for probe\n"
           "      --rays N|auto        rays per probe (128: seed 000's set), or auto: 32, then\n"
           "                           more as their spread asks, as few as give the noise\n"
           "                           --noise says (auto)\n"
           "      --noise T            auto's target: the error, over the mean light, measured\n"
           "                           at 256 of the lattice's probes (0.05)\n"
           "      --max-rays N         auto's cap, a power of two (1024)\n"
           "      --ray-dist M         longest ray in metres (40)\n"
           "      --ambient A          seed model: ambient fill received at every hit (0.15)\n"
           "      --sun X,Y,Z|scene    direction towards the sun, or the scene's directional\n"
           "                           light (the scene's if it has one, else 0.4,0.8,0.3;\n"
           "                           physical: none where the scene's own lamps are used)\n"
           "      --sun-color R,G,B    sun colour, linear; 0,0,0 turns the sun off (1,1,1)\n"
           "      --falloff M          seed model: distance falloff 1/(1+(d/M)^2) in metres,\n"
           "                           or inf (4)\n"
           "      --sky R,G,B          what a ray that hits nothing adds, linear (0,0,0)\n"
           "      --sky-map FILE       an equirectangular .hdr or .exr sky in place of --sky\n"
           "      --sky-intensity X    the sky map's scale (1)\n"
           "      --sky-rotation DEG   the sky map's turn about +y (0)\n"
           "      --lights on|off      the scene's point, spot and directional lights (on)\n"
           "      --model M            seed: seed 000's ambient fill and falloff; physical:\n"
           "                           neither, only lights, emission, sky and bounces, as a\n"
           "                           path tracer counts light (physical)\n"
           "      --bounces N|auto     reflections, 1..16: every source's light reaches a probe\n"
           "                           over at most N (physical: lamps, sky and emitters\n"
           "                           alike; seed: its sky and emitters one fewer); auto:\n"
           "                           until the next adds under --converge of the light,\n"
           "                           three traced and the rest carried by the third\n"
           "                           (physical model: auto; seed: 1, its fill stands in)\n"
           "      --converge S         auto's share of the light, in (0, 1) (0.002)\n"
           "      --sampling S         fibonacci (one set, as seed 000) or random (a random\n"
           "                           rotation of that set per probe) (fibonacci)\n"
           "      --seed N             seed of random sampling (0)\n"
           "      --threads N          worker threads; results do not depend on it (all cores)\n"
           "      --invalid-threshold F  back-face fraction above which a probe is invalid "
           "(0.25)\n"
           "      --trace METHOD       auto, single, packet8, packet16 or stream (auto)\n"
           "      --basis B            scalar: one colour per probe (seed 000); ambient-cube:\n"
           "                           also six directional colours, for Bevy's irradiance\n"
           "                           volumes; sh2: also eight L2 spherical-harmonic terms,\n"
           "                           so a surface reads the light on its own side (scalar)\n"
           "  -q, --quiet              errors only, no progress\n"
           "  -v, --verbose            more detail on stderr\n"
           "  -h, --help               print this help and exit\n"
           "      --version            print the version and exit\n"
           "\n"
           "Examples:\n"
           "  gi-bake data/world.glb -o world.vdb\n"
           "  gi-bake data/room.obj -o room.vdb --spacing 0.25 --model seed --sun-color 0,0,0\n"
           "  gi-bake data/world.glb -o world.vdb --sampling random --rays 256\n"
           "  gi-bake data/world.glb -o world.vdb --basis ambient-cube\n"
           "  gi-bake data/world.glb -o world.vdb --basis sh2\n"
           "  gi-bake interior.glb -o interior.vdb --bounces 3\n"
           "  gi-bake data/world.glb -o world-seed.vdb --model seed\n"
           "  gi-bake data/world.glb -o tile2.vdb --tile 2/4\n");
}

enum {
    OPT_SPACING = 256,
    OPT_MARGIN,
    OPT_MAX_PROBES,
    OPT_WALKABLE,
    OPT_KEEP_BOX,
    OPT_RAYS,
    OPT_TRACE,
    OPT_BASIS,
    OPT_BOUNCES,
    OPT_CONVERGE,
    OPT_TILE,
    OPT_BUDGET
};

typedef struct options {
    const char *scene;
    const char *output;
    vdbgi_place_desc place;
    double keep_boxes[VDBGI_MAX_KEEP_BOXES][6];
    vdbgi_bake_desc bake;
    bool bounces_auto; /* --bounces auto: only the physical model bounces until converged */
    bool spacing_given, basis_given;
    bool keep_scene;    /* --keep-box scene: the scene's vdbgi_keep nodes join keep_boxes */
    double budget;      /* --budget, bytes; 0: none */
    double budget_est;  /* the chosen spacing's estimated VRAM */
    double budget_next; /* the next finer spacing's, where placed (0: not) */
} options;

static const char *trace_names[] = {"auto", "single", "packet8", "packet16", "stream"};

/* Parse argv into o (one case an option, kept whole); returns -1 to go on, else the exit code. */
static int parse_args(int argc, char **argv, options *o)
{
    static const struct option longs[] = {{"output", required_argument, NULL, 'o'},
                                          {"spacing", required_argument, NULL, OPT_SPACING},
                                          {"budget", required_argument, NULL, OPT_BUDGET},
                                          {"margin", required_argument, NULL, OPT_MARGIN},
                                          {"max-probes", required_argument, NULL, OPT_MAX_PROBES},
                                          {"walkable", required_argument, NULL, OPT_WALKABLE},
                                          {"keep-box", required_argument, NULL, OPT_KEEP_BOX},
                                          {"rays", required_argument, NULL, OPT_RAYS},
                                          CLI_LIGHT_LONG_OPTIONS,
                                          {"trace", required_argument, NULL, OPT_TRACE},
                                          {"basis", required_argument, NULL, OPT_BASIS},
                                          {"bounces", required_argument, NULL, OPT_BOUNCES},
                                          {"converge", required_argument, NULL, OPT_CONVERGE},
                                          {"tile", required_argument, NULL, OPT_TILE},
                                          CLI_COMMON_LONG_OPTIONS};
    cli_light_defaults(&o->bake);
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, ":o:qvh", longs, NULL)) != -1) {
        double d = 0.0;
        long long i = 0;
        const int light = cli_light_option(c, optarg, &o->bake);
        if (light == -2)
            continue;
        if (light >= 0)
            return light;
        switch (c) {
        case 'o': o->output = optarg; break;
        case OPT_SPACING:
            if (!cli_parse_double(optarg, &d) || !(d > 0.0) || !isfinite(d))
                return cli_usage_error("--spacing must be a number > 0 (got '%s')", optarg);
            o->place.spacing = d;
            o->spacing_given = true;
            break;
        case OPT_BUDGET:
            if (!budget_parse(optarg, &o->budget))
                return CLI_USAGE;
            break;
        case OPT_MARGIN:
            if (!cli_parse_double(optarg, &d) || !(d >= 0.0) || !isfinite(d))
                return cli_usage_error("--margin must be a number >= 0 (got '%s')", optarg);
            o->place.margin = d;
            o->place.margin_is_set = 1;
            break;
        case OPT_WALKABLE:
            if (!cli_parse_double(optarg, &d) || !(d > 0.0 && d <= 1000.0))
                return cli_usage_error(
                    "--walkable must be a height in metres, > 0 and <= 1000 (got '%s')", optarg);
            o->place.walkable_height = d;
            break;
        case OPT_KEEP_BOX: {
            if (strcmp(optarg, "scene") == 0) {
                o->keep_scene = true;
                break;
            }
            double *const box = o->keep_boxes[o->place.keep_box_count];
            if (o->place.keep_box_count == VDBGI_MAX_KEEP_BOXES)
                return cli_usage_error("at most %d --keep-box options", VDBGI_MAX_KEEP_BOXES);
            if (!cli_parse_doubles(optarg, box, 6) || !(box[0] <= box[3]) || !(box[1] <= box[4]) ||
                !(box[2] <= box[5]))
                return cli_usage_error(
                    "--keep-box must be X0,Y0,Z0,X1,Y1,Z1 with each min <= its max (got '%s')",
                    optarg);
            o->place.keep_boxes = (const double(*)[6])o->keep_boxes;
            o->place.keep_box_count++;
            break;
        }
        case OPT_MAX_PROBES:
            if (!cli_parse_int(optarg, &i) || i < 1)
                return cli_usage_error("--max-probes must be an integer >= 1 (got '%s')", optarg);
            o->place.max_probes = (uint64_t)i;
            break;
        case OPT_RAYS: {
            const int rays = cli_rays_option(optarg, 1000000, &o->bake);
            if (rays != -2)
                return rays;
            break;
        }
        case OPT_TRACE: {
            int m = -1;
            for (int k = 0; k < 5; k++)
                if (strcmp(optarg, trace_names[k]) == 0)
                    m = k;
            if (m < 0)
                return cli_usage_error(
                    "--trace must be auto, single, packet8, packet16 or stream (got '%s')", optarg);
            o->bake.trace_method = (vdbgi_trace_method)m;
            break;
        }
        case OPT_BASIS:
            if (strcmp(optarg, "scalar") == 0)
                o->bake.basis = VDBGI_BASIS_SCALAR;
            else if (strcmp(optarg, "ambient-cube") == 0)
                o->bake.basis = VDBGI_BASIS_AMBIENT_CUBE;
            else if (strcmp(optarg, "sh2") == 0)
                o->bake.basis = VDBGI_BASIS_SH2;
            else
                return cli_usage_error("--basis must be scalar, ambient-cube or sh2 (got '%s')",
                                       optarg);
            o->basis_given = true;
            break;
        case OPT_TILE: {
            long long t = 0, n = 0;
            char *slash = strchr(optarg, '/');
            if (slash)
                *slash = '\0';
            const bool ok = slash && cli_parse_int(optarg, &t) && cli_parse_int(slash + 1, &n) &&
                            n >= 2 && n <= VDBGI_MAX_TILES && t >= 1 && t <= n;
            if (slash)
                *slash = '/';
            if (!ok)
                return cli_usage_error("--tile must be I/N with 1 <= I <= N, N in 2..%d (got '%s')",
                                       VDBGI_MAX_TILES, optarg);
            o->place.tile_index = (int)t - 1;
            o->place.tile_count = (int)n;
            break;
        }
        case OPT_BOUNCES:
            if (strcmp(optarg, "auto") == 0) {
                o->bake.bounces = 0;
                o->bounces_auto = true;
            } else if (!cli_parse_int(optarg, &i) || i < 1 || i > 16) {
                return cli_usage_error("--bounces must be auto or an integer in 1..16 (got '%s')",
                                       optarg);
            } else {
                o->bake.bounces = (int)i;
                o->bounces_auto = false;
            }
            break;
        case OPT_CONVERGE:
            if (!cli_parse_double(optarg, &d) || !(d > 0.0 && d < 1.0))
                return cli_usage_error("--converge must be a share in (0, 1) (got '%s')", optarg);
            o->bake.converge = (float)d;
            break;
        default: {
            const int done = cli_common_option(c, argv, usage);
            if (done != -2)
                return done;
        }
        }
    }
    const int light = cli_light_check(&o->bake);
    if (light >= 0)
        return light;
    const bool physical = o->bake.model == VDBGI_MODEL_PHYSICAL;
    if (o->bounces_auto && !physical)
        return cli_usage_error("--bounces auto is for --model physical: the seed model's fill "
                               "stands in for further bounces (give --bounces N)");
    if (o->bake.converge != 0.0f && !(physical && o->bake.bounces == 0))
        return cli_usage_error("--converge is for --bounces auto, under --model physical");
    const int taken = cli_one_input(argc, argv, "scene", &o->scene);
    if (taken >= 0)
        return taken;
    if (!o->output)
        return cli_usage_error("no output given: use -o OUT.vdb");
    if (o->budget > 0.0) {
        if (o->spacing_given)
            return cli_usage_error("--budget chooses the spacing: give --budget or --spacing");
        if (o->place.tile_count)
            return cli_usage_error("--budget judges the whole lattice: run it once without "
                                   "--tile, then give every tile the --spacing it chose");
        if (o->bake.basis == VDBGI_BASIS_AMBIENT_CUBE)
            return cli_usage_error("--budget sizes a .gi volume (scalar or sh2); Bevy's volume "
                                   "has a size of its own (vdb-to-gi --res, --voxel)");
        if (!o->basis_given)
            o->bake.basis = VDBGI_BASIS_SH2; /* the terms cost less error than any spacing */
    }
    return -1;
}

/* --keep-box scene: the scene's vdbgi_keep boxes after those given; false when it has none. */
static bool keep_scene_boxes(const vdbgi_scene *scene, options *o)
{
    const double(*boxes)[6];
    const size_t n = vdbgi_scene_keep_boxes(scene, &boxes);
    vdbgi_scene_info si;
    vdbgi_scene_get_info(scene, &si);
    if (si.keep_node_count > VDBGI_MAX_KEEP_BOXES) {
        cli_error("%s: %zu nodes named vdbgi_keep*, at most %d", o->scene, si.keep_node_count,
                  VDBGI_MAX_KEEP_BOXES);
        return false;
    }
    if (n == 0) {
        cli_error(si.keep_node_count ? "%s: --keep-box scene, and its nodes named vdbgi_keep* "
                                       "have no vertex (an empty has no extent: give it a mesh)"
                                     : "%s: --keep-box scene, and no node of the scene is named "
                                       "vdbgi_keep*",
                  o->scene);
        return false;
    }
    if (n < si.keep_node_count)
        cli_log(NULL, VDBGI_LOG_WARNING, "a node named vdbgi_keep* has no vertex: no box from it");
    if (o->place.keep_box_count + n > VDBGI_MAX_KEEP_BOXES) {
        cli_error("%s: %zu boxes of the scene's and %zu given, at most %d", o->scene, n,
                  o->place.keep_box_count, VDBGI_MAX_KEEP_BOXES);
        return false;
    }
    memcpy(o->keep_boxes[o->place.keep_box_count], boxes, n * sizeof(boxes[0]));
    o->place.keep_boxes = (const double(*)[6])o->keep_boxes;
    o->place.keep_box_count += n;
    return true;
}

/*
 * Rays a probe in --budget's previews, and the least their volumes came out
 * above the 128-ray bake's: 7-11 % on the bundled world at 0.5 and 1 m, 7 %
 * on the 200 m world at 1 m, whole or walkable, 90 % on the interior (its
 * noise keeps fewer bricks coarse, and fewer probes invalid). A preview is
 * judged less that much; where the bake still comes out over, vdb-to-gi
 * --budget coarsens it to fit. The bake chosen is auto since (5 % noise),
 * whose volumes come out at or under the 128-ray bake's (the room's L2 at
 * 0.25 m: 0.30 MB against 0.47), so the margin errs on the safe side. A
 * preview's L2 terms are sized as .gi version 7 (24 bytes a texel): an
 * 8-ray bake's noise could tip the converter's choice of version 8 either
 * way, and the real conversion choosing 8 only leaves room.
 */
#define BUDGET_PREVIEW_RAYS 8
#define BUDGET_PREVIEW_OVER 1.07

/* The VRAM of the default conversion of an 8-ray bake at spacing: a measured estimate. */
static vdbgi_result preview_vram(vdbgi_context *ctx, const vdbgi_scene *scene, const options *o,
                                 double spacing, double *vram)
{
    vdbgi_place_desc pd = o->place;
    pd.spacing = spacing;
    vdbgi_bake_desc bd = o->bake;
    bd.rays = BUDGET_PREVIEW_RAYS;
    bd.adaptive = 0;
    bd.noise = 0.0f;
    bd.max_rays = 0;
    bd.progress = NULL;
    const bool terms = bd.basis == VDBGI_BASIS_SH2;
    const vdbgi_convert_desc cd = {.threads = bd.threads,
                                   .terms = terms ? VDBGI_TERMS_KEEP : VDBGI_TERMS_DROP,
                                   .gi_version = terms ? 7 : 0};
    vdbgi_probes *p = NULL;
    vdbgi_volume *v = NULL;
    vdbgi_result r = vdbgi_probes_place(ctx, scene, &pd, &p);
    if (r == VDBGI_OK)
        r = vdbgi_probes_bake(p, scene, &bd, NULL);
    if (r == VDBGI_OK)
        r = vdbgi_volume_build(ctx, p, &cd, &v);
    if (r == VDBGI_OK) {
        vdbgi_volume_info vi;
        vdbgi_volume_get_info(v, &vi);
        *vram = (double)budget_vram(&vi);
    }
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(p);
    return r;
}

/*
 * --budget: preview the volume at 4 m, then at each half of the spacing while
 * the last left room for the next (which holds about four times the probes),
 * and bake at the finest that fits.
 */
static vdbgi_result choose_spacing(vdbgi_context *ctx, const vdbgi_scene *scene, options *o,
                                   bool *said)
{
    cli_progress prog;
    cli_progress_begin(&prog, "sizing", "spacings", 7.0);
    vdbgi_result r = VDBGI_OK;
    double coarsest = 0.0; /* the coarsest spacing with a preview */
    int tried = 0;
    for (double spacing = 4.0; spacing >= 1.0 / 16.0; spacing /= 2.0) {
        double vram = 0.0;
        r = preview_vram(ctx, scene, o, spacing, &vram);
        cli_progress_update(&prog, (float)++tried / 7.0f);
        if (r != VDBGI_OK) {
            /* A coarse lattice may miss every keep box or floor: try finer. A fine one past
               the lattice's limits ends the search at the last that fitted. */
            if (o->budget_est > 0.0)
                break;
            continue;
        }
        coarsest = coarsest > 0.0 ? coarsest : spacing;
        vram /= BUDGET_PREVIEW_OVER;
        if (vram > o->budget) {
            o->budget_next = vram;
            break;
        }
        o->place.spacing = spacing;
        o->budget_est = vram;
        if (vram > o->budget / 2.0)
            break;
    }
    cli_progress_end(&prog);
    if (o->budget_est > 0.0)
        return VDBGI_OK;
    if (coarsest == 0.0)
        return r; /* no spacing gave a preview: the last refusal says why */
    char b[32];
    cli_error("%s: even at %g m its volume would take about %s (an %d-ray preview), past "
              "--budget %g MB",
              o->scene, coarsest, cli_bytes(o->budget_next, b, sizeof(b)), BUDGET_PREVIEW_RAYS,
              o->budget / 1e6);
    *said = true;
    return VDBGI_ERR_INVALID_ARG;
}

/*
 * What the bake's noise came to: the error its settings give 256 of the
 * lattice's probes (vdbgi_bake_stats.noise), and for auto the rays a probe took.
 */
static void print_noise(const vdbgi_bake_stats *st, const vdbgi_bake_desc *bake)
{
    printf("noise    %.2f %% of the light, measured at 256 of the lattice's probes (each baked "
           "twice%s)",
           100.0 * st->noise,
           bake->adaptive || bake->sampling == VDBGI_SAMPLING_RANDOM
               ? ""
               : ", the set under random rotations");
    if (bake->adaptive && st->probe_count)
        printf(": auto, %.0f rays a probe on average for a target of %g %%",
               (double)st->primary_ray_count / (double)st->probe_count,
               100.0 * (bake->noise != 0.0f ? bake->noise : VDBGI_NOISE));
    printf("\n");
}

int main(int argc, char **argv)
{
    cli_init("gi-bake");
    options o = {0};
    const int parsed = parse_args(argc, argv, &o);
    if (parsed >= 0)
        return parsed;
    /* The scene, and no file of another kind (its .mtl, a texture), is ever replaced. */
    const char *const inputs[2] = {o.scene, cli_light.sky_map};
    const cli_file out = {o.output, "VDB", "\x20\x42\x44\x56", 4};
    const int clash = cli_check_files(inputs, cli_light.sky_map ? 2 : 1, &out, 1);
    if (clash >= 0)
        return clash;

    vdbgi_context *const ctx = cli_context();
    if (!ctx)
        return CLI_FAILED;
    vdbgi_scene *scene = NULL;
    vdbgi_probes *probes = NULL;
    vdbgi_sky *sky = NULL;
    int code = CLI_FAILED;
    vdbgi_result r = vdbgi_output_check(ctx, o.output);
    const double t0 = cli_now();
    if (r == VDBGI_OK)
        r = vdbgi_scene_load(ctx, o.scene, &scene);
    if (r == VDBGI_OK && (code = cli_light_prepare(ctx, scene, &o.bake, &sky)) >= 0) {
        vdbgi_sky_destroy(sky);
        vdbgi_scene_destroy(scene);
        vdbgi_context_destroy(ctx);
        return code;
    }
    code = CLI_FAILED;
    const double t1 = cli_now();
    bool said = false; /* choose_spacing or keep_scene_boxes said why it failed */
    if (r == VDBGI_OK && o.keep_scene && !keep_scene_boxes(scene, &o))
        said = true, r = VDBGI_ERR_INVALID_ARG;
    if (r == VDBGI_OK && o.budget > 0.0)
        r = choose_spacing(ctx, scene, &o, &said);
    const double t1b = cli_now();
    if (r == VDBGI_OK)
        r = vdbgi_probes_place(ctx, scene, &o.place, &probes);
    const double t2 = cli_now();
    vdbgi_bake_stats st = {0};
    if (r == VDBGI_OK) {
        vdbgi_probes_info pi;
        vdbgi_probes_get_info(probes, &pi);
        cli_progress prog;
        cli_progress_begin(&prog, "baking", "probes", (double)pi.probe_count);
        o.bake.progress = cli_progress_update;
        o.bake.progress_user = &prog;
        r = vdbgi_probes_bake(probes, scene, &o.bake, &st);
        cli_progress_end(&prog);
    }
    const double t3 = cli_now();
    if (r == VDBGI_OK)
        r = vdbgi_probes_write(probes, o.output);
    const double t4 = cli_now();
    if (said) {
        code = CLI_FAILED;
    } else if (r != VDBGI_OK) {
        code = cli_fail(ctx, r);
    } else if (cli_verbosity >= 2) { /* -q: errors only */
        vdbgi_scene_info si;
        vdbgi_probes_info pi;
        vdbgi_scene_get_info(scene, &si);
        vdbgi_probes_get_info(probes, &pi);
        struct stat fs;
        char size[32];
        const double rays = (double)(st.primary_ray_count + st.shadow_ray_count);
        printf("scene    %s: %zu triangles (%zu skipped), %zu textures", si.name, si.triangle_count,
               si.skipped_triangle_count, si.texture_count);
        if (si.light_count)
            printf(", %zu lights%s", si.light_count,
                   o.bake.lights == VDBGI_LIGHTS_OFF ? " (off)" : "");
        if (si.keep_box_count)
            printf(", %zu vdbgi_keep box%s%s", si.keep_box_count,
                   si.keep_box_count == 1 ? "" : "es",
                   o.keep_scene ? "" : " (not used without --keep-box scene)");
        printf("\n");
        float sun_dir[3], sun_e[3];
        if (sky && vdbgi_sky_sun(sky, sun_dir, sun_e))
            printf(
                "sky      %s: its sun taken out as a lamp, E %.3g,%.3g,%.3g from %.2f,%.2f,%.2f\n",
                cli_light.sky_map, (double)sun_e[0], (double)sun_e[1], (double)sun_e[2],
                (double)sun_dir[0], (double)sun_dir[1], (double)sun_dir[2]);
        printf("probes   %zu (%zu invalid) at %g m spacing, %g m margin", pi.probe_count,
               pi.invalid_count, pi.spacing, pi.margin);
        if (pi.tile_count)
            printf(", tile %d of %d (i %d..%d)", pi.tile_index + 1, pi.tile_count, pi.tile_x[0],
                   pi.tile_x[1] - 1);
        printf("\n");
        if (o.budget > 0.0) {
            char est[32], e[320];
            const bool terms = o.bake.basis == VDBGI_BASIS_SH2;
            budget_expected(pi.spacing, terms, 0.1, e, sizeof(e));
            printf("budget   %g MB of GPU memory: %g m %s, an estimated %s converted (an %d-ray "
                   "preview's, less %.0f %%)",
                   o.budget / 1e6, pi.spacing, terms ? "with the L2 terms" : "scalar",
                   cli_bytes(o.budget_est, est, sizeof(est)), BUDGET_PREVIEW_RAYS,
                   100.0 * (1.0 - 1.0 / BUDGET_PREVIEW_OVER));
            if (o.budget_next > 0.0)
                printf(" (%g m: %s)", pi.spacing / 2.0, cli_bytes(o.budget_next, est, sizeof(est)));
            printf("; vdb-to-gi --budget %g makes it fit; %s\n", o.budget / 1e6, e);
        }
        if (o.bake.model == VDBGI_MODEL_PHYSICAL && o.bake.bounces == 0)
            printf("bounces  %d until the next adds under %g %% of the light (the last added %.2f "
                   "%%): %d traced, the last carrying the rest (%.1f %% of the light)\n",
                   st.bounces, 100.0 * (o.bake.converge != 0.0f ? o.bake.converge : VDBGI_CONVERGE),
                   100.0 * st.last_share, st.bounces_traced, 100.0 * st.tail_share);
        printf("rays     %llu primary + %llu %s, %.1f Mrays/s on %d threads\n",
               (unsigned long long)st.primary_ray_count, (unsigned long long)st.shadow_ray_count,
               st.bounces_traced > 1 ? "shadow and bounce" : "shadow",
               st.seconds > 0.0 ? rays / st.seconds * 1e-6 : 0.0, st.threads);
        print_noise(&st, &o.bake);
        printf("time     %.2f s: load %.2f, ", t4 - t0, t1 - t0);
        if (o.budget > 0.0)
            printf("size %.2f, ", t1b - t1);
        printf("place %.2f, bake %.2f, write %.2f\n", t2 - t1b, t3 - t2, t4 - t3);
        printf("output   %s (%s)\n", o.output,
               stat(o.output, &fs) == 0 ? cli_bytes((double)fs.st_size, size, sizeof(size)) : "?");
    }
    if (r == VDBGI_OK)
        code = CLI_OK;
    vdbgi_probes_destroy(probes);
    vdbgi_sky_destroy(sky);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
    return code;
}
