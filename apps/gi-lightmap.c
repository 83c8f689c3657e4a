/* gi-lightmap: bake a scene's static surfaces into lightmaps (seed 004), as a .glb with its maps. */
#define _POSIX_C_SOURCE 200809L
#include "budget.h"
#include "cli.h"
#include "vdbgi.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(void)
{
    printf("Usage: gi-lightmap SCENE -o OUT.glb [options]\n"
           "\n"
           "Bake the light on SCENE's surfaces (any format assimp reads) into lightmaps:\n"
           "unwrap it into charts, give every texel a sample point on its triangle, and\n"
           "gather each point's hemisphere with the probes' light model, pass after pass,\n"
           "each pass lighting the hits with the map before it. Writes OUT.glb (the\n"
           "scene, its second UV set and each atlas as an 8-bit map on TEXCOORD_1) and,\n"
           "beside it, OUT.lightmapN.exr (the irradiance, half floats).\n"
           "\n"
           "Options:\n"
           "  -o, --output FILE        the .glb to write (required; replaced only on success)\n"
           "      --texel M            metres a texel edge (0.25)\n"
           "      --budget MB          GPU memory the map may take (decimal MB, RGBA8): the\n"
           "                           finest texel of 4, 3, 2, 1.5, 1, 0.75 .. 1/64 m whose\n"
           "                           atlases fit, found by unwrapping (no texel baked)\n"
           "      --size N             atlas edge in texels (the least that holds the charts,\n"
           "                           a multiple of 32, up to 1024); more atlases if needed\n"
           "      --passes N|auto      reflections, 1..16: every source's light reaches a\n"
           "                           texel over at most N, as gi-bake's --bounces; auto:\n"
           "                           until the next would add under 0.2 %% of the light, at\n"
           "                           most three swept and the third carrying the rest\n"
           "                           (physical model: auto; seed: 2, its fill stands in)\n"
           "      --converge S         auto's share of the light, in (0, 1) (0.002)\n"
           "      --direct             add the direct sun and lights (fully baked); default:\n"
           "                           bounced light only, the lights stay on at runtime\n"
           "      --mode M             lightmap or ao (ambient occlusion, the glTF\n"
           "                           occlusionTexture) (lightmap)\n"
           "      --ao-dist M          how far AO looks, metres (1)\n"
           "      --layers             also one map per light (sun, each scene light,\n"
           "                           ambient, sky, each emissive material), each alone:\n"
           "                           they add up to the map; in the .glb's extras and as\n"
           "                           OUT.NAME.lightmapN.exr\n"
           "      --slices DIR         pictures of each atlas: the map, and its charts\n"
           "                           (gutters black, texels inside geometry red)\n"
           "      --stats FILE         also write the figures -v prints as JSON\n"
           "      --rays N|auto        rays per texel, or auto: 32, then more as their spread\n"
           "                           asks, as few as give the noise --noise says (auto;\n"
           "                           --mode ao: 64)\n"
           "      --noise T            auto's target: a pass's error, over the mean light,\n"
           "                           measured at 256 points on the surfaces (0.05)\n"
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
           "                           neither: lights, emission, sky; bounces by --passes,\n"
           "                           as a path tracer counts light (physical)\n"
           "      --sampling S         fibonacci or random (fibonacci)\n"
           "      --seed N             seed of random sampling (0)\n"
           "      --threads N          worker threads; results do not depend on it (all cores)\n"
           "      --invalid-threshold F  back-face fraction above which a texel is invalid "
           "(0.25)\n"
           "  -q, --quiet              errors only\n"
           "  -v, --verbose            more detail on stderr\n"
           "  -h, --help               print this help and exit\n"
           "      --version            print the version and exit\n"
           "\n"
           "Examples:\n"
           "  gi-lightmap data/world.glb -o world-lit.glb\n"
           "  gi-lightmap data/room.obj -o room-ao.glb --mode ao --ao-dist 0.5\n"
           "  gi-lightmap data/world.glb -o world-baked.glb --direct --passes 3 --texel 0.1\n"
           "  gi-lightmap data/world.glb -o world-lit.glb --slices slices --stats stats.json\n"
           "  gi-lightmap data/world.glb -o world-layers.glb --layers\n"
           "  gi-lightmap data/world.glb -o world-seed.glb --model seed\n"
           "\n"
           "Emissive materials (glTF emissiveFactor, emissiveTexture,\n"
           "KHR_materials_emissive_strength; OBJ Ke) light the scene.\n");
}

enum {
    OPT_TEXEL = 256,
    OPT_SIZE,
    OPT_PASSES,
    OPT_CONVERGE,
    OPT_DIRECT,
    OPT_MODE,
    OPT_AO_DIST,
    OPT_RAYS,
    OPT_SLICES,
    OPT_LAYERS,
    OPT_STATS,
    OPT_BUDGET
};

/* A map texel's bytes on the GPU: the .glb's RGBA8 (docs/lightmap.md). */
#define MAP_TEXEL_BYTES 4.0

typedef struct options {
    const char *scene, *output, *slices, *stats;
    bool ao;
    bool passes_auto; /* --passes auto: only the physical model bakes until converged */
    bool texel_given, size_given, auto_given;
    double budget; /* --budget, bytes; 0: none */
    vdbgi_lightmap_desc lm;
} options;

/* Parse argv into o (one case an option, kept whole); returns -1 to go on, else the exit code. */
static int parse_args(int argc, char **argv, options *o)
{
    static const struct option longs[] = {{"output", required_argument, NULL, 'o'},
                                          {"texel", required_argument, NULL, OPT_TEXEL},
                                          {"size", required_argument, NULL, OPT_SIZE},
                                          {"passes", required_argument, NULL, OPT_PASSES},
                                          {"converge", required_argument, NULL, OPT_CONVERGE},
                                          {"direct", no_argument, NULL, OPT_DIRECT},
                                          {"mode", required_argument, NULL, OPT_MODE},
                                          {"ao-dist", required_argument, NULL, OPT_AO_DIST},
                                          {"rays", required_argument, NULL, OPT_RAYS},
                                          {"slices", required_argument, NULL, OPT_SLICES},
                                          {"layers", no_argument, NULL, OPT_LAYERS},
                                          {"stats", required_argument, NULL, OPT_STATS},
                                          {"budget", required_argument, NULL, OPT_BUDGET},
                                          CLI_LIGHT_LONG_OPTIONS,
                                          CLI_COMMON_LONG_OPTIONS};
    cli_light_defaults(&o->lm.bake);
    opterr = 0;
    int c;
    double ao_dist = 1.0;
    while ((c = getopt_long(argc, argv, ":o:qvh", longs, NULL)) != -1) {
        double d = 0.0;
        long long i = 0;
        const int light = cli_light_option(c, optarg, &o->lm.bake);
        if (light == -2)
            continue;
        if (light >= 0)
            return light;
        switch (c) {
        case 'o': o->output = optarg; break;
        case OPT_TEXEL:
            if (!cli_parse_double(optarg, &d) || !(d >= 1e-4 && d <= 1e4))
                return cli_usage_error("--texel must be a number of metres in 1e-4..1e4 (got '%s')",
                                       optarg);
            o->lm.texel = (float)d;
            o->texel_given = true;
            break;
        case OPT_BUDGET:
            if (!budget_parse(optarg, &o->budget))
                return CLI_USAGE;
            break;
        case OPT_SIZE:
            if (!cli_parse_int(optarg, &i) || i < 16 || i > 16384)
                return cli_usage_error("--size must be an integer in 16..16384 (got '%s')", optarg);
            o->lm.size = (int)i;
            o->size_given = true;
            break;
        case OPT_PASSES:
            if (strcmp(optarg, "auto") == 0) {
                o->lm.passes = 0;
                o->passes_auto = true;
            } else if (!cli_parse_int(optarg, &i) || i < 1 || i > VDBGI_LIGHTMAP_MAX_PASSES)
                return cli_usage_error("--passes must be auto or an integer in 1..%d (got '%s')",
                                       VDBGI_LIGHTMAP_MAX_PASSES, optarg);
            else
                o->lm.passes = (int)i;
            break;
        case OPT_CONVERGE:
            if (!cli_parse_double(optarg, &d) || !(d > 0.0 && d < 1.0))
                return cli_usage_error("--converge must be a share in (0, 1) (got '%s')", optarg);
            o->lm.converge = (float)d;
            break;
        case OPT_DIRECT: o->lm.direct = 1; break;
        case OPT_MODE:
            if (strcmp(optarg, "lightmap") != 0 && strcmp(optarg, "ao") != 0)
                return cli_usage_error("--mode must be lightmap or ao (got '%s')", optarg);
            o->ao = strcmp(optarg, "ao") == 0;
            break;
        case OPT_AO_DIST:
            if (!cli_parse_double(optarg, &ao_dist) || !(ao_dist > 0.0) || !isfinite(ao_dist))
                return cli_usage_error("--ao-dist must be a number > 0 (got '%s')", optarg);
            break;
        case OPT_RAYS: {
            const int rays = cli_rays_option(optarg, 65536, &o->lm.bake);
            if (rays != -2)
                return rays;
            o->auto_given = o->lm.bake.adaptive != 0;
            break;
        }
        case OPT_SLICES: o->slices = optarg; break;
        case OPT_LAYERS: o->lm.layers = 1; break;
        case OPT_STATS: o->stats = optarg; break;
        default: {
            const int done = cli_common_option(c, argv, usage);
            if (done != -2)
                return done;
        }
        }
    }
    if (o->ao && o->lm.layers)
        return cli_usage_error("--layers is for lightmaps, not --mode ao");
    if (o->ao && (o->auto_given || o->lm.bake.noise != 0.0f || o->lm.bake.max_rays != 0))
        return cli_usage_error("--mode ao takes a fixed --rays N, not auto%s",
                               o->auto_given              ? ""
                               : o->lm.bake.noise != 0.0f ? "'s --noise"
                                                          : "'s --max-rays");
    if (o->ao)
        o->lm.bake.adaptive = 0; /* occlusion has no auto (the library's 64 rays) */
    if (o->budget > 0.0 && (o->texel_given || o->size_given))
        return cli_usage_error("--budget chooses the texel and the atlas: give --budget, or "
                               "--texel and --size");
    if (o->budget > 0.0 && o->lm.layers)
        return cli_usage_error("--budget sizes one map: with --layers (a map a light), give "
                               "--texel");
    const int light = cli_light_check(&o->lm.bake);
    if (light >= 0)
        return light;
    if (o->passes_auto && o->lm.bake.model != VDBGI_MODEL_PHYSICAL)
        return cli_usage_error("--passes auto is for --model physical: the seed model's fill "
                               "stands in for further passes (give --passes N)");
    if (o->lm.converge != 0.0f && !(o->lm.bake.model == VDBGI_MODEL_PHYSICAL && o->lm.passes == 0))
        return cli_usage_error("--converge is for --passes auto, under --model physical");
    if (o->ao)
        o->lm.ao_dist = (float)ao_dist;
    else if (ao_dist != 1.0)
        return cli_usage_error("--ao-dist is for --mode ao");
    const int taken = cli_one_input(argc, argv, "scene", &o->scene);
    if (taken >= 0)
        return taken;
    if (!o->output)
        return cli_usage_error("no output given: use -o OUT.glb");
    const size_t len = strlen(o->output);
    if (len < 5 || strcmp(o->output + len - 4, ".glb") != 0)
        return cli_usage_error("the output must end in .glb (got '%s')", o->output);
    return -1;
}

/* What a run gave: a few lines for people (-v), or JSON (--stats). */
typedef struct run_figures {
    const options *o;
    vdbgi_scene_info si;
    vdbgi_lightmap_stats st;
    double load, bake, write, glb_bytes;
} run_figures;

static void print_figures(FILE *f, const run_figures *g, bool json)
{
    const vdbgi_lightmap_stats *const st = &g->st;
    const int size = st->atlas_size;
    const double mrays = g->bake > 0.0 ? (double)st->rays / g->bake * 1e-6 : 0.0;
    const double texel = g->o->lm.texel > 0.0f ? (double)g->o->lm.texel : 0.25;
    if (json) {
        fputs("{\n  \"scene\": ", f);
        cli_json_string(f, g->o->scene);
        fputs(",\n  \"output\": ", f);
        cli_json_string(f, g->o->output);
        fprintf(f,
                ",\n  \"mode\": \"%s\",\n  \"triangles\": %zu,\n  \"kept_uv1\": %s,\n"
                "  \"charts\": %zu,\n  \"atlases\": %zu,\n  \"atlas_size\": %d,\n"
                "  \"texels\": %zu,\n  \"utilisation\": %.4f,\n  \"samples\": %zu,\n"
                "  \"invalid\": %zu,\n  \"layers\": %zu,\n  \"passes\": %d,\n"
                "  \"last_pass_share\": %.5f,\n  \"bounces\": %d,\n  \"tail_share\": %.5f,\n"
                "  \"pass_seconds\": [",
                g->o->ao ? "ao" : "lightmap", g->si.triangle_count, st->kept_uv1 ? "true" : "false",
                st->charts, st->atlases, size, st->texels, st->utilisation, st->samples,
                st->invalid, st->layers, st->passes, st->last_share,
                st->bounces ? st->bounces : st->passes, st->tail_share);
        for (int p = 0; p < st->passes && p < 16; p++)
            fprintf(f, "%s%.4f", p ? ", " : "", st->pass_seconds[p]);
        fprintf(f,
                "],\n  \"rays\": %llu,\n  \"mrays_per_second\": %.3f,\n"
                "  \"load_seconds\": %.4f,\n  \"bake_seconds\": %.4f,\n"
                "  \"write_seconds\": %.4f,\n  \"glb_bytes\": %.0f,\n  \"texel\": %g,\n"
                "  \"vram_bytes\": %.0f,\n  \"gather_rays\": %.1f,\n  \"noise\": %.5f",
                st->rays, mrays, g->load, g->bake, g->write, g->glb_bytes, texel,
                (double)st->texels * MAP_TEXEL_BYTES * (double)(1 + st->layers), st->gather_rays,
                st->noise);
        if (g->o->budget > 0.0)
            fprintf(f, ",\n  \"budget_bytes\": %.0f", g->o->budget);
        fputs("\n}\n", f);
        return;
    }
    char bytes[32];
    fprintf(f, "scene    %s: %zu triangles\n", g->si.name, g->si.triangle_count);
    if (st->kept_uv1)
        fprintf(f, "charts   the scene's own second UV set, one atlas of %d texels\n", size);
    else
        fprintf(f, "charts   %zu in %zu atlas%s of %d texels, %.1f %% used\n", st->charts,
                st->atlases, st->atlases == 1 ? "" : "es", size, 100.0 * st->utilisation);
    fprintf(f, "texels   %zu samples (%zu invalid, filled from neighbours)\n", st->samples,
            st->invalid);
    if (g->o->budget > 0.0) {
        char e[320], v[32];
        budget_lightmap_expected(st->kept_uv1 ? 0.0 : texel, e, sizeof(e));
        fprintf(f, "budget   %g MB of GPU memory: ", g->o->budget / 1e6);
        if (st->kept_uv1)
            fprintf(f, "an atlas of %d", size);
        else
            fprintf(f, "texels of %g m", texel);
        fprintf(f, ", %s of RGBA8; %s\n",
                cli_bytes((double)st->texels * MAP_TEXEL_BYTES, v, sizeof(v)), e);
    }
    if (st->layers)
        fprintf(f, "layers   %zu, one light each, adding up to the map\n", st->layers);
    fprintf(f, "passes   %d:", st->passes);
    for (int p = 0; p < st->passes && p < 16; p++)
        fprintf(f, " %.2f s", st->pass_seconds[p]);
    fprintf(f, ", %.1f Mrays/s", mrays);
    if (!g->o->ao && st->bounces)
        fprintf(f,
                "; the light needs %d (the last adds %.2f %%), the last swept carrying the rest "
                "(%.1f %% of the light)",
                st->bounces, 100.0 * st->last_share, 100.0 * st->tail_share);
    else if (!g->o->ao)
        fprintf(f, "; the last added %.2f %% of the light", 100.0 * st->last_share);
    fputc('\n', f);
    if (!g->o->ao) {
        const vdbgi_bake_desc *const b = &g->o->lm.bake;
        fprintf(f,
                "noise    %.2f %% of the light in a pass, measured at 256 points on the surfaces "
                "(each gathered twice%s): ",
                100.0 * st->noise,
                b->adaptive || b->sampling == VDBGI_SAMPLING_RANDOM
                    ? ""
                    : ", the set under random turns");
        if (b->adaptive)
            fprintf(f, "auto, %.0f rays a texel on average for a target of %g %%\n",
                    st->gather_rays, 100.0 * (b->noise != 0.0f ? b->noise : VDBGI_NOISE));
        else
            fprintf(f, "%.0f rays a texel\n", st->gather_rays);
    }
    fprintf(f, "time     %.2f s: load %.2f, bake %.2f, write %.2f\n", g->load + g->bake + g->write,
            g->load, g->bake, g->write);
    fprintf(f, "output   %s (%s)\n", g->o->output, cli_bytes(g->glb_bytes, bytes, sizeof(bytes)));
}

/* The JSON figures, for cli_write_printed (held with the .glb). */
static void print_json(FILE *f, const void *g)
{
    print_figures(f, g, true);
}

/*
 * --budget: unwrap at each texel of the ladder, coarse to fine (each step
 * 3/4 or 2/3 of the last), and keep the finest whose atlases fit. A scene
 * keeping its own second UV set has one atlas whatever the texel: its edge
 * is the largest multiple of 32 that fits, at most the default 1024.
 */
static vdbgi_result choose_texel(vdbgi_context *ctx, const vdbgi_scene *scene, options *o,
                                 bool *said)
{
    static const float ladder[] = {4.0f,    3.0f,      2.0f,     1.5f,       1.0f,     0.75f,
                                   0.5f,    0.375f,    0.25f,    0.1875f,    0.125f,   0.09375f,
                                   0.0625f, 0.046875f, 0.03125f, 0.0234375f, 0.015625f};
    float best = 0.0f;
    double first = 0.0;
    for (size_t k = 0; k < sizeof(ladder) / sizeof(ladder[0]); k++) {
        vdbgi_lightmap_desc d = o->lm;
        d.texel = ladder[k];
        vdbgi_lightmap_stats st;
        const vdbgi_result r = vdbgi_lightmap_plan(ctx, scene, &d, &st);
        if (r != VDBGI_OK && k == 0)
            return r; /* the context says why */
        if (r != VDBGI_OK) {
            /* Past the bake's atlas or ray limits: finer texels are too. Said, since the
               budget may have held them. */
            char why[512];
            snprintf(why, sizeof(why), "--budget: texels of %g m stop the ladder: %s", ladder[k],
                     vdbgi_context_error(ctx));
            cli_log(NULL, VDBGI_LOG_WARNING, why);
            break;
        }
        if (k == 0)
            first = (double)st.texels * MAP_TEXEL_BYTES;
        if (st.kept_uv1) {
            /* Its own UV set, one atlas: the largest edge that fits, if the set holds at it. */
            const int edge = (int)(sqrt(o->budget / MAP_TEXEL_BYTES) / 32.0) * 32;
            d.size = edge < 1024 ? edge : 1024;
            if (d.size < 32 || vdbgi_lightmap_plan(ctx, scene, &d, &st) != VDBGI_OK ||
                !st.kept_uv1) {
                cli_error("%s: its own second UV set needs an atlas larger than --budget %g MB "
                          "allows (give --size, or drop the set to unwrap anew)",
                          o->scene, o->budget / 1e6);
                *said = true;
                return VDBGI_ERR_INVALID_ARG;
            }
            o->lm.size = d.size;
            return VDBGI_OK;
        }
        const double bytes = (double)st.texels * MAP_TEXEL_BYTES;
        if (bytes > o->budget)
            break;
        best = ladder[k];
    }
    if (best == 0.0f) {
        char b[32];
        cli_error("%s: even at %g m texels its map takes %s, past --budget %g MB", o->scene,
                  (double)ladder[0], cli_bytes(first, b, sizeof(b)), o->budget / 1e6);
        *said = true;
        return VDBGI_ERR_INVALID_ARG;
    }
    o->lm.texel = best;
    return VDBGI_OK;
}

int main(int argc, char **argv)
{
    cli_init("gi-lightmap");
    options o = {0};
    const int parsed = parse_args(argc, argv, &o);
    if (parsed >= 0)
        return parsed;
    /* The scene, and no file of another kind, is ever replaced. */
    const char *const inputs[2] = {o.scene, cli_light.sky_map};
    const cli_file outs[2] = {{o.output, "glTF binary", "glTF", 4}, {o.stats, "JSON", "{", 1}};
    /* The .glb, its EXR maps and the figures, or nothing: each waits under a temporary name. */
    vdbgi_context *ctx = NULL;
    const int started = cli_start(inputs, cli_light.sky_map ? 2 : 1, outs, o.stats ? 2 : 1, &ctx);
    if (started >= 0)
        return started;
    vdbgi_scene *scene = NULL;
    vdbgi_sky *sky = NULL;
    vdbgi_lightmap_result *lm = NULL;
    run_figures g = {.o = &o};
    const double t0 = cli_now();
    vdbgi_result r = vdbgi_output_check(ctx, o.output);
    if (r == VDBGI_OK && o.stats)
        r = vdbgi_output_check(ctx, o.stats);
    if (r == VDBGI_OK)
        r = vdbgi_scene_load(ctx, o.scene, &scene);
    int code = CLI_OK;
    if (r == VDBGI_OK && (code = cli_light_prepare(ctx, scene, &o.lm.bake, &sky)) >= 0) {
        vdbgi_sky_destroy(sky);
        vdbgi_scene_destroy(scene);
        vdbgi_context_destroy(ctx);
        return code;
    }
    code = CLI_OK;
    const double t1 = cli_now();
    bool said = false; /* choose_texel said why it failed */
    if (r == VDBGI_OK && o.budget > 0.0 && (r = choose_texel(ctx, scene, &o, &said)) != VDBGI_OK)
        code = said ? CLI_FAILED : cli_fail_about(ctx, o.scene);
    if (r == VDBGI_OK &&
        (r = vdbgi_lightmap_bake_scene(ctx, scene, &o.lm, &lm, &g.st)) != VDBGI_OK) {
        /* The bake sees a scene, not a file: say which one asked for more work than the
           budget at these options, or cannot be baked (a bad value is the command's). */
        if (r == VDBGI_ERR_OUT_OF_MEMORY || r == VDBGI_ERR_FORMAT)
            code = cli_fail_about(ctx, o.scene);
        else
            code = cli_fail(ctx, r);
    }
    const double t2 = cli_now();
    size_t glb_bytes = 0;
    if (r == VDBGI_OK)
        r = vdbgi_lightmap_write(lm, o.output, &glb_bytes);
    if (r == VDBGI_OK && o.slices)
        r = vdbgi_lightmap_write_slices(lm, o.slices);
    const double t3 = cli_now();
    if (r == VDBGI_OK) {
        vdbgi_scene_get_info(scene, &g.si);
        g.load = t1 - t0, g.bake = t2 - t1, g.write = t3 - t2;
        g.glb_bytes = (double)glb_bytes;
    }
    if (r == VDBGI_OK && o.stats)
        r = cli_write_printed(ctx, o.stats, print_json, &g);
    if (r == VDBGI_OK)
        r = vdbgi_context_commit_outputs(ctx);
    if (r != VDBGI_OK && code == CLI_OK)
        code = cli_fail(ctx, r);
    else if (r == VDBGI_OK && cli_verbosity >= 2)
        print_figures(stdout, &g, false);
    vdbgi_lightmap_result_destroy(lm);
    vdbgi_sky_destroy(sky);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
    return code;
}
