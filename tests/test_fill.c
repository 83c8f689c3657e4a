/*
 * test_fill.c: the fill over the fine lattice and over a dense box: values
 * spread ring by ring with face, edge and corner weights; an invalid probe in
 * a thin wall takes one neighbour for every channel; leaves and cells come in
 * OpenVDB's tree order; the bytes do not depend on the thread count.
 */
#include "check.h"
#include "context.h"
#include "field.h"

#include <stdlib.h>
#include <string.h>

static vdbgi_context *make_context(void)
{
    vdbgi_context *ctx = NULL;
    vdbgi_context_create(NULL, &ctx);
    return ctx;
}

/* Fill points with the default parameters (mean unless darkest) and return the field. */
static vdbgi_result fill(vdbgi_context *ctx, const int32_t *ijk, const float *values,
                         const float *backface, size_t count, int channels, bool darkest,
                         int threads, vdbgi_field *field, int32_t **cells, size_t *cell_count,
                         size_t *unreached)
{
    vdbgi_fill_params fp =
        vdbgi_fill_params_default(0.25f, darkest ? VDBGI_FILL_DARKEST : VDBGI_FILL_MEAN, threads);
    const vdbgi_fill_input in = {
        .count = count, .ijk = ijk, .values = values, .backface = backface, .channels = channels};
    return vdbgi_field_fill(ctx, &in, &fp, field, cells, cell_count, NULL, NULL, unreached);
}

/* The cells a source's filter reaches: its own, and the next one where it sits within a
   point of a face (rim 1), for a source inside a cell, on a face and at a corner. */
static void one_source_reaches_the_cells_whose_filter_reads_it(void)
{
    static const struct {
        int32_t ijk[3];
        size_t cells;
    } cases[] = {{{1, 2, 1}, 1}, {{1, 2, 3}, 2}, {{4, 3, -1}, 8}};
    for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
        vdbgi_context *const ctx = make_context();
        const float rgb[3] = {0.25f, 0.5f, 2.0f}, bf = 0.0f;
        vdbgi_field f;
        int32_t *cells = NULL;
        size_t cell_count = 0, unreached = 1;
        CHECK_RESULT(
            ctx,
            fill(ctx, cases[c].ijk, rgb, &bf, 1, 1, true, 0, &f, &cells, &cell_count, &unreached),
            VDBGI_OK);
        CHECK(cell_count == cases[c].cells);
        CHECK(unreached == 0);
        /* Every point of those cells and a rim of one: (4 n + 2) along each axis. */
        size_t points = 0, want = 1;
        for (size_t l = 0; l < f.leaf_count; l++)
            for (int w = 0; w < 8; w++)
                points += (size_t)__builtin_popcountll(f.leaves[l].mask[w]);
        for (int k = 0; k < 3; k++) {
            const int32_t p = cases[c].ijk[k];
            const int32_t n = vdbgi_floor_div(p + 1, 4) - vdbgi_floor_div(p - 1, 4) + 1;
            want *= (size_t)(4 * n + 2);
        }
        CHECK(points == want);
        /* One source: every point takes its colour exactly, however far. */
        int32_t lo[3], hi[3], past[3];
        for (int k = 0; k < 3; k++) {
            lo[k] = 4 * vdbgi_floor_div(cases[c].ijk[k] - 1, 4) - 1;
            hi[k] = 4 * vdbgi_floor_div(cases[c].ijk[k] + 1, 4) + 4;
            past[k] = hi[k];
        }
        past[0] = hi[0] + 1;
        const float *const a = vdbgi_field_at(&f, lo, NULL);
        const float *const b = vdbgi_field_at(&f, hi, NULL);
        CHECK(a && a[0] == rgb[0] && a[1] == rgb[1] && a[2] == rgb[2]);
        CHECK(b && b[0] == rgb[0] && b[1] == rgb[1] && b[2] == rgb[2]);
        CHECK(vdbgi_field_at(&f, past, NULL) == NULL);
        vdbgi_free(ctx, cells);
        vdbgi_field_free(&f);
        vdbgi_context_destroy(ctx);
    }
}

static void a_ring_takes_the_weighted_mean_of_its_valued_neighbours(void)
{
    vdbgi_context *const ctx = make_context();
    /* Two sources along x, two apart: the point between has them as face neighbours
       (weight 1 each); the point beside it has them as edge neighbours (1/2 each). */
    const int32_t ijk[6] = {0, 0, 0, 2, 0, 0};
    const float rgb[6] = {1.0f, 1.0f, 1.0f, 4.0f, 4.0f, 4.0f}, bf[2] = {0.0f, 0.0f};
    vdbgi_field f;
    int32_t *cells = NULL;
    size_t cell_count = 0, unreached = 0;
    CHECK_RESULT(ctx, fill(ctx, ijk, rgb, bf, 2, 1, false, 1, &f, &cells, &cell_count, &unreached),
                 VDBGI_OK);
    const int32_t mid[3] = {1, 0, 0}, side[3] = {1, 1, 0};
    const float *const m = vdbgi_field_at(&f, mid, NULL);
    const float *const s = vdbgi_field_at(&f, side, NULL);
    CHECK(m && s);
    if (m && s) {
        CHECK_NEAR(m[0], 2.5, 1e-6);
        /* (1,1,0) is in the first ring too: its valued neighbours are the two sources, diagonal. */
        CHECK_NEAR(s[0], 2.5, 1e-6);
    }
    const int32_t next[3] = {1, 2, 0}; /* second ring: from (0..2, 1, 0), all valued by then */
    const float *const n = vdbgi_field_at(&f, next, NULL);
    CHECK(n != NULL);
    if (n) {
        /* Ring one is every point next to a source (y <= 1 here), so (1,2,0) draws on
           its nine neighbours at y = 1, weighted by face (1), edge (1/2) or corner (1/3). */
        double sum = 0.0, wsum = 0.0;
        static const float w[4] = {0.0f, 1.0f, 0.5f, 1.0f / 3.0f};
        for (int dz = -1; dz <= 1; dz++)
            for (int dx = -1; dx <= 1; dx++) {
                const int32_t q[3] = {next[0] + dx, 1, next[2] + dz};
                const int k = abs(dx) + 1 + abs(dz);
                const float *const v = vdbgi_field_at(&f, q, NULL);
                CHECK(v != NULL);
                if (v) {
                    sum += (double)v[0] * w[k];
                    wsum += w[k];
                }
            }
        CHECK_NEAR(n[0], sum / wsum, 1e-6);
    }
    vdbgi_free(ctx, cells);
    vdbgi_field_free(&f);
    vdbgi_context_destroy(ctx);
}

static void an_invalid_probe_in_a_wall_takes_one_neighbour_for_every_channel(void)
{
    vdbgi_context *const ctx = make_context();
    /* Two channels. The lit side (-x) is bright in channel 1, dim in channel 0; the
       dark side (+x) the other way round but darker over all. Per channel, darkest would
       mix the two; one choice takes the +x neighbour for both. */
    const int32_t ijk[9] = {-1, 0, 0, 1, 0, 0, 0, 0, 0};
    const float values[18] = {0.1f, 0.1f, 0.1f, 9.0f, 9.0f, 9.0f, 0.5f, 0.5f, 0.5f,
                              0.2f, 0.2f, 0.2f, 7.0f, 7.0f, 7.0f, 7.0f, 7.0f, 7.0f};
    const float bf[3] = {0.0f, 0.0f, 1.0f};
    vdbgi_field f;
    int32_t *cells = NULL;
    size_t cell_count = 0, unreached = 0;
    CHECK_RESULT(ctx,
                 fill(ctx, ijk, values, bf, 3, 2, true, 0, &f, &cells, &cell_count, &unreached),
                 VDBGI_OK);
    const int32_t wall[3] = {0, 0, 0};
    const float *const v = vdbgi_field_at(&f, wall, NULL);
    CHECK(v != NULL);
    if (v)
        for (int i = 0; i < 6; i++)
            CHECK(v[i] == values[6 + i]);
    vdbgi_free(ctx, cells);
    vdbgi_field_free(&f);
    /* The mean fill ignores the wall: face weights 1 each. */
    CHECK_RESULT(ctx,
                 fill(ctx, ijk, values, bf, 3, 2, false, 0, &f, &cells, &cell_count, &unreached),
                 VDBGI_OK);
    const float *const m = vdbgi_field_at(&f, wall, NULL);
    CHECK(m != NULL);
    if (m) {
        CHECK_NEAR(m[0], 0.3, 1e-6);
        CHECK_NEAR(m[3], 4.6, 1e-6);
    }
    vdbgi_free(ctx, cells);
    vdbgi_field_free(&f);
    vdbgi_context_destroy(ctx);
}

static void leaves_and_cells_come_in_tree_order(void)
{
    /* 4096-blocks first (x, then y, then z), then 128-blocks, 8-blocks and points. */
    const int32_t a[3] = {-1, 5000, 5000}, b[3] = {0, -5000, -5000};
    CHECK(vdbgi_tree_order(a, b) < 0);
    const int32_t c[3] = {8, 0, 0}, d[3] = {0, 200, 0};
    CHECK(vdbgi_tree_order(c, d) < 0); /* one 4096-block; d's 128-block is later in y */
    const int32_t e[3] = {0, 0, 9}, g[3] = {1, 0, 0};
    CHECK(vdbgi_tree_order(e, g) > 0); /* leaf (0,0,1) after leaf (0,0,0) */
    CHECK(vdbgi_tree_order(a, a) == 0);

    vdbgi_context *const ctx = make_context();
    const int32_t ijk[9] = {5000, 0, 0, -3000, 7, 0, 0, 0, -9};
    const float rgb[9] = {1, 1, 1, 2, 2, 2, 3, 3, 3}, bf[3] = {0, 0, 0};
    vdbgi_field f;
    int32_t *cells = NULL;
    size_t cell_count = 0, unreached = 0;
    CHECK_RESULT(ctx, fill(ctx, ijk, rgb, bf, 3, 1, true, 0, &f, &cells, &cell_count, &unreached),
                 VDBGI_OK);
    CHECK(cell_count == 3 * 8); /* each source on a face of its cell along every axis */
    for (size_t i = 1; i < cell_count; i++)
        CHECK(vdbgi_tree_order(&cells[3 * (i - 1)], &cells[3 * i]) < 0);
    for (size_t l = 1; l < f.leaf_count; l++)
        CHECK(vdbgi_tree_order(f.leaves[l - 1].origin, f.leaves[l].origin) < 0);
    vdbgi_free(ctx, cells);
    vdbgi_field_free(&f);
    vdbgi_context_destroy(ctx);
}

static void the_field_does_not_depend_on_the_thread_count(void)
{
    /* A sparse random cloud of sources and invalid probes over a 64^3 box: rings of
       tens of thousands of points, split over threads. */
    enum { N = 3000 };
    int32_t *const ijk = malloc(sizeof(int32_t) * 3 * N);
    float *const values = malloc(sizeof(float) * 18 * N);
    float *const bf = malloc(sizeof(float) * N);
    uint32_t s = 12345;
    for (size_t i = 0; i < N; i++) {
        for (int k = 0; k < 3; k++)
            ijk[3 * i + k] = (int32_t)((s = s * 1664525u + 1013904223u) >> 26) - 32;
        for (int k = 0; k < 18; k++)
            values[18 * i + k] = (float)((s = s * 1664525u + 1013904223u) >> 8) / 16777216.0f;
        bf[i] = (s = s * 1664525u + 1013904223u) >> 30 ? 0.0f : 1.0f;
    }
    vdbgi_context *const ctx = make_context();
    vdbgi_field f[3];
    int32_t *cells[3] = {NULL, NULL, NULL};
    size_t cell_count[3], unreached[3];
    const int threads[3] = {1, 2, 5};
    for (int t = 0; t < 3; t++)
        CHECK_RESULT(ctx,
                     fill(ctx, ijk, values, bf, N, 6, true, threads[t], &f[t], &cells[t],
                          &cell_count[t], &unreached[t]),
                     VDBGI_OK);
    for (int t = 1; t < 3; t++) {
        CHECK(f[t].leaf_count == f[0].leaf_count && cell_count[t] == cell_count[0]);
        if (f[t].leaf_count != f[0].leaf_count)
            continue;
        for (size_t l = 0; l < f[0].leaf_count; l++) {
            CHECK(memcmp(f[t].leaves[l].mask, f[0].leaves[l].mask, 64) == 0);
            CHECK(memcmp(f[t].leaves[l].values, f[0].leaves[l].values,
                         VDBGI_LEAF_VOXELS * 18 * sizeof(float)) == 0);
        }
    }
    for (int t = 0; t < 3; t++) {
        vdbgi_free(ctx, cells[t]);
        vdbgi_field_free(&f[t]);
    }
    vdbgi_context_destroy(ctx);
    free(ijk);
    free(values);
    free(bf);
}

static void the_dense_fill_reaches_every_point_of_the_box(void)
{
    vdbgi_context *const ctx = make_context();
    const int res[3] = {11, 3, 9};
    const size_t n = 11 * 3 * 9;
    float *const values = calloc(n, 3 * sizeof(float));
    unsigned char *const valued = calloc(n, 1);
    values[0] = values[1] = values[2] = 2.0f; /* one corner valued */
    valued[0] = 1;
    const vdbgi_fill_params fp = vdbgi_fill_params_default(0.25f, VDBGI_FILL_AUTO, 0);
    CHECK_RESULT(ctx, vdbgi_fill_dense(ctx, res, 1, values, valued, &fp), VDBGI_OK);
    size_t reached = 0;
    for (size_t i = 0; i < n; i++) {
        reached += valued[i];
        CHECK(values[3 * i] == 2.0f);
    }
    CHECK(reached == n);
    free(values);
    free(valued);
    vdbgi_context_destroy(ctx);
}

static void no_source_is_refused(void)
{
    vdbgi_context *const ctx = make_context();
    const int32_t ijk[3] = {0, 0, 0};
    const float rgb[3] = {1, 1, 1}, bf = 1.0f;
    vdbgi_field f;
    int32_t *cells = NULL;
    size_t cell_count = 0, unreached = 0;
    CHECK_RESULT(ctx, fill(ctx, ijk, rgb, &bf, 1, 1, true, 0, &f, &cells, &cell_count, &unreached),
                 VDBGI_ERR_FORMAT);
    CHECK(strstr(vdbgi_context_error(ctx), "no valid probe") != NULL);
    CHECK(cells == NULL && f.leaves == NULL);
    CHECK_RESULT(ctx,
                 fill(ctx, ijk, rgb, &bf, 1, VDBGI_FIELD_MAX_CHANNELS + 1, true, 0, &f, &cells,
                      &cell_count, &unreached),
                 VDBGI_ERR_INVALID_ARG);
    vdbgi_context_destroy(ctx);
}

int main(void)
{
    RUN(one_source_reaches_the_cells_whose_filter_reads_it);
    RUN(a_ring_takes_the_weighted_mean_of_its_valued_neighbours);
    RUN(an_invalid_probe_in_a_wall_takes_one_neighbour_for_every_channel);
    RUN(leaves_and_cells_come_in_tree_order);
    RUN(the_field_does_not_depend_on_the_thread_count);
    RUN(the_dense_fill_reaches_every_point_of_the_box);
    RUN(no_source_is_refused);
    return CHECK_EXIT();
}
