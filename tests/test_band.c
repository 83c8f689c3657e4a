/*
 * test_band.c: probes are placed at exactly the lattice points within the
 * margin of a surface (checked against a brute force written another way),
 * whatever the thread count; a slab placed from only the triangles that
 * reach it holds exactly the whole lattice's points in it; and the bundled
 * world at its default spacing, in 2 to 8 tiles, places the whole lattice.
 */
#define _POSIX_C_SOURCE 200809L
#include "band.h"
#include "probes.h"
#include "test_util.h"

#include <math.h>
#include <stdlib.h>

/* Distance from p to segment ab, by the parameter of the nearest point. */
static double segment_distance(const double p[3], const double a[3], const double b[3])
{
    double ab2 = 0.0, t = 0.0;
    for (int k = 0; k < 3; k++) {
        ab2 += (b[k] - a[k]) * (b[k] - a[k]);
        t += (p[k] - a[k]) * (b[k] - a[k]);
    }
    t = ab2 > 0.0 ? fmin(1.0, fmax(0.0, t / ab2)) : 0.0;
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        const double q = a[k] + t * (b[k] - a[k]) - p[k];
        d2 += q * q;
    }
    return sqrt(d2);
}

/*
 * Distance from p to a triangle, not by Voronoi regions as the library
 * does: the foot of the perpendicular on the plane if it falls inside
 * (same-side tests against each edge), else the nearest of the three edges.
 */
static double triangle_distance(const double p[3], const double v[3][3])
{
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++)
        e1[k] = v[1][k] - v[0][k], e2[k] = v[2][k] - v[0][k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double edges =
        fmin(segment_distance(p, v[0], v[1]),
             fmin(segment_distance(p, v[1], v[2]), segment_distance(p, v[2], v[0])));
    if (!(len > 1e-9))
        return edges;
    for (int k = 0; k < 3; k++)
        n[k] /= len;
    const double h = (p[0] - v[0][0]) * n[0] + (p[1] - v[0][1]) * n[1] + (p[2] - v[0][2]) * n[2];
    const double foot[3] = {p[0] - h * n[0], p[1] - h * n[1], p[2] - h * n[2]};
    for (int i = 0; i < 3; i++) {
        const double *a = v[i], *b = v[(i + 1) % 3];
        double ab[3], af[3], c[3];
        for (int k = 0; k < 3; k++)
            ab[k] = b[k] - a[k], af[k] = foot[k] - a[k];
        c[0] = ab[1] * af[2] - ab[2] * af[1];
        c[1] = ab[2] * af[0] - ab[0] * af[2];
        c[2] = ab[0] * af[1] - ab[1] * af[0];
        if (c[0] * n[0] + c[1] * n[1] + c[2] * n[2] < 0.0)
            return edges;
    }
    return fabs(h);
}

typedef struct soup {
    float positions[3 * 3 * 64];
    uint32_t indices[3 * 64];
    size_t triangle_count;
} soup;

static float uniform(uint64_t *s, float lo, float hi)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * (float)((*s >> 40) / 16777216.0);
}

/* Triangles of every kind: small, large, slivers, a repeated vertex, three in a line. */
static void make_soup(soup *m)
{
    uint64_t s = 17;
    m->triangle_count = 0;
    for (int t = 0; t < 40; t++) {
        const float size = t % 4 == 0 ? 6.0f : t % 4 == 1 ? 0.2f : 1.5f;
        float c[3] = {uniform(&s, -5, 5), uniform(&s, -2, 2), uniform(&s, -5, 5)};
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 3; k++)
                m->positions[9 * t + 3 * v + k] = c[k] + uniform(&s, -size, size);
        if (t % 10 == 3) /* a sliver 8 m long */
            for (int k = 0; k < 3; k++)
                m->positions[9 * t + 6 + k] = m->positions[9 * t + k] + 8.0f * (k == 0 ? 1 : 0.1f);
        if (t % 10 == 5) /* a repeated vertex */
            for (int k = 0; k < 3; k++)
                m->positions[9 * t + 3 + k] = m->positions[9 * t + k];
        if (t % 10 == 7) /* three in a line */
            for (int k = 0; k < 3; k++)
                m->positions[9 * t + 6 + k] =
                    2.0f * m->positions[9 * t + 3 + k] - m->positions[9 * t + k];
        for (int v = 0; v < 3; v++)
            m->indices[3 * t + v] = (uint32_t)(3 * t + v);
        m->triangle_count++;
    }
}

static int compare_ijk(const void *a, const void *b)
{
    const int32_t *p = a, *q = b;
    for (int k = 0; k < 3; k++)
        if (p[k] != q[k])
            return p[k] < q[k] ? -1 : 1;
    return 0;
}

/* The brute force's points (sorted) within margin of any triangle with i in x_range. */
static size_t brute_force(const soup *m, const vdbgi_band_desc *d, int32_t *out, size_t capacity)
{
    size_t n = 0;
    int32_t lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        float a = INFINITY, b = -INFINITY;
        for (size_t v = 0; v < 3 * m->triangle_count; v++) {
            a = fminf(a, m->positions[3 * m->indices[v] + (size_t)k]);
            b = fmaxf(b, m->positions[3 * m->indices[v] + (size_t)k]);
        }
        lo[k] = (int32_t)floor((a - d->margin - d->origin[k]) / d->spacing) - 1;
        hi[k] = (int32_t)ceil((b + d->margin - d->origin[k]) / d->spacing) + 1;
    }
    for (int32_t x = lo[0]; x <= hi[0]; x++) {
        if (x < d->x_range[0] || x >= d->x_range[1])
            continue;
        for (int32_t y = lo[1]; y <= hi[1]; y++)
            for (int32_t z = lo[2]; z <= hi[2]; z++) {
                const double p[3] = {d->origin[0] + d->spacing * x, d->origin[1] + d->spacing * y,
                                     d->origin[2] + d->spacing * z};
                for (size_t t = 0; t < m->triangle_count; t++) {
                    double v[3][3];
                    for (int c = 0; c < 3; c++)
                        for (int k = 0; k < 3; k++)
                            v[c][k] = m->positions[3 * m->indices[3 * t + c] + k];
                    if (triangle_distance(p, v) <= d->margin) {
                        if (n < capacity)
                            out[3 * n] = x, out[3 * n + 1] = y, out[3 * n + 2] = z;
                        n++;
                        break;
                    }
                }
            }
    }
    return n;
}

/* ijk (sorted here) holds the points of want (sorted), no more; what names want. */
static bool same_sorted(int32_t *ijk, size_t count, const int32_t *want, size_t want_count,
                        const char *what)
{
    if (count != want_count) {
        fprintf(stderr, "  %zu points, %s %zu\n", count, what, want_count);
        return false;
    }
    qsort(ijk, count, 3 * sizeof(int32_t), compare_ijk);
    return memcmp(ijk, want, 3 * sizeof(int32_t) * count) == 0;
}

static void band_holds_exactly_the_points_within_the_margin(void)
{
    vdbgi_context *ctx = test_context();
    static soup m;
    make_soup(&m);
    vdbgi_band_desc d = {.positions = m.positions,
                         .indices = m.indices,
                         .triangle_count = m.triangle_count,
                         .origin = {0.11, -0.23, 0.05},
                         .spacing = 0.37,
                         .margin = 0.9,
                         .x_range = {INT64_MIN, INT64_MAX},
                         .max_count = 1000000};
    enum { capacity = 400000 };
    int32_t *const want = malloc(3 * sizeof(int32_t) * capacity);
    const size_t want_count = brute_force(&m, &d, want, capacity);
    CHECK(want_count > 1000 && want_count < capacity);
    qsort(want, want_count, 3 * sizeof(int32_t), compare_ijk);
    static const int threads[4] = {1, 2, 3, 7};
    for (int i = 0; i < 4; i++) {
        d.threads = threads[i];
        int32_t *ijk = NULL;
        size_t count = 0;
        CHECK_RESULT(ctx, vdbgi_band_points(ctx, &d, &ijk, &count), VDBGI_OK);
        CHECK(ijk && same_sorted(ijk, count, want, want_count, "the brute force"));
        vdbgi_free(ctx, ijk);
    }
    /* Past the stated count: refused, naming it. */
    d.max_count = want_count - 1;
    int32_t *ijk = NULL;
    size_t count = 0;
    CHECK_RESULT(ctx, vdbgi_band_points(ctx, &d, &ijk, &count), VDBGI_ERR_OUT_OF_MEMORY);
    CHECK(!ijk && count == 0 && strstr(vdbgi_context_error(ctx), "above the limit") != NULL);
    free(want);
    vdbgi_context_destroy(ctx);
}

/*
 * A slab of lattice x from only the triangles whose x extent comes within
 * the margin of it holds the brute force's points of that slab, none more:
 * what lets a tile of a bake equal the whole bake there.
 */
static void a_slab_from_its_triangles_holds_the_whole_lattices_points(void)
{
    vdbgi_context *ctx = test_context();
    static soup m, part;
    make_soup(&m);
    const double origin[3] = {0.25, 0.25, 0.25}, spacing = 0.5, margin = 2.0;
    enum { capacity = 400000 };
    int32_t *const want = malloc(3 * sizeof(int32_t) * capacity);
    static const int64_t cuts[4][2] = {{-40, -8}, {-8, 0}, {0, 3}, {3, 40}};
    for (int c = 0; c < 4; c++) {
        part = m;
        part.triangle_count = 0;
        const double x0 = origin[0] + spacing * (double)cuts[c][0] - margin - spacing;
        const double x1 = origin[0] + spacing * (double)(cuts[c][1] - 1) + margin + spacing;
        for (size_t t = 0; t < m.triangle_count; t++) {
            float lo = INFINITY, hi = -INFINITY;
            for (int v = 0; v < 3; v++) {
                lo = fminf(lo, m.positions[3 * m.indices[3 * t + v]]);
                hi = fmaxf(hi, m.positions[3 * m.indices[3 * t + v]]);
            }
            if (hi >= x0 && lo <= x1)
                memcpy(&part.indices[3 * part.triangle_count++], &m.indices[3 * t],
                       3 * sizeof(uint32_t));
        }
        CHECK(part.triangle_count < m.triangle_count || c == 0);
        const vdbgi_band_desc d = {.positions = m.positions,
                                   .indices = part.indices,
                                   .triangle_count = part.triangle_count,
                                   .origin = {origin[0], origin[1], origin[2]},
                                   .spacing = spacing,
                                   .margin = margin,
                                   .x_range = {cuts[c][0], cuts[c][1]},
                                   .max_count = 1000000,
                                   .threads = 2};
        /* The brute force sees every triangle. */
        vdbgi_band_desc whole = d;
        const size_t want_count = brute_force(&m, &whole, want, capacity);
        qsort(want, want_count, 3 * sizeof(int32_t), compare_ijk);
        int32_t *ijk = NULL;
        size_t count = 0;
        CHECK_RESULT(ctx, vdbgi_band_points(ctx, &d, &ijk, &count), VDBGI_OK);
        CHECK(ijk && count > 0 && same_sorted(ijk, count, want, want_count, "the brute force"));
        vdbgi_free(ctx, ijk);
    }
    free(want);
    vdbgi_context_destroy(ctx);
}

/* The bundled world at the default 0.5 m, in 2 to 8 tiles, places the whole lattice's probes. */
static void tiles_of_the_bundled_world_place_the_whole_lattice(void)
{
    vdbgi_context *ctx = test_context();
    vdbgi_scene *world = NULL;
    CHECK_RESULT(ctx, vdbgi_scene_load(ctx, "data/world.glb", &world), VDBGI_OK);
    if (!world) {
        vdbgi_context_destroy(ctx);
        return;
    }
    vdbgi_place_desc pd = {0};
    vdbgi_probes *whole = NULL;
    CHECK_RESULT(ctx, vdbgi_probes_place(ctx, world, &pd, &whole), VDBGI_OK);
    if (!whole) {
        vdbgi_scene_destroy(world);
        vdbgi_context_destroy(ctx);
        return;
    }
    const size_t n = whole->count;
    int32_t *const all = malloc(3 * sizeof(int32_t) * (n + 1));
    int32_t *const tiled = malloc(3 * sizeof(int32_t) * (n + 1));
    memcpy(all, whole->ijk, 3 * sizeof(int32_t) * n);
    qsort(all, n, 3 * sizeof(int32_t), compare_ijk);
    for (int tiles = 2; tiles <= 8; tiles++) {
        size_t got = 0;
        bool fits = true;
        for (int t = 0; t < tiles; t++) {
            vdbgi_probes *tile = NULL;
            pd.tile_index = t;
            pd.tile_count = tiles;
            CHECK_RESULT(ctx, vdbgi_probes_place(ctx, world, &pd, &tile), VDBGI_OK);
            if (tile && got + tile->count <= n)
                memcpy(&tiled[3 * got], tile->ijk, 3 * sizeof(int32_t) * tile->count);
            fits = fits && tile && got + tile->count <= n;
            got += tile ? tile->count : 0;
            vdbgi_probes_destroy(tile);
        }
        const bool same = fits && same_sorted(tiled, got, all, n, "the whole lattice");
        if (!same)
            fprintf(stderr, "  %d tiles differ from the whole lattice\n", tiles);
        CHECK(same);
    }
    free(all);
    free(tiled);
    vdbgi_probes_destroy(whole);
    vdbgi_scene_destroy(world);
    vdbgi_context_destroy(ctx);
}

int main(void)
{
    RUN(band_holds_exactly_the_points_within_the_margin);
    RUN(a_slab_from_its_triangles_holds_the_whole_lattices_points);
    RUN(tiles_of_the_bundled_world_place_the_whole_lattice);
    return CHECK_EXIT();
}
