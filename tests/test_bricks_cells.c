/*
 * test_bricks_cells.c: which cells of the bricked volume get bricks, and
 * what the others read: only cells whose filter reads a valid probe get
 * bricks; every cell of a column gets its indirection texel; the cell under
 * the first valid plane is lifted, and coarse bricks there read the filled
 * field.
 */
#define _POSIX_C_SOURCE 200809L
#include "encode.h"
#include "field.h"
#include "gifile.h"
#include "image_shim.h"
#include "test_bricks.h"
#include "test_slab.h"
#include "test_util.h"
#include "util.h"

#include <math.h>
#include <stdio.h>
#include <unistd.h>

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
    const vdbgi_convert_desc cd = {.max_level_is_set = 1, .layout = (vdbgi_layout)layout};
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
        const float c = floorf(u * (float)vi->ind_dims[k]);
        if (!(c >= 0.0f && c < (float)vi->ind_dims[k]))
            return NULL;
        i = i * vi->ind_dims[k] + (size_t)c;
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
        const uint32_t *const d = vi.ind_dims;
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
                                  .noise_sigmas_is_set = 1,
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

int main(void)
{
    test_tmpdir_make("test-bricks-cells");
    RUN(only_cells_whose_filter_reads_a_valid_probe_get_bricks);
    RUN(columns_give_every_cell_its_indirection_texel);
    RUN(the_cell_under_the_first_valid_plane_is_lifted);
    RUN(coarse_bricks_under_the_first_valid_plane_read_the_filled_field);
    test_tmpdir_remove();
    return CHECK_EXIT();
}
