/*
 * test_bevy.c: Bevy exports put every voxel side exactly where seeds 001 and
 * 002 say, in valid KTX2 and PNG files; a bake's ambient cubes resample onto
 * the dense grid; bad boxes, resolutions and scalar-only probes are refused
 * without leaving a file.
 */
#define _POSIX_C_SOURCE 200809L
#include "encode.h"
#include "field.h"
#include "image_shim.h"
#include "probes.h"
#include "test_util.h"

#include <unistd.h>

static const int res[3] = {3, 5, 7}; /* odd and all different */

/* Side s of voxel (x, y, z) says who it is: exact in half floats and in RGB9E5. */
static void expected(int x, int y, int z, int side, float rgb[3])
{
    rgb[0] = (float)(x + 1);
    rgb[1] = (float)(y + 1 + 8 * side);
    rgb[2] = (float)(z + 1);
}

static vdbgi_bevy *synthetic(vdbgi_context *ctx)
{
    float *const cube = malloc((size_t)res[0] * res[1] * res[2] * 18 * sizeof(float));
    for (int z = 0; z < res[2]; z++)
        for (int y = 0; y < res[1]; y++)
            for (int x = 0; x < res[0]; x++)
                for (int side = 0; side < 6; side++)
                    expected(x, y, z, side,
                             &cube[18 * (((size_t)z * res[1] + y) * res[0] + x) + 3 * side]);
    const double lo[3] = {-1, 0, 2}, hi[3] = {2, 5, 9};
    vdbgi_bevy *b = NULL;
    CHECK_RESULT(ctx, vdbgi_bevy_create(ctx, cube, res, lo, hi, &b), VDBGI_OK);
    free(cube);
    return b;
}

static uint8_t *slurp(const char *path, size_t *size)
{
    FILE *const f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *const b = malloc(*size);
    if (fread(b, 1, *size, f) != *size)
        *size = 0;
    fclose(f);
    return b;
}

static uint32_t u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Side names of the seeds, for messages. */
static const char *const side_name[6] = {"+X", "-X", "+Y", "-Y", "+Z", "-Z"};

static void ktx2_layout_follows_seed_001(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_bevy *b = synthetic(ctx);
    for (int format = 0; format < 2 && b; format++) {
        CHECK_RESULT(ctx,
                     vdbgi_bevy_write_ktx2(b, tmp_path("v.ktx2"), (vdbgi_bevy_format)format, NULL),
                     VDBGI_OK);
        size_t size = 0;
        uint8_t *const f = slurp(tmp_path("v.ktx2"), &size);
        CHECK(f && size > 104);
        if (!f || size <= 104)
            continue;
        static const uint8_t id[12] = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                       '0',  0xBB, '\r', '\n', 0x1A, '\n'};
        CHECK(memcmp(f, id, 12) == 0);
        CHECK(u32(f + 12) == (format ? 123u : 97u)); /* VkFormat */
        const uint32_t w = u32(f + 20), h = u32(f + 24), d = u32(f + 28);
        CHECK(w == 3 && h == 2 * 5 && d == 3 * 7);   /* (Rx, 2Ry, 3Rz) */
        CHECK(u32(f + 36) == 1 && u32(f + 40) == 1); /* one face, one level */
        const uint64_t offset = u32(f + 80), length = u32(f + 88);
        const size_t texel = format ? 4 : 8;
        CHECK(length == (uint64_t)w * h * d * texel && offset + length == size);
        CHECK(offset % texel == 0);
        int wrong = 0;
        for (int z = 0; z < res[2]; z++)
            for (int y = 0; y < res[1]; y++)
                for (int x = 0; x < res[0]; x++)
                    for (int side = 0; side < 6; side++) {
                        const int positive = side % 2 == 0, axis = side / 2;
                        const size_t s = (size_t)x, t = (size_t)(y + (positive ? res[1] : 0));
                        const size_t p = (size_t)(z + axis * res[2]);
                        const uint8_t *const tx = f + offset + ((p * h + t) * w + s) * texel;
                        float got[3], want[3];
                        expected(x, y, z, side, want);
                        if (format) {
                            vdbgi_rgb9e5_decode(u32(tx), got);
                        } else {
                            for (int k = 0; k < 3; k++)
                                got[k] =
                                    vdbgi_half_to_float((uint16_t)(tx[2 * k] | tx[2 * k + 1] << 8));
                            CHECK(vdbgi_half_to_float((uint16_t)(tx[6] | tx[7] << 8)) == 1.0f);
                        }
                        if (memcmp(got, want, sizeof(got)) != 0 && wrong++ < 3)
                            fprintf(stderr, "voxel %d,%d,%d side %s: got %g %g %g\n", x, y, z,
                                    side_name[side], (double)got[0], (double)got[1],
                                    (double)got[2]);
                    }
        CHECK(wrong == 0);
        free(f);
    }
    vdbgi_bevy_destroy(b);
    vdbgi_context_destroy(ctx);
}

static void baked_gi_layout_follows_seed_002(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_bevy *b = synthetic(ctx);
    if (b)
        CHECK_RESULT(ctx, vdbgi_bevy_write_baked_gi(b, tmp_path("v.png"), NULL), VDBGI_OK);
    vdbgi_image img = {0, 0, NULL};
    CHECK_RESULT(ctx, vdbgi_image_decode(ctx, tmp_path("v.png"), NULL, 0, NULL, &img), VDBGI_OK);
    CHECK(img.width == 3 * 3 && img.height == 2 * 5 * 7);
    int wrong = 0;
    for (int z = 0; z < res[2] && img.rgba; z++)
        for (int y = 0; y < res[1]; y++)
            for (int x = 0; x < res[0]; x++) {
                /* i = z w h + y w + x; cell at (3 (i mod W/3), 2 floor(i / (W/3))). */
                const int i = (z * res[1] + y) * res[0] + x, per_row = img.width / 3;
                const int cx = 3 * (i % per_row), cy = 2 * (i / per_row);
                for (int side = 0; side < 6; side++) {
                    /* Upper row +x +y +z, lower row -x -y -z. */
                    const int tx = cx + side / 2, ty = cy + (side % 2);
                    const float *const px = &img.rgba[4 * ((size_t)ty * img.width + tx)];
                    uint8_t t[4];
                    for (int k = 0; k < 4; k++)
                        t[k] = (uint8_t)lrintf(px[k] * 255.0f);
                    float got[3], want[3];
                    vdbgi_sharedexp8_decode(t, got);
                    expected(x, y, z, side, want);
                    const float step = ldexpf(1.0f, (int)t[3] - 128) / 255.0f;
                    for (int k = 0; k < 3; k++)
                        if (!(fabsf(got[k] - want[k]) <= 0.5f * step * 1.0001f) && wrong++ < 3)
                            fprintf(stderr, "cell %d side %s: got %g, want %g\n", i,
                                    side_name[side], (double)got[k], (double)want[k]);
                }
            }
    CHECK(wrong == 0);
    vdbgi_free(ctx, img.rgba);
    vdbgi_bevy_destroy(b);
    vdbgi_context_destroy(ctx);
}

/* Probes baked with ambient cubes over a closed room and a floor. */
static vdbgi_probes *baked_room(vdbgi_context *ctx, vdbgi_basis basis, vdbgi_scene **scene)
{
    test_mesh m = {0};
    const float lo[3] = {-3, 0, -2}, hi[3] = {3, 3, 2};
    test_mesh_box(&m, lo, hi, 1);
    const vdbgi_mesh_desc md = test_mesh_desc(&m, 0.5f, 0);
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &md, 1, scene), VDBGI_OK);
    vdbgi_probes *p = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, *scene, NULL, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 64, .falloff = INFINITY, .basis = basis};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, *scene, &bd, NULL), VDBGI_OK);
    return p;
}

static void baked_cubes_resample_onto_the_grid(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = baked_room(ctx, VDBGI_BASIS_AMBIENT_CUBE, &s);
    /* Inside the room only: every ray hits a wall of albedo 0.5 lit by ambient 0.15. */
    const vdbgi_bevy_desc d = {
        .resolution = {6, 3, 4}, .box_min = {-3, 0, -2}, .box_max = {3, 3, 2}, .box_is_set = 1};
    vdbgi_bevy *b = NULL;
    CHECK_RESULT(ctx, vdbgi_bevy_build(ctx, p, &d, &b), VDBGI_OK);
    if (b) {
        vdbgi_bevy_info info;
        vdbgi_bevy_get_info(b, &info);
        CHECK(info.resolution[0] == 6 && info.resolution[2] == 4);
        CHECK_NEAR(info.center[1], 1.5, 1e-12);
        CHECK_NEAR(info.size[0], 6.0, 1e-12);
        CHECK_RESULT(ctx, vdbgi_bevy_write_ktx2(b, tmp_path("room.ktx2"), VDBGI_BEVY_RGBA16F, NULL),
                     VDBGI_OK);
        size_t size = 0;
        uint8_t *const f = slurp(tmp_path("room.ktx2"), &size);
        int off = 0;
        for (size_t t = 0; f && t < (size_t)6 * 6 * 12; t++) {
            const uint8_t *const tx = f + u32(f + 80) + 8 * t;
            off += fabsf(vdbgi_half_to_float((uint16_t)(tx[0] | tx[1] << 8)) - 0.075f) > 1e-3f;
        }
        CHECK(f && off == 0); /* every voxel side reads albedo x ambient */
        free(f);
        CHECK_RESULT(ctx, vdbgi_bevy_write_json(b, tmp_path("room.json"), "room.ktx2", "ktx2"),
                     VDBGI_OK);
        size = 0;
        uint8_t *const j = slurp(tmp_path("room.json"), &size);
        CHECK(j && size > 0 && strstr((const char *)j, "\"scale\": [6, 3, 4]"));
        free(j);
    }
    vdbgi_bevy_destroy(b);
    /* Default grid: the baked bounds at 4 x spacing. */
    CHECK_RESULT(ctx, vdbgi_bevy_build(ctx, p, NULL, &b), VDBGI_OK);
    if (b) {
        vdbgi_bevy_info info;
        vdbgi_bevy_get_info(b, &info);
        for (int k = 0; k < 3; k++)
            CHECK(info.resolution[k] == (int)ceil(info.size[k] / 2.0));
    }
    vdbgi_bevy_destroy(b);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void bad_volumes_are_refused_without_files(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL, *s2 = NULL;
    vdbgi_probes *cubes = baked_room(ctx, VDBGI_BASIS_AMBIENT_CUBE, &s);
    vdbgi_probes *scalar = baked_room(ctx, VDBGI_BASIS_SCALAR, &s2);
    vdbgi_bevy *b = (vdbgi_bevy *)1;
    CHECK_RESULT(ctx, vdbgi_bevy_build(ctx, scalar, NULL, &b), VDBGI_ERR_INVALID_ARG);
    CHECK(b == NULL && strstr(vdbgi_context_error(ctx), "ambient-cube"));
    const vdbgi_bevy_desc bad[] = {
        {.box_min = {-100, 0, 0}, .box_max = {1, 1, 1}, .box_is_set = 1}, /* outside */
        {.box_min = {0, 0, 0}, .box_max = {0, 1, 1}, .box_is_set = 1},    /* empty */
        {.resolution = {4, 0, 4}},                                        /* zero */
        {.resolution = {3000, 1, 1}},                                     /* > 2048 */
        {.resolution = {4, 2000, 4}},                                     /* 2Ry > 2048 */
        {.fill = (vdbgi_fill)5},
        {.voxel_size = -1.0},
    };
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        b = (vdbgi_bevy *)1;
        CHECK_RESULT(ctx, vdbgi_bevy_build(ctx, cubes, &bad[i], &b), VDBGI_ERR_INVALID_ARG);
        CHECK(b == NULL);
        CHECK(strchr(vdbgi_context_error(ctx), '\n') == NULL);
    }
    CHECK(strstr(vdbgi_context_error(ctx), "voxel size") != NULL);
    const int zero[3] = {0, 1, 1};
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    float cube[18] = {0};
    CHECK_RESULT(ctx, vdbgi_bevy_create(ctx, cube, zero, lo, hi, &b), VDBGI_ERR_INVALID_ARG);
    CHECK(access(tmp_path("never.ktx2"), F_OK) != 0);
    vdbgi_probes_destroy(cubes);
    vdbgi_probes_destroy(scalar);
    vdbgi_scene_destroy(s);
    vdbgi_scene_destroy(s2);
    vdbgi_context_destroy(ctx);
}

static void writers_count_the_colours_they_clamp(void)
{
    /* One voxel whose +X side is far past half floats (65504) and RGB9E5 (65408). */
    float cube[18] = {0};
    cube[0] = cube[1] = cube[2] = 1e6f;
    const int one[3] = {1, 1, 1};
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    vdbgi_context *ctx = test_context();
    vdbgi_bevy *b = NULL;
    CHECK_RESULT(ctx, vdbgi_bevy_create(ctx, cube, one, lo, hi, &b), VDBGI_OK);
    size_t half = 99, e5 = 99, png = 99;
    if (b) {
        CHECK_RESULT(ctx, vdbgi_bevy_write_ktx2(b, tmp_path("c.ktx2"), VDBGI_BEVY_RGBA16F, &half),
                     VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_bevy_write_ktx2(b, tmp_path("c.ktx2"), VDBGI_BEVY_RGB9E5, &e5),
                     VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_bevy_write_baked_gi(b, tmp_path("c.png"), &png), VDBGI_OK);
    }
    CHECK(half == 3); /* per channel */
    CHECK(e5 == 1);   /* per texel */
    CHECK(png == 0);  /* 2^(255A - 128) reaches 1e6 */
    vdbgi_bevy_destroy(b);
    vdbgi_context_destroy(ctx);
}

int main(void)
{
    test_tmpdir_make("test-bevy");
    RUN(writers_count_the_colours_they_clamp);
    RUN(ktx2_layout_follows_seed_001);
    RUN(baked_gi_layout_follows_seed_002);
    RUN(baked_cubes_resample_onto_the_grid);
    RUN(bad_volumes_are_refused_without_files);
    test_tmpdir_remove();
    return CHECK_EXIT();
}
