/*
 * test_unwrap.c: lightmap UVs and texels. Every triangle mapped inside its
 * atlas; no texel centre inside two triangles; no texel touched by two
 * charts, and none within two gutters of another chart; texel density as
 * asked where the atlas allows it; degenerate and sliver triangles; 50 000
 * triangles; the same bytes twice. Every triangle gets samples on itself,
 * and dilation fills exactly the gutters' reach.
 */
#define _POSIX_C_SOURCE 200809L
#include "scene.h"
#include "test_util.h"
#include "texels.h"
#include "unwrap.h"

#include <math.h>

/* Does the triangle (2D) overlap the closed square [x, x+1] x [y, y+1]? Separating axes. */
static bool touches(const float *t, double x, double y)
{
    const double sq[4][2] = {{x, y}, {x + 1, y}, {x + 1, y + 1}, {x, y + 1}};
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 2; a++) {
            lo[a] = fmin(lo[a], t[2 * k + a]);
            hi[a] = fmax(hi[a], t[2 * k + a]);
        }
    if (hi[0] < x || lo[0] > x + 1 || hi[1] < y || lo[1] > y + 1)
        return false;
    for (int e = 0; e < 3; e++) {
        const double ax = -(t[2 * ((e + 1) % 3) + 1] - t[2 * e + 1]),
                     ay = t[2 * ((e + 1) % 3)] - t[2 * e];
        double tl = INFINITY, th = -INFINITY, sl = INFINITY, sh = -INFINITY;
        for (int k = 0; k < 3; k++) {
            const double d = ax * t[2 * k] + ay * t[2 * k + 1];
            tl = fmin(tl, d), th = fmax(th, d);
        }
        for (int k = 0; k < 4; k++) {
            const double d = ax * sq[k][0] + ay * sq[k][1];
            sl = fmin(sl, d), sh = fmax(sh, d);
        }
        if (th < sl || sh < tl)
            return false;
    }
    return true;
}

/* Is point (x, y) strictly inside the triangle (either winding)? */
static bool inside(const float *t, double x, double y)
{
    double s[3];
    for (int e = 0; e < 3; e++) {
        const float *a = &t[2 * e], *b = &t[2 * ((e + 1) % 3)];
        s[e] = (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
    }
    const double eps = 1e-9;
    return (s[0] > eps && s[1] > eps && s[2] > eps) || (s[0] < -eps && s[1] < -eps && s[2] < -eps);
}

/* Everything an unwrap promises, checked against the scene it came from. */
static void check_unwrap(const vdbgi_scene *s, const vdbgi_unwrap *u, bool density_as_asked)
{
    const int size = u->size, reach = 2 * (int)u->gutter;
    CHECK(u->triangle_count == s->triangle_count && u->page_count >= 1);
    uint32_t *owner = calloc((size_t)size * size * u->page_count, sizeof(*owner));
    uint8_t *centres = calloc((size_t)size * size * u->page_count, 1);
    size_t bad_uv = 0, shared = 0, overlaps = 0, off_density = 0;
    for (size_t t = 0; t < u->triangle_count; t++) {
        const float *const uv = &u->uv[6 * t];
        const uint32_t c = u->chart[t];
        CHECK(c < u->chart_count && u->page[c] < u->page_count);
        for (int k = 0; k < 6; k++)
            bad_uv += !(uv[k] >= 0.0f && uv[k] <= (float)size);
        const size_t page = (size_t)u->page[c] * size * size;
        const int x0 = (int)floor(fmin(uv[0], fmin(uv[2], uv[4]))),
                  x1 = (int)floor(fmax(uv[0], fmax(uv[2], uv[4]))),
                  y0 = (int)floor(fmin(uv[1], fmin(uv[3], uv[5]))),
                  y1 = (int)floor(fmax(uv[1], fmax(uv[3], uv[5])));
        for (int y = y0 < 0 ? 0 : y0; y <= y1 && y < size; y++)
            for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < size; x++) {
                if (touches(uv, x, y)) {
                    uint32_t *const o = &owner[page + (size_t)y * size + x];
                    shared += *o && *o != c + 1;
                    *o = c + 1;
                }
                if (inside(uv, x + 0.5, y + 0.5))
                    overlaps += centres[page + (size_t)y * size + x]++ > 0;
            }
        /* Texel density: the uv area against the world area at the chart's density. */
        const double area =
            fabs((uv[2] - uv[0]) * (uv[5] - uv[1]) - (uv[4] - uv[0]) * (uv[3] - uv[1])) / 2.0;
        const double want = vdbgi_scene_triangle_area(s, t) * u->density[c] * u->density[c];
        if (want > 1e-3)
            off_density += fabs(area / want - 1.0) > 0.1;
        if (density_as_asked)
            CHECK(fabs(u->density[c] * u->texel - 1.0) < 1e-5);
    }
    /* Gutters: no texel of another chart within two gutters of a chart's texel. */
    size_t close = 0;
    for (size_t p = 0; p < u->page_count; p++)
        for (int y = 0; y < size; y++)
            for (int x = 0; x < size; x++) {
                const uint32_t o = owner[p * size * size + (size_t)y * size + x];
                if (!o)
                    continue;
                for (int dy = -reach; dy <= reach; dy++)
                    for (int dx = -reach; dx <= reach; dx++) {
                        const int xx = x + dx, yy = y + dy;
                        if (xx < 0 || yy < 0 || xx >= size || yy >= size)
                            continue;
                        const uint32_t q = owner[p * size * size + (size_t)yy * size + xx];
                        close += q && q != o;
                    }
            }
    CHECK(bad_uv == 0);
    CHECK(overlaps == 0);
    CHECK(shared == 0);
    CHECK(close == 0);
    CHECK(off_density == 0);
    free(owner);
    free(centres);
}

static vdbgi_scene *scene_of(vdbgi_context *ctx, const float *pos, size_t nv, const uint32_t *idx,
                             size_t nt)
{
    const vdbgi_mesh_desc d = {.positions = pos,
                               .vertex_count = nv,
                               .indices = idx,
                               .triangle_count = nt,
                               .albedo = {0.5f, 0.5f, 0.5f}};
    vdbgi_scene *s = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_create(ctx, &d, 1, &s), VDBGI_OK);
    return s;
}

/* A 4 x 3 x 2 m box, its faces out. */
static vdbgi_scene *box_scene(vdbgi_context *ctx)
{
    test_mesh m = {0};
    const float lo[3] = {0, 0, 0}, hi[3] = {4, 3, 2};
    test_mesh_box(&m, lo, hi, 0);
    return scene_of(ctx, m.pos, m.vertex_count, m.idx, m.triangle_count);
}

static void a_box_is_six_charts_at_the_texel_size(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = box_scene(ctx);
    vdbgi_unwrap u;
    const vdbgi_unwrap_params p = {.texel = 0.25f, .size = 128};
    CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, s, &p, &u), VDBGI_OK);
    CHECK(u.chart_count == 6 && u.page_count == 1);
    check_unwrap(s, &u, true);
    /* The 4 x 3 m faces span 16 x 12 texels. */
    float w = 0, h = 0;
    for (int k = 0; k < 6; k += 2) {
        w = fmaxf(w, fabsf(u.uv[k] - u.uv[0]));
        h = fmaxf(h, fabsf(u.uv[k + 1] - u.uv[1]));
    }
    CHECK((fabsf(w - 16) < 1e-3f && fabsf(h - 12) < 1e-3f) ||
          (fabsf(w - 12) < 1e-3f && fabsf(h - 16) < 1e-3f));
    vdbgi_unwrap_free(&u);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* An n x n terrain of 2 n^2 triangles with hills, and a sliver and a degenerate triangle. */
static void terrain(int n, float cell, float **pos, size_t *nv, uint32_t **idx, size_t *nt)
{
    *nv = (size_t)(n + 1) * (n + 1) + 3;
    *nt = 2 * (size_t)n * n + 2;
    *pos = malloc(3 * *nv * sizeof(float));
    *idx = malloc(3 * *nt * sizeof(uint32_t));
    for (int z = 0; z <= n; z++)
        for (int x = 0; x <= n; x++) {
            float *const v = &(*pos)[3 * ((size_t)z * (n + 1) + x)];
            v[0] = x * cell, v[2] = z * cell;
            v[1] = 2.0f * sinf(0.3f * x * cell) * cosf(0.2f * z * cell);
        }
    size_t t = 0;
    for (int z = 0; z < n; z++)
        for (int x = 0; x < n; x++) {
            const uint32_t a = (uint32_t)(z * (n + 1) + x), b = a + 1, c = a + (uint32_t)n + 1,
                           d = c + 1;
            const uint32_t q[6] = {a, c, b, b, c, d};
            memcpy(&(*idx)[3 * t], q, sizeof(q));
            t += 2;
        }
    /* A sliver 10 m long and 0.1 mm wide, and a triangle with two equal corners. */
    float *const e = &(*pos)[3 * (*nv - 3)];
    const float extra[9] = {-5, 1, -5, 5, 1, -5, 0, 1, -5.0001f};
    memcpy(e, extra, sizeof(extra));
    const uint32_t base = (uint32_t)(*nv - 3);
    const uint32_t q[6] = {base, base + 2, base + 1, base, base, base + 1};
    memcpy(&(*idx)[3 * t], q, sizeof(q));
}

/* The terrain as a scene (which copies it), and its triangle count before the scene drops any. */
static vdbgi_scene *terrain_scene(vdbgi_context *ctx, int n, float cell, size_t *triangles)
{
    float *pos;
    uint32_t *idx;
    size_t nv, nt;
    terrain(n, cell, &pos, &nv, &idx, &nt);
    vdbgi_scene *const s = scene_of(ctx, pos, nv, idx, nt);
    free(pos);
    free(idx);
    if (triangles)
        *triangles = nt;
    return s;
}

static void fifty_thousand_triangles_slivers_and_determinism(void)
{
    vdbgi_context *ctx = test_context();
    size_t nt;
    vdbgi_scene *s = terrain_scene(ctx, 159, 0.25f, &nt);
    CHECK(s && s->triangle_count == nt - 1 && nt - 1 >= 50000); /* the degenerate one dropped */
    vdbgi_unwrap a, b;
    const vdbgi_unwrap_params p = {.texel = 0.1f, .size = 256};
    CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, s, &p, &a), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, s, &p, &b), VDBGI_OK);
    CHECK(a.page_count > 1 && a.chart_count > 1);
    check_unwrap(s, &a, true);
    CHECK(memcmp(a.uv, b.uv, 6 * a.triangle_count * sizeof(float)) == 0 &&
          memcmp(a.chart, b.chart, a.triangle_count * sizeof(uint32_t)) == 0);
    vdbgi_unwrap_free(&a);
    vdbgi_unwrap_free(&b);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void a_chart_larger_than_the_atlas_shrinks_to_fit(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    test_mesh_plane(&m, 100.0f, 0.0f);
    vdbgi_scene *s = scene_of(ctx, m.pos, m.vertex_count, m.idx, m.triangle_count);
    vdbgi_unwrap u;
    const vdbgi_unwrap_params p = {.texel = 0.25f, .size = 64};
    CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, s, &p, &u), VDBGI_OK);
    CHECK(u.chart_count == 1 && u.page_count == 1 && u.density[0] < 4.0f);
    check_unwrap(s, &u, false);
    vdbgi_unwrap_free(&u);
    vdbgi_scene_destroy(s);
    /* Sizes whose shrunk density rounded up as a float overflowed the atlas by a texel. */
    for (float side = 290.0f; side <= 310.0f; side += 2.5f) {
        test_mesh q = {0};
        test_mesh_plane(&q, side, 0.0f);
        s = scene_of(ctx, q.pos, q.vertex_count, q.idx, q.triangle_count);
        const vdbgi_unwrap_params big = {.texel = 0.25f, .size = 1024};
        CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, s, &big, &u), VDBGI_OK);
        CHECK(u.page_count == 1);
        vdbgi_unwrap_free(&u);
        vdbgi_scene_destroy(s);
    }
    vdbgi_context_destroy(ctx);
}

/* A ramp that turns twice round a column: one chart by its normals, folded over itself. */
static void a_spiral_ramp_is_split_where_it_folds(void)
{
    vdbgi_context *ctx = test_context();
    enum { STEPS = 192 };
    float pos[2 * (STEPS + 1) * 3];
    uint32_t idx[2 * STEPS * 3];
    for (int i = 0; i <= STEPS; i++) {
        const float a = 2.0f * 3.14159265f * 2.0f * i / STEPS, y = 2.0f * i / STEPS;
        for (int r = 0; r < 2; r++) {
            float *const v = &pos[3 * (2 * i + r)];
            v[0] = (2.0f + 2.0f * r) * cosf(a), v[1] = y, v[2] = (2.0f + 2.0f * r) * sinf(a);
        }
    }
    for (int i = 0; i < STEPS; i++) {
        const uint32_t a = (uint32_t)(2 * i), q[6] = {a, a + 2, a + 1, a + 1, a + 2, a + 3};
        memcpy(&idx[6 * i], q, sizeof(q));
    }
    vdbgi_scene *s = scene_of(ctx, pos, 2 * (STEPS + 1), idx, 2 * STEPS);
    vdbgi_unwrap u;
    const vdbgi_unwrap_params p = {.texel = 0.05f, .size = 512};
    CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, s, &p, &u), VDBGI_OK);
    CHECK(u.chart_count >= 2);
    check_unwrap(s, &u, true);
    vdbgi_unwrap_free(&u);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/* Each triangle has a texel, and each sample lies on its triangle. */
static void every_triangle_gets_samples_on_itself(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *s = terrain_scene(ctx, 40, 0.5f, NULL);
    vdbgi_unwrap u;
    vdbgi_texels tx;
    const vdbgi_unwrap_params p = {.texel = 0.2f, .size = 256};
    CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, s, &p, &u), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_texels_build(ctx, s, &u, &tx), VDBGI_OK);
    size_t *per = calloc(s->triangle_count, sizeof(*per)), off = 0, outside = 0;
    const size_t texels = (size_t)tx.size * tx.size * tx.page_count;
    for (size_t i = 0; i < texels; i++) {
        if (tx.tri[i] < 0)
            continue;
        const size_t t = (size_t)tx.tri[i];
        per[t]++;
        const float *const n = s->tris[t].normal, *const q = &tx.pos[3 * i];
        const float *v[3];
        for (int k = 0; k < 3; k++)
            v[k] = &s->positions[3 * (size_t)s->indices[3 * t + (size_t)k]];
        /* Height over the plane, and the side of each edge (in the plane). */
        double h = 0.0;
        for (int k = 0; k < 3; k++)
            h += (q[k] - v[0][k]) * n[k];
        off += fabs(h) > 1e-5;
        for (int e = 0; e < 3; e++) {
            const float *a = v[e], *b = v[(e + 1) % 3];
            const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                         aq[3] = {q[0] - a[0], q[1] - a[1], q[2] - a[2]};
            const double cr[3] = {ab[1] * aq[2] - ab[2] * aq[1], ab[2] * aq[0] - ab[0] * aq[2],
                                  ab[0] * aq[1] - ab[1] * aq[0]};
            /* Distance inside the edge: float positions a few metres out round by ~1e-6 m. */
            const double len = sqrt(ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]);
            outside += (cr[0] * n[0] + cr[1] * n[1] + cr[2] * n[2]) / len < -1e-5;
        }
    }
    size_t empty = 0;
    for (size_t t = 0; t < s->triangle_count; t++)
        empty += per[t] == 0;
    CHECK(empty == 0 && off == 0 && outside == 0);
    CHECK(tx.sample_count > tx.centre_count && tx.centre_count > 0);
    /* Dilation: ones spread exactly two rings from the samples, as means of ones. */
    unsigned char *keep = calloc(texels, 1);
    float *val = calloc(texels, sizeof(float));
    for (size_t i = 0; i < texels; i++)
        keep[i] = tx.tri[i] >= 0, val[i] = keep[i] ? 1.0f : 0.0f;
    CHECK_RESULT(ctx, vdbgi_texels_dilate(&tx, val, 1, keep, 2), VDBGI_OK);
    size_t wrong = 0;
    for (size_t i = 0; i < texels; i++) {
        const size_t page = i / ((size_t)tx.size * tx.size), y = i / tx.size % tx.size,
                     x = i % tx.size;
        bool near = false;
        for (int dy = -2; dy <= 2 && !near; dy++)
            for (int dx = -2; dx <= 2 && !near; dx++) {
                const long xx = (long)x + dx, yy = (long)y + dy;
                near = xx >= 0 && yy >= 0 && xx < tx.size && yy < tx.size &&
                       tx.tri[(page * tx.size + (size_t)yy) * tx.size + (size_t)xx] >= 0;
            }
        wrong += keep[i] != near || (keep[i] && val[i] != 1.0f);
    }
    CHECK(wrong == 0);
    free(keep);
    free(val);
    free(per);
    vdbgi_texels_free(&tx);
    vdbgi_unwrap_free(&u);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

static void a_box_face_of_16_by_12_texels_samples_17_by_13(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    const float lo[3] = {0, 0, 0}, hi[3] = {4, 3, 2};
    test_mesh_box(&m, lo, hi, 0);
    vdbgi_scene *s = scene_of(ctx, m.pos, m.vertex_count, m.idx, m.triangle_count);
    vdbgi_unwrap u;
    vdbgi_texels tx;
    const vdbgi_unwrap_params p = {.texel = 0.25f, .size = 128};
    CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, s, &p, &u), VDBGI_OK);
    CHECK_RESULT(ctx, vdbgi_texels_build(ctx, s, &u, &tx), VDBGI_OK);
    /* Faces of 16 x 12, 16 x 8 and 12 x 8 texels, half a texel in: one more each way. */
    CHECK(tx.sample_count == 2 * (17 * 13 + 17 * 9 + 13 * 9));
    vdbgi_texels_free(&tx);
    vdbgi_unwrap_free(&u);
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

/*
 * By default the atlas is the smallest multiple of 32 texels that holds every
 * chart at the texel size: one of 32 fewer needs a second page. Past one
 * atlas of 1024, atlases of 1024.
 */
static void the_default_atlas_is_the_least_that_holds_the_charts(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *const terrain = terrain_scene(ctx, 159, 0.25f, NULL), *const box = box_scene(ctx);
    const struct {
        vdbgi_scene *s;
        float texel;
    } cases[2] = {{box, 0.25f}, {terrain, 0.1f}};
    for (int i = 0; i < 2; i++) {
        vdbgi_unwrap u, less;
        const vdbgi_unwrap_params p = {.texel = cases[i].texel};
        CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, cases[i].s, &p, &u), VDBGI_OK);
        CHECK(u.page_count == 1 && u.size % 32 == 0 && u.size >= 64 && u.size < 1024);
        check_unwrap(cases[i].s, &u, true);
        const vdbgi_unwrap_params smaller = {.texel = cases[i].texel, .size = u.size - 32};
        CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, cases[i].s, &smaller, &less), VDBGI_OK);
        CHECK(less.page_count > 1);
        vdbgi_unwrap_free(&u);
        vdbgi_unwrap_free(&less);
    }
    vdbgi_unwrap big;
    const vdbgi_unwrap_params fine = {.texel = 0.02f};
    CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, terrain, &fine, &big), VDBGI_OK);
    CHECK(big.size == 1024 && big.page_count > 1);
    vdbgi_unwrap_free(&big);
    vdbgi_scene_destroy(box);
    vdbgi_scene_destroy(terrain);
    vdbgi_context_destroy(ctx);
}

static void bad_parameters_are_refused(void)
{
    vdbgi_context *ctx = test_context();
    test_mesh m = {0};
    test_mesh_plane(&m, 4.0f, 0.0f);
    vdbgi_scene *s = scene_of(ctx, m.pos, m.vertex_count, m.idx, m.triangle_count);
    const vdbgi_unwrap_params bad[] = {{.texel = -1},    {.texel = NAN},    {.size = 8},
                                       {.size = 100000}, {.max_angle = 90}, {.gutter = -1}};
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        vdbgi_unwrap u;
        CHECK_RESULT(ctx, vdbgi_unwrap_build(ctx, s, &bad[i], &u), VDBGI_ERR_INVALID_ARG);
        CHECK(u.uv == NULL);
    }
    vdbgi_scene_destroy(s);
    vdbgi_context_destroy(ctx);
}

int main(void)
{
    RUN(a_box_is_six_charts_at_the_texel_size);
    RUN(fifty_thousand_triangles_slivers_and_determinism);
    RUN(a_chart_larger_than_the_atlas_shrinks_to_fit);
    RUN(a_spiral_ramp_is_split_where_it_folds);
    RUN(every_triangle_gets_samples_on_itself);
    RUN(a_box_face_of_16_by_12_texels_samples_17_by_13);
    RUN(the_default_atlas_is_the_least_that_holds_the_charts);
    RUN(bad_parameters_are_refused);
    return CHECK_EXIT();
}
