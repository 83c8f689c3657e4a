/*
 * test_bricks.c: the bricked volume gives back what was baked. With no
 * coarsening every valid probe reads back within the encoding's step; aprons
 * make brick boundaries invisible; a larger eps never grows the atlas; a flat
 * field becomes a few level-3 bricks and a linear one stays coarse under the
 * interpolation criterion; Unreal's RMSE rule never keeps more bricks than
 * the max-error one; at eps 0 every layout and criterion gives back every
 * probe; compact bricks share atlas texels only where they agree; invalid
 * probes never leak; only cells whose filter
 * reads a valid probe get bricks; files round-trip and
 * damaged ones are refused; bad parameters and failing allocations are
 * reported cleanly.
 */
#define _POSIX_C_SOURCE 200809L
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

static float smooth(double x, double y, double z, int c)
{
    return (float)(0.2 + 0.08 * sin(0.35 * x + c) * cos(0.23 * z) + 0.01 * y);
}

static float flat(double x, double y, double z, int c)
{
    (void)x, (void)y, (void)z;
    return 0.3f + 0.1f * (float)c;
}

static float ramp(double x, double y, double z, int c)
{
    (void)y, (void)z;
    return (float)(0.05 + 0.01 * x + 0.001 * c);
}

static void world_of(const vdbgi_probes *p, const double ijk[3], float pos[3])
{
    for (int k = 0; k < 3; k++)
        pos[k] = (float)(p->origin[k] + p->spacing * ijk[k]);
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
        const vdbgi_convert_desc d = {.eps = VDBGI_ZERO,
                                      .max_level = VDBGI_ZERO,
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
        .layout = VDBGI_LAYOUT_SEED, .eps = VDBGI_ZERO, .max_level = VDBGI_ZERO};
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
    const float eps[] = {VDBGI_ZERO, 0.01f, 0.03f, 0.1f, 0.3f, 1.0f, 3.0f};
    for (int c = VDBGI_CRITERION_RANGE; c <= VDBGI_CRITERION_RMSE; c++) {
        size_t last_atlas = SIZE_MAX, last_bricks = SIZE_MAX;
        double last_rmse = 0.0;
        for (size_t i = 0; i < sizeof(eps) / sizeof(eps[0]); i++) {
            const vdbgi_convert_desc d = {
                .layout = VDBGI_LAYOUT_SEED, .eps = eps[i], .criterion = (vdbgi_criterion)c};
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
    const float eps[] = {VDBGI_ZERO, 0.01f, 0.03f, 0.1f, 0.3f};
    bool fewer = false;
    for (size_t i = 0; i < sizeof(eps) / sizeof(eps[0]); i++) {
        vdbgi_volume *v[2] = {NULL, NULL};
        vdbgi_volume_info info[2];
        for (int c = 0; c < 2; c++) {
            const vdbgi_convert_desc d = {.layout = VDBGI_LAYOUT_SEED,
                                          .eps = eps[i],
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
        const vdbgi_convert_desc d = {.eps = VDBGI_ZERO,
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
        const uint32_t *const ad = v->info.atlas_dims, *const id = v->info.indirection_dims;
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
        .layout = VDBGI_LAYOUT_SEED, .eps = VDBGI_ZERO, .max_level = VDBGI_ZERO};
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
        .eps = VDBGI_ZERO,
        .max_level = VDBGI_ZERO,
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

/* A lit 16 m floor with a closed box from lo to hi, baked as pd places the probes. */
static vdbgi_probes *floor_and_box(vdbgi_context *ctx, const float lo[3], const float hi[3],
                                   const vdbgi_place_desc *pd, int rays, vdbgi_scene **s)
{
    test_mesh m = {0};
    test_mesh_plane(&m, 16.0f, 0.0f);
    test_mesh_box(&m, lo, hi, 0);
    const vdbgi_mesh_desc md = test_mesh_desc(&m, 0.6f, 0);
    vdbgi_probes *p = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, s), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, *s, pd, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = rays};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, *s, &bd, NULL), VDBGI_OK);
    return p;
}

/* The floor with an 8 m box standing on it, baked at 0.5 m on a lattice at origin. */
static vdbgi_probes *boxed_floor(vdbgi_context *ctx, double origin, vdbgi_scene **s)
{
    const float lo[3] = {-4.0f, 0.0f, -4.0f}, hi[3] = {4.0f, 8.0f, 4.0f};
    const vdbgi_place_desc pd = {
        .spacing = 0.5, .origin = {origin, origin, origin}, .origin_is_set = 1};
    return floor_and_box(ctx, lo, hi, &pd, 64, s);
}

/* Level-0 bricks only, so that no coarse brick covers the cells a test looks at. */
static vdbgi_volume *level0_volume(vdbgi_context *ctx, const vdbgi_probes *p, int layout)
{
    const vdbgi_convert_desc cd = {.max_level = VDBGI_ZERO, .layout = (vdbgi_layout)layout};
    vdbgi_volume *v = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v), VDBGI_OK);
    return v;
}

static bool reads_black(const vdbgi_volume *v, const float pos[3])
{
    float got[3];
    vdbgi_volume_sample(v, pos, got);
    return got[0] == 0.0f && got[1] == 0.0f && got[2] == 0.0f;
}

/* The indirection texel of the level-0 cell holding pos, or NULL outside the box. */
static const uint8_t *cell_texel(const vdbgi_volume *v, const float pos[3])
{
    const vdbgi_volume_info *const vi = &v->info;
    size_t i = 0;
    for (int k = 2; k >= 0; k--) {
        const float u = (pos[k] - vi->box_min[k]) / (vi->box_max[k] - vi->box_min[k]);
        const float c = floorf(u * (float)vi->indirection_dims[k]);
        if (!(c >= 0.0f && c < (float)vi->indirection_dims[k]))
            return NULL;
        i = i * vi->indirection_dims[k] + (size_t)c;
    }
    return &v->tex.indirection[4 * i];
}

/* Whether the level-0 cell holding pos has no brick (outside the box: none). */
static bool no_brick(const vdbgi_volume *v, const float pos[3])
{
    const uint8_t *const t = cell_texel(v, pos);
    return !t || !(t[0] | t[1] | t[2] | t[3]);
}

/*
 * On the boxed floor, in both layouts: every position whose filter reads a lit
 * valid probe (within one spacing of it on every axis) lands in a brick and
 * reads light. With the lattice at 1.25 m the first probes outside the wall at
 * x = 4 m stand at index 6, mid-cell: the cell of indices 0..3 inside it is next
 * to theirs (the one-cell margin of old kept it), yet its filter reads none of
 * them, so it has no brick and reads black. With the lattice at 0.25 m the first
 * probes outside the -x wall stand at index -9, one below the cell of indices
 * -8..-5 inside it: the seed layout's apron reads them, the compact layout's
 * filter reads beyond the + faces only and keeps no brick there.
 */
static void only_cells_whose_filter_reads_a_valid_probe_get_bricks(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = boxed_floor(ctx, 1.25, &s);
    for (int layout = VDBGI_LAYOUT_SEED; p && layout <= VDBGI_LAYOUT_COMPACT; layout++) {
        vdbgi_volume *const v = level0_volume(ctx, p, layout);
        if (!v)
            continue;
        int dark = 0, tried = 0;
        for (size_t i = 0; i < p->count; i++) {
            /* Beyond the floor's edge a valid probe sees only the black sky. */
            if (p->backface[i] > p->invalid_threshold || p->rgb[3 * i] < 0.01f)
                continue;
            for (int corner = 0; corner < 8; corner++) {
                const double q[3] = {p->ijk[3 * i] + (corner & 1 ? 0.95 : -0.95),
                                     p->ijk[3 * i + 1] + (corner & 2 ? 0.95 : -0.95),
                                     p->ijk[3 * i + 2] + (corner & 4 ? 0.95 : -0.95)};
                float pos[3];
                world_of(p, q, pos);
                dark += reads_black(v, pos);
                tried++;
            }
        }
        CHECK(tried > 1000 && dark == 0);
        /* No brick; the seed layout reads black there, the compact one the roof's
           first valid plane, under which the lift reaches (docs/format.md). */
        const float inside[3] = {2.0f, 4.0f, 0.0f};
        CHECK(no_brick(v, inside) && reads_black(v, inside) == (layout == VDBGI_LAYOUT_SEED));
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);

    p = boxed_floor(ctx, 0.25, &s);
    for (int layout = VDBGI_LAYOUT_SEED; p && layout <= VDBGI_LAYOUT_COMPACT; layout++) {
        vdbgi_volume *const v = level0_volume(ctx, p, layout);
        if (!v)
            continue;
        const float inside[3] = {-3.0f, 4.0f, 0.0f};
        CHECK(no_brick(v, inside) == (layout == VDBGI_LAYOUT_COMPACT));
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/*
 * The runtime's indirection (docs/format.md) read as the shaders read it gives
 * every cell its 3D indirection texel, in both layouts: cells below, inside
 * and above a column's run alike. A roof 10 m above a floor, with probes
 * within 2 m of a surface, leaves empty cells inside the runs under the roof.
 * A buffer one byte short gets nothing.
 */
static void columns_give_every_cell_its_indirection_texel(void)
{
    vdbgi_context *ctx = test_context();
    const float lo[3] = {-4.0f, 10.0f, -4.0f}, hi[3] = {4.0f, 11.0f, 4.0f};
    const vdbgi_place_desc pd = {.spacing = 0.5, .margin = 2.0};
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = floor_and_box(ctx, lo, hi, &pd, 16, &s);
    for (int layout = VDBGI_LAYOUT_SEED; p && layout <= VDBGI_LAYOUT_COMPACT; layout++) {
        vdbgi_volume *const v = level0_volume(ctx, p, layout);
        if (!v)
            continue;
        vdbgi_volume_info vi;
        vdbgi_volume_get_info(v, &vi);
        const size_t size = vdbgi_volume_copy_columns(v, NULL, 0);
        CHECK(size == vi.columns_size &&
              size == 4 * (size_t)vi.columns_dims[0] * vi.columns_dims[1]);
        CHECK(size > 0 && size < vi.indirection_size);
        uint8_t *const t = malloc(size);
        memset(t, 0xA5, size);
        CHECK(vdbgi_volume_copy_columns(v, t, size - 1) == 0 && t[0] == 0xA5);
        CHECK(vdbgi_volume_copy_columns(v, t, size) == size);
        const uint32_t *const d = vi.indirection_dims;
        const size_t columns = (size_t)d[0] * d[2];
        size_t wrong = 0, gaps = 0;
        for (uint32_t z = 0; z < d[2]; z++)
            for (uint32_t x = 0; x < d[0]; x++) {
                const uint8_t *const run = &t[8 * (x + (size_t)d[0] * z)];
                const uint32_t ymin = run[0] | run[1] << 8, count = run[2] | run[3] << 8;
                const size_t first = 2 * columns + (run[4] | run[5] << 8 | (size_t)run[6] << 16);
                for (uint32_t y = 0; y < d[1]; y++) {
                    const uint8_t *const want =
                        &v->tex.indirection[4 * ((z * d[1] + y) * d[0] + x)];
                    static const uint8_t zero[4];
                    const bool in = y >= ymin && y < ymin + count;
                    const uint8_t *const got = in ? &t[4 * (first + y - ymin)] : zero;
                    wrong += memcmp(got, want, 4) != 0;
                    gaps += in && memcmp(want, zero, 4) == 0;
                }
            }
        CHECK(wrong == 0 && gaps > 0);
        free(t);
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/*
 * The compact layout's lift (docs/format.md): with the lattice at 0.25 m, the
 * first valid plane over a one-sided floor at y = 0 is index 0, the bottom
 * face of a cell, so the cell below it (indices -4..-1) is kept by no other
 * probe of its filter. It holds no brick, and every position beneath the plane,
 * on the floor and below it, reads exactly what the plane above it reads. The
 * box on the floor makes the plane vary, so that interpolating towards the
 * filled probes below would not give the same values.
 */
static void the_cell_under_the_first_valid_plane_is_lifted(void)
{
    vdbgi_context *ctx = test_context();
    const float lo[3] = {-2.0f, 0.0f, -2.0f}, hi[3] = {2.0f, 3.0f, 2.0f};
    const vdbgi_place_desc pd = {.spacing = 0.5, .origin = {0.25, 0.25, 0.25}, .origin_is_set = 1};
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = floor_and_box(ctx, lo, hi, &pd, 64, &s);
    vdbgi_volume *const v = p ? level0_volume(ctx, p, VDBGI_LAYOUT_COMPACT) : NULL;
    if (v) {
        size_t tried = 0, same = 0, empty = 0, lit = 0;
        for (float x = -6.9f; x < 7.0f; x += 0.37f)
            for (float z = -6.9f; z < 7.0f; z += 0.41f) {
                if (fabsf(x) < 2.6f && fabsf(z) < 2.6f)
                    continue;
                const float plane[3] = {x, 0.25f, z}, floor_at[3] = {x, 0.0f, z},
                            under[3] = {x, -0.4f, z};
                float want[3], got[3], deep[3];
                vdbgi_volume_sample(v, plane, want);
                vdbgi_volume_sample(v, floor_at, got);
                vdbgi_volume_sample(v, under, deep);
                same +=
                    memcmp(want, got, sizeof(got)) == 0 && memcmp(want, deep, sizeof(deep)) == 0;
                lit += want[0] > 0.01f;
                /* The cell that holds y = -0.25 m, one below the plane's: in the box, empty. */
                const float below[3] = {x, -0.25f, z};
                const uint8_t *const t = cell_texel(v, below);
                empty += t && !(t[0] | t[1] | t[2] | t[3]);
                tried++;
            }
        CHECK(tried > 500 && same == tried && lit == tried && empty == tried);
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/*
 * The lift runs after coarsening: a coarse brick may cover the cell under the
 * first valid plane, and then every position there reads, within eps, the
 * filled field that its test checked, never values nobody filled. On a slab
 * whose lower half (y < 12) is invalid, the first valid plane is the bottom
 * face of cell 3, and level-1 blocks pair cell 2 (the one the lift would
 * leave out) with cell 3.
 */
static void coarse_bricks_under_the_first_valid_plane_read_the_filled_field(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 24, 24, 24, smooth);
    for (size_t i = 0; i < p->count; i++)
        if (p->ijk[3 * i + 1] < 12)
            p->backface[i] = 1.0f;
    const vdbgi_convert_desc d = {.eps = 0.2f,
                                  .noise_sigmas = VDBGI_ZERO,
                                  .encoding = VDBGI_ENCODING_RGB9E5,
                                  .layout = VDBGI_LAYOUT_COMPACT};
    vdbgi_volume *v = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v), VDBGI_OK);
    if (v) {
        const vdbgi_volume_info *const vi = &v->info;
        const float tolerance = 0.2f * (float)vi->mean_irradiance;
        size_t coarse = 0, lifted = 0, wrong = 0;
        for (int32_t z = 0; z < 24; z++)
            for (int32_t x = 0; x < 24; x++)
                for (int32_t y = 8; y < 12; y++) {
                    const double q[3] = {x, y, z};
                    float pos[3], got[3];
                    world_of(p, q, pos);
                    const int32_t ijk[3] = {x, y, z};
                    const float *const want = vdbgi_field_at(v->filled, ijk, NULL);
                    if (no_brick(v, pos)) {
                        lifted++;
                        continue;
                    }
                    coarse++;
                    vdbgi_volume_sample(v, pos, got);
                    for (int k = 0; want && k < 3; k++)
                        wrong += fabsf(got[k] - want[k]) > tolerance * 1.01f + want[k] / 256.0f;
                    wrong += !want;
                }
        CHECK(coarse > 0 && wrong == 0);
        (void)lifted;
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

static void round_trip(vdbgi_layout layout)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 40, 10, 24, smooth);
    vdbgi_volume *a = NULL, *b = NULL, *r = NULL;
    const vdbgi_convert_desc d = {.eps = 0.02f, .layout = layout};
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &a), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &b), VDBGI_OK);
    if (a && b) {
        /* The file is made when first written (or sized), the same bytes each build. */
        CHECK(a->file == NULL && vdbgi_volume_write_memory(a, NULL, 0) > 0 &&
              vdbgi_volume_write_memory(b, NULL, 0) == a->info.file_size &&
              memcmp(a->file, b->file, a->info.file_size) == 0);
        CHECK_RESULT(ctx, vdbgi_volume_write(a, tmp_path("a.gi.gz")), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("a.gi.gz"), &r), VDBGI_OK);
    }
    if (r) {
        vdbgi_volume_info ia, ir;
        vdbgi_volume_get_info(a, &ia);
        vdbgi_volume_get_info(r, &ir);
        CHECK(memcmp(ia.indirection_dims, ir.indirection_dims, sizeof(ia.indirection_dims)) == 0);
        CHECK(memcmp(ia.atlas_dims, ir.atlas_dims, sizeof(ia.atlas_dims)) == 0);
        CHECK(memcmp(ia.bricks, ir.bricks, sizeof(ia.bricks)) == 0);
        CHECK(ir.file_size == ia.file_size && ir.spacing == ia.spacing);
        CHECK(ir.layout == layout);
        /* The compact layout's file is packed (version 5): textures rebuilt, byte for byte. */
        const bool packed = layout == VDBGI_LAYOUT_COMPACT;
        vdbgi_volume_info hi;
        uint32_t version = 0;
        uint8_t *body = NULL;
        size_t body_size = 0;
        CHECK_RESULT(
            ctx,
            vdbgi_gifile_parse(ctx, "a", a->file, ia.file_size, &hi, &version, &body, &body_size),
            VDBGI_OK);
        vdbgi_free(ctx, body);
        CHECK(version == (packed ? 5u : 1u));
        CHECK(ir.stored_points == ia.stored_points && (ia.stored_points > 0) == packed);
        CHECK(memcmp(a->tex.indirection, r->tex.indirection, ia.indirection_size) == 0);
        CHECK(memcmp(a->tex.atlas, r->tex.atlas, ia.atlas_size) == 0);
        /* Its textures written as they are (version 2) read back the same too. */
        vdbgi_volume *t = NULL;
        CHECK_RESULT(ctx, vdbgi_volume_write_textures(r, tmp_path("t.gi")), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("t.gi"), &t), VDBGI_OK);
        if (t) {
            uint8_t *plain = NULL;
            size_t plain_size = 0;
            CHECK_RESULT(ctx, vdbgi_gifile_slurp(ctx, tmp_path("t.gi"), &plain, &plain_size),
                         VDBGI_OK);
            CHECK(plain && vdbgi_get_u32(plain + 8) == (packed ? 2u : 1u));
            vdbgi_free(ctx, plain);
            CHECK(memcmp(t->tex.indirection, r->tex.indirection, ia.indirection_size) == 0);
            CHECK(memcmp(t->tex.atlas, r->tex.atlas, ia.atlas_size) == 0);
            vdbgi_volume_destroy(t);
        }
        /* In memory: the file's bytes out (after a size query), the same textures in. */
        const size_t n = vdbgi_volume_write_memory(a, NULL, 0);
        uint8_t *const bytes = malloc(n);
        CHECK(n == ia.file_size && vdbgi_volume_write_memory(a, bytes, n - 1) == 0 &&
              vdbgi_volume_write_memory(a, bytes, n) == n && memcmp(bytes, a->file, n) == 0);
        /* A read volume writes back the very bytes it came from. */
        uint8_t *const again = malloc(n);
        CHECK(vdbgi_volume_write_memory(r, again, n) == n && memcmp(again, bytes, n) == 0);
        free(again);
        vdbgi_volume *m = NULL;
        CHECK_RESULT(ctx, vdbgi_volume_read_memory(ctx, bytes, n, "bytes", &m), VDBGI_OK);
        if (m) {
            CHECK(memcmp(m->tex.indirection, r->tex.indirection, ia.indirection_size) == 0);
            CHECK(memcmp(m->tex.atlas, r->tex.atlas, ia.atlas_size) == 0);
            vdbgi_volume_destroy(m);
        }
        CHECK_RESULT(ctx, vdbgi_volume_read_memory(ctx, bytes, n - 1, "bytes", &m),
                     VDBGI_ERR_FORMAT);
        CHECK(strncmp(vdbgi_context_error(ctx), "bytes: ", 7) == 0 && m == NULL);
        free(bytes);
        for (int i = 0; i < 1000; i++) {
            const float pos[3] = {(float)(i % 23) * 0.9f - 1.0f, (float)(i % 7) * 0.8f - 0.5f,
                                  (float)(i % 13) * 1.1f - 1.0f};
            float x[3], y[3];
            vdbgi_volume_sample(a, pos, x);
            vdbgi_volume_sample(r, pos, y);
            CHECK(memcmp(x, y, sizeof(x)) == 0);
        }
    }
    vdbgi_volume_destroy(r);
    vdbgi_volume_destroy(a);
    vdbgi_volume_destroy(b);
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

/* Both layouts: the same bytes twice, and a file that reads back to the same lookups. */
static void files_round_trip_and_are_deterministic(void)
{
    round_trip(VDBGI_LAYOUT_SEED);
    round_trip(VDBGI_LAYOUT_COMPACT);
}

static void damaged_files_are_refused(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 12, 6, 12, smooth);
    vdbgi_volume *v = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &seed_layout, &v), VDBGI_OK);
    if (!v) {
        vdbgi_probes_destroy(p);
        vdbgi_context_destroy(ctx);
        return;
    }
    const size_t size = vdbgi_volume_write_memory(v, NULL, 0);
    /* The uncompressed file: header, then the textures. */
    const size_t raw = VDBGI_GI_HEADER_SIZE + v->info.indirection_size + v->info.atlas_size;
    uint8_t *const plain = malloc(raw);
    vdbgi_gifile_header(&v->info, 0, plain);
    memcpy(plain + VDBGI_GI_HEADER_SIZE, v->tex.indirection, raw - VDBGI_GI_HEADER_SIZE);
    /* Every prefix of the gzip'd file. */
    for (size_t cut = 0; cut < size; cut += 1 + cut / 64) {
        FILE *f = fopen(tmp_path("cut.gi.gz"), "wb");
        fwrite(v->file, 1, cut, f);
        fclose(f);
        vdbgi_volume *r = (vdbgi_volume *)1;
        CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("cut.gi.gz"), &r), VDBGI_ERR_FORMAT);
        CHECK(r == NULL);
    }
    /* Flipped bytes: refused, or (in gzip header fields zlib ignores) read unchanged. */
    uint8_t *const copy = malloc(size);
    for (size_t i = 0; i < size; i += 1 + size / 300) {
        memcpy(copy, v->file, size);
        copy[i] ^= 0x5A;
        FILE *f = fopen(tmp_path("flip.gi.gz"), "wb");
        fwrite(copy, 1, size, f);
        fclose(f);
        vdbgi_volume *r = NULL;
        const vdbgi_result res = vdbgi_volume_read(ctx, tmp_path("flip.gi.gz"), &r);
        CHECK(res == VDBGI_ERR_FORMAT ||
              (res == VDBGI_OK && memcmp(r->tex.indirection, v->tex.indirection,
                                         v->info.indirection_size + v->info.atlas_size) == 0));
        vdbgi_volume_destroy(r);
    }
    /* Uncompressed, with a byte of trailing junk; and a lying header. */
    FILE *f = fopen(tmp_path("plain.gi"), "wb");
    fwrite(plain, 1, raw, f);
    fclose(f);
    vdbgi_volume *r = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("plain.gi"), &r), VDBGI_OK);
    vdbgi_volume_destroy(r);
    f = fopen(tmp_path("plain.gi"), "ab");
    fputc(0, f);
    fclose(f);
    CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("plain.gi"), &r), VDBGI_ERR_FORMAT);
    uint8_t *const lie = malloc(raw);
    memcpy(lie, plain, raw);
    lie[24] = 0xFF; /* indirection width 255 disagrees with the stored byte count */
    f = fopen(tmp_path("lie.gi"), "wb");
    fwrite(lie, 1, raw, f);
    fclose(f);
    CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("lie.gi"), &r), VDBGI_ERR_FORMAT);
    memcpy(lie, plain, raw);
    lie[VDBGI_GI_HEADER_SIZE + 3] = 9; /* an indirection level no file allows */
    lie[VDBGI_GI_HEADER_SIZE + 0] = 200;
    f = fopen(tmp_path("lie.gi"), "wb");
    fwrite(lie, 1, raw, f);
    fclose(f);
    CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("lie.gi"), &r), VDBGI_ERR_FORMAT);
    /*
     * The layout field: version 1 must leave it 0; version 2 knows 1 and 2
     * (and 0 and 3, their numbers before), version 5 only 2; versions 3 and
     * 4 (older compact forms) and 6 are refused. This seed-layout file reads
     * as version 2 with 1 or 0.
     */
    static const uint32_t seed_fields[] = {VDBGI_LAYOUT_SEED, 0};
    for (int c = 0; c < 2; c++) {
        memcpy(lie, plain, raw);
        vdbgi_put_u32(lie + 8, 2);
        vdbgi_put_u32(lie + 104, seed_fields[c]);
        f = fopen(tmp_path("lie.gi"), "wb");
        fwrite(lie, 1, raw, f);
        fclose(f);
        CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("lie.gi"), &r), VDBGI_OK);
        vdbgi_volume_destroy(r);
        r = NULL;
    }
    static const uint32_t version_layout[][2] = {{1, 1}, {1, 2}, {2, 4}, {3, 1}, {4, 2}, {4, 3},
                                                 {5, 0}, {5, 1}, {5, 3}, {6, 2}, {7, 2}, {8, 2}};
    for (size_t c = 0; c < sizeof(version_layout) / sizeof(version_layout[0]); c++) {
        memcpy(lie, plain, raw);
        vdbgi_put_u32(lie + 8, version_layout[c][0]);
        vdbgi_put_u32(lie + 104, version_layout[c][1]);
        f = fopen(tmp_path("lie.gi"), "wb");
        fwrite(lie, 1, raw, f);
        fclose(f);
        CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("lie.gi"), &r), VDBGI_ERR_FORMAT);
    }
    CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("missing.gi.gz"), &r), VDBGI_ERR_IO);
    free(lie);
    free(plain);
    free(copy);
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

static void bad_parameters_and_probes_are_refused(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 8, 4, 8, flat);
    vdbgi_volume *v = (vdbgi_volume *)1;
    const vdbgi_convert_desc bad[] = {{.eps = -1.0f},
                                      {.eps = -0.5f},
                                      {.eps = NAN},
                                      {.max_level = 4},
                                      {.max_level = -1},
                                      {.criterion = (vdbgi_criterion)9},
                                      {.encoding = (vdbgi_encoding)7},
                                      {.term_bits = 3},
                                      {.term_bits = 9},
                                      {.gi_version = 5},
                                      {.gi_version = 6}, /* probes without terms */
                                      {.fill = (vdbgi_fill)3}};
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &bad[i], &v), VDBGI_ERR_INVALID_ARG);
        CHECK(v == NULL);
        v = (vdbgi_volume *)1;
    }
    CHECK(strstr(vdbgi_context_error(ctx), "fill") != NULL);
    /* Every probe invalid: nothing to fill from. */
    for (size_t i = 0; i < p->count; i++)
        p->backface[i] = 1.0f;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, NULL, &v), VDBGI_ERR_FORMAT);
    CHECK(strstr(vdbgi_context_error(ctx), "no valid probe") != NULL);
    vdbgi_probes_destroy(p);
    /* No probes at all, and probes with no values. */
    CHECK_RESULT(ctx, vdbgi_probes_alloc(ctx, 0, true, &p), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, NULL, &v), VDBGI_ERR_FORMAT);
    vdbgi_probes_destroy(p);
    CHECK_RESULT(ctx, vdbgi_probes_alloc(ctx, 4, false, &p), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, NULL, &v), VDBGI_ERR_FORMAT);
    vdbgi_probes_destroy(p);
    /* Two probes 10 km apart at 0.5 m: the indirection would exceed a 3D texture. */
    p = test_slab(ctx, 2, 1, 1, flat);
    p->ijk[3] = 20000;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, NULL, &v), VDBGI_ERR_OUT_OF_MEMORY);
    CHECK(strstr(vdbgi_context_error(ctx), "2048") && strstr(vdbgi_context_error(ctx), "spacing"));
    vdbgi_probes_destroy(p);
    /* A read volume has no fields to slice. */
    p = test_slab(ctx, 8, 4, 8, flat);
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, NULL, &v), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_write(v, tmp_path("s.gi.gz")), VDBGI_OK);
    vdbgi_volume *r = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("s.gi.gz"), &r), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_write_slices(r, p, VDBGI_AXIS_Y, 0.5, 0.0f, tmp_path("sl")),
                 VDBGI_ERR_INVALID_ARG);
    CHECK_RESULT(ctx, vdbgi_volume_write_slices(v, p, VDBGI_AXIS_Y, 0.5, 0.0f, tmp_path("sl")),
                 VDBGI_OK);
    CHECK(access(tmp_path("sl/levels.png"), R_OK) == 0 &&
          access(tmp_path("sl/atlas.exr"), R_OK) == 0);
    vdbgi_volume_destroy(r);
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

/*
 * levels.png shows, at every lattice point of its plane, the level of the
 * brick covering that point's cell in the viewer's colours (grey: no brick),
 * in both layouts: each pixel is compared with the level its cell's
 * indirection texel gives, through the public copy of the indirection.
 */
static void levels_png_shows_each_cells_level(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 40, 12, 40, smooth);
    for (int layout = VDBGI_LAYOUT_SEED; p && layout <= VDBGI_LAYOUT_COMPACT; layout++) {
        const vdbgi_convert_desc d = {.eps = 0.02f, .layout = (vdbgi_layout)layout};
        vdbgi_volume *v = NULL;
        CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &v), VDBGI_OK);
        if (!v)
            continue;
        vdbgi_volume_info info;
        vdbgi_volume_get_info(v, &info);
        const double at = p->origin[1] + p->spacing * 5; /* a plane through the slab */
        CHECK_RESULT(ctx, vdbgi_volume_write_slices(v, p, VDBGI_AXIS_Y, at, 0.0f, tmp_path("lv")),
                     VDBGI_OK);
        vdbgi_image img = {0};
        CHECK_RESULT(ctx, vdbgi_image_decode(ctx, tmp_path("lv/levels.png"), NULL, 0, NULL, &img),
                     VDBGI_OK);
        const uint32_t *const dims = info.indirection_dims;
        uint8_t *const ind = malloc(info.indirection_size);
        vdbgi_volume_copy_indirection(v, ind, info.indirection_size);
        const vdbgi_volume_view view = vdbgi_volume_view_of(v);
        CHECK(img.width == (int)dims[0] * 4 && img.height == (int)dims[2] * 4);
        const int32_t cy =
            vdbgi_floor_div((int32_t)lround((at - v->lattice_origin[1]) / p->spacing), 4) -
            v->origin_cell[1];
        size_t wrong = 0, seen[5] = {0};
        for (int y = 0; img.rgba && y < img.height && y < (int)dims[2] * 4; y++)
            for (int x = 0; x < img.width && x < (int)dims[0] * 4; x++) {
                const size_t c =
                    ((size_t)(y / 4) * dims[1] + (size_t)cy) * dims[0] + (size_t)(x / 4);
                const int level = vdbgi_cell_level(&view, &ind[4 * c]);
                const float *const got = &img.rgba[4 * ((size_t)y * (size_t)img.width + (size_t)x)];
                bool same = true;
                for (int k = 0; k < 3; k++)
                    same = same &&
                           fabsf(got[k] - vdbgi_srgb_from_linear(vdbgi_level_colour(level)[k])) <
                               0.6f / 255;
                wrong += !same;
                seen[level + 1]++;
            }
        CHECK(wrong == 0);
        /* The plane crosses bricks of more than one level, and cells with none. */
        CHECK(seen[0] > 0 && seen[1] > 0 && seen[2] + seen[3] + seen[4] > 0);
        if (wrong || !seen[0] || !seen[1])
            fprintf(stderr, "# layout %d: %zu pixels wrong; none %zu, levels %zu %zu %zu %zu\n",
                    layout, wrong, seen[0], seen[1], seen[2], seen[3], seen[4]);
        vdbgi_free(ctx, img.rgba);
        free(ind);
        vdbgi_volume_destroy(v);
    }
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

static void failing_allocations_are_reported_without_leaks(void)
{
    int succeeded = 0;
    for (long n = 0; n < 400 && !succeeded; n++) {
        test_alloc a = {0, -1, 0};
        const vdbgi_context_desc cd = {.alloc = test_alloc_fn, .free = test_free_fn, .user = &a};
        vdbgi_context *ctx = NULL;
        vdbgi_context_create(&cd, &ctx);
        vdbgi_probes *p = test_slab(ctx, 12, 6, 12, smooth);
        a.calls = 0;
        a.fail_at = n; /* fail inside the build only */
        vdbgi_volume *v = NULL;
        const vdbgi_result r = vdbgi_volume_build(ctx, p, NULL, &v);
        CHECK(r == VDBGI_OK || r == VDBGI_ERR_OUT_OF_MEMORY);
        CHECK((r == VDBGI_OK) == (v != NULL));
        succeeded = r == VDBGI_OK;
        vdbgi_volume_destroy(v);
        vdbgi_probes_destroy(p);
        vdbgi_context_destroy(ctx);
        CHECK(a.live == 0);
    }
    CHECK(succeeded);
}

static void textures_and_probes_copy_into_caller_buffers_after_a_size_query(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 12, 6, 12, smooth);
    vdbgi_volume *v = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, NULL, &v), VDBGI_OK);
    if (!v) {
        vdbgi_probes_destroy(p);
        vdbgi_context_destroy(ctx);
        return;
    }
    vdbgi_volume_info di;
    vdbgi_volume_get_info(v, &di);
    CHECK(di.layout == VDBGI_LAYOUT_COMPACT); /* what no desc asks for: vdb-to-gi's default */
    size_t (*const copy[2])(const vdbgi_volume *, void *, size_t) = {vdbgi_volume_copy_indirection,
                                                                     vdbgi_volume_copy_atlas};
    const uint8_t *const want[2] = {v->tex.indirection, v->tex.atlas};
    for (int t = 0; t < 2; t++) {
        const size_t size = copy[t](v, NULL, 0);
        CHECK(size == (t ? v->info.atlas_size : v->info.indirection_size) && size > 0);
        /* A fresh buffer each time, one byte short first: nothing may be written. */
        uint8_t *const shorter = malloc(size - 1);
        memset(shorter, 0xA5, size - 1);
        CHECK(copy[t](v, shorter, size - 1) == 0);
        CHECK(shorter[0] == 0xA5 && shorter[size - 2] == 0xA5);
        free(shorter);
        uint8_t *const exact = malloc(size);
        CHECK(copy[t](v, exact, size) == size);
        CHECK(memcmp(exact, want[t], size) == 0);
        free(exact);
    }
    const size_t n = vdbgi_probes_copy(p, NULL, NULL, NULL, 0);
    CHECK(n == p->count && n > 0);
    int32_t *const ijk = malloc(n * 3 * sizeof(int32_t));
    float *const rgb = malloc(n * 3 * sizeof(float));
    float *const bf = malloc(n * sizeof(float));
    CHECK(vdbgi_probes_copy(p, ijk, rgb, bf, n - 1) == 0);
    CHECK(vdbgi_probes_copy(p, ijk, rgb, bf, n) == n);
    for (size_t i = 0; i < n; i += 97) {
        int32_t c[3];
        float col[3], b;
        CHECK_RESULT(ctx, vdbgi_probes_get(p, i, c, col, &b), VDBGI_OK);
        CHECK(memcmp(c, &ijk[3 * i], sizeof(c)) == 0 &&
              memcmp(col, &rgb[3 * i], sizeof(col)) == 0 && b == bf[i]);
    }
    free(ijk);
    free(rgb);
    free(bf);
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

/*
 * L2 terms in bricks (.gi version 7, and 6): a surface reads its own side, as the
 * probes' own L2 does; the L0 atlas is the scalar volume's, byte for byte;
 * the file round-trips, does not depend on the thread count, and a damaged
 * basis, a cut or a wrong version is refused.
 */
static void l2_bricks_read_each_side_and_round_trip(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    const float lo[3] = {-4.0f, 0.0f, -4.0f}, hi[3] = {4.0f, 8.0f, 4.0f};
    test_mesh_plane(&m, 16.0f, 0.0f);
    test_mesh_box(&m, lo, hi, 0);
    const vdbgi_mesh_desc md = test_mesh_desc(&m, 0.6f, 0);
    vdbgi_scene *scene = NULL;
    vdbgi_probes *p = NULL;
    const vdbgi_place_desc pd = {.spacing = 0.5, .origin = {0.25, 0.25, 0.25}, .origin_is_set = 1};
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &scene), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 64, .basis = VDBGI_BASIS_SH2};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, scene, &bd, NULL), VDBGI_OK);
    vdbgi_convert_desc cd = {.eps = VDBGI_ZERO, .max_level = VDBGI_ZERO, .threads = 1};
    vdbgi_volume *v = NULL, *v3 = NULL, *v6 = NULL, *scalar = NULL, *back = NULL, *back6 = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v), VDBGI_OK);
    cd.threads = 3;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v3), VDBGI_OK);
    cd.gi_version = 6;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v6), VDBGI_OK);
    cd.gi_version = 5;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &scalar), VDBGI_ERR_INVALID_ARG);
    cd.scalar_only = 1;
    cd.gi_version = 6; /* a scalar volume has no terms to write as version 6 */
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &scalar), VDBGI_ERR_INVALID_ARG);
    CHECK(strstr(vdbgi_context_error(ctx), "holds L2 terms") != NULL);
    cd.gi_version = 0;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &scalar), VDBGI_OK);
    if (!v || !v3 || !v6 || !scalar)
        goto done;
    CHECK(v->info.basis == VDBGI_BASIS_SH2 && scalar->info.basis == VDBGI_BASIS_SCALAR);
    CHECK(v->tex.sh != NULL && scalar->tex.sh == NULL);
    /* The terms leave L0 alone: the fill's choices, the bricks and the atlas are the scalar's. */
    CHECK(v->info.atlas_size == scalar->info.atlas_size &&
          memcmp(v->tex.atlas, scalar->tex.atlas, v->info.atlas_size) == 0);
    /* Half a metre over the lit floor, two metres from the box: all eight probes valid. */
    const float at[3] = {6.1f, 0.5f, 0.1f}, up[3] = {0, 1, 0}, down[3] = {0, -1, 0};
    float vu[3], vd[3], pu[3], pdn[3], flat[3];
    vdbgi_volume_sample_normal(v, at, up, vu);
    vdbgi_volume_sample_normal(v, at, down, vd);
    vdbgi_volume_sample_normal(scalar, at, up, flat);
    CHECK_RESULT(ctx, vdbgi_probes_sample_points(p, 1, at, up, 0.0f, pu, NULL), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_sample_points(p, 1, at, down, 0.0f, pdn, NULL), VDBGI_OK);
    for (int k = 0; k < 3; k++) {
        CHECK_NEAR(vu[k], pu[k], 0.1f * pdn[k] + 1e-4f);
        CHECK_NEAR(vd[k], pdn[k], 0.1f * pdn[k] + 1e-4f);
    }
    /* Facing the floor reads far more than facing the black sky; the scalar sits between. */
    CHECK(vd[1] > 2.0f * vu[1] && flat[1] < vd[1] && flat[1] > vu[1]);
    /* Same bytes for one thread and three; the file reads back to the same textures. */
    const size_t size = vdbgi_volume_write_memory(v, NULL, 0);
    CHECK(size > 0 && size == vdbgi_volume_write_memory(v3, NULL, 0) &&
          memcmp(v->file, v3->file, size) == 0);
    CHECK_RESULT(ctx, vdbgi_volume_write(v, tmp_path("l2.gi.gz")), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("l2.gi.gz"), &back), VDBGI_OK);
    if (back) {
        CHECK(back->info.basis == VDBGI_BASIS_SH2 && back->tex.sh);
        CHECK(memcmp(back->tex.atlas, v->tex.atlas, v->info.atlas_size) == 0);
        CHECK(back->tex.sh && memcmp(back->tex.sh, v->tex.sh, 6 * v->info.atlas_size) == 0);
        float again[3];
        vdbgi_volume_sample_normal(back, at, down, again);
        CHECK(memcmp(again, vd, sizeof(again)) == 0);
        CHECK_RESULT(ctx, vdbgi_volume_write_textures(back, tmp_path("l2-textures.gi")),
                     VDBGI_ERR_INVALID_ARG);
        CHECK(strstr(vdbgi_context_error(ctx), "L2") != NULL);
    }
    /*
     * Version 6 predicts the terms from one neighbour, version 7 better, in
     * a smaller file. The points no receiver reads take the prediction, so
     * only their terms differ: every valid probe reads alike, any normal.
     * Either version reads back as written.
     */
    CHECK(v->version == 7 && v6->version == 6 && scalar->version == 5);
    CHECK(memcmp(v6->tex.atlas, v->tex.atlas, v->info.atlas_size) == 0);
    size_t same = 0;
    for (size_t i = 0; i < p->count; i++)
        for (int a = 0; p->backface[i] <= p->invalid_threshold && a < 6; a++) {
            const float n[3] = {a == 0   ? 1.0f
                                : a == 1 ? -1.0f
                                         : 0.0f,
                                a == 2   ? 1.0f
                                : a == 3 ? -1.0f
                                         : 0.0f,
                                a == 4   ? 1.0f
                                : a == 5 ? -1.0f
                                         : 0.0f};
            float pos[3], r6[3], r7[3];
            for (int k = 0; k < 3; k++)
                pos[k] = (float)(p->origin[k] + p->spacing * p->ijk[3 * i + k]);
            vdbgi_volume_sample_normal(v6, pos, n, r6);
            vdbgi_volume_sample_normal(v, pos, n, r7);
            same += memcmp(r6, r7, sizeof(r6)) == 0;
            CHECK(memcmp(r6, r7, sizeof(r6)) == 0);
        }
    CHECK(same > 1000);
    CHECK(vdbgi_volume_write_memory(v6, NULL, 0) > size);
    CHECK_RESULT(ctx, vdbgi_volume_write(v6, tmp_path("l2-v6.gi.gz")), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("l2-v6.gi.gz"), &back6), VDBGI_OK);
    if (back6) {
        CHECK(back6->version == 6 && back6->info.basis == VDBGI_BASIS_SH2);
        CHECK(memcmp(back6->tex.sh, v6->tex.sh, 6 * v->info.atlas_size) == 0);
        const size_t again = vdbgi_volume_write_memory(back6, NULL, 0);
        CHECK(again == vdbgi_volume_write_memory(v6, NULL, 0) &&
              memcmp(back6->file, v6->file, again) == 0);
    }
    /* The plain file: header (116 bytes, version 7) and payload; then damaged. */
    uint8_t h[VDBGI_GI_HEADER_MAX];
    const size_t hs = vdbgi_gifile_header(&v->info, v->version, h);
    CHECK(hs == 116 && vdbgi_get_u32(h + 8) == 7 && vdbgi_get_u32(h + 112) == 2);
    const size_t raw = hs + v->payload_size;
    CHECK(v->payload_size ==
          v->info.indirection_size / 4 + 6 * v->info.brick_count + 28 * v->info.stored_points);
    uint8_t *const plain = malloc(raw);
    memcpy(plain, h, hs);
    memcpy(plain + hs, v->payload, v->payload_size);
    const struct {
        size_t offset, size; /* bytes written; size < raw cuts the file */
        uint32_t value;      /* at offset, if offset < hs */
        const char *says;
    } damage[] = {{raw, raw, 0, NULL},
                  {112, raw, 3, "unknown basis 3"},
                  {8, raw, 5, "cannot come from"},
                  {8, raw, 8, "this reader knows 1..7"},
                  {12, raw, 112, "bad header size"},
                  {raw, raw - 1, 0, "cannot come from"},
                  {raw, 114, 0, "too short"}};
    for (size_t d = 0; d < sizeof(damage) / sizeof(damage[0]); d++) {
        uint8_t *const copy = malloc(raw);
        memcpy(copy, plain, raw);
        if (damage[d].offset < hs)
            vdbgi_put_u32(copy + damage[d].offset, damage[d].value);
        FILE *f = fopen(tmp_path("l2-damaged.gi"), "wb");
        fwrite(copy, 1, damage[d].size, f);
        fclose(f);
        vdbgi_volume *r = NULL;
        CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("l2-damaged.gi"), &r),
                     damage[d].says ? VDBGI_ERR_FORMAT : VDBGI_OK);
        if (damage[d].says && !strstr(vdbgi_context_error(ctx), damage[d].says)) {
            fprintf(stderr, "case %zu: %s\n", d, vdbgi_context_error(ctx));
            CHECK(false);
        }
        vdbgi_volume_destroy(r);
        free(copy);
    }
    free(plain);
done:
    vdbgi_volume_destroy(back);
    vdbgi_volume_destroy(back6);
    vdbgi_volume_destroy(scalar);
    vdbgi_volume_destroy(v6);
    vdbgi_volume_destroy(v3);
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
}

/* p's terms with band drop left out (0: none) or sign_of negated (0: none), read along n. */
static void probe_l2_reading(const vdbgi_probes *p, size_t i, const float n[3], int drop,
                             int sign_of, float rgb[3])
{
    float sh[VDBGI_SH2_TERMS][3];
    CHECK_RESULT(p->ctx, vdbgi_probes_get_sh2(p, i, sh), VDBGI_OK);
    for (int k = 0; k < 3; k++) {
        if (drop)
            sh[drop][k] = 0.0f;
        if (sign_of)
            sh[sign_of][k] = -sh[sign_of][k];
    }
    vdbgi_sh2_eval((const float(*)[3])sh, n, rgb);
}

/*
 * The worst error over every valid probe of an eps-0 L2 volume, read at the
 * probe along each of the normals, against the probe's own E(n) (a band
 * dropped or negated when asked), in encoding steps: L0's RGBM step, and
 * one step of each term's ratio (term_step of its range over 127, as
 * term_bits rounds it) weighted by |p_k(n)|.
 */
static double worst_l2_error_in_steps(const vdbgi_probes *p, const vdbgi_volume *v,
                                      const float (*normals)[3], int count, int drop, int sign_of,
                                      int term_step)
{
    double worst = 0.0;
    for (size_t i = 0; i < p->count; i++) {
        if (p->backface[i] > p->invalid_threshold)
            continue; /* the volume holds the fill there, not the probe */
        const double q[3] = {p->ijk[3 * i], p->ijk[3 * i + 1], p->ijk[3 * i + 2]};
        float pos[3];
        world_of(p, q, pos);
        const float *const c0 = &p->rgb[3 * i];
        const float mx = fmaxf(c0[0], fmaxf(c0[1], c0[2]));
        for (int j = 0; j < count; j++) {
            const float *const n = normals[j];
            const double pk[8] = {n[0],        n[1],
                                  n[2],        n[0] * n[1],
                                  n[1] * n[2], 3 * n[2] * n[2] - 1,
                                  n[0] * n[2], n[0] * n[0] - n[1] * n[1]};
            double s = 0.0;
            for (int k = 0; k < 8; k++)
                s += fabs(pk[k]) * vdbgi_sh_ratio_range(k);
            float got[3], want[3];
            vdbgi_volume_sample_normal(v, pos, n, got);
            probe_l2_reading(p, i, n, drop, sign_of, want);
            for (int k = 0; k < 3; k++) {
                const double step =
                    (mx + 8.0 / 255.0) / 255.0 * (1.0 + s) + c0[k] * s * term_step / 127.0;
                worst = fmax(worst, fabs(got[k] - want[k]) / step);
            }
        }
    }
    return worst;
}

/*
 * At eps 0 every probe's E(n) comes back within one encoding step, for the
 * six axis normals and 20 random ones, with every bit of the terms kept and
 * with the default's; and the same check fails when any one band is left
 * out of the probe's own reading, or negated.
 */
static void at_eps_0_every_probe_reads_its_own_l2_for_any_normal(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    const float lo[3] = {-2.0f, 0.0f, -2.0f}, hi[3] = {2.0f, 3.0f, 2.0f};
    const float wlo[3] = {4.0f, 0.0f, -4.0f}, whi[3] = {4.5f, 2.0f, 4.0f};
    test_mesh_plane(&m, 16.0f, 0.0f);
    test_mesh_box(&m, lo, hi, 0);
    test_mesh_box(&m, wlo, whi, 0);
    const vdbgi_mesh_desc md = test_mesh_desc(&m, 0.6f, 0);
    vdbgi_scene *scene = NULL;
    vdbgi_probes *p = NULL;
    vdbgi_volume *v = NULL, *coarse = NULL;
    const vdbgi_place_desc pd = {.spacing = 0.5, .origin = {0.25, 0.25, 0.25}, .origin_is_set = 1};
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &scene), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 64, .basis = VDBGI_BASIS_SH2, .sky = {0.2f, 0.3f, 0.5f}};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, scene, &bd, NULL), VDBGI_OK);
    vdbgi_convert_desc cd = {.eps = VDBGI_ZERO, .max_level = VDBGI_ZERO, .term_bits = 8};
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v), VDBGI_OK);
    cd.term_bits = 0;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &coarse), VDBGI_OK);
    float normals[26][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    uint64_t state = 12345;
    for (int j = 6; j < 26; j++) {
        float l = 0.0f;
        for (int k = 0; k < 3; k++) {
            normals[j][k] = (float)(2.0 * vdbgi_uniform01(&state) - 1.0);
            l += normals[j][k] * normals[j][k];
        }
        for (int k = 0; k < 3; k++)
            normals[j][k] /= sqrtf(l);
    }
    if (v && coarse) {
        const float(*const ns)[3] = (const float(*)[3])normals;
        CHECK(worst_l2_error_in_steps(p, v, ns, 26, 0, 0, 1) <= 1.0);
        /* The default rounds each ratio to a step 2^(8 - bits) times as large: within it. */
        const int step = 1 << (8 - VDBGI_TERM_BITS);
        CHECK(coarse->info.term_bits == VDBGI_TERM_BITS &&
              worst_l2_error_in_steps(p, coarse, ns, 26, 0, 0, step) <= 1.0);
        CHECK(worst_l2_error_in_steps(p, coarse, ns, 26, 0, 0, 1) > 1.0);
        for (int band = 1; band <= 8; band++) {
            const double dropped = worst_l2_error_in_steps(p, v, ns, 26, band, 0, 1);
            const double negated = worst_l2_error_in_steps(p, v, ns, 26, 0, band, 1);
            if (!(dropped > 1.0 && negated > 1.0)) {
                fprintf(stderr, "band %d: %.2f steps dropped, %.2f negated\n", band, dropped,
                        negated);
                CHECK(false);
            }
        }
    }
    vdbgi_volume_destroy(coarse);
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(scene);
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
    RUN(only_cells_whose_filter_reads_a_valid_probe_get_bricks);
    RUN(columns_give_every_cell_its_indirection_texel);
    RUN(the_cell_under_the_first_valid_plane_is_lifted);
    RUN(coarse_bricks_under_the_first_valid_plane_read_the_filled_field);
    RUN(files_round_trip_and_are_deterministic);
    RUN(damaged_files_are_refused);
    RUN(bad_parameters_and_probes_are_refused);
    RUN(levels_png_shows_each_cells_level);
    RUN(failing_allocations_are_reported_without_leaks);
    RUN(textures_and_probes_copy_into_caller_buffers_after_a_size_query);
    RUN(l2_bricks_read_each_side_and_round_trip);
    RUN(at_eps_0_every_probe_reads_its_own_l2_for_any_normal);
    test_tmpdir_remove();
    return CHECK_EXIT();
}
