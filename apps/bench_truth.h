/* bench_truth.h: gi-bench truth, every method against the hemisphere estimator. */
#ifndef VDBGI_BENCH_TRUTH_H
#define VDBGI_BENCH_TRUTH_H

#include "vdbgi.h"

#include <stdbool.h>
#include <stddef.h>

/* Receivers and what the truth says there; kinds: 0 floor, 1 wall, 2 other, 3 character. */
typedef struct bench_receivers {
    size_t surface, count;       /* surface receivers first, then character ones */
    float *pos, *normal, *truth; /* truth: E, the hemisphere estimator at 2048 rays */
    uint32_t *prim;
    float *uv;
    unsigned char *kind;
} bench_receivers;

/* The light model every method and the truth share (gi-bench truth --model, --bounces). */
typedef struct bench_light {
    vdbgi_model model;
    int bounces; /* a lightmap's passes */
} bench_light;

/*
 * 3000 points on the scene's surfaces spread by area, each with its
 * triangle's front normal, and 400 character points 0.5-2 m over walkable
 * ones, each read by six normals (up, the four horizontal, down); those whose
 * rays mostly meet back faces (inside solids) dropped.
 */
/* d under light's model and bounces, counted (never auto); NULL: d as it is. */
vdbgi_bake_desc bench_lit(vdbgi_bake_desc d, const bench_light *light);

vdbgi_result bench_receivers_make(const vdbgi_scene *scene, const bench_light *light,
                                  bench_receivers *rv);
void bench_receivers_free(bench_receivers *rv);

/* RMSE over the truth's mean, and the mean read over the mean truth. */
typedef struct bench_error {
    double rmse, bias;
    size_t n;
} bench_error;

/* got (E, 3 floats a receiver) against the truth over one kind (< 0: every surface one). */
bench_error bench_error_of(const bench_receivers *rv, const float *got, int kind);

/*
 * What a volume gives every receiver, as E: a scalar one at the point; one
 * with L2 terms with the receiver's normal, a surface's point moved half a
 * spacing along it first (as the shaders read it).
 */
void bench_volume_reading(const vdbgi_volume *v, const bench_receivers *rv, float *got);

/* Run it on the scene at path; one spacing when spacing_given, else 0.5 and 0.25 m. */
int bench_truth(const char *scene, double spacing, bool spacing_given, int rays, int threads,
                const bench_light *light, const char *out);

#endif /* VDBGI_BENCH_TRUTH_H */
