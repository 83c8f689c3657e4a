/* gi-merge: the .vdb tiles of one bake (gi-bake --tile I/N) into the whole lattice's .vdb. */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "vdbgi.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

static void usage(void)
{
    printf("Usage: gi-merge TILE.vdb... -o WORLD.vdb [options]\n"
           "\n"
           "Merge the tiles of one bake, each written by gi-bake --tile I/N, given in any\n"
           "order, into the .vdb a one-machine bake of the whole lattice writes: the same\n"
           "probes with the same values, its grids merged by OpenVDB's tree merge. Every\n"
           "tile is read with the checks of any .vdb; a file that is not a tile, a tile\n"
           "of another bake (any setting, the scene or the lattice), of another tile\n"
           "count, given twice, outside its range or overlapping another, and a missing\n"
           "tile or a gap between the tiles' slabs are refused by name, and nothing is\n"
           "written.\n"
           "\n"
           "Options:\n"
           "  -o, --output FILE   the whole .vdb (required; replaced only on success)\n"
           "      --memory-limit SIZE\n"
           "                      stop with one line before holding more than SIZE of\n"
           "                      grids (K, M, G, T: powers of 1024)\n"
           "  -q, --quiet         errors only\n"
           "  -v, --verbose       more detail on stderr\n"
           "  -h, --help          print this help and exit\n"
           "      --version       print the version and exit\n"
           "\n"
           "Example:\n"
           "  for i in 1 2 3 4; do gi-bake world.glb -o tile$i.vdb --tile $i/4; done\n"
           "  gi-merge tile1.vdb tile2.vdb tile3.vdb tile4.vdb -o world.vdb\n");
}

int main(int argc, char **argv)
{
    cli_init("gi-merge");
    static const struct option longs[] = {
        {"output", required_argument, NULL, 'o'},
        {"memory-limit", required_argument, NULL, CLI_OPT_MEMORY_LIMIT},
        CLI_COMMON_LONG_OPTIONS};
    const char *output = NULL;
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, ":o:qvh", longs, NULL)) != -1) {
        if (c == 'o') {
            output = optarg;
            continue;
        }
        const int done = c == CLI_OPT_MEMORY_LIMIT ? cli_memory_limit_option(optarg)
                                                   : cli_common_option(c, argv, usage);
        if (done != -2)
            return done;
    }
    if (optind == argc)
        return cli_usage_error("no tiles given");
    if (!output)
        return cli_usage_error("no output given: use -o WORLD.vdb");
    const char *const *tiles = (const char *const *)&argv[optind];
    const int count = argc - optind;
    const cli_file out = {output, "VDB", "\x20\x42\x44\x56", 4};
    const int clash = cli_check_files(tiles, count, &out, 1);
    if (clash >= 0)
        return clash;
    vdbgi_context *const ctx = cli_context();
    if (!ctx)
        return CLI_FAILED;
    const double t0 = cli_now();
    vdbgi_result r = vdbgi_output_check(ctx, output);
    if (r == VDBGI_OK)
        r = vdbgi_probes_merge(ctx, tiles, (size_t)count, output);
    int code = CLI_OK;
    if (r != VDBGI_OK) {
        code = cli_fail(ctx, r);
    } else if (cli_verbosity >= 2) {
        struct stat st;
        char size[32];
        printf("merged   %d tiles in %.2f s\n", count, cli_now() - t0);
        printf("output   %s (%s)\n", output,
               stat(output, &st) == 0 ? cli_bytes((double)st.st_size, size, sizeof(size)) : "?");
    }
    vdbgi_context_destroy(ctx);
    return code;
}
