/*
 * test_scene.c: scenes load through assimp with node transforms applied and
 * albedo = base colour x texture at the UV (external files and textures
 * embedded in .glb, sRGB-decoded) x vertex colour; double-sided materials are
 * honoured; bad files and non-finite vertices are refused or skipped as
 * documented.
 */
#define _POSIX_C_SOURCE 200809L
#include "scene.h"
#include "test_util.h"
#include "tracer.h"

#include <math.h>
#include <stdio.h>
#include <unistd.h>
#include <zlib.h>

static void write_file(const char *name, const void *data, size_t size)
{
    FILE *const f = fopen(tmp_path(name), "wb");
    if (!f || fwrite(data, 1, size, f) != size) {
        fprintf(stderr, "cannot write %s\n", tmp_path(name));
        exit(1);
    }
    fclose(f);
}

static void write_text(const char *name, const char *text)
{
    write_file(name, text, strlen(text));
}

static float srgb(int c)
{
    const float v = (float)c / 255.0f;
    return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

/* First hit straight down from (x, 10, z): the triangle and its barycentrics. */
static int hit_below(const vdbgi_scene *s, float x, float z, vdbgi_hit *h)
{
    const float org[3] = {x, 10.0f, z}, dir[3] = {0.0f, -1.0f, 0.0f};
    const vdbgi_ray_batch b = {org, dir, 3, 3, 0.0f, 100.0f, 1, NULL};
    unsigned char scratch[512];
    vdbgi_tracer *t = NULL;
    if (vdbgi_tracer_create(s->ctx, s->positions, s->vertex_count, s->indices, s->triangle_count,
                            &t) != VDBGI_OK)
        return 0;
    vdbgi_tracer_intersect(t, VDBGI_TRACE_SINGLE, &b, h, scratch);
    vdbgi_tracer_destroy(t);
    return h->t < INFINITY;
}

/* 2x2 texture: red, green / blue, white (row 0 on top). */
static const unsigned char texels[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}};

static void obj_albedo_is_kd_times_external_texture(void)
{
    /* A 2 m quad, u = x / 2 and v = -z / 2; Kd 0.5; a PPM texture beside it. */
    write_text("quad.obj", "mtllib quad.mtl\n"
                           "v 0 0 0\nv 2 0 0\nv 2 0 -2\nv 0 0 -2\n"
                           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                           "usemtl tex\nf 1/1 2/2 3/3 4/4\n");
    write_text("quad.mtl", "newmtl tex\nKd 0.5 0.5 0.5\nmap_Kd quad.ppm\n");
    char ppm[64];
    const int head = snprintf(ppm, sizeof(ppm), "P6\n2 2\n255\n");
    memcpy(ppm + head, texels, sizeof(texels));
    write_file("quad.ppm", ppm, (size_t)head + sizeof(texels));

    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, tmp_path("quad.obj"), &s), VDBGI_OK);
    if (!s)
        goto done;
    vdbgi_scene_info info;
    vdbgi_scene_get_info(s, &info);
    CHECK(info.triangle_count == 2 && info.texture_count == 1);
    CHECK(strcmp(info.name, "quad.obj") == 0);
    /* Texel centres: uv (0.25, 0.75) is the top-left texel, and so on. */
    const float uv[4][2] = {{0.25f, 0.75f}, {0.75f, 0.75f}, {0.25f, 0.25f}, {0.75f, 0.25f}};
    for (int t = 0; t < 4; t++) {
        vdbgi_hit h;
        CHECK(hit_below(s, 2.0f * uv[t][0], -2.0f * uv[t][1], &h));
        float rgb[3];
        vdbgi_scene_albedo(s, h.prim, h.u, h.v, rgb);
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(rgb[k], 0.5f * srgb(texels[t][k]), 1e-5);
    }
    /* OBJ faces are single-sided. */
    CHECK(!(s->tris[0].flags & VDBGI_TRI_DOUBLE_SIDED));
done:
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* ---- a minimal .glb writer: one triangle fan, optional embedded PNG ------- */

static size_t png_encode(const unsigned char (*rgb)[3], int w, int h, unsigned char *out)
{
    unsigned char raw[64];
    size_t n = 0;
    for (int y = 0; y < h; y++) {
        raw[n++] = 0;
        for (int x = 0; x < w; x++)
            for (int k = 0; k < 3; k++)
                raw[n++] = rgb[y * w + x][k];
    }
    unsigned char z[128];
    uLongf zlen = sizeof(z);
    compress(z, &zlen, raw, n);
    size_t o = 0;
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    memcpy(out, sig, 8);
    o = 8;
#define PUT32(v)                                                                                   \
    (out[o++] = (unsigned char)((v) >> 24), out[o++] = (unsigned char)((v) >> 16),                 \
     out[o++] = (unsigned char)((v) >> 8), out[o++] = (unsigned char)(v))
    const unsigned char ihdr[13] = {0, 0, 0, (unsigned char)w, 0, 0, 0, (unsigned char)h, 8, 2};
    const struct {
        const char *tag;
        const unsigned char *data;
        size_t size;
    } chunks[3] = {{"IHDR", ihdr, 13}, {"IDAT", z, zlen}, {"IEND", NULL, 0}};
    for (int c = 0; c < 3; c++) {
        PUT32(chunks[c].size);
        const size_t start = o;
        memcpy(out + o, chunks[c].tag, 4);
        o += 4;
        if (chunks[c].size)
            memcpy(out + o, chunks[c].data, chunks[c].size);
        o += chunks[c].size;
        const uLong crc = crc32(0, out + start, (uInt)(o - start));
        PUT32(crc);
    }
#undef PUT32
    return o;
}

/*
 * Quad (0,0,0)-(2,0,-2) as in the OBJ test, with UVs (glTF: v down), vertex
 * colours, baseColorFactor (0.5, 0.25, 1), and optionally the 2x2 texture
 * embedded. Its node is translated (10,0,0) and scaled 2, under a parent
 * translated (0,5,0).
 */
static void write_glb(const char *name, int textured, int double_sided)
{
    const float pos[12] = {0, 0, 0, 2, 0, 0, 2, 0, -2, 0, 0, -2};
    const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    const float col[12] = {1, 1, 1, 1, 0.5f, 0.5f, 0.5f, 1, 0.5f, 0.2f, 0.2f, 0.2f};
    const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    unsigned char png[256];
    const size_t png_size = png_encode(texels, 2, 2, png);
    unsigned char bin[1024];
    size_t off[5], n = 0;
    const void *parts[5] = {pos, uv, col, idx, png};
    const size_t sizes[5] = {sizeof(pos), sizeof(uv), sizeof(col), sizeof(idx), png_size};
    for (int i = 0; i < 5; i++) {
        off[i] = n;
        memcpy(bin + n, parts[i], sizes[i]);
        n += (sizes[i] + 3) & ~(size_t)3;
    }
    char json[4096];
    int j = snprintf(
        json, sizeof(json),
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%zu}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
        "\"min\":[0,0,-2],\"max\":[2,0,0]},"
        "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},"
        "{\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
        "{\"bufferView\":3,\"componentType\":5125,\"count\":6,\"type\":\"SCALAR\"}],"
        "\"images\":[{\"bufferView\":4,\"mimeType\":\"image/png\"}],"
        "\"textures\":[{\"source\":0}],"
        "\"materials\":[{\"doubleSided\":%s,\"pbrMetallicRoughness\":{"
        "\"baseColorFactor\":[0.5,0.25,1,1]%s}}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1,"
        "\"COLOR_0\":2},\"indices\":3,\"material\":0}]}],"
        "\"nodes\":[{\"children\":[1],\"translation\":[0,5,0]},"
        "{\"mesh\":0,\"translation\":[10,0,0],\"scale\":[2,2,2]}],"
        "\"scenes\":[{\"nodes\":[0]}],\"scene\":0}",
        n, off[0], sizes[0], off[1], sizes[1], off[2], sizes[2], off[3], sizes[3], off[4], sizes[4],
        double_sided ? "true" : "false", textured ? ",\"baseColorTexture\":{\"index\":0}" : "");
    while (j % 4)
        json[j++] = ' ';
    unsigned char glb[8192];
    size_t o = 0;
    const uint32_t header[3] = {0x46546C67u, 2u, (uint32_t)(12 + 8 + j + 8 + n)};
    memcpy(glb + o, header, 12), o += 12;
    const uint32_t jh[2] = {(uint32_t)j, 0x4E4F534Au};
    memcpy(glb + o, jh, 8), o += 8;
    memcpy(glb + o, json, (size_t)j), o += (size_t)j;
    const uint32_t bh[2] = {(uint32_t)n, 0x004E4942u};
    memcpy(glb + o, bh, 8), o += 8;
    memcpy(glb + o, bin, n), o += n;
    write_file(name, glb, o);
}

static void glb_applies_transforms_factor_vertex_colour_and_embedded_texture(void)
{
    write_glb("plain.glb", 0, 1);
    write_glb("textured.glb", 1, 0);
    vdbgi_context *ctx = test_context();
    vdbgi_scene *plain = NULL, *tex = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, tmp_path("plain.glb"), &plain), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, tmp_path("textured.glb"), &tex), VDBGI_OK);
    if (!plain || !tex)
        goto done;
    vdbgi_scene_info info;
    vdbgi_scene_get_info(plain, &info);
    /* Child scale 2 then translation (10,0,0), parent translation (0,5,0). */
    CHECK_NEAR(info.bounds_min[0], 10.0, 1e-6);
    CHECK_NEAR(info.bounds_max[0], 14.0, 1e-6);
    CHECK_NEAR(info.bounds_min[1], 5.0, 1e-6);
    CHECK_NEAR(info.bounds_min[2], -4.0, 1e-6);
    CHECK(info.texture_count == 0);
    CHECK((plain->tris[0].flags & VDBGI_TRI_DOUBLE_SIDED));
    vdbgi_scene_get_info(tex, &info);
    CHECK(info.texture_count == 1);
    CHECK(!(tex->tris[0].flags & VDBGI_TRI_DOUBLE_SIDED));

    /* At a vertex the colour is that vertex's; in the middle of a texel the texel's. */
    const float factor[3] = {0.5f, 0.25f, 1.0f};
    vdbgi_hit h;
    float rgb[3];
    CHECK(hit_below(plain, 10.0f + 1e-3f, -1e-3f, &h)); /* next to vertex 0: colour (1,1,1) */
    vdbgi_scene_albedo(plain, h.prim, h.u, h.v, rgb);
    for (int k = 0; k < 3; k++)
        CHECK_NEAR(rgb[k], factor[k], 2e-3);
    CHECK(hit_below(plain, 14.0f - 1e-3f, -4.0f + 1e-3f, &h)); /* vertex 2: (0.5, 1, 0.5) */
    vdbgi_scene_albedo(plain, h.prim, h.u, h.v, rgb);
    CHECK_NEAR(rgb[0], 0.25, 2e-3);
    CHECK_NEAR(rgb[1], 0.25, 2e-3);
    CHECK_NEAR(rgb[2], 0.5, 2e-3);
    /* Textured: the upper-right texel (green) sits at u = 0.75, v = 0.75. */
    CHECK(hit_below(tex, 10.0f + 4.0f * 0.75f, -4.0f * 0.75f, &h));
    vdbgi_scene_albedo(tex, h.prim, h.u, h.v, rgb);
    float col[3] = {0, 0, 0};
    {
        /* Vertex colour there, interpolated the way the scene does. */
        const uint32_t *const idx = &tex->indices[3 * h.prim];
        const float w = 1.0f - h.u - h.v;
        for (int k = 0; k < 3; k++)
            col[k] = w * tex->colors[3 * idx[0] + k] + h.u * tex->colors[3 * idx[1] + k] +
                     h.v * tex->colors[3 * idx[2] + k];
    }
    CHECK_NEAR(rgb[0], 0.0, 1e-5);
    CHECK_NEAR(rgb[1], factor[1] * col[1] * srgb(255), 1e-5);
    CHECK_NEAR(rgb[2], 0.0, 1e-5);
    CHECK(rgb[1] > 0.05f);
done:
    vdbgi_scene_destroy(plain);
    vdbgi_scene_destroy(tex);
    vdbgi_context_destroy(ctx);
}

static void double_sided_back_hits_do_not_count_as_invalid(void)
{
    write_glb("two.glb", 0, 1);
    write_glb("one.glb", 1, 0);
    vdbgi_context *ctx = test_context();
    vdbgi_scene *two = NULL, *one = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, tmp_path("two.glb"), &two), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, tmp_path("one.glb"), &one), VDBGI_OK);
    /* Under the quad (its back side): every hit is a back face of 'one', none of 'two'. */
    const float pt[3] = {12.0f, 4.5f, -2.0f};
    float rgb[3], bf_two = -1.0f, bf_one = -1.0f;
    const vdbgi_bake_desc d = {.rays = 64};
    if (two && one) {
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(two, &d, pt, 1, rgb, &bf_two), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_scene_bake_points(one, &d, pt, 1, rgb, &bf_one), VDBGI_OK);
    }
    CHECK(bf_two == 0.0f);
    CHECK(bf_one == 1.0f);
    vdbgi_scene_destroy(two);
    vdbgi_scene_destroy(one);
    vdbgi_context_destroy(ctx);
}

static void bundled_scenes_load_with_their_textures(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *world = NULL, *room = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, "data/world.glb", &world), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, "data/room.obj", &room), VDBGI_OK);
    if (world && room) {
        vdbgi_scene_info wi, ri;
        vdbgi_scene_get_info(world, &wi);
        vdbgi_scene_get_info(room, &ri);
        CHECK(wi.texture_count == 1 && ri.texture_count == 1);
        CHECK(wi.triangle_count > 1000 && wi.skipped_triangle_count == 0);
        CHECK(ri.triangle_count == 6 * 2 + 12); /* six walls, a table box */
        int double_sided = 0;
        for (size_t m = 0; m < world->material_count; m++)
            double_sided += world->materials[m].double_sided;
        CHECK(double_sided == 1); /* the thin wall */
        /* A 48 m world; a room 6 x 3 x 5 m. */
        CHECK(wi.bounds_max[0] - wi.bounds_min[0] >= 47.0f);
        CHECK_NEAR(ri.bounds_max[0] - ri.bounds_min[0], 6.0, 1e-5);
        CHECK_NEAR(ri.bounds_max[1] - ri.bounds_min[1], 3.0, 1e-5);
    }
    vdbgi_scene_destroy(world);
    vdbgi_scene_destroy(room);
    vdbgi_context_destroy(ctx);
}

static void non_finite_vertices_are_skipped_with_a_warning(void)
{
    write_text("nan.obj", "v 0 0 0\nv 1 0 0\nv 1 0 -1\nv nan 0 0\nv 0 inf 0\n"
                          "f 1 2 3\nf 1 2 4\nf 1 5 3\n");
    write_text("allnan.obj", "v nan 0 0\nv 1 0 0\nv 1 0 -1\nf 1 2 3\n");
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL;
    test_warning_count = 0;
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, tmp_path("nan.obj"), &s), VDBGI_OK);
    if (s) {
        vdbgi_scene_info info;
        vdbgi_scene_get_info(s, &info);
        CHECK(info.triangle_count == 1 && info.skipped_triangle_count == 2);
        CHECK(isfinite(info.bounds_min[0]) && isfinite(info.bounds_max[1]));
    }
    CHECK(test_warning_count == 1 && strstr(test_last_warning, "2 triangles with non-finite"));
    vdbgi_scene_destroy(s);
    s = (vdbgi_scene *)1;
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, tmp_path("allnan.obj"), &s), VDBGI_ERR_FORMAT);
    CHECK(s == NULL && strstr(vdbgi_context_error(ctx), "no triangles"));
    vdbgi_context_destroy(ctx);
}

static void bad_scene_files_are_refused(void)
{
    write_text("garbage.glb", "this is not a glb file at all");
    write_text("empty.obj", "# nothing here\n");
    write_text("points.obj", "v 0 0 0\nv 1 0 0\np 1 2\n");
    write_text("nobin.gltf", "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":36,"
                             "\"uri\":\"missing.bin\"}],\"bufferViews\":[{\"buffer\":0,"
                             "\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,"
                             "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],"
                             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
                             "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]}");
    vdbgi_context *ctx = test_context();
    const struct {
        const char *path;
        vdbgi_result want;
        const char *says;
    } cases[] = {
        {"does-not-exist.glb", VDBGI_ERR_IO, "No such file"},
        {"garbage.glb", VDBGI_ERR_FORMAT, "garbage.glb"},
        {"empty.obj", VDBGI_ERR_FORMAT, "empty.obj"},
        {"points.obj", VDBGI_ERR_FORMAT, "points.obj"},
        {"nobin.gltf", VDBGI_ERR_FORMAT, "nobin.gltf"},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        vdbgi_scene *s = (vdbgi_scene *)1;
        CHECK_RESULT(ctx, vdbgi_scene_load(ctx, tmp_path(cases[i].path), &s), cases[i].want);
        CHECK(s == NULL);
        CHECK(strstr(vdbgi_context_error(ctx), cases[i].says) != NULL);
        CHECK(strchr(vdbgi_context_error(ctx), '\n') == NULL);
    }
    /* A directory is not a scene either. */
    vdbgi_scene *s = NULL;
    CHECK(vdbgi_scene_load(ctx, test_tmpdir, &s) != VDBGI_OK && s == NULL);
    vdbgi_context_destroy(ctx);
}

static void memory_scenes_check_their_input(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    test_mesh_plane(&m, 2.0f, 0.0f);
    vdbgi_mesh_desc d = test_mesh_desc(&m, 0.5f, 0);
    vdbgi_scene *s = NULL;
    d.albedo[1] = 1.5f;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, &s), VDBGI_ERR_INVALID_ARG);
    d = test_mesh_desc(&m, 0.5f, 0);
    m.idx[4] = 99;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, &s), VDBGI_ERR_INVALID_ARG);
    CHECK(strstr(vdbgi_context_error(ctx), "index 99 out of range") != NULL);
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, NULL, 0, &s), VDBGI_ERR_FORMAT);
    /* Zero-area triangles only: nothing to trace. */
    const float flat[9] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
    const uint32_t tri[3] = {0, 1, 2};
    const vdbgi_mesh_desc line = {.positions = flat,
                                  .vertex_count = 3,
                                  .indices = tri,
                                  .triangle_count = 1,
                                  .albedo = {0.5f, 0.5f, 0.5f}};
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &line, 1, &s), VDBGI_ERR_FORMAT);
    CHECK(s == NULL);
    vdbgi_context_destroy(ctx);
}

static void failing_allocations_while_loading_do_not_leak(void)
{
    int succeeded = 0;
    for (long n = 0; n < 400 && !succeeded; n++) {
        test_alloc a = {0, n, 0};
        const vdbgi_context_desc cd = {.alloc = test_alloc_fn, .free = test_free_fn, .user = &a};
        vdbgi_context *ctx = NULL;
        vdbgi_result r = vdbgi_context_create(&cd, &ctx);
        vdbgi_scene *s = NULL;
        if (r == VDBGI_OK)
            r = vdbgi_scene_load(ctx, tmp_path("quad.obj"), &s);
        CHECK(r == VDBGI_OK || r == VDBGI_ERR_OUT_OF_MEMORY);
        succeeded = r == VDBGI_OK;
        vdbgi_scene_destroy(s);
        vdbgi_context_destroy(ctx);
        CHECK(a.live == 0);
    }
    CHECK(succeeded);
}

int main(void)
{
    test_tmpdir_make("test-scene");
    RUN(obj_albedo_is_kd_times_external_texture);
    RUN(glb_applies_transforms_factor_vertex_colour_and_embedded_texture);
    RUN(double_sided_back_hits_do_not_count_as_invalid);
    RUN(bundled_scenes_load_with_their_textures);
    RUN(non_finite_vertices_are_skipped_with_a_warning);
    RUN(bad_scene_files_are_refused);
    RUN(memory_scenes_check_their_input);
    RUN(failing_allocations_while_loading_do_not_leak);
    test_tmpdir_remove();
    return CHECK_EXIT();
}
