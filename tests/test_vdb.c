/*
 * test_vdb.c: baked probes written as .vdb read back bit for bit, with the
 * lattice transform and the bake settings as metadata; a failed write leaves
 * no file and never replaces an existing one; files that are not VDB, or are
 * cut short, are refused; the tiles of a bake merge into the whole bake; a
 * conversion region by region gives the whole conversion's bytes.
 */
#define _POSIX_C_SOURCE 200809L
#include "probes.h"
#include "test_util.h"
#include "volume.h"

#include <dirent.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

static vdbgi_probes *baked_probes(vdbgi_context *ctx, vdbgi_scene **scene_out)
{
    test_mesh m = {0};
    test_mesh_plane(&m, 6.0f, 0.0f);
    const float lo[3] = {-1, 0, -1}, hi[3] = {1, 2, 1};
    test_mesh_box(&m, lo, hi, 0);
    const vdbgi_mesh_desc d = test_mesh_desc(&m, 0.6f, 0);
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, scene_out), VDBGI_OK);
    vdbgi_probes *p = NULL;
    const vdbgi_place_desc pd = {.spacing = 0.4, .origin = {0.1, -0.2, 0.3}, .origin_is_set = 1};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, *scene_out, &pd, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 32,
                                .falloff = INFINITY,
                                .sampling = VDBGI_SAMPLING_RANDOM,
                                .seed = 9,
                                .sky = {0.01f, 0.02f, 0.03f}};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, *scene_out, &bd, NULL), VDBGI_OK);
    return p;
}

static const char *meta(const vdbgi_probes *p, const char *name)
{
    const size_t n = strlen(name);
    for (size_t i = 0;; i++) {
        const char *const line = vdbgi_probes_metadata(p, i);
        if (!line)
            return "";
        if (strncmp(line, name, n) == 0 && line[n] == '=')
            return line + n + 1;
    }
}

static void written_probes_read_back_exactly(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = baked_probes(ctx, &s);
    CHECK_RESULT(ctx, vdbgi_probes_write(p, tmp_path("a.vdb")), VDBGI_OK);
    vdbgi_probes *q = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_read(ctx, tmp_path("a.vdb"), &q), VDBGI_OK);
    if (!q)
        goto done;
    vdbgi_probes_info a, b;
    vdbgi_probes_get_info(p, &a);
    vdbgi_probes_get_info(q, &b);
    CHECK(a.probe_count == b.probe_count && a.probe_count > 100);
    CHECK(a.invalid_count == b.invalid_count && a.invalid_count > 0);
    CHECK_NEAR(b.spacing, 0.4, 1e-12);
    CHECK_NEAR(b.margin, 1.6, 1e-12);
    CHECK_NEAR(b.origin[0], 0.1, 1e-12);
    CHECK_NEAR(b.origin[1], -0.2, 1e-12);
    CHECK_NEAR(b.origin[2], 0.3, 1e-12);
    CHECK(b.invalid_threshold == a.invalid_threshold);
    /* Same order (VDB tree order both ways) and the same bits. */
    int same = 1;
    for (size_t i = 0; i < a.probe_count; i++) {
        int32_t ia[3], ib[3];
        float ra[3], rb[3], fa, fb;
        vdbgi_probes_get(p, i, ia, ra, &fa);
        vdbgi_probes_get(q, i, ib, rb, &fb);
        same &= memcmp(ia, ib, sizeof(ia)) == 0 && memcmp(ra, rb, sizeof(ra)) == 0 && fa == fb;
    }
    CHECK(same);
    CHECK(strcmp(meta(q, "scene"), "memory") == 0);
    CHECK(strcmp(meta(q, "sampling"), "random") == 0);
    CHECK(strcmp(meta(q, "rays"), "32") == 0);
    CHECK(strcmp(meta(q, "seed"), "9") == 0);
    CHECK(strcmp(meta(q, "falloff"), "inf") == 0);
    CHECK(strcmp(meta(q, "sky"), "0.00999999978,0.0199999996,0.0299999993") == 0);
    CHECK(strcmp(meta(q, "triangles"), "14") == 0);
    CHECK(atol(meta(q, "probes")) == (long)a.probe_count);
    CHECK(strtod(meta(q, "bake_seconds"), NULL) > 0.0);
    CHECK(strlen(meta(q, "vdbgi_version")) > 0);
done:
    vdbgi_probes_destroy(q);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static int count_entries(const char *dir)
{
    DIR *const d = opendir(dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));)
        n += e->d_name[0] != '.';
    if (d)
        closedir(d);
    return n;
}

static void failed_writes_leave_nothing_and_clobber_nothing(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = baked_probes(ctx, &s);
    mkdir(tmp_path("w"), 0755);
    /* Into a directory that does not exist. */
    CHECK_RESULT(ctx, vdbgi_probes_write(p, tmp_path("w/no/such/dir/x.vdb")), VDBGI_ERR_IO);
    CHECK(strstr(vdbgi_context_error(ctx), "x.vdb") != NULL);
    /* Onto a directory: the rename fails, the temporary file is removed. */
    mkdir(tmp_path("w/taken.vdb"), 0755);
    CHECK_RESULT(ctx, vdbgi_probes_write(p, tmp_path("w/taken.vdb")), VDBGI_ERR_IO);
    CHECK(count_entries(tmp_path("w")) == 1);
    /* Unbaked probes have nothing to write: the existing file stays as it was. */
    FILE *f = fopen(tmp_path("w/keep.vdb"), "w");
    fputs("precious", f);
    fclose(f);
    vdbgi_probes *unbaked = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, NULL, &unbaked), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_write(unbaked, tmp_path("w/keep.vdb")), VDBGI_ERR_INVALID_ARG);
    char buf[16] = {0};
    f = fopen(tmp_path("w/keep.vdb"), "r");
    CHECK(f && fgets(buf, sizeof(buf), f) && strcmp(buf, "precious") == 0);
    if (f)
        fclose(f);
    CHECK(count_entries(tmp_path("w")) == 2);
    /* A successful write replaces it whole. */
    CHECK_RESULT(ctx, vdbgi_probes_write(p, tmp_path("w/keep.vdb")), VDBGI_OK);
    vdbgi_probes *q = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_read(ctx, tmp_path("w/keep.vdb"), &q), VDBGI_OK);
    CHECK(count_entries(tmp_path("w")) == 2);
    vdbgi_probes_destroy(q);
    vdbgi_probes_destroy(unbaked);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void unreadable_files_are_refused(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = baked_probes(ctx, &s);
    CHECK_RESULT(ctx, vdbgi_probes_write(p, tmp_path("good.vdb")), VDBGI_OK);
    /* Cut the good file short at several places. */
    FILE *const f = fopen(tmp_path("good.vdb"), "rb");
    static unsigned char bytes[1 << 20];
    const size_t size = f ? fread(bytes, 1, sizeof(bytes), f) : 0;
    if (f)
        fclose(f);
    CHECK(size > 1000 && size < sizeof(bytes));
    const size_t cuts[] = {0, 8, 100, size / 2, size - 1};
    for (size_t c = 0; c < sizeof(cuts) / sizeof(cuts[0]); c++) {
        FILE *const g = fopen(tmp_path("cut.vdb"), "wb");
        fwrite(bytes, 1, cuts[c], g);
        fclose(g);
        vdbgi_probes *q = (vdbgi_probes *)1;
        const vdbgi_result r = vdbgi_probes_read(ctx, tmp_path("cut.vdb"), &q);
        CHECK(r == VDBGI_ERR_FORMAT || r == VDBGI_ERR_BACKEND);
        CHECK(q == NULL);
        /* Past the header, refused from the grid descriptors before any grid is read. */
        if (cuts[c] >= size / 2)
            CHECK(strstr(vdbgi_context_error(ctx), "truncated") != NULL);
        if (r == VDBGI_OK)
            vdbgi_probes_destroy(q);
    }
    FILE *const t = fopen(tmp_path("text.vdb"), "w");
    fputs("not a vdb file\n", t);
    fclose(t);
    vdbgi_probes *q = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_read(ctx, tmp_path("text.vdb"), &q), VDBGI_ERR_FORMAT);
    CHECK(strstr(vdbgi_context_error(ctx), "text.vdb") != NULL);
    CHECK_RESULT(ctx, vdbgi_probes_read(ctx, tmp_path("missing.vdb"), &q), VDBGI_ERR_IO);
    CHECK(strstr(vdbgi_context_error(ctx), "No such file") != NULL);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void ambient_cubes_round_trip_as_six_grids(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    test_mesh_plane(&m, 6.0f, 0.0f);
    const vdbgi_mesh_desc d = test_mesh_desc(&m, 0.6f, 0);
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = NULL, *q = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, &s), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, NULL, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 32, .basis = VDBGI_BASIS_AMBIENT_CUBE};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, NULL), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_write(p, tmp_path("cube.vdb")), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_read(ctx, tmp_path("cube.vdb"), &q), VDBGI_OK);
    if (q) {
        vdbgi_probes_info info;
        vdbgi_probes_get_info(q, &info);
        CHECK(info.basis == VDBGI_BASIS_AMBIENT_CUBE);
        CHECK(strcmp(meta(q, "basis"), "ambient-cube") == 0);
        int same = 1, lit = 0;
        for (size_t i = 0; i < info.probe_count; i++) {
            float a[6][3], b[6][3];
            vdbgi_probes_get_cube(p, i, a);
            vdbgi_probes_get_cube(q, i, b);
            same &= memcmp(a, b, sizeof(a)) == 0;
            lit += a[VDBGI_SIDE_NY][0] > 0.0f;
        }
        CHECK(same && lit > 0);
    }
    vdbgi_probes_destroy(q);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void sh2_terms_round_trip_as_eight_grids(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    test_mesh_plane(&m, 6.0f, 0.0f);
    const vdbgi_mesh_desc d = test_mesh_desc(&m, 0.6f, 0);
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = NULL, *q = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, &s), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, NULL, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 32, .basis = VDBGI_BASIS_SH2};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, NULL), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_write(p, tmp_path("sh2.vdb")), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_read(ctx, tmp_path("sh2.vdb"), &q), VDBGI_OK);
    if (q) {
        vdbgi_probes_info info;
        vdbgi_probes_get_info(q, &info);
        CHECK(info.basis == VDBGI_BASIS_SH2);
        CHECK(strcmp(meta(q, "basis"), "sh2") == 0);
        int same = 1, signs = 0;
        for (size_t i = 0; i < info.probe_count; i++) {
            float a[VDBGI_SH2_TERMS][3], b[VDBGI_SH2_TERMS][3];
            vdbgi_probes_get_sh2(p, i, a);
            vdbgi_probes_get_sh2(q, i, b);
            same &= memcmp(a, b, sizeof(a)) == 0;
            signs += a[2][0] < 0.0f; /* light from the plane below: the y term is negative */
        }
        CHECK(same && signs > 0);
        float cube[6][3];
        CHECK_RESULT(ctx, vdbgi_probes_get_cube(q, 0, cube), VDBGI_ERR_INVALID_ARG);
    }
    vdbgi_probes_destroy(q);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* a and b hold the same probes in the same order: ijk, values, validity, L2 terms, bit for bit. */
static bool same_probes(const vdbgi_probes *a, const vdbgi_probes *b)
{
    vdbgi_probes_info ia, ib;
    vdbgi_probes_get_info(a, &ia);
    vdbgi_probes_get_info(b, &ib);
    if (ia.probe_count != ib.probe_count || ia.invalid_count != ib.invalid_count)
        return false;
    for (size_t i = 0; i < ia.probe_count; i++) {
        int32_t ca[3], cb[3];
        float ra[3], rb[3], ba, bb;
        float sa[VDBGI_SH2_TERMS][3], sb[VDBGI_SH2_TERMS][3], ea, eb;
        uint32_t na, nb;
        if (vdbgi_probes_get_noise(a, i, &ea, &na) != VDBGI_OK ||
            vdbgi_probes_get_noise(b, i, &eb, &nb) != VDBGI_OK || ea != eb || na != nb ||
            vdbgi_probes_get(a, i, ca, ra, &ba) != VDBGI_OK ||
            vdbgi_probes_get(b, i, cb, rb, &bb) != VDBGI_OK || memcmp(ca, cb, sizeof(ca)) ||
            memcmp(ra, rb, sizeof(ra)) || memcmp(&ba, &bb, sizeof(ba)) ||
            vdbgi_probes_get_sh2(a, i, sa) != VDBGI_OK ||
            vdbgi_probes_get_sh2(b, i, sb) != VDBGI_OK || memcmp(sa, sb, sizeof(sa)))
            return false;
    }
    return true;
}

/*
 * A bake in 2, 3 and 5 tiles (each on its own thread count) merged with
 * OpenVDB's tree merge equals the whole bake probe for probe, bit for bit,
 * given in any order, with a fixed ray count and with rays by each probe's
 * spread (auto, in 3 tiles); and a set with a tile missing, given twice, from
 * another bake or another tiling, or a file that is no tile, is refused.
 */
static void tiles_merge_into_the_whole_bake(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    test_mesh_plane(&m, 12.0f, 0.0f);
    const float lo[3] = {-1, 0, -1}, hi[3] = {1, 2, 1}, lo2[3] = {3, 0, 2}, hi2[3] = {5, 4, 3};
    test_mesh_box(&m, lo, hi, 0);
    test_mesh_box(&m, lo2, hi2, 0);
    const vdbgi_mesh_desc d = test_mesh_desc(&m, 0.6f, 0);
    vdbgi_scene *scene = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, &scene), VDBGI_OK);
    /* Bounces until converged: every tile's pilot is the whole scene's (cli/merge_tiles tiles
       the seed model's one bounce). */
    vdbgi_bake_desc bd = {.rays = 32,
                          .sampling = VDBGI_SAMPLING_RANDOM,
                          .seed = 4,
                          .basis = VDBGI_BASIS_SH2,
                          .model = VDBGI_MODEL_PHYSICAL,
                          .sky = {0.4f, 0.5f, 0.7f},
                          .threads = 2};
    vdbgi_place_desc pd = {.spacing = 0.25};
    vdbgi_probes *whole = NULL, *merged = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &whole), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_bake(whole, scene, &bd, NULL), VDBGI_OK);
    if (!whole) {
        vdbgi_scene_destroy(scene);
        vdbgi_context_destroy(ctx);
        return;
    }
    static const int counts[3] = {2, 3, 5};
    char names[5][64];
    const char *paths[6];
    for (int c = 0; c < 3; c++) {
        const int n = counts[c];
        size_t sum = 0;
        for (int t = 0; t < n; t++) {
            vdbgi_probes *tile = NULL;
            pd.tile_index = t;
            pd.tile_count = n;
            bd.threads = 1 + t % 3;
            snprintf(names[t], sizeof(names[t]), "%s", tmp_path(""));
            snprintf(names[t] + strlen(names[t]), sizeof(names[t]) - strlen(names[t]),
                     "tile%d-%d.vdb", n, t);
            CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &tile), VDBGI_OK);
            CHECK_RESULT(ctx, vdbgi_probes_bake(tile, scene, &bd, NULL), VDBGI_OK);
            CHECK_RESULT(ctx, vdbgi_probes_write(tile, names[t]), VDBGI_OK);
            vdbgi_probes_info ti;
            vdbgi_probes_get_info(tile, &ti);
            CHECK(ti.tile_count == n && ti.tile_index == t && ti.probe_count > 0);
            sum += ti.probe_count;
            vdbgi_probes_destroy(tile);
            paths[n - 1 - t] = names[t]; /* in reverse order */
        }
        vdbgi_probes_info wi;
        vdbgi_probes_get_info(whole, &wi);
        CHECK(sum == wi.probe_count);
        CHECK_RESULT(ctx, vdbgi_probes_merge(ctx, paths, (size_t)n, tmp_path("merged.vdb")),
                     VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_probes_read(ctx, tmp_path("merged.vdb"), &merged), VDBGI_OK);
        CHECK(merged && same_probes(whole, merged));
        vdbgi_probes_destroy(merged);
        merged = NULL;
    }
    /* Rays by each probe's spread: the pilot is the whole scene's, whatever the tile. */
    vdbgi_bake_desc auto_d = bd;
    auto_d.rays = 0;
    auto_d.adaptive = 1;
    auto_d.max_rays = 256;
    auto_d.noise = 0.01f;
    vdbgi_probes *auto_whole = NULL, *auto_merged = NULL;
    CHECK_RESULT(ctx,
                 vdbgi_probes_place(ctx, scene, &(vdbgi_place_desc){.spacing = 0.25}, &auto_whole),
                 VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_bake(auto_whole, scene, &auto_d, NULL), VDBGI_OK);
    const char *auto_paths[3];
    char auto_names[3][64];
    for (int t = 0; t < 3; t++) {
        vdbgi_probes *tile = NULL;
        const vdbgi_place_desc td = {.spacing = 0.25, .tile_index = t, .tile_count = 3};
        auto_d.threads = 1 + t % 2;
        snprintf(auto_names[t], sizeof(auto_names[t]), "%s", tmp_path(""));
        snprintf(auto_names[t] + strlen(auto_names[t]),
                 sizeof(auto_names[t]) - strlen(auto_names[t]), "auto3-%d.vdb", t);
        CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &td, &tile), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_probes_bake(tile, scene, &auto_d, NULL), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_probes_write(tile, auto_names[t]), VDBGI_OK);
        vdbgi_probes_destroy(tile);
        auto_paths[t] = auto_names[t];
    }
    CHECK_RESULT(ctx, vdbgi_probes_merge(ctx, auto_paths, 3, tmp_path("auto.vdb")), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_read(ctx, tmp_path("auto.vdb"), &auto_merged), VDBGI_OK);
    CHECK(auto_merged && same_probes(auto_whole, auto_merged));
    uint32_t fewest = UINT32_MAX, most = 0;
    vdbgi_probes_info ai;
    vdbgi_probes_get_info(auto_whole, &ai);
    for (size_t i = 0; i < ai.probe_count; i++) {
        uint32_t n = 0;
        vdbgi_probes_get_noise(auto_whole, i, NULL, &n);
        fewest = n < fewest ? n : fewest;
        most = n > most ? n : most;
    }
    CHECK(fewest == 32 && most > 64); /* the counts differ, so the test says something */
    vdbgi_probes_destroy(auto_merged);
    vdbgi_probes_destroy(auto_whole);
    /* The 5 tiles' set, damaged: one missing, one twice, one of the 3-tile set. */
    unlink(tmp_path("refused.vdb"));
    CHECK_RESULT(ctx, vdbgi_probes_merge(ctx, paths, 4, tmp_path("refused.vdb")), VDBGI_ERR_FORMAT);
    CHECK(strstr(vdbgi_context_error(ctx), "is missing") != NULL);
    paths[5] = paths[0];
    CHECK_RESULT(ctx, vdbgi_probes_merge(ctx, paths, 6, tmp_path("refused.vdb")), VDBGI_ERR_FORMAT);
    CHECK(strstr(vdbgi_context_error(ctx), "given twice") != NULL);
    char three[64];
    snprintf(three, sizeof(three), "%s", tmp_path("tile3-0.vdb"));
    paths[4] = three;
    CHECK_RESULT(ctx, vdbgi_probes_merge(ctx, paths, 5, tmp_path("refused.vdb")), VDBGI_ERR_FORMAT);
    CHECK(strstr(vdbgi_context_error(ctx), "not a tile of the same bake") != NULL);
    CHECK_RESULT(ctx, vdbgi_probes_write(whole, tmp_path("whole.vdb")), VDBGI_OK);
    const char *not_tile[1] = {tmp_path("whole.vdb")};
    CHECK_RESULT(ctx, vdbgi_probes_merge(ctx, not_tile, 1, tmp_path("refused.vdb")),
                 VDBGI_ERR_FORMAT);
    CHECK(strstr(vdbgi_context_error(ctx), "not a tile") != NULL);
    struct stat st;
    CHECK(stat(tmp_path("refused.vdb"), &st) != 0);
    /* Tiles that cannot exist: past the count, or more than the lattice has leaf columns. */
    vdbgi_probes *none = NULL;
    pd.tile_index = 3;
    pd.tile_count = 3;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &none), VDBGI_ERR_INVALID_ARG);
    pd.tile_index = 1999;
    pd.tile_count = 4000;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, scene, &pd, &none), VDBGI_ERR_INVALID_ARG);
    CHECK(strstr(vdbgi_context_error(ctx), "would hold no probe") != NULL);
    vdbgi_probes_destroy(whole);
    vdbgi_scene_destroy(scene);
    vdbgi_context_destroy(ctx);
}

/*
 * An adaptive bake's rays as earlier files held them, an Int32 grid
 * (tests/files/README.md): still read, and written again as a float grid
 * with the same counts.
 */
static void rays_of_older_files_are_read(void)
{
    vdbgi_context *ctx = test_context();
    gzFile in = gzopen("tests/files/rays_int32.vdb.gz", "rb");
    FILE *out = fopen(tmp_path("rays_int32.vdb"), "wb");
    CHECK(in && out);
    char buf[65536];
    int got;
    while (in && out && (got = gzread(in, buf, sizeof(buf))) > 0)
        fwrite(buf, 1, (size_t)got, out);
    if (in)
        gzclose(in);
    if (out)
        fclose(out);
    vdbgi_probes *old = NULL, *again = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_read(ctx, tmp_path("rays_int32.vdb"), &old), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_write(old, tmp_path("rays_float.vdb")), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probes_read(ctx, tmp_path("rays_float.vdb"), &again), VDBGI_OK);
    vdbgi_probes_info info = {0};
    if (old)
        vdbgi_probes_get_info(old, &info);
    size_t pilot = 0, sixty_four = 0, same = 0;
    for (size_t i = 0; again && i < info.probe_count; i++) {
        uint32_t a = 0, b = 0;
        vdbgi_probes_get_noise(old, i, NULL, &a);
        vdbgi_probes_get_noise(again, i, NULL, &b);
        pilot += a == 32; /* the pilot alone, or with a second set of 32: the cap */
        sixty_four += a == 64;
        same += a == b;
    }
    CHECK(info.probe_count > 100 && pilot > 0 && sixty_four > 0 &&
          pilot + sixty_four == info.probe_count && same == info.probe_count);
    vdbgi_probes_destroy(old);
    vdbgi_probes_destroy(again);
    vdbgi_context_destroy(ctx);
}

/*
 * Read and convert a .vdb on a context limited to limit bytes (0: none) on one
 * thread; the result, the context's peak and (on success) the file's bytes.
 */
static vdbgi_result convert_limited(const char *path, size_t limit, size_t *peak,
                                    unsigned char *bytes, size_t *size, char *why)
{
    const vdbgi_context_desc d = {.memory_limit = limit};
    vdbgi_context *ctx = NULL;
    CHECK(vdbgi_context_create(&d, &ctx) == VDBGI_OK);
    CHECK(vdbgi_context_memory_peak(ctx) == 0);
    vdbgi_probes *p = NULL;
    vdbgi_volume *v = NULL;
    vdbgi_result r = vdbgi_probes_read(ctx, path, &p);
    const vdbgi_convert_desc cd = {.threads = 1};
    if (r == VDBGI_OK)
        r = vdbgi_volume_build(ctx, p, &cd, &v);
    *size = 0;
    if (r == VDBGI_OK)
        r = vdbgi_volume_write_memory(v, bytes, 1 << 20, size);
    *peak = vdbgi_context_memory_peak(ctx);
    snprintf(why, 512, "%s", vdbgi_context_error(ctx));
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(p);
    vdbgi_context_destroy(ctx);
    return r;
}

/*
 * The memory limit counts what a conversion holds, the same on every run: at
 * the peak an unlimited run measured it gives the same bytes; one byte under,
 * it stops with one line naming the file and the limit.
 */
static void a_memory_limit_stops_a_conversion_at_its_figure(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = NULL;
    vdbgi_probes *p = baked_probes(ctx, &s);
    CHECK_RESULT(ctx, vdbgi_probes_write(p, tmp_path("limit.vdb")), VDBGI_OK);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
    static unsigned char whole[1 << 20], limited[1 << 20];
    char why[512];
    size_t peak = 0, again = 0, size = 0, limited_size = 0;
    CHECK(convert_limited(tmp_path("limit.vdb"), 0, &peak, whole, &size, why) == VDBGI_OK);
    /* The grids OpenVDB held count too: more than the probes' own arrays. */
    CHECK(peak > 100000 && size > 0);
    CHECK(convert_limited(tmp_path("limit.vdb"), peak, &again, limited, &limited_size, why) ==
          VDBGI_OK);
    CHECK(again == peak && limited_size == size && memcmp(whole, limited, size) == 0);
    CHECK(convert_limited(tmp_path("limit.vdb"), peak - 1, &again, limited, &limited_size, why) ==
          VDBGI_ERR_OUT_OF_MEMORY);
    CHECK(again <= peak - 1 && limited_size == 0);
    CHECK(strstr(why, "memory limit of") != NULL);
    /* Every limit below the read's own need names the file. */
    CHECK(convert_limited(tmp_path("limit.vdb"), 50000, &again, limited, &limited_size, why) ==
          VDBGI_ERR_OUT_OF_MEMORY);
    CHECK(strstr(why, "limit.vdb") != NULL && strstr(why, "memory limit of") != NULL);
}

/* The .gi bytes and figures of a conversion, whole (region 0) or region by region. */
static size_t convert_to(const char *path, int region, int halo, int threads, unsigned char *bytes,
                         vdbgi_volume_info *info)
{
    vdbgi_context *ctx = test_context();
    vdbgi_probes *p = NULL;
    vdbgi_probe_file *f = NULL;
    vdbgi_volume *v = NULL;
    const vdbgi_convert_desc cd = {.threads = threads};
    if (region) {
        CHECK_RESULT(ctx, vdbgi_probe_file_open(ctx, path, &f), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_volume_build_regions_halo(ctx, f, region, halo, &cd, &v), VDBGI_OK);
    } else {
        CHECK_RESULT(ctx, vdbgi_probes_read(ctx, path, &p), VDBGI_OK);
        CHECK_RESULT(ctx, vdbgi_volume_build(ctx, p, &cd, &v), VDBGI_OK);
    }
    size_t size = 0;
    if (v)
        CHECK_RESULT(ctx, vdbgi_volume_write_memory(v, bytes, 1 << 22, &size), VDBGI_OK);
    if (v)
        vdbgi_volume_get_info(v, info);
    vdbgi_volume_destroy(v);
    vdbgi_probes_destroy(p);
    vdbgi_probe_file_close(f);
    vdbgi_context_destroy(ctx);
    return size;
}

/*
 * A lattice read a z range at a time holds every probe once, in the whole
 * read's order; converted region by region (any size, any threads) it gives
 * the whole conversion's bytes and figures, L2 terms and all. Without a
 * halo the fill at a region's faces lacks its neighbours and the bytes
 * change: the comparison can fail.
 */
static void regions_match_on_a_floor(float floor_size)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    test_mesh_plane(&m, floor_size, 0.0f);
    const float lo[3] = {-1, 0, -2}, hi[3] = {1, 2, 0.5f};
    test_mesh_box(&m, lo, hi, 0);
    const vdbgi_mesh_desc d = test_mesh_desc(&m, 0.6f, 0);
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, &s), VDBGI_OK);
    vdbgi_probes *p = NULL;
    const vdbgi_place_desc pd = {.spacing = 0.125, .origin = {0.1, -0.2, 0.3}, .origin_is_set = 1};
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, s, &pd, &p), VDBGI_OK);
    const vdbgi_bake_desc bd = {.rays = 16,
                                .falloff = INFINITY,
                                .sampling = VDBGI_SAMPLING_RANDOM,
                                .seed = 3,
                                .basis = VDBGI_BASIS_SH2,
                                .sky = {0.05f, 0.06f, 0.08f}};
    CHECK_RESULT(ctx, vdbgi_probes_bake(p, s, &bd, NULL), VDBGI_OK);
    const char *const path = tmp_path("regions.vdb");
    CHECK_RESULT(ctx, vdbgi_probes_write(p, path), VDBGI_OK);
    vdbgi_probes_destroy(p);
    vdbgi_scene_destroy(s);
    /* Regions read back the whole read, probe for probe. */
    vdbgi_probes *whole = NULL;
    vdbgi_probe_file *f = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_read(ctx, path, &whole), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probe_file_open(ctx, path, &f), VDBGI_OK);
    int32_t box_lo[3], box_hi[3];
    vdbgi_probe_file_extent(f, box_lo, box_hi);
    const int32_t z[2] = {box_lo[2], box_hi[2]};
    size_t seen = 0;
    bool same = true;
    for (size_t i = 0; i < whole->count; i++) /* the box holds every probe */
        for (int k = 0; k < 3; k++)
            same = same && whole->ijk[3 * i + k] >= box_lo[k] && whole->ijk[3 * i + k] <= box_hi[k];
    for (int32_t z0 = z[0]; z0 <= z[1]; z0 += 32) {
        vdbgi_probes *r = NULL;
        CHECK_RESULT(ctx, vdbgi_probe_file_read(f, z0, z0 + 32, &r), VDBGI_OK);
        for (size_t i = 0; r && i < r->count; i++) {
            same = same && r->ijk[3 * i + 2] >= z0 && r->ijk[3 * i + 2] < z0 + 32;
            /* the whole read's next probe in this slab */
            while (seen < whole->count &&
                   !(whole->ijk[3 * seen + 2] >= z0 && whole->ijk[3 * seen + 2] < z0 + 32))
                seen++;
            same = same && seen < whole->count &&
                   memcmp(&r->ijk[3 * i], &whole->ijk[3 * seen], 12) == 0 &&
                   memcmp(&r->rgb[3 * i], &whole->rgb[3 * seen], 12) == 0 &&
                   memcmp(&r->sh[24 * i], &whole->sh[24 * seen], 24 * sizeof(*r->sh)) == 0 &&
                   r->backface[i] == whole->backface[seen];
            seen++;
        }
        size_t in_slab = 0; /* and none of the whole read's is missing */
        for (size_t i = 0; i < whole->count; i++)
            in_slab += whole->ijk[3 * i + 2] >= z0 && whole->ijk[3 * i + 2] < z0 + 32;
        same = same && r && r->count == in_slab;
        seen = 0;
        vdbgi_probes_destroy(r);
    }
    CHECK(same);
    CHECK(z[1] - z[0] > 32); /* two regions of 32 at least */
    vdbgi_probes *none = NULL;
    CHECK_RESULT(ctx, vdbgi_probe_file_read(f, z[1] + 8, z[1] + 40, &none), VDBGI_OK);
    CHECK(none && none->count == 0);
    vdbgi_probes_destroy(none);
    /* A file replaced since open is not read. */
    CHECK_RESULT(ctx, vdbgi_probes_write(whole, path), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_probe_file_read(f, z[0], z[0] + 32, &none), VDBGI_ERR_IO);
    CHECK(none == NULL && strstr(vdbgi_context_error(ctx), "changed since it was opened"));
    vdbgi_probes_destroy(whole);
    /* Refused: a region not a multiple of 32, the seed layout. */
    vdbgi_volume *v = NULL;
    CHECK_RESULT(ctx, vdbgi_volume_build_regions(ctx, f, 33, NULL, &v), VDBGI_ERR_INVALID_ARG);
    CHECK_RESULT(ctx, vdbgi_volume_build_regions(ctx, f, 0, NULL, &v), VDBGI_ERR_INVALID_ARG);
    const vdbgi_convert_desc seed = {.layout = VDBGI_LAYOUT_SEED};
    CHECK_RESULT(ctx, vdbgi_volume_build_regions(ctx, f, 32, &seed, &v), VDBGI_ERR_INVALID_ARG);
    CHECK(v == NULL);
    vdbgi_probe_file_close(f);
    vdbgi_context_destroy(ctx);

    static unsigned char a[1 << 22], b[1 << 22];
    vdbgi_volume_info ia, ib;
    const size_t size = convert_to(path, 0, 0, 1, a, &ia);
    CHECK(size > 0 && ia.basis == VDBGI_BASIS_SH2);
    const int cases[][3] = {
        {32, VDBGI_REGION_HALO, 1}, {32, VDBGI_REGION_HALO, 2}, {64, VDBGI_REGION_HALO, 2}};
    for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
        CHECK(convert_to(path, cases[c][0], cases[c][1], cases[c][2], b, &ib) == size);
        CHECK(memcmp(a, b, size) == 0);
        CHECK(ia.rmse == ib.rmse && ia.p99 == ib.p99 && ia.max_error == ib.max_error);
        CHECK(ia.filled_count == ib.filled_count && ia.unreached_count == ib.unreached_count &&
              ia.fallback_count == ib.fallback_count && ia.valid_count == ib.valid_count &&
              ia.mean_irradiance == ib.mean_irradiance);
    }
    const size_t bare = convert_to(path, 32, 0, 1, b, &ib);
    CHECK(bare > 0 && (bare != size || memcmp(a, b, size) != 0));
}

/* A 6 m floor (two regions of 32 points: its cells reach below the first, its + borders
   above the last) and a 10 m one (more). */
static void regions_convert_to_the_whole_conversions_bytes(void)
{
    regions_match_on_a_floor(6.0f);
    regions_match_on_a_floor(10.0f);
}

int main(void)
{
    test_tmpdir_make("test-vdb");
    RUN(written_probes_read_back_exactly);
    RUN(failed_writes_leave_nothing_and_clobber_nothing);
    RUN(unreadable_files_are_refused);
    RUN(ambient_cubes_round_trip_as_six_grids);
    RUN(sh2_terms_round_trip_as_eight_grids);
    RUN(tiles_merge_into_the_whole_bake);
    RUN(rays_of_older_files_are_read);
    RUN(a_memory_limit_stops_a_conversion_at_its_figure);
    RUN(regions_convert_to_the_whole_conversions_bytes);
    test_tmpdir_remove();
    return CHECK_EXIT();
}
