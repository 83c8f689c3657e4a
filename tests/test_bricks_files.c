/*
 * test_bricks_files.c: the bricked volume's files and API edges: both
 * layouts round-trip and are deterministic; damaged files are refused; bad
 * parameters and probes are refused; the levels picture shows each cell's
 * level; failing allocations are reported without leaks; textures and
 * probes copy into caller buffers after a size query.
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

/* The seed layout, for the tests written against its 6^3 slots (the default is compact). */
static const vdbgi_convert_desc seed_layout = {.layout = VDBGI_LAYOUT_SEED};

static void round_trip(vdbgi_layout layout)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = test_slab(ctx, 40, 10, 24, smooth);
    vdbgi_volume *a = NULL, *b = NULL, *r = NULL;
    const vdbgi_convert_desc d = {.eps = 0.02f, .layout = layout};
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &a), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &d, &b), VDBGI_OK);
    if (a && b) {
        /* The file is made with the volume, the same bytes each build. */
        size_t na = 0, nb = 0;
        CHECK(a->file != NULL && a->file_size == a->info.file_size);
        CHECK_RESULT(ctx, vdbgi_volume_write_memory(a, NULL, 0, &na), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_volume_write_memory(b, NULL, 0, &nb), VDBGI_OK);
        CHECK(na > 0 && nb == a->info.file_size && memcmp(a->file, b->file, na) == 0);
        CHECK_RESULT(ctx, vdbgi_volume_write(a, tmp_path("a.gi.gz")), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_volume_read(ctx, tmp_path("a.gi.gz"), &r), VDBGI_OK);
    }
    if (r) {
        vdbgi_volume_info ia, ir;
        vdbgi_volume_get_info(a, &ia);
        vdbgi_volume_get_info(r, &ir);
        CHECK(memcmp(ia.ind_dims, ir.ind_dims, sizeof(ia.ind_dims)) == 0);
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
            /* Parsed in place (the WebAssembly reader's way): the body a copy would be, moved
               to the front of the file's own block; a refused file is left as it was. */
            uint8_t *copied = NULL, *moved = NULL;
            size_t copied_size = 0, moved_size = 0;
            CHECK_RESULT(ctx,
                         vdbgi_gifile_parse(ctx, "t", plain, plain_size, &hi, &version, &copied,
                                            &copied_size),
                         VDBGI_OK);
            uint8_t *const before = malloc(plain_size);
            memcpy(before, plain, plain_size);
            CHECK_RESULT(ctx,
                         vdbgi_gifile_parse_in_place(ctx, "t", plain, plain_size - 1, &hi, &version,
                                                     &moved, &moved_size),
                         VDBGI_ERR_FORMAT);
            CHECK(moved == NULL && memcmp(before, plain, plain_size) == 0);
            CHECK_RESULT(ctx,
                         vdbgi_gifile_parse_in_place(ctx, "t", plain, plain_size, &hi, &version,
                                                     &moved, &moved_size),
                         VDBGI_OK);
            CHECK(moved == plain && moved_size == copied_size && copied_size > 0 &&
                  memcmp(moved, copied, copied_size) == 0);
            free(before);
            vdbgi_free(ctx, copied);
            vdbgi_free(ctx, plain);
            CHECK(memcmp(t->tex.indirection, r->tex.indirection, ia.indirection_size) == 0);
            CHECK(memcmp(t->tex.atlas, r->tex.atlas, ia.atlas_size) == 0);
            vdbgi_volume_destroy(t);
        }
        /* In memory: the file's bytes out (after a size query), the same textures in. */
        size_t n = 0, got = 0;
        CHECK_RESULT(ctx, vdbgi_volume_write_memory(a, NULL, 0, &n), VDBGI_OK);
        uint8_t *const bytes = malloc(n);
        /* A buffer too small is the caller's error, told apart from running out of memory. */
        CHECK_RESULT(ctx, vdbgi_volume_write_memory(a, bytes, n - 1, &got), VDBGI_ERR_INVALID_ARG);
        CHECK(got == n && strstr(vdbgi_context_error(ctx), "a buffer of") != NULL);
        CHECK_RESULT(ctx, vdbgi_volume_write_memory(a, bytes, n, &got), VDBGI_OK);
        CHECK(n == ia.file_size && got == n && memcmp(bytes, a->file, n) == 0);
        /* A read volume writes back the very bytes it came from. */
        uint8_t *const again = malloc(n);
        CHECK_RESULT(ctx, vdbgi_volume_write_memory(r, again, n, &got), VDBGI_OK);
        CHECK(got == n && memcmp(again, bytes, n) == 0);
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

/*
 * A seed-layout volume of a smooth slab into *v (with its probes *p), and its
 * file uncompressed (header, then the textures: *raw bytes, malloc'd); NULL,
 * everything freed but ctx, when the build fails.
 */
static uint8_t *plain_seed_file(vdbgi_context *ctx, vdbgi_probes **p, vdbgi_volume **v, size_t *raw)
{
    *p = test_slab(ctx, 12, 6, 12, smooth);
    *v = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build(ctx, *p, &seed_layout, v), VDBGI_OK);
    if (!*v) {
        vdbgi_probes_destroy(*p);
        return NULL;
    }
    *raw = VDBGI_GI_HEADER_SIZE + (*v)->info.indirection_size + (*v)->info.atlas_size;
    uint8_t *const plain = malloc(*raw);
    vdbgi_gifile_header(&(*v)->info, 0, plain);
    memcpy(plain + VDBGI_GI_HEADER_SIZE, (*v)->tex.indirection, *raw - VDBGI_GI_HEADER_SIZE);
    return plain;
}

static void damaged_files_are_refused(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p;
    vdbgi_volume *v;
    size_t raw;
    uint8_t *const plain = plain_seed_file(ctx, &p, &v, &raw);
    if (!plain) {
        vdbgi_context_destroy(ctx);
        return;
    }
    size_t size = 0;
    CHECK_RESULT(ctx, vdbgi_volume_write_memory(v, NULL, 0, &size), VDBGI_OK);
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

/*
 * Header values that are legal numbers but that no writer makes, and that
 * would reach the frame (issue 47): an RGBM range of 3.4e38 or 1e-9, a
 * spacing of 1e-6 m, corners at +-3.4e38 or 1e10 m, a box twice its
 * lattice's extent. Each is refused naming the field; the same box moved
 * whole by 1 km still reads (it moves the volume), as does a range of 65504.
 */
static void absurd_header_values_are_refused(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p;
    vdbgi_volume *v;
    size_t raw;
    uint8_t *const plain = plain_seed_file(ctx, &p, &v, &raw);
    if (!plain) {
        vdbgi_context_destroy(ctx);
        return;
    }
    uint8_t *const lie = malloc(raw);
    const float lo = vdbgi_get_f32(plain + 48), hi = vdbgi_get_f32(plain + 60);
    static const struct {
        int offset[3]; /* the f32 fields set, -1 for none */
        float value[3];
        const char *says; /* in the refusal; NULL: the file reads */
    } cases[] = {
        {{20, -1, -1}, {3.4e38f}, "rgbm_range"},
        {{20, -1, -1}, {1e-9f}, "rgbm_range"},
        {{20, -1, -1}, {65504.0f}, NULL},
        {{72, -1, -1}, {1e-6f}, "spacing"},
        {{48, 52, 56}, {-3.4e38f, -3.4e38f, -3.4e38f}, "reach"},
        {{48, 60, -1}, {1e10f, 2e10f}, "reach"},
        {{60, -1, -1}, {0.0f}, "the box is"}, /* set below: twice the extent */
        {{48, 60, -1}, {0.0f, 0.0f}, NULL},   /* set below: moved 1 km */
    };
    for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
        memcpy(lie, plain, raw);
        for (int k = 0; k < 3 && cases[c].offset[k] >= 0; k++)
            vdbgi_put_f32(lie + cases[c].offset[k], cases[c].value[k]);
        if (c == 6)
            vdbgi_put_f32(lie + 60, hi + (hi - lo));
        if (c == 7)
            vdbgi_put_f32(lie + 48, lo + 1000.0f), vdbgi_put_f32(lie + 60, hi + 1000.0f);
        FILE *f = fopen(tmp_path("absurd.gi"), "wb");
        fwrite(lie, 1, raw, f);
        fclose(f);
        vdbgi_volume *r = NULL;
        const vdbgi_result res = vdbgi_volume_read(ctx, tmp_path("absurd.gi"), &r);
        if (cases[c].says) {
            CHECK(res == VDBGI_ERR_FORMAT && r == NULL);
            CHECK(strstr(vdbgi_context_error(ctx), cases[c].says) != NULL);
        } else {
            CHECK(res == VDBGI_OK);
        }
        vdbgi_volume_destroy(r);
    }
    free(lie);
    free(plain);
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
}

/*
 * The volume budget (vdbgi_context_desc.volume_budget): a file whose textures
 * pass it is refused from its header, naming both sizes; the same bytes read
 * under the default (VDBGI_VOLUME_BUDGET) and under a budget just large enough.
 */
static void the_volume_budget_refuses_before_allocating(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = NULL;
    vdbgi_volume *v = NULL;
    size_t raw = 0;
    uint8_t *const plain = plain_seed_file(ctx, &p, &v, &raw);
    if (!plain) {
        vdbgi_context_destroy(ctx);
        return;
    }
    const size_t textures = v->info.indirection_size + v->info.atlas_size;
    vdbgi_volume *r = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_read_memory(ctx, plain, raw, "slab", &r), VDBGI_OK);
    vdbgi_volume_destroy(r);
    for (int k = 0; k < 2; k++) {
        /* One byte short of the larger of body and textures, then exactly it. */
        const size_t need = textures > raw - VDBGI_GI_HEADER_SIZE ? textures : raw;
        const vdbgi_context_desc cd = {.volume_budget = need - 1 + (size_t)k};
        vdbgi_context *small = NULL;
        CHECK(vdbgi_context_create(&cd, &small) == VDBGI_OK);
        r = NULL;
        CHECK_RESULT(small, vdbgi_volume_read_memory(small, plain, raw, "slab", &r),
                     k ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY);
        CHECK(k || (strstr(vdbgi_context_error(small), "slab: the volume unpacks to") &&
                    strstr(vdbgi_context_error(small), "volume budget") && !r));
        CHECK(k || vdbgi_context_memory_peak(small) == 0);
        vdbgi_volume_destroy(r);
        vdbgi_context_destroy(small);
    }
    free(plain);
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
                                      {.terms = (vdbgi_terms)2},
                                      {.eps = -1.0f, .eps_is_set = 1},
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
        const uint32_t *const dims = info.ind_dims;
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

int main(void)
{
    test_tmpdir_make("test-bricks-files");
    RUN(files_round_trip_and_are_deterministic);
    RUN(damaged_files_are_refused);
    RUN(absurd_header_values_are_refused);
    RUN(the_volume_budget_refuses_before_allocating);
    RUN(bad_parameters_and_probes_are_refused);
    RUN(levels_png_shows_each_cells_level);
    RUN(failing_allocations_are_reported_without_leaks);
    RUN(textures_and_probes_copy_into_caller_buffers_after_a_size_query);
    test_tmpdir_remove();
    return CHECK_EXIT();
}
