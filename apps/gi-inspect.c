/* gi-inspect: print what a .vdb or .gi file holds, and the value at points. */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "vdbgi.h"

#include <fcntl.h>
#include <getopt.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void usage(void)
{
    printf("Usage: gi-inspect FILE [--at X,Y,Z]... [--normal NX,NY,NZ] [--textures OUT.gi]\n"
           "\n"
           "Print the header and statistics of FILE, either probes baked by gi-bake (.vdb)\n"
           "or a bricked volume written by vdb-to-gi (.gi.gz, or a plain .gi), told apart\n"
           "by their first bytes. Each --at prints the value at a world position: for a\n"
           ".gi the runtime shader's lookup, exactly; for a .vdb the trilinear\n"
           "interpolation of the valid probes around it. A compact .gi stores each probe\n"
           "once; --textures writes the textures a reader rebuilds from it, as the GPU\n"
           "takes them (an uncompressed .gi, version 2; not for L2 terms). With --normal,\n"
           "probes baked with a directional basis (sh2, ambient-cube), and a .gi converted\n"
           "from sh2 probes, give what a surface facing that way receives (E / pi, clamped\n"
           "at 0), each term interpolated before evaluation.\n"
           "\n"
           "Options:\n"
           "      --at X,Y,Z    a world position in metres (repeat for more)\n"
           "      --normal N    the receiving surface's normal at every --at (need not be unit)\n"
           "      --textures F  write a .gi's runtime textures to F (replaced on success)\n"
           "      --max-bytes SIZE  read a .gi that unpacks to more than 32M (its body or\n"
           "                    its textures; the web loader's maxBytes is the same bound)\n"
           "  -h, --help        print this help and exit\n"
           "      --version     print the version and exit\n"
           "\n"
           "Examples:\n"
           "  gi-inspect world.vdb\n"
           "  gi-inspect world.gi.gz --at 0,1,0 --at 10,0.5,-3\n"
           "  gi-inspect world.vdb --at 0,0.1,0 --normal 0,1,0\n"
           "  gi-inspect world-sh2.gi.gz --at 0,0.1,0 --normal 0,1,0\n"
           "  gi-inspect world.gi.gz --textures world-textures.gi\n");
}

enum { OPT_AT = 256, OPT_NORMAL, OPT_TEXTURES, OPT_MAX_BYTES };

/*
 * VDB files start with the 64-bit magic 0x56444220 (" BDV" little-endian).
 * Only a regular file is sniffed: anything else goes to the .gi reader,
 * which refuses it by name (a FIFO read here would block).
 */
static int is_vdb(const char *path)
{
    const int fd = open(path, O_RDONLY | O_NONBLOCK);
    struct stat st;
    unsigned char m[8] = {0};
    ssize_t n = 0;
    if (fd >= 0 && fstat(fd, &st) == 0 && S_ISREG(st.st_mode))
        n = read(fd, m, 8);
    if (fd >= 0)
        close(fd);
    static const unsigned char magic[8] = {0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0};
    return n == 8 && memcmp(m, magic, 8) == 0;
}

static int inspect_vdb(vdbgi_context *ctx, const char *path, float (*at)[3], int at_count,
                       const float *normal)
{
    vdbgi_probes *p = NULL;
    vdbgi_result r = vdbgi_probes_read(ctx, path, &p);
    if (r != VDBGI_OK)
        return cli_fail(ctx, r);
    vdbgi_probes_info pi;
    vdbgi_probes_get_info(p, &pi);
    printf("file         %s (OpenVDB)\n", path);
    printf("probes       %zu (%zu invalid, back-face fraction above %g)\n", pi.probe_count,
           pi.invalid_count, (double)pi.invalid_threshold);
    printf("lattice      spacing %g m, origin %g,%g,%g, ijk %d,%d,%d .. %d,%d,%d\n", pi.spacing,
           pi.origin[0], pi.origin[1], pi.origin[2], pi.ijk_min[0], pi.ijk_min[1], pi.ijk_min[2],
           pi.ijk_max[0], pi.ijk_max[1], pi.ijk_max[2]);
    for (size_t i = 0; vdbgi_probes_metadata(p, i); i++)
        printf("meta         %s\n", vdbgi_probes_metadata(p, i));
    int code = CLI_OK;
    for (int i = 0; i < at_count; i++) {
        float rgb[3];
        unsigned char valid = 1;
        r = normal ? vdbgi_probes_sample_points(p, 1, at[i], normal, 0.0f, rgb, &valid)
                   : vdbgi_probes_sample(p, at[i], rgb);
        if (r != VDBGI_OK)
            code = cli_fail(ctx, r);
        else if (!valid) {
            cli_error("no valid probe around (%g, %g, %g)", (double)at[i][0], (double)at[i][1],
                      (double)at[i][2]);
            code = CLI_FAILED;
        } else
            printf("at           %g,%g,%g -> %.6g %.6g %.6g\n", (double)at[i][0], (double)at[i][1],
                   (double)at[i][2], (double)rgb[0], (double)rgb[1], (double)rgb[2]);
    }
    vdbgi_probes_destroy(p);
    return code;
}

static int inspect_gi(vdbgi_context *ctx, const char *path, float (*at)[3], int at_count,
                      const float *normal, const char *textures)
{
    vdbgi_volume *v = NULL;
    const vdbgi_result r = vdbgi_volume_read(ctx, path, &v);
    if (r == VDBGI_ERR_OUT_OF_MEMORY && strstr(vdbgi_context_error(ctx), "volume budget")) {
        cli_error("%s: --max-bytes lifts it", vdbgi_context_error(ctx));
        return CLI_FAILED;
    }
    if (r != VDBGI_OK)
        return cli_fail(ctx, r);
    vdbgi_volume_info vi;
    vdbgi_volume_get_info(v, &vi);
    if (normal && vi.basis == VDBGI_BASIS_SCALAR) {
        vdbgi_volume_destroy(v);
        cli_error("%s: one colour a point (the scalar basis): --normal needs L2 terms "
                  "(gi-bake --basis sh2, then vdb-to-gi)",
                  path);
        return CLI_FAILED;
    }
    char a[32], b[32], c[32];
    printf("file         %s (.gi, %s)\n", path, cli_bytes((double)vi.file_size, a, sizeof(a)));
    printf("encoding     %s", vi.encoding == VDBGI_ENCODING_RGB9E5 ? "rgb9e5\n" : "rgbm");
    if (vi.encoding == VDBGI_ENCODING_RGBM)
        printf(", range %g\n", (double)vi.rgbm_range);
    printf("box          %g,%g,%g .. %g,%g,%g m, spacing %g m\n", (double)vi.box_min[0],
           (double)vi.box_min[1], (double)vi.box_min[2], (double)vi.box_max[0],
           (double)vi.box_max[1], (double)vi.box_max[2], (double)vi.spacing);
    printf("indirection  %ux%ux%u cells, %s\n", vi.ind_dims[0], vi.ind_dims[1], vi.ind_dims[2],
           cli_bytes((double)vi.indirection_size, b, sizeof(b)));
    printf("atlas        %ux%ux%u texels%s, %s\n", vi.atlas_dims[0], vi.atlas_dims[1],
           vi.atlas_dims[2],
           vi.layout == VDBGI_LAYOUT_COMPACT ? " (compact: 5^3 bricks sharing borders)" : "",
           cli_bytes((double)vi.atlas_size, c, sizeof(c)));
    cli_print_runtime(stdout, &vi);
    printf("bricks       %u (max level %u): level 0 %u, level 1 %u, level 2 %u, level 3 %u\n",
           vi.brick_count, vi.max_level, vi.bricks[0], vi.bricks[1], vi.bricks[2], vi.bricks[3]);
    if (vi.stored_points)
        printf("stored       %zu probe values, each once; the textures rebuilt from them\n",
               vi.stored_points);
    if (vi.basis == VDBGI_BASIS_SH2)
        printf("basis        L2: eight terms a texel beside the atlas (%s), %s more VRAM\n",
               cli_term_form(&vi), cli_bytes((double)vi.sh_size, b, sizeof(b)));
    for (int i = 0; i < at_count; i++) {
        float rgb[3];
        if (normal)
            vdbgi_volume_sample_normal(v, at[i], normal, rgb);
        else
            vdbgi_volume_sample(v, at[i], rgb);
        printf("at           %g,%g,%g -> %.6g %.6g %.6g\n", (double)at[i][0], (double)at[i][1],
               (double)at[i][2], (double)rgb[0], (double)rgb[1], (double)rgb[2]);
    }
    const vdbgi_result w = textures ? vdbgi_volume_write_textures(v, textures) : VDBGI_OK;
    vdbgi_volume_destroy(v);
    if (w != VDBGI_OK)
        return cli_fail(ctx, w);
    if (textures)
        printf("textures     %s\n", textures);
    return CLI_OK;
}

int main(int argc, char **argv)
{
    cli_init("gi-inspect");
    static const struct option longs[] = {{"at", required_argument, NULL, OPT_AT},
                                          {"normal", required_argument, NULL, OPT_NORMAL},
                                          {"textures", required_argument, NULL, OPT_TEXTURES},
                                          {"max-bytes", required_argument, NULL, OPT_MAX_BYTES},
                                          {"help", no_argument, NULL, 'h'},
                                          {"version", no_argument, NULL, CLI_OPT_VERSION},
                                          {NULL, 0, NULL, 0}};
    float(*at)[3] = calloc((size_t)argc, sizeof(*at));
    int at_count = 0, c;
    const char *textures = NULL;
    float normal[3];
    bool has_normal = false;
    if (!at) {
        cli_error("out of memory");
        return CLI_FAILED;
    }
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":h", longs, NULL)) != -1) {
        switch (c) {
        case OPT_AT:
            if (!cli_parse_vec3(optarg, at[at_count])) {
                free(at);
                return cli_usage_error("--at must be x,y,z (got '%s')", optarg);
            }
            at_count++;
            break;
        case OPT_NORMAL: {
            const float *const n = normal;
            const double len =
                cli_parse_vec3(optarg, normal)
                    ? sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2])
                    : 0.0;
            if (!(len > 1e-12) || !isfinite(len)) {
                free(at);
                return cli_usage_error("--normal must be a non-zero x,y,z (got '%s')", optarg);
            }
            for (int k = 0; k < 3; k++)
                normal[k] = (float)(normal[k] / len);
            has_normal = true;
            break;
        }
        case OPT_TEXTURES: textures = optarg; break;
        case OPT_MAX_BYTES: {
            const int rc = cli_volume_budget_option(optarg);
            if (rc != -2) {
                free(at);
                return rc;
            }
            break;
        }
        default: free(at); return cli_common_option(c, argv, usage);
        }
    }
    if (argc - optind != 1) {
        free(at);
        return cli_usage_error(optind == argc ? "no file given" : "one file at a time");
    }
    const char *const path = argv[optind];
    vdbgi_context *const ctx = cli_context();
    if (!ctx) {
        free(at);
        return CLI_FAILED;
    }
    if (textures && is_vdb(path)) {
        vdbgi_context_destroy(ctx);
        free(at);
        return cli_usage_error("--textures needs a .gi file, not probes");
    }
    const float *const n = has_normal ? normal : NULL;
    const int code = is_vdb(path) ? inspect_vdb(ctx, path, at, at_count, n)
                                  : inspect_gi(ctx, path, at, at_count, n, textures);
    vdbgi_context_destroy(ctx);
    free(at);
    return code;
}
