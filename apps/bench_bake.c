/* bench_bake.c: gi-bench bake: the bake against a bare Embree loop over the same rays, and the
   whole gi-bake process. */
#define _DEFAULT_SOURCE /* mkstemps */
#include "bench.h"
#include "bench_lights.h"
#include "cli.h"
#include "vdbgi.h"
#include "vdbgi_bench.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

static const char *const method_names[] = {"auto", "rtcIntersect1", "packet 8", "packet 16",
                                           "stream 1M"};

int bench_bake(const bench_options *o, const char *argv0)
{
    /* gi-bake lives beside gi-bench unless told otherwise. */
    char gi_bake[PATH_MAX];
    if (o->gi_bake) {
        snprintf(gi_bake, sizeof(gi_bake), "%s", o->gi_bake);
    } else {
        const char *const slash = strrchr(argv0, '/');
        snprintf(gi_bake, sizeof(gi_bake), "%.*sgi-bake", slash ? (int)(slash - argv0 + 1) : 0,
                 argv0);
    }
    char out[PATH_MAX];
    snprintf(out, sizeof(out), "%s", o->out ? o->out : "/tmp/gi-bench-XXXXXX.vdb");
    if (!o->out) {
        const int fd = mkstemps(out, 4);
        if (fd < 0) {
            cli_error("cannot make a temporary file: %s", out);
            return CLI_FAILED;
        }
        close(fd);
    }

    /* The whole gi-bake process with its default (auto) query shape, first: a child's peak
       memory (wait4's ru_maxrss) counts what its parent held when it was spawned, and this
       process holds little before it loads the scene. */
    char spacing[32], rays[32], threads[32];
    snprintf(spacing, sizeof(spacing), "%g", o->spacing);
    snprintf(rays, sizeof(rays), "%d", o->rays);
    snprintf(threads, sizeof(threads), "%d", o->threads);
    char scene_arg[PATH_MAX], o_flag[] = "-o", q_flag[] = "-q", spacing_flag[] = "--spacing",
                              rays_flag[] = "--rays", threads_flag[] = "--threads";
    snprintf(scene_arg, sizeof(scene_arg), "%s", o->scene);
    /* The light model of the in-process rows (the library's default), not gi-bake's physical
       one, which traces other rays. Then the same with L2 terms, run in turn with it: its
       time and peak memory against it. */
    char basis_flag[] = "--basis", sh2[] = "sh2", model_flag[] = "--model", seed[] = "seed";
    char *const bake_argv[] = {gi_bake, scene_arg,  o_flag, out,
                               q_flag,  model_flag, seed,   spacing_flag,
                               spacing, rays_flag,  rays,   o->threads ? threads_flag : NULL,
                               threads, NULL};
    char *sh2_argv[16]; /* the same, --basis sh2 before the spacing */
    memcpy(sh2_argv, bake_argv, 7 * sizeof(char *));
    sh2_argv[7] = basis_flag, sh2_argv[8] = sh2;
    memcpy(&sh2_argv[9], &bake_argv[7], 7 * sizeof(char *));
    double process = -1.0, process_sh2 = -1.0, peak = 0.0, peak_sh2 = 0.0;
    for (int rep = 0; rep < o->repeat; rep++) {
        double mb, mb_sh2;
        const double t = bench_time_process(bake_argv, &mb);
        const double t_sh2 = t < 0.0 ? t : bench_time_process(sh2_argv, &mb_sh2);
        if (t < 0.0 || t_sh2 < 0.0) {
            cli_error("%s failed on %s", gi_bake, o->scene);
            if (!o->out)
                unlink(out);
            return CLI_FAILED;
        }
        process = rep == 0 || t < process ? t : process;
        process_sh2 = rep == 0 || t_sh2 < process_sh2 ? t_sh2 : process_sh2;
        peak = mb > peak ? mb : peak; /* the same every run, but for the allocator's luck */
        peak_sh2 = mb_sh2 > peak_sh2 ? mb_sh2 : peak_sh2;
    }

    vdbgi_context *const ctx = cli_context();
    vdbgi_scene *scene = NULL;
    vdbgi_probes *probes = NULL;
    if (!ctx)
        return CLI_FAILED;
    int code = CLI_FAILED;
    vdbgi_result r = vdbgi_scene_load(ctx, o->scene, &scene);
    const vdbgi_place_desc pd = {.spacing = o->spacing};
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
    for (int rep = 0; rep < o->repeat; rep++) {
        for (int m = VDBGI_TRACE_SINGLE; m <= VDBGI_TRACE_STREAM; m++) {
            const vdbgi_bake_desc bd = {
                .rays = o->rays, .threads = o->threads, .trace_method = (vdbgi_trace_method)m};
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
    /* The directional bases on the default query shape, against the scalar bake beside them. */
    double scalar_auto = 0.0, cube_auto = 0.0, sh2_auto = 0.0;
    for (int rep = 0; rep < o->repeat; rep++) {
        vdbgi_bake_desc bd = {.rays = o->rays, .threads = o->threads};
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
        bd.basis = VDBGI_BASIS_SH2;
        if ((r = vdbgi_probes_bake(probes, scene, &bd, &s)) != VDBGI_OK) {
            code = cli_fail(ctx, r);
            goto done;
        }
        sh2_auto = rep == 0 || s.seconds < sh2_auto ? s.seconds : sh2_auto;
    }
    int best = VDBGI_TRACE_SINGLE;
    for (int m = VDBGI_TRACE_SINGLE; m <= VDBGI_TRACE_STREAM; m++)
        best = bare[m] < bare[best] ? m : best;

    vdbgi_probes_get_info(probes, &pi); /* now baked: invalid count known */
    const double nrays = (double)(st.primary_ray_count + st.shadow_ray_count);
    char buf[32];
    printf("### %s: %zu triangles, %g m spacing, %d rays per probe, %d threads\n\n", si.name,
           si.triangle_count, o->spacing, o->rays, st.threads);
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
    printf("| bake in-process, auto, scalar (paired with the next two rows) | %.3f | %.2f | %.0f | "
           "%.3f "
           "|\n",
           scalar_auto, nrays / scalar_auto * 1e-6, (double)pi.probe_count / scalar_auto,
           bare[best] / scalar_auto);
    printf("| bake in-process, auto, ambient cube | %.3f | %.2f | %.0f | %.3f |\n", cube_auto,
           nrays / cube_auto * 1e-6, (double)pi.probe_count / cube_auto, bare[best] / cube_auto);
    printf("| bake in-process, auto, L2 (sh2) | %.3f | %.2f | %.0f | %.3f |\n", sh2_auto,
           nrays / sh2_auto * 1e-6, (double)pi.probe_count / sh2_auto, bare[best] / sh2_auto);
    printf("| **gi-bake process** (load, topology, trace, write) | %.3f | %.2f | %.0f | **%.3f** "
           "|\n",
           process, nrays / process * 1e-6, (double)pi.probe_count / process, bare[best] / process);
    printf("| gi-bake process, --basis sh2 (paired with the row above) | %.3f | %.2f | %.0f | %.3f "
           "|\n\n",
           process_sh2, nrays / process_sh2 * 1e-6, (double)pi.probe_count / process_sh2,
           bare[best] / process_sh2);
    printf("The whole gi-bake process with L2 terms takes %.2fx the scalar's time and %.2fx its "
           "peak memory (%.0f MiB against %.0f MiB, the largest of %d runs each).\n\n",
           process_sh2 / process, peak_sh2 / peak, peak_sh2, peak, o->repeat);
    struct stat fs;
    printf("Fastest bare loop: %s. Ambient cubes cost %.1f%%, L2 terms %.1f%% of the scalar "
           "bake. gi-bake wrote a %s .vdb with L2 terms.\n\n",
           method_names[best], 100.0 * (cube_auto / scalar_auto - 1.0),
           100.0 * (sh2_auto / scalar_auto - 1.0),
           stat(out, &fs) == 0 ? cli_bytes((double)fs.st_size, buf, sizeof(buf)) : "?");
    code = CLI_OK;
done:
    if (!o->out)
        unlink(out);
    vdbgi_probes_destroy(probes);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
    return code;
}
