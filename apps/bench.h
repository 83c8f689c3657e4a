/* bench.h: what gi-bench's subcommands share: the options, helpers and one entry each. */
#ifndef VDBGI_BENCH_H
#define VDBGI_BENCH_H

#include "bench_truth.h"
#include "vdbgi.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef struct bench_options {
    const char *mode, *scene, *gi_bake, *out;
    double spacing;
    bool spacing_given;
    int rays, threads, repeat;
    bench_light light;
} bench_options;

/*
 * Wall seconds of running argv to completion, or -1 if it failed; with
 * peak_mb not NULL, the child's peak resident memory (MiB) too.
 */
double bench_time_process(char *const argv[], double *peak_mb);
/* A built volume's figures with its file's size: its file made (gzip happens on write). */
void bench_info(const vdbgi_volume *v, vdbgi_volume_info *vi);
/* --out, build/chart by default, made when missing; NULL (said on stderr) when it cannot be. */
const char *bench_out_dir(const bench_options *o);
/*
 * --out (as bench_out_dir), a context and o->scene loaded: CLI_OK, or the
 * exit code, said on stderr, with nothing left to free.
 */
int bench_open_scene(const bench_options *o, const char **dir, vdbgi_context **ctx,
                     vdbgi_scene **scene);
/* dir/name opened for writing with its header line, or NULL (said on stderr). */
FILE *bench_open_csv(const char *dir, const char *name, const char *header);
/* RMSE and p99 of b against a over n RGB values, relative to a's mean. */
void bench_compare(const float *a, const float *b, size_t n, double *rmse_rel, double *p99_rel);
/* A tool beside gi-bench (argv0's directory) into out. */
void bench_beside(const char *argv0, const char *tool, char *out, size_t cap);

/* The subcommands (gi-bench --help); each returns the exit code. */
int bench_bake(const bench_options *o, const char *argv0);
int bench_convert(const bench_options *o);
int bench_sweep(const bench_options *o);
int bench_rays(const bench_options *o);
/*
 * gi-bench rays' table on a loaded scene: probes at spacing, under light (NULL:
 * the seed model), into dir/rays.csv; the exit code.
 */
int bench_rays_table(vdbgi_context *ctx, const vdbgi_scene *scene, double spacing,
                     const bench_light *light, const char *dir);
/* gi-bench texel-rays: the same for a lightmap's texels (--spacing: the texel, 0.5 m). */
int bench_texel_rays(const bench_options *o);
int bench_memory(const bench_options *o, bool one_spacing);
int bench_lightmap(const bench_options *o, const char *argv0);

#endif /* VDBGI_BENCH_H */
