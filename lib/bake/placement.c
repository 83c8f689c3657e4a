/* placement.c: the probe lattice (origin, spacing) and which probes exist near the surfaces. */
#include "band.h"
#include "keep.h"
#include "probes.h"
#include "scene.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

static double estimate_probe_count(const vdbgi_scene *s, double spacing, double margin)
{
    double area = 0.0;
    for (size_t t = 0; t < s->triangle_count; t++) {
        area += vdbgi_scene_triangle_area(s, t);
    }
    return area * (2.0 * margin + spacing) / (spacing * spacing * spacing);
}

/* Triangle t's extent along x. */
static void x_extent(const vdbgi_scene *scene, size_t t, double *lo, double *hi)
{
    *lo = INFINITY, *hi = -INFINITY;
    for (int v = 0; v < 3; v++) {
        const double px = scene->positions[3 * scene->indices[3 * t + (size_t)v]];
        *lo = px < *lo ? px : *lo;
        *hi = px > *hi ? px : *hi;
    }
}

/*
 * Tile t of n: the slab [x[0], x[1]) of lattice i, cut between leaf columns
 * (multiples of 8) across the columns the scene's margin reaches (span[0]
 * .. span[1], the same for every tile). Each column goes to the tile in
 * whose n-th of the surface its middle falls, each triangle's area spread
 * over the columns it crosses: the probes lie in a band about the surfaces,
 * so area stands in for their count without placing them all.
 */
static vdbgi_result tile_slab(vdbgi_context *ctx, const vdbgi_scene *scene, const double origin[3],
                              double spacing, double margin, int t, int n, int32_t x[2],
                              int32_t span[2])
{
    const int32_t lo =
        vdbgi_floor_div((int32_t)floor((scene->bounds_min[0] - margin - origin[0]) / spacing), 8);
    const int32_t hi =
        vdbgi_floor_div((int32_t)ceil((scene->bounds_max[0] + margin - origin[0]) / spacing), 8);
    const size_t columns = (size_t)(hi - lo) + 1;
    double *const area = vdbgi_calloc(ctx, columns, sizeof(double));
    if (!area)
        return VDBGI_ERR_OUT_OF_MEMORY;
    /* Each triangle's area spread over the columns its x extent crosses, by length. */
    const double width = 8.0 * spacing, base = origin[0] + lo * width;
    double total = 0.0;
    for (size_t tri = 0; tri < scene->triangle_count; tri++) {
        double a0, a1;
        x_extent(scene, tri, &a0, &a1);
        const double a = vdbgi_scene_triangle_area(scene, tri);
        const double u0 = (a0 - base) / width, u1 = (a1 - base) / width;
        const double c0 = fmax(0.0, floor(u0)), c1 = fmin((double)columns - 1.0, floor(u1));
        for (double c = c0; c <= c1; c += 1.0) {
            const double part = u1 > u0 ? (fmin(u1, c + 1.0) - fmax(u0, c)) / (u1 - u0) : 1.0;
            area[(size_t)c] += a * part;
        }
        total += a;
    }
    double before = 0.0;
    int32_t first = INT32_MAX, last = INT32_MIN;
    for (size_t c = 0; c < columns; c++) {
        const int share = total > 0.0 ? (int)((before + 0.5 * area[c]) / total * n) : 0;
        if ((share < n ? share : n - 1) == t) {
            first = (int32_t)c < first ? (int32_t)c : first;
            last = (int32_t)c;
        }
        before += area[c];
    }
    vdbgi_free(ctx, area);
    VDBGI_FAIL_IF(
        ctx, first > last, VDBGI_ERR_INVALID_ARG,
        "tile %d of %d would hold no probe: the lattice has %zu leaf columns across x: use "
        "fewer tiles",
        t + 1, n, columns);
    x[0] = (lo + first) * 8, x[1] = (lo + last + 1) * 8;
    span[0] = lo * 8, span[1] = (hi + 1) * 8;
    return VDBGI_OK;
}

/*
 * The triangles a tile's probes can be near: those whose x extent meets the
 * slab widened by the margin and a spacing, as indices into scene's
 * vertices, into *out (*count of them).
 */
static vdbgi_result tile_triangles(vdbgi_context *ctx, const vdbgi_scene *scene,
                                   const double origin[3], double spacing, double margin,
                                   const int32_t x[2], uint32_t **out, size_t *count)
{
    const double x0 = origin[0] + x[0] * spacing - margin - spacing;
    const double x1 = origin[0] + (x[1] - 1) * spacing + margin + spacing;
    uint32_t *const idx = vdbgi_alloc(ctx, 3 * sizeof(uint32_t) * (scene->triangle_count + 1));
    if (!idx)
        return VDBGI_ERR_OUT_OF_MEMORY;
    size_t n = 0;
    for (size_t t = 0; t < scene->triangle_count; t++) {
        double lo, hi;
        x_extent(scene, t, &lo, &hi);
        if (hi >= x0 && lo <= x1)
            memcpy(&idx[3 * n++], &scene->indices[3 * t], 3 * sizeof(uint32_t));
    }
    *out = idx;
    *count = n;
    return VDBGI_OK;
}

vdbgi_result vdbgi_probes_place(vdbgi_context *ctx, const vdbgi_scene *scene,
                                const vdbgi_place_desc *desc, vdbgi_probes **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_FAIL_IF(ctx, !scene, VDBGI_ERR_INVALID_ARG, "no scene given");
    const vdbgi_place_desc none = {0};
    if (!desc)
        desc = &none;
    const double spacing = desc->spacing == 0.0 ? 0.5 : desc->spacing;
    VDBGI_FAIL_IF(ctx, !(spacing > 0.0) || !isfinite(spacing), VDBGI_ERR_INVALID_ARG,
                  "probe spacing must be > 0 and finite (got %g)", spacing);
    const double margin =
        desc->margin == 0.0 && !desc->margin_is_set ? 4.0 * spacing : desc->margin;
    VDBGI_FAIL_IF(ctx, !(margin >= 0.0) || !isfinite(margin), VDBGI_ERR_INVALID_ARG,
                  "probe margin must be >= 0 and finite (got %g)", desc->margin);
    VDBGI_FAIL_IF(ctx, margin / spacing > 64.0, VDBGI_ERR_INVALID_ARG,
                  "probe margin %g m is more than 64 spacings of %g m", margin, spacing);
    const uint64_t max_probes = desc->max_probes ? desc->max_probes : 50000000u;
    const int tiles = desc->tile_count > 1 ? desc->tile_count : 1;
    VDBGI_FAIL_IF(ctx, desc->tile_count < 0 || desc->tile_count > VDBGI_MAX_TILES,
                  VDBGI_ERR_INVALID_ARG, "tile count must be in 1..%d (got %d)", VDBGI_MAX_TILES,
                  desc->tile_count);
    VDBGI_FAIL_IF(ctx, desc->tile_index < 0 || desc->tile_index >= tiles, VDBGI_ERR_INVALID_ARG,
                  "tile %d of %d does not exist (tiles are 1..%d)", desc->tile_index + 1, tiles,
                  tiles);
    const bool origin_given = desc->origin_is_set || desc->origin[0] != 0.0 ||
                              desc->origin[1] != 0.0 || desc->origin[2] != 0.0;
    double origin[3];
    for (int k = 0; k < 3; k++) {
        origin[k] = origin_given ? desc->origin[k] : 0.5 * spacing;
        VDBGI_FAIL_IF(ctx, !isfinite(origin[k]), VDBGI_ERR_INVALID_ARG,
                      "lattice origin must be finite");
    }
    VDBGI_FAIL_IF(ctx, !(desc->walkable_height >= 0.0 && desc->walkable_height <= 1000.0),
                  VDBGI_ERR_INVALID_ARG, "walkable height must be 0..1000 m (got %g)",
                  desc->walkable_height);
    VDBGI_FAIL_IF(ctx, desc->keep_box_count > VDBGI_MAX_KEEP_BOXES, VDBGI_ERR_INVALID_ARG,
                  "at most %d keep boxes (got %zu)", VDBGI_MAX_KEEP_BOXES, desc->keep_box_count);
    VDBGI_FAIL_IF(ctx, desc->keep_box_count && !desc->keep_boxes, VDBGI_ERR_INVALID_ARG,
                  "%zu keep boxes counted and none given", desc->keep_box_count);
    for (size_t b = 0; b < desc->keep_box_count; b++)
        for (int k = 0; k < 3; k++)
            VDBGI_FAIL_IF(ctx,
                          !isfinite(desc->keep_boxes[b][k]) ||
                              !isfinite(desc->keep_boxes[b][3 + k]) ||
                              desc->keep_boxes[b][k] > desc->keep_boxes[b][3 + k],
                          VDBGI_ERR_INVALID_ARG,
                          "keep box %zu must be finite, its min no greater than its max on %c",
                          b + 1, "xyz"[k]);
    /* Probe indices stay within VDBGI_MAX_INDEX, as every reader of a .vdb demands. */
    for (int k = 0; k < 3; k++) {
        const double lo = (scene->bounds_min[k] - margin - origin[k]) / spacing;
        const double hi = (scene->bounds_max[k] + margin - origin[k]) / spacing;
        VDBGI_FAIL_IF(ctx, lo < -VDBGI_MAX_INDEX || hi > VDBGI_MAX_INDEX, VDBGI_ERR_INVALID_ARG,
                      "the scene reaches %g..%g m on %c: at spacing %g m its probes would be "
                      "numbered beyond +-%d",
                      (double)scene->bounds_min[k], (double)scene->bounds_max[k], "xyz"[k], spacing,
                      VDBGI_MAX_INDEX);
    }
    /* Refuse early, before OpenVDB spends the memory finding out exactly. */
    const double estimate = estimate_probe_count(scene, spacing, margin);
    VDBGI_FAIL_IF(ctx, estimate > 2.0 * (double)max_probes, VDBGI_ERR_OUT_OF_MEMORY,
                  "lattice would hold about %.0f probes (%.1f GiB) at spacing %g m, above the "
                  "limit of %llu",
                  estimate, estimate * VDBGI_BYTES_PER_PROBE / (1 << 30), spacing,
                  (unsigned long long)max_probes);

    vdbgi_probes *p = NULL;
    VDBGI_TRY(vdbgi_probes_alloc(ctx, 0, false, &p));
    p->spacing = spacing;
    p->margin = margin;
    memcpy(p->origin, origin, sizeof(origin));
    /* A tile places only its slab, from the triangles that can reach it. */
    const uint32_t *indices = scene->indices;
    size_t triangles = scene->triangle_count;
    uint32_t *subset = NULL;
    vdbgi_result r = VDBGI_OK;
    if (tiles > 1) {
        r = tile_slab(ctx, scene, origin, spacing, margin, desc->tile_index, tiles, p->tile_x,
                      p->tile_span);
        if (r == VDBGI_OK)
            r = tile_triangles(ctx, scene, origin, spacing, margin, p->tile_x, &subset, &triangles);
        indices = subset;
        p->tile_index = desc->tile_index;
        p->tile_count = tiles;
    }
    if (r == VDBGI_OK && triangles) {
        vdbgi_band_desc band = {
            .positions = scene->positions,
            .indices = indices,
            .triangle_count = triangles,
            .spacing = spacing,
            .margin = margin,
            .x_range = {tiles > 1 ? p->tile_x[0] : INT64_MIN, tiles > 1 ? p->tile_x[1] : INT64_MAX},
            .max_count = max_probes};
        memcpy(band.origin, origin, sizeof(origin));
        r = vdbgi_band_points(ctx, &band, &p->ijk, &p->count);
    }
    vdbgi_free(ctx, subset);
    const size_t near = p->count;
    if (r == VDBGI_OK && near)
        r = vdbgi_probes_keep(ctx, scene, desc, p);
    if (r == VDBGI_OK && near && p->count == 0)
        r = vdbgi_fail(ctx, VDBGI_ERR_INVALID_ARG,
                       "none of the %zu probes near surfaces%s stands %s", near,
                       tiles > 1 ? " in this tile" : "",
                       desc->walkable_height > 0.0 ? "over a walkable surface or in a keep box"
                                                   : "in a keep box");
    if (r == VDBGI_OK && tiles > 1 && p->count == 0)
        r = vdbgi_fail(ctx, VDBGI_ERR_INVALID_ARG,
                       "tile %d of %d (lattice i %d..%d) would hold no probe: use fewer tiles",
                       desc->tile_index + 1, tiles, p->tile_x[0], p->tile_x[1] - 1);
    if (r == VDBGI_OK && p->count == 0)
        r = vdbgi_fail(ctx, VDBGI_ERR_INVALID_ARG,
                       "no lattice point lies within the %g m margin of a surface", margin);
    if (r != VDBGI_OK) {
        vdbgi_probes_destroy(p);
        return r;
    }
    *out = p;
    return VDBGI_OK;
}
