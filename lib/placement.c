/* placement.c: the probe lattice (origin, spacing) and which probes exist near the surfaces. */
#include "probes.h"
#include "scene.h"
#include "vdb_shim.h"

#include <math.h>
#include <string.h>

static double estimate_probe_count(const vdbgi_scene *s, double spacing, double margin)
{
    double area = 0.0;
    for (size_t t = 0; t < s->triangle_count; t++) {
        area += vdbgi_scene_triangle_area(s, t);
    }
    return area * (2.0 * margin + spacing) / (spacing * spacing * spacing);
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
    if (r != VDBGI_OK) {
        vdbgi_probes_destroy(p);
        return r;
    }
    *out = p;
    return VDBGI_OK;
}
