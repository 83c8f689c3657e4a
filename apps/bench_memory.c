/* bench_memory.c: gi-bench memory: VRAM and file against the error at the receivers (CSV). */
#include "bench.h"
#include "bench_lights.h"
#include "cli.h"
#include "vdbgi.h"
#include "vdbgi_bench.h"

#include <stdlib.h>
#include <string.h>
#include <zlib.h>

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

int bench_memory(const bench_options *o, bool one_spacing)
{
    const char *dir = NULL;
    vdbgi_context *ctx = NULL;
    vdbgi_scene *scene = NULL;
    const int opened = bench_open_scene(o, &dir, &ctx, &scene);
    if (opened != CLI_OK)
        return opened;
    bench_receivers rv = {0};
    float *got = NULL;
    vdbgi_result r = bench_receivers_make(scene, &o->light, &rv);
    if (r == VDBGI_OK && !(got = calloc(3 * rv.count + 3, sizeof(float))))
        r = VDBGI_ERR_OUT_OF_MEMORY;
    FILE *const f =
        r == VDBGI_OK
            ? bench_open_csv(dir, "memory.csv",
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
        const vdbgi_bake_desc bd =
            bench_lit((vdbgi_bake_desc){.rays = o->rays, .basis = VDBGI_BASIS_SH2}, &o->light);
        vdbgi_probes *p = NULL;
        r = vdbgi_probes_place(ctx, scene, &pd, &p);
        if (r == VDBGI_OK)
            r = vdbgi_probes_bake(p, scene, &bd, NULL);
        /* A dense grid holds every probe: the bricks at eps 0, level 0 (L2 terms rounded as
           by default), with the dense grid's bytes (RGBM; L2: 24 more a probe). */
        for (int b = 0; r == VDBGI_OK && b < 2; b++) {
            vdbgi_volume *exact = NULL;
            const vdbgi_convert_desc ed = {.eps_is_set = 1,
                                           .max_level_is_set = 1,
                                           .terms = b ? VDBGI_TERMS_KEEP : VDBGI_TERMS_DROP};
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
                                              .terms = m < 2 ? VDBGI_TERMS_DROP : VDBGI_TERMS_KEEP,
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
        p = NULL;
        /* The volume only where what moves reads it (gi-bake --walkable 2.5): the probes up
           to 2.5 m over walkable surfaces, the default conversion, scalar and L2. */
        const vdbgi_place_desc wd = {.spacing = spacing, .margin = 2.5, .walkable_height = 2.5};
        if (r == VDBGI_OK && (r = vdbgi_probes_place(ctx, scene, &wd, &p)) == VDBGI_OK)
            r = vdbgi_probes_bake(p, scene, &bd, NULL);
        for (int b = 0; r == VDBGI_OK && b < 2; b++) {
            const vdbgi_convert_desc d = {.terms = b ? VDBGI_TERMS_KEEP : VDBGI_TERMS_DROP};
            vdbgi_volume *v = NULL;
            if ((r = vdbgi_volume_build(ctx, p, &d, &v)) == VDBGI_OK) {
                vdbgi_volume_info vi;
                bench_info(v, &vi);
                memory_row(f, spacing, "compact-walkable-2.5m", b ? "L2" : "scalar", "0.1", v,
                           vi.columns_size + vi.atlas_size + vi.sh_size, vi.file_size, &rv, got);
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
