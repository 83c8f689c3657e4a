/*
 * test_bricks.c: the bricked volume gives back what was baked (the
 * coarsening and its accuracy). With no coarsening every valid probe reads
 * back within the encoding's step; aprons make brick boundaries invisible; a
 * larger eps never grows the atlas; a flat field becomes a few level-3
 * bricks and a linear one stays coarse under the interpolation criterion;
 * Unreal's RMSE rule never keeps more bricks than the max-error one; at eps
 * 0 every layout and criterion gives back every probe; compact bricks share
 * atlas texels only where they agree; invalid probes never leak. Which cells
 * get bricks: test_bricks_cells.c; files: test_bricks_files.c; L2 terms:
 * test_bricks_l2.c.
 */
#define _POSIX_C_SOURCE 200809L
#include "test_bricks.h"
#include "encode.h"
#include "field.h"
#include "gifile.h"
#include "image_shim.h"
#include "test_slab.h"
#include "test_util.h"
#include "util.h"

#include <math.h>
#include <stdio.h>
#include <unistd.h>

/* The seed layout, for the tests written against its 6^3 slots (the default is compact). */
static const vdbgi_convert_desc seed_layout = {.layout = VDBGI_LAYOUT_SEED};

static float ramp(double x, double y, double z, int c)
{
    (void)y, (void)z;
    return (float)(0.05 + 0.01 * x + 0.001 * c);
}

/* Trilinear interpolation of f between lattice points: what the probes alone say. */
static float lattice_trilinear(field_fn f, const double q[3], int c)
{
    const double x0 = floor(q[0]), y0 = floor(q[1]), z0 = floor(q[2]);
    const double fx = q[0] - x0, fy = q[1] - y0, fz = q[2] - z0;
    double v = 0.0;
    for (int i = 0; i < 8; i++) {
        const double w = (i & 1 ? fx : 1 - fx) * (i & 2 ? fy : 1 - fy) * (i & 4 ? fz : 1 - fz);
        v += w * f(x0 + (i & 1), y0 + (i >> 1 & 1), z0 + (i >> 2 & 1), c);
    }
    return (float)v;
}

/* The largest error of v at p's probes, in units of one encoding step of each probe's value. */
static double worst_probe_error_in_steps(const vdbgi_probes *p, const vdbgi_volume *v,
                                         vdbgi_encoding encoding)
{
    double worst = 0.0;
    for (size_t i = 0; i < p->count; i++) {
        const double q[3] = {p->ijk[3 * i], p->ijk[3 * i + 1], p->ijk[3 * i + 2]};
        float pos[3], got[3];
        world_of(p, q, pos);
        vdbgi_volume_sample(v, pos, got);
        const float *const want = &p->rgb[3 * i];
        const float mx = fmaxf(want[0], fmaxf(want[1], want[2]));
        /* One RGBM step of this texel (M rounded up adds at most 8/255), or 2^-9. */
        const float step =
            encoding == VDBGI_ENCODING_RGBM ? (mx + 8.0f / 255.0f) / 255.0f : mx / 512.0f;
        for (int k = 0; k < 3; k++)
            worst = fmax(worst, fabs(got[k] - want[k]) / step);
    }
    return worst;
}

static void exact_bricks_give_back_every_valid_probe(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 20, 9, 13, smooth);
    for (int run = 0; run < 4; run++) {
        const int e = run % 2;
        const vdbgi_convert_desc d = {.eps_is_set = 1,
                                      .max_level_is_set = 1,
                                      .encoding = (vdbgi_encoding)e,
                                      .layout = (vdbgi_layout)(1 + run / 2)};
        vdbgi_volume *v = NULL;
        CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v), VDBGI_OK);
        if (!v)
            continue;
        vdbgi_volume_info info;
        vdbgi_volume_get_info(v, &info);
        CHECK(info.bricks[1] == 0 && info.bricks[0] == info.brick_count);
        CHECK(worst_probe_error_in_steps(p, v, (vdbgi_encoding)e) <= 1.0);
        CHECK(info.rmse <= 0.004 * info.mean_irradiance);
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

static void aprons_hide_brick_boundaries(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 40, 10, 24, smooth);
    const vdbgi_convert_desc d = {
        .layout = VDBGI_LAYOUT_SEED, .eps_is_set = 1, .max_level_is_set = 1};
    vdbgi_volume *v = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v), VDBGI_OK);
    if (v) {
        /* Lines crossing many level-0 brick boundaries (every 4 probes) on all axes. */
        double worst = 0.0;
        for (int axis = 0; axis < 3; axis++)
            for (double t = 1.0; t <= (axis == 1 ? 7.0 : 20.0); t += 0.0625) {
                double q[3] = {13.3, 4.6, 10.7};
                q[axis] = t;
                float pos[3], got[3];
                world_of(p, q, pos);
                vdbgi_volume_sample(v, pos, got);
                for (int k = 0; k < 3; k++) {
                    const float want = lattice_trilinear(smooth, q, k);
                    const float step = (0.35f + 8.0f / 255.0f) / 255.0f;
                    worst = fmax(worst, fabs(got[k] - want) / step);
                }
            }
        CHECK(worst <= 1.0);
        /* Without aprons a sample beside a boundary would blend the neighbouring slot. */
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

static void larger_eps_never_grows_the_atlas(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 64, 10, 48, smooth);
    const float eps[] = {0.0f, 0.01f, 0.03f, 0.1f, 0.3f, 1.0f, 3.0f};
    for (int c = VDBGI_CRITERION_RANGE; c <= VDBGI_CRITERION_RMSE; c++) {
        size_t last_atlas = SIZE_MAX, last_bricks = SIZE_MAX;
        double last_rmse = 0.0;
        for (size_t i = 0; i < sizeof(eps) / sizeof(eps[0]); i++) {
            const vdbgi_convert_desc d = {.layout = VDBGI_LAYOUT_SEED,
                                          .eps = eps[i],
                                          .eps_is_set = 1,
                                          .criterion = (vdbgi_criterion)c};
            vdbgi_volume *v = NULL;
            CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v), VDBGI_OK);
            if (!v)
                continue;
            vdbgi_volume_info info;
            vdbgi_volume_get_info(v, &info);
            CHECK(info.atlas_size <= last_atlas);
            CHECK(info.brick_count <= last_bricks);
            CHECK(info.rmse >= last_rmse * 0.999);
            last_atlas = info.atlas_size;
            last_bricks = info.brick_count;
            last_rmse = info.rmse;
            vdbgi_volume_destroy(v);
        }
        CHECK(last_bricks == 4 * 2 * 3); /* eps 3: one brick per level-3 block */
    }
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

/*
 * Unreal's rule (rmse) passes every block the max-error rule (interp) passes,
 * so at one eps it never keeps more bricks, and on a bending field it keeps
 * fewer; at eps 0 both keep only blocks they reproduce exactly: the same
 * textures.
 */
static void rmse_criterion_coarsens_at_least_as_much_as_interp(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 64, 10, 48, smooth);
    const float eps[] = {0.0f, 0.01f, 0.03f, 0.1f, 0.3f};
    bool fewer = false;
    for (size_t i = 0; i < sizeof(eps) / sizeof(eps[0]); i++) {
        vdbgi_volume *v[2] = {NULL, NULL};
        vdbgi_volume_info info[2];
        for (int c = 0; c < 2; c++) {
            const vdbgi_convert_desc d = {.layout = VDBGI_LAYOUT_SEED,
                                          .eps = eps[i],
                                          .eps_is_set = 1,
                                          .criterion =
                                              c ? VDBGI_CRITERION_RMSE : VDBGI_CRITERION_INTERP};
            CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v[c]), VDBGI_OK);
            if (v[c])
                vdbgi_volume_get_info(v[c], &info[c]);
        }
        if (v[0] && v[1]) {
            CHECK(info[1].brick_count <= info[0].brick_count);
            fewer |= info[1].brick_count < info[0].brick_count;
            if (i == 0) {
                const size_t n = vdbgi_volume_copy_atlas(v[0], NULL, 0);
                uint8_t *const a = malloc(n), *const b = malloc(n);
                CHECK(n == vdbgi_volume_copy_atlas(v[1], NULL, 0) && a && b &&
                      vdbgi_volume_copy_atlas(v[0], a, n) == n &&
                      vdbgi_volume_copy_atlas(v[1], b, n) == n && memcmp(a, b, n) == 0);
                free(a);
                free(b);
            }
        }
        vdbgi_volume_destroy(v[0]);
        vdbgi_volume_destroy(v[1]);
    }
    CHECK(fewer);
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

/*
 * At eps 0 every layout and criterion gives back every valid probe within the
 * encoding's step, whatever the max level: a coarse brick survives only where
 * it is exact.
 */
static void at_eps_0_every_layout_returns_every_probe(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 40, 10, 24, ramp);
    for (int run = 0; run < 6; run++) {
        const vdbgi_convert_desc d = {.eps_is_set = 1,
                                      .layout = (vdbgi_layout)(1 + run % 2),
                                      .criterion = (vdbgi_criterion)(1 + run / 2)};
        vdbgi_volume *v = NULL;
        CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v), VDBGI_OK);
        if (!v)
            continue;
        const double worst = worst_probe_error_in_steps(p, v, VDBGI_ENCODING_RGBM);
        CHECK(worst <= 1.0);
        if (worst > 1.0)
            fprintf(stderr, "# layout %d criterion %d: %.2f steps\n", run % 2, 1 + run / 2, worst);
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

/*
 * Compact bricks overlap in the atlas only where they hold the same lattice
 * point at the same level (a border plane and its neighbour's first plane),
 * and they do overlap: the atlas is smaller than 5^3 texels a brick. The
 * block of zeros at texel 0, which empty cells read, belongs to no brick.
 */
static void compact_bricks_share_only_texels_they_agree_on(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 64, 10, 48, smooth);
    for (int run = 0; run < 2; run++) {
        const vdbgi_convert_desc d = {.layout = VDBGI_LAYOUT_COMPACT, .eps = run ? 0.3f : 0.05f};
        vdbgi_volume *v = NULL;
        CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v), VDBGI_OK);
        if (!v)
            continue;
        const uint32_t *const ad = v->info.atlas_dims, *const id = v->info.ind_dims;
        const size_t texels = (size_t)ad[0] * ad[1] * ad[2];
        int64_t *const owner = calloc(texels, sizeof(*owner)); /* 0: none, else point id + 1 */
        size_t painted = 0, brick_texels = 0, conflicts = 0, bricks = 0, levels = 0;
        for (uint32_t z = 0; z < id[2]; z++)
            for (uint32_t y = 0; y < id[1]; y++)
                for (uint32_t x = 0; x < id[0]; x++) {
                    const uint8_t *const t =
                        &v->tex.indirection[4 * (((size_t)z * id[1] + y) * id[0] + x)];
                    if (!(t[0] | t[1] | t[2] | t[3]))
                        continue;
                    const int level = t[3] & 3, span = 1 << level;
                    const uint32_t c[3] = {x, y, z};
                    if (x % span || y % span || z % span)
                        continue; /* each brick once, from its first cell */
                    bricks++;
                    levels |= 1u << level;
                    for (int q = 0; q < 125; ++q) {
                        const int qq[3] = {q % 5, q / 5 % 5, q / 25};
                        size_t a[3];
                        int64_t point = level;
                        for (int k = 0; k < 3; k++) {
                            a[k] = 4u * t[k] + (t[3] >> (2 + 2 * k) & 3u) + (size_t)qq[k];
                            point = point * 4096 + (int64_t)(4 * c[k] + (uint32_t)(qq[k] * span));
                        }
                        const size_t i = (a[2] * ad[1] + a[1]) * ad[0] + a[0];
                        brick_texels++;
                        if (a[0] < 5 && a[1] < 5 && a[2] < 5)
                            conflicts++;
                        else if (!owner[i])
                            owner[i] = point + 1, painted++;
                        else if (owner[i] != point + 1)
                            conflicts++;
                    }
                }
        CHECK(bricks == v->info.brick_count && bricks > 10);
        CHECK(run == 0 || (levels & ~1u) != 0); /* coarse bricks too */
        CHECK(conflicts == 0);
        CHECK(painted < brick_texels);
        /* Fine bricks side by side: less atlas than a slot each (a few coarse ones need not). */
        CHECK(run == 1 || texels < 125 * (bricks + 1));
        if (conflicts || painted >= brick_texels || (run == 0 && texels >= 125 * (bricks + 1)))
            fprintf(stderr,
                    "# eps %.2f: %zu bricks (levels %#zx), %zu texels, %zu painted of %zu\n",
                    (double)d.eps, bricks, levels, texels, painted, brick_texels);
        free(owner);
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

static void flat_field_becomes_a_few_level3_bricks(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 64, 8, 64, flat);
    vdbgi_volume *v = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &seed_layout, &v), VDBGI_OK);
    if (v) {
        vdbgi_volume_info info;
        vdbgi_volume_get_info(v, &info);
        CHECK(info.bricks[0] == 0 && info.bricks[1] == 0 && info.bricks[2] == 0);
        /* Cells -1..16 across, -1..2 up (a cell of margin): level-3 blocks -1..2 and -1..0. */
        CHECK(info.bricks[3] == 4 * 2 * 4);
        CHECK(info.max_error <= (0.5 + 8.0 / 255.0) / 255.0);
        float pos[3] = {10.0f, 1.0f, 20.0f}, got[3];
        vdbgi_volume_sample(v, pos, got);
        CHECK_NEAR(got[0], 0.3, 0.002);
        CHECK_NEAR(got[2], 0.5, 0.002);
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

static void linear_ramp_stays_coarse_under_interpolation(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 64, 8, 64, ramp);
    uint32_t bricks[2] = {0, 0}, fine[2] = {0, 0};
    double rmse[2] = {0, 0};
    for (int c = 0; c < 2; c++) {
        const vdbgi_convert_desc d = {.layout = VDBGI_LAYOUT_SEED,
                                      .eps = 0.05f,
                                      .criterion =
                                          c ? VDBGI_CRITERION_INTERP : VDBGI_CRITERION_RANGE};
        vdbgi_volume *v = NULL;
        CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v), VDBGI_OK);
        if (!v)
            continue;
        vdbgi_volume_info info;
        vdbgi_volume_get_info(v, &info);
        bricks[c] = info.brick_count;
        fine[c] = info.bricks[0];
        rmse[c] = info.rmse / info.mean_irradiance;
        vdbgi_volume_destroy(v);
    }
    /*
     * The ramp climbs 0.01 a probe: its range splits every block down to level 0,
     * while interpolation reproduces it exactly except where the fill flattens it
     * beyond the slab's ends, which level-1 bricks absorb (1168 against 240).
     */
    CHECK(fine[0] > 1000 && fine[1] == 0);
    CHECK(bricks[1] * 4 < bricks[0]);
    CHECK(rmse[1] < 0.01);
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

static void invalid_probes_never_leak_their_value(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 24, 12, 24, flat);
    /* The lower half is "inside geometry": invalid, and absurdly bright. */
    for (size_t i = 0; i < p->count; i++)
        if (p->ijk[3 * i + 1] < 6) {
            p->backface[i] = 1.0f;
            p->rgb[3 * i] = p->rgb[3 * i + 1] = p->rgb[3 * i + 2] = 100.0f;
        }
    const vdbgi_convert_desc d = {
        .layout = VDBGI_LAYOUT_SEED, .eps_is_set = 1, .max_level_is_set = 1};
    vdbgi_volume *v = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v), VDBGI_OK);
    if (v) {
        float worst = 0.0f;
        for (size_t i = 0; i < p->count; i++) {
            const double q[3] = {p->ijk[3 * i], p->ijk[3 * i + 1], p->ijk[3 * i + 2]};
            float pos[3], got[3];
            world_of(p, q, pos);
            vdbgi_volume_sample(v, pos, got);
            worst = fmaxf(worst, got[2]);
        }
        CHECK(worst <= 0.51f); /* the valid field's 0.5, never 100 */
        for (size_t l = 0; l < v->filled->leaf_count; l++)
            for (int n = 0; n < 512; n++)
                if (v->filled->leaves[l].mask[n >> 6] >> (n & 63) & 1)
                    CHECK(v->filled->leaves[l].values[3 * n + 2] <= 0.5f + 1e-6f);
        vdbgi_volume_info info;
        vdbgi_volume_get_info(v, &info);
        CHECK(info.valid_count == p->count / 2 && info.unreached_count == 0);
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

/*
 * The packed file leaves out (gives its predictor's value to) points no
 * receiver reads: any position in a lattice cell with a valid corner must
 * read the trilinear of the filled field at its 8 corners, within an
 * encoding step, however deep the invalid region beside it.
 */
static void cells_with_a_valid_corner_read_the_filled_field(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 24, 16, 24, smooth);
    for (size_t i = 0; i < p->count; i++)
        if (p->ijk[3 * i + 1] < 8) /* the lower half is inside geometry */
            p->backface[i] = 1.0f;
    const vdbgi_convert_desc d = {
        .eps_is_set = 1,
        .max_level_is_set = 1,
        .encoding = VDBGI_ENCODING_RGB9E5, /* decoded before filtering: trilinear exactly */
        .layout = VDBGI_LAYOUT_COMPACT};
    vdbgi_volume *v = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v), VDBGI_OK);
    if (v) {
        double worst = 0.0;
        size_t tried = 0;
        for (size_t i = 0; i < p->count; i++) {
            if (p->backface[i] > p->invalid_threshold)
                continue;
            /* A point inside each of the 8 cells this valid probe is a corner of. */
            for (int c = 0; c < 8; c++) {
                int32_t lo[3];
                double q[3];
                for (int k = 0; k < 3; k++) {
                    lo[k] = p->ijk[3 * i + k] - (c >> k & 1);
                    q[k] = lo[k] + 0.3 + 0.15 * k;
                }
                float want[3] = {0.0f, 0.0f, 0.0f}, mx = 0.0f;
                bool all = true;
                for (int corner = 0; corner < 8 && all; corner++) {
                    int32_t ijk[3];
                    double w = 1.0;
                    for (int k = 0; k < 3; k++) {
                        ijk[k] = lo[k] + (corner >> k & 1);
                        /* Below y = 8, the first valid plane and a cell's bottom face,
                           the lift reads that plane (docs/format.md). */
                        const double f = k == 1 && lo[1] < 8 ? 1.0 : q[k] - lo[k];
                        w *= corner >> k & 1 ? f : 1.0 - f;
                    }
                    const float *const at = vdbgi_field_at(v->filled, ijk, NULL);
                    all = at != NULL;
                    for (int k = 0; all && k < 3; k++) {
                        want[k] += (float)w * at[k];
                        mx = fmaxf(mx, at[k]);
                    }
                }
                if (!all)
                    continue;
                float pos[3], got[3];
                world_of(p, q, pos);
                vdbgi_volume_sample(v, pos, got);
                const float step = mx / 512.0f; /* what RGB9E5 rounds a corner by, at most */
                for (int k = 0; k < 3; k++)
                    worst = fmax(worst, fabs(got[k] - want[k]) / step);
                tried++;
            }
        }
        CHECK(tried > 8000);
        CHECK(worst <= 1.0);
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

int main(void)
{
    test_tmpdir_make("test-bricks");
    RUN(exact_bricks_give_back_every_valid_probe);
    RUN(aprons_hide_brick_boundaries);
    RUN(larger_eps_never_grows_the_atlas);
    RUN(rmse_criterion_coarsens_at_least_as_much_as_interp);
    RUN(at_eps_0_every_layout_returns_every_probe);
    RUN(compact_bricks_share_only_texels_they_agree_on);
    RUN(flat_field_becomes_a_few_level3_bricks);
    RUN(linear_ramp_stays_coarse_under_interpolation);
    RUN(invalid_probes_never_leak_their_value);
    RUN(cells_with_a_valid_corner_read_the_filled_field);
    test_tmpdir_remove();
    return CHECK_EXIT();
}
