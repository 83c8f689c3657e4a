/* bench_sweep.c: gi-bench sweep: speed against accuracy over rays, size and spacing (CSV). */
#include "bench.h"
#include "bench_lights.h"
#include "cli.h"
#include "vdbgi.h"
#include "vdbgi_bench.h"

#include <stdlib.h>
#include <string.h>

/* ---- sweep ------------------------------------------------------------------ */

typedef struct sweep {
    vdbgi_context *ctx;
    const bench_options *o;
    vdbgi_scene *scene;
    FILE *csv;
} sweep;

static int sweep_size(sweep *w, const char *dir)
{
    vdbgi_context *const ctx = w->ctx;
    vdbgi_probes *p = NULL;
    vdbgi_result r = vdbgi_probes_place(ctx, w->scene, NULL, &p);
    if (r == VDBGI_OK)
        r = vdbgi_probes_bake(p, w->scene, NULL, NULL);
    FILE *const f = r == VDBGI_OK ? bench_open_csv(dir, "size.csv",
                                                   "criterion,eps,max_level,encoding,raw_bytes,"
                                                   "gzip_bytes,dense_bytes,rmse_rel,p99_rel")
                                  : NULL;
    static const float eps[] = {0.0f, 0.01f, 0.03f, 0.1f, 0.2f, 0.4f, 0.8f, 1.6f};
    static const char *const eps_text[] = {"0", "0.01", "0.03", "0.1", "0.2", "0.4", "0.8", "1.6"};
    for (int c = VDBGI_CRITERION_RANGE; f && r == VDBGI_OK && c <= VDBGI_CRITERION_INTERP; c++)
        for (int e = 0; r == VDBGI_OK && e < 2; e++)
            for (int max_level = 0; r == VDBGI_OK && max_level <= 3; max_level += 3)
                for (size_t i = 0; r == VDBGI_OK && i < sizeof(eps) / sizeof(eps[0]); i++) {
                    const vdbgi_convert_desc d = {.eps = eps[i],
                                                  .eps_is_set = 1,
                                                  .max_level = max_level,
                                                  .max_level_is_set = 1,
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
    FILE *const f = r == VDBGI_OK
                        ? bench_open_csv(dir, "spacing.csv",
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

int bench_sweep(const bench_options *o)
{
    const char *const dir = bench_out_dir(o);
    if (!dir)
        return CLI_FAILED;
    sweep w = {.o = o};
    if (!(w.ctx = cli_context()))
        return CLI_FAILED;
    vdbgi_result r = vdbgi_scene_load(w.ctx, o->scene, &w.scene);
    int code = r == VDBGI_OK ? CLI_OK : cli_fail(w.ctx, r);
    if (code == CLI_OK)
        code = bench_rays_table(w.ctx, w.scene, 1.0, NULL, dir);
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
