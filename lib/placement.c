/* placement.c: the probe lattice (origin, spacing) and which probes exist near the surfaces. */
#include "probes.h"
#include "scene.h"
#include "vdb_shim.h"

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

/*
 * Keep tile t of n of p's probes (in their order): slabs across i, cut at
 * leaf boundaries (multiples of 8): each leaf column goes to the tile in
 * whose n-th of the probes, counted along x, its middle probe falls.
 */
static vdbgi_result keep_tile(vdbgi_context *ctx, vdbgi_probes *p, int t, int n)
{
    int32_t lo = INT32_MAX, hi = INT32_MIN;
    for (size_t i = 0; i < p->count; i++) {
        const int32_t c = vdbgi_floor_div(p->ijk[3 * i], 8);
        lo = c < lo ? c : lo;
        hi = c > hi ? c : hi;
    }
    const size_t columns = (size_t)(hi - lo) + 1;
    size_t *const count = vdbgi_calloc(ctx, columns + 1, sizeof(size_t));
    if (!count)
        return VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; i < p->count; i++)
        count[vdbgi_floor_div(p->ijk[3 * i], 8) - lo]++;
    /* Tile t takes the columns whose middle probe, counted along x, falls in its n-th. */
    size_t before = 0;
    int32_t first = INT32_MAX, last = INT32_MIN;
    for (size_t c = 0; c < columns; c++) {
        const size_t share = (2 * before + count[c]) * (size_t)n / (2 * p->count);
        if ((int)share == t) {
            first = (int32_t)c < first ? (int32_t)c : first;
            last = (int32_t)c;
        }
        before += count[c];
    }
    vdbgi_free(ctx, count);
    VDBGI_FAIL_IF(ctx, first > last, VDBGI_ERR_INVALID_ARG,
                  "tile %d of %d would hold no probe: the lattice has %zu leaf columns across x",
                  t + 1, n, columns);
    p->tile_x[0] = (lo + first) * 8;
    p->tile_x[1] = (lo + last + 1) * 8;
    size_t kept = 0;
    for (size_t i = 0; i < p->count; i++)
        if (p->ijk[3 * i] >= p->tile_x[0] && p->ijk[3 * i] < p->tile_x[1]) {
            memmove(&p->ijk[3 * kept], &p->ijk[3 * i], 3 * sizeof(int32_t));
            kept++;
        }
    p->lattice_count = p->count;
    p->count = kept;
    p->tile_index = t;
    p->tile_count = n;
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
    const double margin = desc->margin == 0.0          ? 4.0 * spacing
                          : desc->margin == VDBGI_ZERO ? 0.0
                                                       : desc->margin;
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
    double origin[3];
    for (int k = 0; k < 3; k++) {
        origin[k] = desc->origin_is_set ? desc->origin[k] : 0.5 * spacing;
        VDBGI_FAIL_IF(ctx, !isfinite(origin[k]), VDBGI_ERR_INVALID_ARG,
                      "lattice origin must be finite");
    }
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
    vdbgi_result r = vdbgi_vdb_topology(ctx, scene->positions, scene->vertex_count, scene->indices,
                                        scene->triangle_count, origin, spacing, margin, max_probes,
                                        &p->ijk, &p->count);
    if (r == VDBGI_OK && p->count == 0)
        r = vdbgi_fail(ctx, VDBGI_ERR_INVALID_ARG,
                       "no lattice point lies within the %g m margin of a surface", margin);
    if (r == VDBGI_OK && tiles > 1)
        r = keep_tile(ctx, p, desc->tile_index, tiles);
    if (r != VDBGI_OK) {
        vdbgi_probes_destroy(p);
        return r;
    }
    *out = p;
    return VDBGI_OK;
}
