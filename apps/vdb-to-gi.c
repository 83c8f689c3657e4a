/* vdb-to-gi: convert baked probes (.vdb) into seed 000's bricked volume (.gi.gz). */
#define _POSIX_C_SOURCE 200809L
#include "budget.h"
#include "cli.h"
#include "convert_report.h"
#include "vdbgi.h"

#include <getopt.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(void)
{
    printf("Usage: vdb-to-gi IN.vdb -o OUT.gi.gz [options]\n"
           "       vdb-to-gi IN.vdb --bevy OUT.ktx2 | --bevy-baked-gi OUT.png [options]\n"
           "\n"
           "Convert the probes baked by gi-bake into what a game ships: adaptive bricks of\n"
           "4x4x4 probes (big where light is flat, small where it changes), packed into an\n"
           "atlas texture (neighbours sharing their border texels), an indirection texture\n"
           "pointing every 4x4x4-probe cell at its brick, both RGBM-encoded (or RGB9E5);\n"
           "the file stores each probe once, gzip'd (docs/format.md). Invalid and absent\n"
           "probes are filled from valid neighbours first. Statistics go to stdout.\n"
           "\n"
           "With --bevy or --bevy-baked-gi (probes baked with --basis ambient-cube), also\n"
           "resample the ambient cubes onto a dense grid for Bevy's irradiance volumes and\n"
           "write OUT plus OUT.json, the volume's box and transform (docs/bevy.md).\n"
           "\n"
           "Options:\n"
           "  -o, --output FILE     the .gi.gz to write (required; replaced only on success)\n"
           "      --eps E           coarsening tolerance, relative to the mean irradiance\n"
           "                        (0.1); 0 keeps every varying block fine\n"
           "      --max-level L     largest brick level, 0..3: a level-L brick spans 4*2^L\n"
           "                        probes (3)\n"
           "      --criterion C     interp: keep a coarse brick when its interpolation\n"
           "                        reproduces every probe it covers within eps; rmse: when\n"
           "                        its RMSE over them is within eps (Unreal); range: when\n"
           "                        its colour range is within eps, as seed 000 (interp)\n"
           "      --encoding E      rgbm (rgba8, range 8, as seed 000) or rgb9e5 (rgbm)\n"
           "      --noise-sigmas K  allow each block K standard errors of sampling noise\n"
           "                        (the bake's stderr grid) before it splits; 0 for none\n"
           "                        (1 for random or adaptive bakes, 0 for Fibonacci ones)\n"
           "      --fill F          what an invalid probe inside a thin wall takes from its\n"
           "                        neighbours: darkest, which keeps light from leaking into\n"
           "                        dark rooms, or mean (darkest); applies to --bevy too\n"
           "      --layout L        seed: 6^3 texels a brick, for seed 000's shader as it\n"
           "                        is; compact: 5^3 texels, coarse probes at block corners,\n"
           "                        levels stitched, neighbours sharing borders\n"
           "                        (docs/format.md) (compact)\n"
           "      --basis B         auto: probes baked with --basis sh2 keep their L2 terms\n"
           "                        in the compact layout (.gi version 8 or 7, read with\n"
           "                        the surface's normal); scalar: one colour a probe (auto)\n"
           "      --gi-version V    L2 terms: 8, the second band's terms one ratio for all\n"
           "                        three channels (14 bytes a texel on the GPU); 7, each\n"
           "                        term in colour (24 bytes); 6, version 7 for runtimes\n"
           "                        from before it (a larger file); auto: 8 where that\n"
           "                        moves the probes' readings by at most 4 %%, else 7 (auto)\n"
           "      --budget MB       GPU memory the volume may take (decimal MB): convert\n"
           "                        at --eps (0.1), then 0.2 and 0.4, then those as .gi\n"
           "                        version 8 (where auto chose 7), then without the L2\n"
           "                        terms, until it fits; print what fitted and the error\n"
           "                        the measured curves give it (docs/directional.md)\n"
           "      --term-bits B     L2 terms: bits kept of each ratio byte, 4..8; each bit\n"
           "                        fewer doubles the rounding step and shrinks the file\n"
           "                        (6: the bake's noise is larger than its step)\n"
           "      --slices DIR      write slice images (PNG and EXR) into DIR\n"
           "      --slice-axis A    x, y or z (y)\n"
           "      --slice-at M      world coordinate of the slice (the plane with most probes)\n"
           "      --exposure S      stops applied to the PNG slices (auto)\n"
           "      --stats FILE      also write the statistics as JSON\n"
           "      --bevy FILE       Bevy IrradianceVolume texture, KTX2 (seed 001's layout)\n"
           "      --bevy-format F   rgba16f or rgb9e5 texels for --bevy (rgba16f)\n"
           "      --bevy-baked-gi FILE  bevy-baked-gi's RGBA8 PNG of 3x2 cells (seed 002)\n"
           "      --box X0,Y0,Z0,X1,Y1,Z1  world box of the Bevy volume (the baked bounds)\n"
           "      --res N|X,Y,Z     Bevy voxels per axis (from --voxel)\n"
           "      --voxel M         Bevy voxel size in metres (4 x the probe spacing)\n"
           "      --threads N       worker threads; the output does not depend on it (all\n"
           "                        cores)\n"
           "      --memory-limit SIZE  stop with one line before holding more than SIZE\n"
           "                        (K, M, G, T: powers of 1024; vdbgi's own memory and\n"
           "                        the grids read)\n"
           "      --region N        convert region by region: slabs of N lattice points\n"
           "                        along z (a multiple of 32), each read with a halo of 16\n"
           "                        points, filled, coarsened and sampled, then dropped; the\n"
           "                        same bytes in less memory, the file read four times\n"
           "                        (not with --slices or --bevy; docs/scale.md)\n"
           "  -q, --quiet           no statistics, errors only\n"
           "  -v, --verbose         more detail on stderr (-vv: timings of each step)\n"
           "  -h, --help            print this help and exit\n"
           "      --version         print the version and exit\n"
           "\n"
           "Examples:\n"
           "  vdb-to-gi world.vdb -o world.gi.gz\n"
           "  vdb-to-gi world.vdb -o world.gi.gz --eps 0.05 --slices slices --stats stats.json\n"
           "  vdb-to-gi world.vdb -o exact.gi.gz --eps 0 --max-level 0 --encoding rgb9e5\n"
           "  vdb-to-gi big.vdb -o big.gi.gz --region 256 --memory-limit 8G\n"
           "  vdb-to-gi cubes.vdb --bevy volume.ktx2 --voxel 1\n");
}

enum {
    OPT_EPS = 256,
    OPT_MAX_LEVEL,
    OPT_CRITERION,
    OPT_ENCODING,
    OPT_NOISE_SIGMAS,
    OPT_FILL,
    OPT_LAYOUT,
    OPT_BASIS,
    OPT_GI_VERSION,
    OPT_TERM_BITS,
    OPT_SLICES,
    OPT_SLICE_AXIS,
    OPT_SLICE_AT,
    OPT_EXPOSURE,
    OPT_STATS,
    OPT_BEVY,
    OPT_BEVY_FORMAT,
    OPT_BEVY_BAKED_GI,
    OPT_BOX,
    OPT_RES,
    OPT_VOXEL,
    OPT_THREADS,
    OPT_REGION,
    OPT_BUDGET
};

/* The volume of desc, from the whole lattice or region by region (--region). */
static vdbgi_result build(vdbgi_context *ctx, vdbgi_probes *probes, vdbgi_probe_file *file,
                          int region, const vdbgi_convert_desc *desc, vdbgi_volume **vol)
{
    vdbgi_volume_destroy(*vol);
    *vol = NULL;
    return file ? vdbgi_volume_build_regions(ctx, file, region, desc, vol)
                : vdbgi_volume_build(ctx, probes, desc, vol);
}

/*
 * The volume, built at the options; with --budget, built again at each step of
 * the ladder until one fits (*fits false, vol the last, when none does). The
 * measured curves order it (docs/directional.md, "A budget"): coarser bricks,
 * eps 0.2 then 0.4, cost characters under 2 points, the second band in
 * luminance (.gi version 8, where the converter chose 7) 1-2 more, dropping
 * the L2 terms about 80, so the terms go last. Each step is measured, not
 * assumed smaller: a coarser brick can pack worse.
 */
static vdbgi_result build_within(vdbgi_context *ctx, vdbgi_probes *probes, vdbgi_probe_file *file,
                                 options *o, vdbgi_volume **vol, bool *fits)
{
    *fits = true;
    if (o->budget <= 0.0)
        return build(ctx, probes, file, o->region, &o->convert, vol);
    const float eps0 = o->convert.eps_is_set ? o->convert.eps : 0.1f;
    const float ladder[3] = {eps0, fmaxf(eps0, 0.2f), fmaxf(eps0, 0.4f)};
    bool terms = o->convert.terms == VDBGI_TERMS_KEEP; /* a round without them to come */
    /* A round as version 8 to come: where the version is the converter's to choose, and it
       chose 7. */
    bool luma2 = terms && o->convert.gi_version == 0;
    o->budget_smallest = SIZE_MAX;
    for (int round = 0; round < (terms ? 3 : 1); round++)
        for (int step = 0; step < 3; step++) {
            if ((step > 0 && ladder[step] == ladder[step - 1]) || (round == 1 && !luma2))
                continue;
            vdbgi_convert_desc d = o->convert;
            d.eps = ladder[step];
            d.eps_is_set = 1;
            if (round == 1)
                d.gi_version = 8;
            if (round == 2) {
                d.terms = VDBGI_TERMS_DROP;
                d.gi_version = 0; /* 6 to 8 are versions with terms */
            }
            const vdbgi_result r = build(ctx, probes, file, o->region, &d, vol);
            if (r != VDBGI_OK)
                return r;
            vdbgi_volume_info vi;
            vdbgi_volume_get_info(*vol, &vi);
            const size_t vram = budget_vram(&vi);
            const bool fitted = (double)vram <= o->budget, smallest = vram < o->budget_smallest;
            o->budget_tries++;
            terms = terms && vi.basis == VDBGI_BASIS_SH2; /* probes without terms: none to drop */
            if (round == 0)                               /* the converter chose 7 */
                luma2 = luma2 && terms && !cli_terms_luma2(&vi);
            if (smallest)
                o->budget_smallest = vram;
            if (fitted || smallest) {
                o->budget_eps = d.eps;
                o->budget_terms = vi.basis == VDBGI_BASIS_SH2;
            }
            if (fitted)
                return VDBGI_OK;
        }
    *fits = false;
    return VDBGI_OK;
}

/* Parse argv into o (one case an option, kept whole); returns -1 to go on, else the exit code. */
static int parse_args(int argc, char **argv, options *o)
{
    static const struct option longs[] = {
        {"output", required_argument, NULL, 'o'},
        {"eps", required_argument, NULL, OPT_EPS},
        {"max-level", required_argument, NULL, OPT_MAX_LEVEL},
        {"criterion", required_argument, NULL, OPT_CRITERION},
        {"encoding", required_argument, NULL, OPT_ENCODING},
        {"noise-sigmas", required_argument, NULL, OPT_NOISE_SIGMAS},
        {"fill", required_argument, NULL, OPT_FILL},
        {"layout", required_argument, NULL, OPT_LAYOUT},
        {"basis", required_argument, NULL, OPT_BASIS},
        {"gi-version", required_argument, NULL, OPT_GI_VERSION},
        {"term-bits", required_argument, NULL, OPT_TERM_BITS},
        {"slices", required_argument, NULL, OPT_SLICES},
        {"slice-axis", required_argument, NULL, OPT_SLICE_AXIS},
        {"slice-at", required_argument, NULL, OPT_SLICE_AT},
        {"exposure", required_argument, NULL, OPT_EXPOSURE},
        {"stats", required_argument, NULL, OPT_STATS},
        {"bevy", required_argument, NULL, OPT_BEVY},
        {"bevy-format", required_argument, NULL, OPT_BEVY_FORMAT},
        {"bevy-baked-gi", required_argument, NULL, OPT_BEVY_BAKED_GI},
        {"box", required_argument, NULL, OPT_BOX},
        {"res", required_argument, NULL, OPT_RES},
        {"voxel", required_argument, NULL, OPT_VOXEL},
        {"threads", required_argument, NULL, OPT_THREADS},
        {"memory-limit", required_argument, NULL, CLI_OPT_MEMORY_LIMIT},
        {"region", required_argument, NULL, OPT_REGION},
        {"budget", required_argument, NULL, OPT_BUDGET},
        CLI_COMMON_LONG_OPTIONS};
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
            o->convert.eps = (float)d;
            o->convert.eps_is_set = 1;
            break;
        case OPT_MAX_LEVEL:
            if (!cli_parse_int(optarg, &i) || i < 0 || i > 3)
                return cli_usage_error("--max-level must be 0, 1, 2 or 3 (got '%s')", optarg);
            o->convert.max_level = (int)i;
            o->convert.max_level_is_set = 1;
            break;
        case OPT_CRITERION:
            if (strcmp(optarg, "range") == 0)
                o->convert.criterion = VDBGI_CRITERION_RANGE;
            else if (strcmp(optarg, "interp") == 0)
                o->convert.criterion = VDBGI_CRITERION_INTERP;
            else if (strcmp(optarg, "rmse") == 0)
                o->convert.criterion = VDBGI_CRITERION_RMSE;
            else
                return cli_usage_error("--criterion must be range, interp or rmse (got '%s')",
                                       optarg);
            break;
        case OPT_ENCODING:
            if (strcmp(optarg, "rgbm") == 0)
                o->convert.encoding = VDBGI_ENCODING_RGBM;
            else if (strcmp(optarg, "rgb9e5") == 0)
                o->convert.encoding = VDBGI_ENCODING_RGB9E5;
            else
                return cli_usage_error("--encoding must be rgbm or rgb9e5 (got '%s')", optarg);
            break;
        case OPT_NOISE_SIGMAS:
            if (!cli_parse_double(optarg, &d) || !(d >= 0.0) || !isfinite(d) || d > 100.0)
                return cli_usage_error("--noise-sigmas must be a number in 0..100 (got '%s')",
                                       optarg);
            o->convert.noise_sigmas = (float)d;
            o->convert.noise_sigmas_is_set = 1;
            break;
        case OPT_FILL:
            if (strcmp(optarg, "mean") == 0)
                o->convert.fill = VDBGI_FILL_MEAN;
            else if (strcmp(optarg, "darkest") == 0)
                o->convert.fill = VDBGI_FILL_DARKEST;
            else
                return cli_usage_error("--fill must be mean or darkest (got '%s')", optarg);
            break;
        case OPT_BASIS:
            if (strcmp(optarg, "scalar") == 0)
                o->convert.terms = VDBGI_TERMS_DROP;
            else if (strcmp(optarg, "auto") == 0)
                o->convert.terms = VDBGI_TERMS_KEEP;
            else
                return cli_usage_error("--basis must be auto or scalar (got '%s')", optarg);
            break;
        case OPT_GI_VERSION:
            if (strcmp(optarg, "6") == 0 || strcmp(optarg, "7") == 0 || strcmp(optarg, "8") == 0)
                o->convert.gi_version = optarg[0] - '0';
            else if (strcmp(optarg, "auto") == 0)
                o->convert.gi_version = 0;
            else
                return cli_usage_error("--gi-version must be 6, 7, 8 or auto (got '%s')", optarg);
            break;
        case OPT_BUDGET:
            if (!budget_parse(optarg, &o->budget))
                return CLI_USAGE;
            break;
        case OPT_TERM_BITS:
            if (!cli_parse_int(optarg, &i) || i < 4 || i > 8)
                return cli_usage_error("--term-bits must be 4..8 (got '%s')", optarg);
            o->convert.term_bits = (int)i;
            break;
        case OPT_LAYOUT:
            if (strcmp(optarg, "seed") == 0)
                o->convert.layout = VDBGI_LAYOUT_SEED;
            else if (strcmp(optarg, "compact") == 0)
                o->convert.layout = VDBGI_LAYOUT_COMPACT;
            else
                return cli_usage_error("--layout must be seed or compact (got '%s')", optarg);
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
        case OPT_BEVY: o->bevy = optarg; break;
        case OPT_BEVY_BAKED_GI: o->bevy_baked_gi = optarg; break;
        case OPT_BEVY_FORMAT:
            if (strcmp(optarg, "rgba16f") == 0)
                o->bevy_format = VDBGI_BEVY_RGBA16F;
            else if (strcmp(optarg, "rgb9e5") == 0)
                o->bevy_format = VDBGI_BEVY_RGB9E5;
            else
                return cli_usage_error("--bevy-format must be rgba16f or rgb9e5 (got '%s')",
                                       optarg);
            break;
        case OPT_BOX: {
            double b[6];
            if (!cli_parse_doubles(optarg, b, 6) || b[3] <= b[0] || b[4] <= b[1] || b[5] <= b[2])
                return cli_usage_error("--box must be x0,y0,z0,x1,y1,z1 with x1 > x0, y1 > y0, "
                                       "z1 > z0 (got '%s')",
                                       optarg);
            memcpy(o->bevy_desc.box_min, b, sizeof(o->bevy_desc.box_min));
            memcpy(o->bevy_desc.box_max, b + 3, sizeof(o->bevy_desc.box_max));
            o->bevy_desc.box_is_set = 1;
            break;
        }
        case OPT_RES: {
            double r[3];
            const bool one = cli_parse_doubles(optarg, r, 1);
            if (one)
                r[1] = r[2] = r[0];
            if ((!one && !cli_parse_doubles(optarg, r, 3)) || r[0] < 1 || r[1] < 1 || r[2] < 1 ||
                r[0] > 1e6 || r[1] > 1e6 || r[2] > 1e6 || r[0] != floor(r[0]) ||
                r[1] != floor(r[1]) || r[2] != floor(r[2]))
                return cli_usage_error("--res must be N or X,Y,Z whole numbers >= 1 (got '%s')",
                                       optarg);
            for (int k = 0; k < 3; k++)
                o->bevy_desc.resolution[k] = (int)r[k];
            break;
        }
        case OPT_VOXEL:
            if (!cli_parse_double(optarg, &d) || !(d > 0.0) || !isfinite(d))
                return cli_usage_error("--voxel must be a number > 0 (got '%s')", optarg);
            o->bevy_desc.voxel_size = d;
            break;
        case CLI_OPT_MEMORY_LIMIT: {
            const int rc = cli_memory_limit_option(optarg);
            if (rc != -2)
                return rc;
            break;
        }
        case OPT_REGION:
            if (!cli_parse_int(optarg, &i) || i < VDBGI_REGION_STEP || i % VDBGI_REGION_STEP != 0 ||
                i > (1 << 24))
                return cli_usage_error("--region must be a multiple of %d lattice points, up to "
                                       "%d (got '%s')",
                                       VDBGI_REGION_STEP, 1 << 24, optarg);
            o->region = (int)i;
            break;
        case OPT_THREADS:
            if (!cli_parse_int(optarg, &i) || i < 1 || i > 1024)
                return cli_usage_error("--threads must be an integer in 1..1024 (got '%s')",
                                       optarg);
            o->convert.threads = o->bevy_desc.threads = (int)i;
            break;
        default: {
            const int done = cli_common_option(c, argv, usage);
            if (done != -2)
                return done;
        }
        }
    }
    const int taken = cli_one_input(argc, argv, "input", &o->input);
    if (taken >= 0)
        return taken;
    if (!o->output && !o->bevy && !o->bevy_baked_gi)
        return cli_usage_error("no output given: use -o OUT.gi.gz, --bevy or --bevy-baked-gi");
    if (!o->output && (o->slices || o->stats))
        return cli_usage_error("--slices and --stats describe the .gi: give -o OUT.gi.gz too");
    if (o->region && (o->slices || o->bevy || o->bevy_baked_gi))
        return cli_usage_error("--region converts to a .gi only: --slices, --bevy and "
                               "--bevy-baked-gi need the whole lattice at once");
    if (o->budget > 0.0 && !o->output)
        return cli_usage_error("--budget sizes the .gi: give -o OUT.gi.gz");
    if (o->region && o->convert.layout == VDBGI_LAYOUT_SEED)
        return cli_usage_error("--region writes the compact layout only");
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

static const char *base_name(const char *path)
{
    const char *const slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* Every output checked before any work, so a bad path fails in a second, not a minute. */
static vdbgi_result check_outputs(vdbgi_context *ctx, const options *o,
                                  const char *const bevy_out[2], char json[2][4096])
{
    vdbgi_result r;
    for (int i = 0; i < 2; i++)
        if (bevy_out[i] && ((r = vdbgi_output_check(ctx, bevy_out[i])) != VDBGI_OK ||
                            (r = vdbgi_output_check(ctx, json[i])) != VDBGI_OK))
            return r;
    if (o->output && (r = vdbgi_output_check(ctx, o->output)) != VDBGI_OK)
        return r;
    return o->stats ? vdbgi_output_check(ctx, o->stats) : VDBGI_OK;
}

/* The Bevy volume and its files, first: it refuses probes without cubes before the conversion. */
/* A volume past the readers' default budget: said now, not when a page refuses it. */
static void warn_budget(const char *path, const vdbgi_volume_info *vi)
{
    const double textures =
        (double)vi->indirection_size + (double)vi->atlas_size + (double)vi->sh_size;
    if (textures <= (double)VDBGI_VOLUME_BUDGET)
        return;
    char m[256];
    snprintf(
        m, sizeof(m),
        "%s unpacks to %.1f MiB of textures, past the %.0f MiB that loadGi and gi-inspect read "
        "by default (loadGi's maxBytes, gi-inspect --max-bytes)",
        path, textures / (1 << 20), (double)VDBGI_VOLUME_BUDGET / (1 << 20));
    cli_log(NULL, VDBGI_LOG_WARNING, m);
}

static vdbgi_result write_bevy(vdbgi_context *ctx, vdbgi_probes *probes, options *o,
                               char json[2][4096], vdbgi_bevy **bevy)
{
    o->bevy_desc.fill = o->convert.fill;
    if (!o->bevy && !o->bevy_baked_gi)
        return VDBGI_OK;
    vdbgi_result r = vdbgi_bevy_build(ctx, probes, &o->bevy_desc, bevy);
    if (r == VDBGI_OK && o->bevy &&
        (r = vdbgi_bevy_write_ktx2(*bevy, o->bevy, o->bevy_format, NULL)) == VDBGI_OK)
        r = vdbgi_bevy_write_json(*bevy, json[0], base_name(o->bevy),
                                  "bevy-irradiance-volume-ktx2");
    if (r == VDBGI_OK && o->bevy_baked_gi &&
        (r = vdbgi_bevy_write_baked_gi(*bevy, o->bevy_baked_gi, NULL)) == VDBGI_OK)
        r = vdbgi_bevy_write_json(*bevy, json[1], base_name(o->bevy_baked_gi), "bevy-baked-gi-png");
    if (r == VDBGI_OK && cli_verbosity >= 2)
        print_bevy(*bevy, o);
    return r;
}

int main(int argc, char **argv)
{
    cli_init("vdb-to-gi");
    /* The compact layout, the library's default: half the memory of seed 000's at the
       same error where light is read (docs/converter.md, section 12). */
    options o = {.axis = VDBGI_AXIS_Y, .slice_at = NAN, .exposure = NAN};
    const int parsed = parse_args(argc, argv, &o);
    if (parsed >= 0)
        return parsed;
    char json[2][4096];
    const char *const bevy_out[2] = {o.bevy, o.bevy_baked_gi};
    for (int i = 0; i < 2; i++)
        if (bevy_out[i])
            snprintf(json[i], sizeof(json[i]), "%s.json", bevy_out[i]);
    /* No output may replace the input, another output, or a file of another kind. */
    const char *const inputs[1] = {o.input};
    const cli_file outs[6] = {{o.output, "gzip'd .gi", "\x1f\x8b", 2},
                              {o.stats, "JSON", "{", 1},
                              {o.bevy, "KTX2", "\xabKTX", 4},
                              {o.bevy ? json[0] : NULL, "JSON", "{", 1},
                              {o.bevy_baked_gi, "PNG", "\x89PNG", 4},
                              {o.bevy_baked_gi ? json[1] : NULL, "JSON", "{", 1}};
    /* All the outputs of a run, or none: each waits under its temporary name until the last. */
    vdbgi_context *ctx = NULL;
    const int started = cli_start(inputs, 1, outs, 6, &ctx);
    if (started >= 0)
        return started;
    vdbgi_probes *probes = NULL;
    vdbgi_volume *vol = NULL;
    int code = CLI_FAILED;
    vdbgi_result r = check_outputs(ctx, &o, bevy_out, json);
    const double t0 = cli_now();
    vdbgi_probe_file *file = NULL; /* --region: the probes are read a region at a time */
    if (r == VDBGI_OK)
        r = o.region ? vdbgi_probe_file_open(ctx, o.input, &file)
                     : vdbgi_probes_read(ctx, o.input, &probes);
    const double read_seconds = cli_now() - t0;
    vdbgi_bevy *bevy = NULL;
    if (r == VDBGI_OK)
        r = write_bevy(ctx, probes, &o, json, &bevy);
    bool built = true;
    const double t1 = cli_now();
    bool fits = true;
    if (r == VDBGI_OK && o.output)
        built = (r = build_within(ctx, probes, file, &o, &vol, &fits)) == VDBGI_OK;
    if (r == VDBGI_OK && o.output && fits)
        r = vdbgi_volume_write(vol, o.output);
    vdbgi_volume_info vi;
    vdbgi_probes_info pi;
    if (r == VDBGI_OK && o.output) {
        vdbgi_volume_get_info(vol, &vi);
        vi.seconds = cli_now() - t1; /* the conversion: the build, and the file (gzip on write) */
        if (probes) {
            vdbgi_probes_get_info(probes, &pi);
        } else { /* what the statistics print of the probes, from the volume */
            memset(&pi, 0, sizeof(pi));
            pi.probe_count = vi.probe_count;
            pi.spacing = vi.spacing;
        }
    }
    if (r == VDBGI_OK && o.slices && fits) {
        const double at = isnan(o.slice_at) ? busiest_plane(probes, o.axis) : o.slice_at;
        /* Auto exposure puts the mean irradiance at 18% grey. */
        const double ev = isnan(o.exposure) && vi.mean_irradiance > 0.0
                              ? log2(0.18 / vi.mean_irradiance)
                              : (isnan(o.exposure) ? 0.0 : o.exposure);
        r = vdbgi_volume_write_slices(vol, probes, o.axis, at, (float)ev, o.slices);
    }
    if (!built) {
        /* The build sees probes, not a file: say which input they came from. */
        code = cli_fail_about(ctx, o.input);
    } else if (!fits) {
        char b[32];
        cli_error("%s: no conversion fits --budget %g MB of GPU memory: the smallest, %s at eps "
                  "%g, takes %s; bake at a coarser spacing (twice the spacing takes about a "
                  "quarter: gi-bake --budget chooses it) or raise --budget",
                  o.input, o.budget / 1e6, o.budget_terms ? "with the L2 terms" : "scalar",
                  (double)o.budget_eps, cli_bytes((double)o.budget_smallest, b, sizeof(b)));
    } else if (r != VDBGI_OK) {
        code = cli_fail(ctx, r);
    } else if (o.output) {
        code = CLI_OK;
        warn_budget(o.output, &vi);
        o.memory_peak = vdbgi_context_memory_peak(ctx);
        if (cli_verbosity >= 2)
            print_stats(stdout, &o, &vi, &pi, read_seconds, false);
        const stats_args sa = {&o, &vi, &pi, read_seconds};
        if (o.stats && (r = cli_write_printed(ctx, o.stats, print_json, &sa)) != VDBGI_OK)
            code = cli_fail(ctx, r);
    }
    if (r == VDBGI_OK && !o.output)
        code = CLI_OK;
    if (code == CLI_OK && (r = vdbgi_context_commit_outputs(ctx)) != VDBGI_OK)
        code = cli_fail(ctx, r);
    vdbgi_bevy_destroy(bevy);
    vdbgi_volume_destroy(vol);
    vdbgi_probes_destroy(probes);
    vdbgi_probe_file_close(file);
    vdbgi_context_destroy(ctx);
    return code;
}
