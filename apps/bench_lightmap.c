/* bench_lightmap.c: gi-bench lightmap: the lightmapper's time, charts and error. */
#define _DEFAULT_SOURCE /* mkstemps */
#include "bench.h"
#include "bench_lights.h"
#include "cli.h"
#include "vdbgi.h"
#include "vdbgi_bench.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

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
    bench_compare(ref, got, (size_t)n, rmse, p99);
}

int bench_lightmap(const bench_options *o, const char *argv0)
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
        vdbgi_lightmap_result_destroy(res);
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
    bench_beside(argv0, "gi-lightmap", tool, sizeof(tool));
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
        const double t = bench_time_process(lm_argv, NULL);
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
    vdbgi_lightmap_result_destroy(res);
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
    vdbgi_lightmap_result_destroy(res);
    res = NULL;
    printf("Packing: %zu charts into %.0f texels of atlas, %.1f %% of it covered by triangles "
           "(%s; tests/js/potpack.mjs packs the same boxes as seed 004 does).\n\n",
           bake.charts, ours, 100.0 * (double)bake.samples / ours, path);

    /* Error against memory (only with --out: at 0.125 m a large world takes minutes). */
    if (!o->out) {
        code = CLI_OK;
        goto done;
    }
    /* Error against memory, under --model and --bounces as the truth is: a pass a bounce. */
    const vdbgi_bake_desc rd = bench_lit(
        (vdbgi_bake_desc){.rays = 2048, .sampling = VDBGI_SAMPLING_RANDOM, .seed = 5}, &o->light);
    const int passes = o->light.bounces > 1 ? o->light.bounces : 1;
    vdbgi_bake_desc lit = bench_lit((vdbgi_bake_desc){.threads = o->threads}, &o->light);
    lit.bounces = 0; /* a lightmap bounces by its passes */
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
        /* The atlas gi-lightmap takes by default: the smallest multiple of 32 that holds every
           chart, or pages of 1024 (what --budget and a game pay). */
        vdbgi_lightmap_result_destroy(res);
        res = NULL;
        const vdbgi_lightmap_desc d = {.texel = texels[t], .passes = passes, .bake = lit};
        r = vdbgi_lightmap_bake_scene(ctx, scene, &d, &res, &ls);
        if (r == VDBGI_ERR_OUT_OF_MEMORY) { /* past the lightmap's limits: no row */
            printf("lightmap: %g m texels skipped: %s\n", (double)texels[t],
                   vdbgi_context_error(ctx));
            r = VDBGI_OK;
            continue;
        }
        if (r != VDBGI_OK) {
            code = cli_fail(ctx, r);
            goto done;
        }
        double rmse, p99;
        lightmap_error(res, prims, uv, ref, got, kept, &rmse, &p99);
        fprintf(csv, "%g,%d,%zu,%zu,%zu,%d,%.6f,%.6f,%.3f\n", (double)texels[t], ls.atlas_size,
                ls.atlases, ls.texels * 4, ls.samples, kept, rmse, p99, ls.seconds);
    }
    printf("lightmap: %s (%d surface receivers)\n", path, kept);
    code = CLI_OK;
done:
    if (csv)
        fclose(csv);
    if (json)
        fclose(json);
    vdbgi_lightmap_result_destroy(res);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
    free(prims);
    free(uv);
    free(ref);
    free(got);
    free(bf);
    return code;
}
