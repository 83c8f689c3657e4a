/*
 * test_bricks_l2.c: bricks with L2 terms read each side of a surface and
 * round-trip; at eps 0 every probe reads its own L2 light for any normal.
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

/* The size of v's file (made by the query), which must be made. */
static size_t file_size(vdbgi_context *ctx, const vdbgi_volume *v)
{
    size_t size = 0;
    CHECK_RESULT(ctx, vdbgi_volume_write_memory(v, NULL, 0, &size), VDBGI_OK);
    return size;
}

/* The probes every test here places: at 0.5 m, off the surfaces by a quarter spacing. */
static const vdbgi_place_desc pd = {
    .spacing = 0.5, .origin = {0.25, 0.25, 0.25}, .origin_is_set = 1};

/*
 * The scene of the tests after the first, from mesh m (which must outlive it): a 4 x 3 x
 * 4 m box on a 16 m floor, grey 0.6, and with wall a thin wall beside it.
 */
static vdbgi_scene *box_on_floor(vdbgi_context *ctx, test_mesh *m, bool wall)
{
    const float lo[3] = {-2.0f, 0.0f, -2.0f}, hi[3] = {2.0f, 3.0f, 2.0f};
    const float wlo[3] = {4.0f, 0.0f, -4.0f}, whi[3] = {4.5f, 2.0f, 4.0f};
    test_mesh_plane(m, 16.0f, 0.0f);
    test_mesh_box(m, lo, hi, 0);
    if (wall)
        test_mesh_box(m, wlo, whi, 0);
    const vdbgi_mesh_desc md = test_mesh_desc(m, 0.6f, 0);
    vdbgi_scene *scene = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &scene), VDBGI_OK);
    return scene;
}

/*
 * L2 terms in bricks (.gi version 7, and 6; version 8 below): a surface reads its own side, as the
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
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, &scene), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 64, .basis = VDBGI_BASIS_SH2};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, scene, &bd, NULL), VDBGI_OK);
    vdbgi_convert_desc cd = {.eps_is_set = 1, .max_level_is_set = 1, .threads = 1, .gi_version = 7};
    vdbgi_volume *v = NULL, *v3 = NULL, *v6 = NULL, *scalar = NULL, *back = NULL, *back6 = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v), VDBGI_OK);
    cd.threads = 3;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v3), VDBGI_OK);
    cd.gi_version = 6;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v6), VDBGI_OK);
    cd.gi_version = 5;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &scalar), VDBGI_ERR_INVALID_ARG);
    cd.terms = VDBGI_TERMS_DROP;
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
    const size_t size = file_size(ctx, v);
    CHECK(size > 0 && size == file_size(ctx, v3) && memcmp(v->file, v3->file, size) == 0);
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
    CHECK(file_size(ctx, v6) > size);
    CHECK_RESULT(ctx, vdbgi_volume_write(v6, tmp_path("l2-v6.gi.gz")), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("l2-v6.gi.gz"), &back6), VDBGI_OK);
    if (back6) {
        CHECK(back6->version == 6 && back6->info.basis == VDBGI_BASIS_SH2);
        CHECK(memcmp(back6->tex.sh, v6->tex.sh, 6 * v->info.atlas_size) == 0);
        const size_t again = file_size(ctx, back6);
        CHECK(again == file_size(ctx, v6) && memcmp(back6->file, v6->file, again) == 0);
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
                  {8, raw, 8, "cannot come from"}, /* short of version 8's planes */
                  {8, raw, 9, "this reader knows 1..8"},
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

static double luma(const float c[3])
{
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

/*
 * p's terms with band drop left out (0: none) or sign_of negated (0: none), read along n;
 * with luma2, bands 4-8 as .gi version 8 holds them: each channel's L0 times the band's
 * luminance over L0's.
 */
static void probe_l2_reading(const vdbgi_probes *p, size_t i, const float n[3], int drop,
                             int sign_of, bool luma2, float rgb[3])
{
    float sh[VDBGI_SH2_TERMS][3];
    CHECK_RESULT(p->ctx, vdbgi_probes_get_sh2(p, i, sh), VDBGI_OK);
    for (int b = 4; luma2 && b < VDBGI_SH2_TERMS; b++) {
        const double r = luma(sh[0]) > 0.0 ? luma(sh[b]) / luma(sh[0]) : 0.0;
        for (int k = 0; k < 3; k++)
            sh[b][k] = (float)(sh[0][k] * r);
    }
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
 * dropped or negated when asked; bands 4-8 in luminance with luma2), in
 * encoding steps: L0's RGBM step, and one step of each term's ratio
 * (term_step of its range over 127, as term_bits rounds it) weighted by
 * |p_k(n)|.
 */
static double worst_l2_error_in_steps(const vdbgi_probes *p, const vdbgi_volume *v,
                                      const float (*normals)[3], int count, int drop, int sign_of,
                                      int term_step, bool luma2)
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
            probe_l2_reading(p, i, n, drop, sign_of, luma2, want);
            for (int k = 0; k < 3; k++) {
                const double step =
                    (mx + 8.0 / 255.0) / 255.0 * (1.0 + s) + c0[k] * s * term_step / 127.0;
                worst = fmax(worst, fabs(got[k] - want[k]) / step);
            }
        }
    }
    return worst;
}

/* The six axis normals, then 20 random unit ones from seed. */
static void axes_and_random_normals(float normals[26][3], uint64_t seed)
{
    static const float axes[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                     {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    memcpy(normals, axes, sizeof(axes));
    for (int j = 6; j < 26; j++) {
        float l = 0.0f;
        for (int k = 0; k < 3; k++) {
            normals[j][k] = (float)(2.0 * vdbgi_uniform01(&seed) - 1.0);
            l += normals[j][k] * normals[j][k];
        }
        for (int k = 0; k < 3; k++)
            normals[j][k] /= sqrtf(l);
    }
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
    vdbgi_scene *scene = box_on_floor(ctx, &m, true);
    vdbgi_probes *p = NULL;
    vdbgi_volume *v = NULL, *coarse = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 64, .basis = VDBGI_BASIS_SH2, .sky = {0.2f, 0.3f, 0.5f}};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, scene, &bd, NULL), VDBGI_OK);
    vdbgi_convert_desc cd = {
        .eps_is_set = 1, .max_level_is_set = 1, .term_bits = 8, .gi_version = 7};
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v), VDBGI_OK);
    cd.term_bits = 0;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &coarse), VDBGI_OK);
    float normals[26][3];
    axes_and_random_normals(normals, 12345);
    if (v && coarse) {
        const float(*const ns)[3] = (const float(*)[3])normals;
        CHECK(worst_l2_error_in_steps(p, v, ns, 26, 0, 0, 1, false) <= 1.0);
        /* The default rounds each ratio to a step 2^(8 - bits) times as large: within it. */
        const int step = 1 << (8 - VDBGI_TERM_BITS);
        CHECK(coarse->info.term_bits == VDBGI_TERM_BITS &&
              worst_l2_error_in_steps(p, coarse, ns, 26, 0, 0, step, false) <= 1.0);
        CHECK(worst_l2_error_in_steps(p, coarse, ns, 26, 0, 0, 1, false) > 1.0);
        for (int band = 1; band <= 8; band++) {
            const double dropped = worst_l2_error_in_steps(p, v, ns, 26, band, 0, 1, false);
            const double negated = worst_l2_error_in_steps(p, v, ns, 26, 0, band, 1, false);
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

/*
 * Version 8: terms 1-3 per channel, 4-8 one luminance ratio. Beside a
 * version 7 volume of the same probes, at eps 0 and every bit: the same atlas and the
 * same first-band bytes at every texel, the second band's three channels equal, 14 term
 * bytes a stored point in the file and a texel on the GPU, a smaller file that reads back
 * byte for byte, refused when cut; and every probe reads, for any normal, within one
 * encoding step of its own light with bands 4-8 in luminance, and not of its own light in
 * colour (a white sun on the floor under a blue sky: light whose colour turns with
 * direction).
 */
static void version_8_holds_the_second_band_in_luminance(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    vdbgi_scene *scene = box_on_floor(ctx, &m, false);
    vdbgi_probes *p = NULL;
    vdbgi_volume *v7 = NULL, *v8 = NULL, *back = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 64,
                                .basis = VDBGI_BASIS_SH2,
                                .sky = {0.05f, 0.1f, 0.4f},
                                .sun_dir = {0.4f, 0.8f, 0.3f},
                                .sun_color = {2.0f, 2.0f, 2.0f}};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, scene, &bd, NULL), VDBGI_OK);
    vdbgi_convert_desc cd = {
        .eps_is_set = 1, .max_level_is_set = 1, .term_bits = 8, .gi_version = 7};
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v7), VDBGI_OK);
    cd.gi_version = 8;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v8), VDBGI_OK);
    if (!v7 || !v8)
        goto done;
    CHECK(v7->version == 7 && v8->version == VDBGI_GI_VERSION && VDBGI_GI_VERSION == 8);
    const size_t texels = v8->info.atlas_size / 4;
    CHECK(v8->info.atlas_size == v7->info.atlas_size &&
          memcmp(v8->tex.atlas, v7->tex.atlas, v8->info.atlas_size) == 0);
    size_t first_same = 0, second_equal = 0, second_differs_in_v7 = 0;
    for (size_t t = 0; t < texels; t++) {
        const int8_t *a = &v8->tex.sh[24 * t], *b = &v7->tex.sh[24 * t];
        first_same += memcmp(a, b, 9) == 0;
        bool equal = true, differs = false;
        for (int k = 9; k < 24; k += 3) {
            equal &= a[k] == a[k + 1] && a[k] == a[k + 2];
            differs |= b[k] != b[k + 1] || b[k] != b[k + 2];
        }
        second_equal += equal;
        second_differs_in_v7 += differs;
    }
    CHECK(first_same == texels && second_equal == texels && second_differs_in_v7 > texels / 10);
    vdbgi_volume_info i7, i8;
    vdbgi_volume_get_info(v7, &i7);
    vdbgi_volume_get_info(v8, &i8);
    CHECK(i7.sh_size == 24 * texels && i8.sh_size == 14 * texels);
    CHECK(v8->payload_size ==
          v8->info.indirection_size / 4 + 6 * v8->info.brick_count + 18 * v8->info.stored_points);
    const size_t size = file_size(ctx, v8);
    CHECK(size > 0 && size < file_size(ctx, v7));
    CHECK_RESULT(ctx, vdbgi_volume_write(v8, tmp_path("l2-v8.gi.gz")), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("l2-v8.gi.gz"), &back), VDBGI_OK);
    if (back) {
        CHECK(back->version == 8 && back->info.basis == VDBGI_BASIS_SH2);
        CHECK(memcmp(back->tex.atlas, v8->tex.atlas, v8->info.atlas_size) == 0);
        CHECK(memcmp(back->tex.sh, v8->tex.sh, 24 * texels) == 0);
        CHECK(file_size(ctx, back) == size && memcmp(back->file, v8->file, size) == 0);
    }
    uint8_t h[VDBGI_GI_HEADER_MAX];
    const size_t hs = vdbgi_gifile_header(&v8->info, v8->version, h);
    CHECK(hs == 116 && vdbgi_get_u32(h + 8) == 8 && vdbgi_get_u32(h + 112) == 2);
    const size_t raw = hs + v8->payload_size;
    uint8_t *const plain = malloc(raw);
    memcpy(plain, h, hs);
    memcpy(plain + hs, v8->payload, v8->payload_size);
    /* As version 7 the same bytes are short of the three channels' terms: refused. */
    const struct {
        uint32_t version;
        size_t size;
        vdbgi_result want;
    } cases[] = {{8, raw, VDBGI_OK}, {7, raw, VDBGI_ERR_FORMAT}, {8, raw - 1, VDBGI_ERR_FORMAT}};
    for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
        vdbgi_put_u32(plain + 8, cases[c].version);
        FILE *f = fopen(tmp_path("l2-v8.gi"), "wb");
        fwrite(plain, 1, cases[c].size, f);
        fclose(f);
        vdbgi_volume *r = NULL;
        CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("l2-v8.gi"), &r), cases[c].want);
        vdbgi_volume_destroy(r);
    }
    free(plain);
    float normals[26][3];
    axes_and_random_normals(normals, 777);
    const float(*const ns)[3] = (const float(*)[3])normals;
    const double luma_steps = worst_l2_error_in_steps(p, v8, ns, 26, 0, 0, 1, true);
    const double colour_steps = worst_l2_error_in_steps(p, v8, ns, 26, 0, 0, 1, false);
    if (!(luma_steps <= 1.0 && colour_steps > 2.0)) {
        fprintf(stderr, "version 8: %.2f steps from its luminance bands, %.2f from colour\n",
                luma_steps, colour_steps);
        CHECK(false);
    }
    CHECK(worst_l2_error_in_steps(p, v7, ns, 26, 0, 0, 1, false) <= 1.0);
done:
    vdbgi_volume_destroy(back);
    vdbgi_volume_destroy(v8);
    vdbgi_volume_destroy(v7);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
}

/*
 * luma2_error computed apart: every valid probe read along the six axes and the eight
 * diagonals with all its terms in colour and with terms 4-8 as version 8 holds them, the
 * RMS of the channels' difference over the mean reading.
 */
static double luma2_error_of(const vdbgi_probes *p)
{
    const float d = 1.0f / sqrtf(3.0f);
    double sq = 0.0, sum = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < p->count; i++) {
        if (p->backface[i] > p->invalid_threshold)
            continue;
        for (int j = 0; j < 14; j++) {
            const float a = j < 6         ? 0.0f
                            : (j - 6) & 4 ? -d
                                          : d,
                        b = j < 6         ? 0.0f
                            : (j - 6) & 2 ? -d
                                          : d,
                        c = j < 6         ? 0.0f
                            : (j - 6) & 1 ? -d
                                          : d;
            float n3[3] = {a, b, c};
            if (j < 6) {
                n3[j / 2] = j % 2 ? -1.0f : 1.0f;
            }
            float colour[3], luma2[3];
            probe_l2_reading(p, i, n3, 0, 0, false, colour);
            probe_l2_reading(p, i, n3, 0, 0, true, luma2);
            for (int k = 0; k < 3; k++) {
                sq += (double)(colour[k] - luma2[k]) * (colour[k] - luma2[k]);
                sum += colour[k];
                n++;
            }
        }
    }
    return sum > 0.0 ? sqrt(sq / (double)n) / (sum / (double)n) : 0.0;
}

/*
 * gi_version 0 chooses: version 8 where its second band moves the probes' readings by at
 * most VDBGI_LUMA2_TOLERANCE (info.luma2_error, as computed apart), else 7. Under a white
 * sky over grey surfaces every direction's light has one colour: no error, version 8.
 * A white sun under a faintly blue sky: a small error (0.35 %), version 8. A white sun on
 * the floor under a deep blue sky: version 7.
 */
static void the_default_chooses_the_luminance_band_where_it_costs_little(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    vdbgi_scene *scene = box_on_floor(ctx, &m, false);
    const vdbgi_bake_desc skies[3] = {{.rays = 64,
                                       .basis = VDBGI_BASIS_SH2,
                                       .sky = {0.5f, 0.5f, 0.5f},
                                       .lights = VDBGI_LIGHTS_OFF},
                                      {.rays = 64,
                                       .basis = VDBGI_BASIS_SH2,
                                       .sky = {0.3f, 0.32f, 0.36f},
                                       .sun_dir = {0.4f, 0.8f, 0.3f},
                                       .sun_color = {1.0f, 1.0f, 1.0f}},
                                      {.rays = 64,
                                       .basis = VDBGI_BASIS_SH2,
                                       .sky = {0.02f, 0.05f, 0.4f},
                                       .sun_dir = {0.4f, 0.8f, 0.3f},
                                       .sun_color = {2.0f, 2.0f, 2.0f}}};
    for (int s = 0; s < 3; s++) {
        vdbgi_probes *p = NULL;
        vdbgi_volume *v = NULL;
        CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &p), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_probes_bake(p, scene, &skies[s], NULL), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &(vdbgi_convert_desc){.threads = 2}, &v),
                     VDBGI_OK);
        if (v) {
            vdbgi_volume_info vi;
            vdbgi_volume_get_info(v, &vi);
            const double apart = luma2_error_of(p);
            if (!(fabs(vi.luma2_error - apart) <= 1e-4 * apart + 1e-6) ||
                (s == 0   ? !(vi.luma2_error < 1e-4) || v->version != 8
                 : s == 1 ? !(vi.luma2_error > 0.001 && vi.luma2_error <= VDBGI_LUMA2_TOLERANCE) ||
                                v->version != 8
                          : !(vi.luma2_error > VDBGI_LUMA2_TOLERANCE) || v->version != 7)) {
                fprintf(stderr, "sky %d: luma2_error %g (apart %g), version %u\n", s,
                        vi.luma2_error, apart, v->version);
                CHECK(false);
            }
        }
        vdbgi_volume_destroy(v);
        vdbgi_probes_destroy(p);
    }
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
}

int main(void)
{
    test_tmpdir_make("test-bricks-l2");
    RUN(l2_bricks_read_each_side_and_round_trip);
    RUN(at_eps_0_every_probe_reads_its_own_l2_for_any_normal);
    RUN(version_8_holds_the_second_band_in_luminance);
    RUN(the_default_chooses_the_luminance_band_where_it_costs_little);
    test_tmpdir_remove();
    return CHECK_EXIT();
}
