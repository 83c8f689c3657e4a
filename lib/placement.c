/* placement.c: the probe lattice (origin, spacing) and which probes exist. */
#include "internal.h"
#include "vdb_shim.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

vdbgi_result vdbgi_probes_alloc(vdbgi_context *ctx, size_t count, bool with_values,
                                vdbgi_probes **out)
{
    *out = NULL;
    vdbgi_probes *const p = vdbgi_calloc(ctx, 1, sizeof(*p));
    if (!p)
        return VDBGI_ERR_OUT_OF_MEMORY;
    p->ctx = ctx;
    p->count = count;
    p->invalid_threshold = 0.25f;
    if (with_values) {
        p->ijk = vdbgi_calloc(ctx, count ? count : 1, 3 * sizeof(int32_t));
        p->rgb = vdbgi_calloc(ctx, count ? count : 1, 3 * sizeof(float));
        p->backface = vdbgi_calloc(ctx, count ? count : 1, sizeof(float));
        if (!p->ijk || !p->rgb || !p->backface) {
            vdbgi_probes_destroy(p);
            return VDBGI_ERR_OUT_OF_MEMORY;
        }
    }
    *out = p;
    return VDBGI_OK;
}

void vdbgi_probes_destroy(vdbgi_probes *p)
{
    if (!p)
        return;
    vdbgi_free(p->ctx, p->ijk);
    vdbgi_free(p->ctx, p->rgb);
    vdbgi_free(p->ctx, p->backface);
    vdbgi_free(p->ctx, p->cube);
    vdbgi_free(p->ctx, p->stderr_);
    vdbgi_free(p->ctx, p->rays);
    vdbgi_free(p->ctx, p);
}

/* Upper bound on the probes within margin of the triangles: area x band / spacing^3. */
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
    const double margin = desc->margin == 0.0 ? 4.0 * spacing
                          : desc->margin == VDBGI_MARGIN_ZERO ? 0.0
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
    /* The lattice index is int32: the scene must fit inside it. */
    for (int k = 0; k < 3; k++) {
        const double lo = (scene->bounds_min[k] - margin - origin[k]) / spacing;
        const double hi = (scene->bounds_max[k] + margin - origin[k]) / spacing;
        VDBGI_FAIL_IF(ctx, lo < -1e9 || hi > 1e9, VDBGI_ERR_INVALID_ARG,
                      "spacing %g m is too small for a scene %g m across", spacing,
                      (double)(scene->bounds_max[k] - scene->bounds_min[k]));
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
    vdbgi_result r =
        vdbgi_vdb_topology(ctx, scene->positions, scene->vertex_count, scene->indices,
                           scene->triangle_count, origin, spacing, margin, max_probes, &p->ijk,
                           &p->count);
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

static vdbgi_result write_vdb(vdbgi_context *ctx, const char *tmp, const void *probes)
{
    return vdbgi_vdb_write(ctx, tmp, probes);
}

vdbgi_result vdbgi_probes_write(const vdbgi_probes *p, const char *path)
{
    VDBGI_FAIL_IF(p->ctx, !p->rgb, VDBGI_ERR_INVALID_ARG, "probes have no values: bake them first");
    return vdbgi_write_atomic(p->ctx, path, write_vdb, p);
}

vdbgi_result vdbgi_probes_read(vdbgi_context *ctx, const char *path, vdbgi_probes **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_FAIL_IF(ctx, !path || !*path, VDBGI_ERR_INVALID_ARG, "no input path given");
    FILE *const f = fopen(path, "rb");
    VDBGI_FAIL_IF(ctx, !f, VDBGI_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    fclose(f);
    vdbgi_probes *p = NULL;
    VDBGI_TRY(vdbgi_vdb_read(ctx, path, &p));
    if (p->count == 0) {
        vdbgi_probes_destroy(p);
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid 'irradiance' holds no probes", path);
    }
    const vdbgi_meta *m = vdbgi_meta_find(p, "invalid_threshold");
    if (m && m->type == VDBGI_META_DOUBLE)
        p->invalid_threshold = (float)m->d;
    m = vdbgi_meta_find(p, "margin");
    if (m && m->type == VDBGI_META_DOUBLE)
        p->margin = m->d;
    for (size_t i = 0; i < p->count; i++)
        p->invalid_count += p->backface[i] > p->invalid_threshold;
    *out = p;
    return VDBGI_OK;
}

void vdbgi_probes_get_info(const vdbgi_probes *p, vdbgi_probes_info *info)
{
    memset(info, 0, sizeof(*info));
    info->probe_count = p->count;
    info->invalid_count = p->invalid_count;
    info->spacing = p->spacing;
    info->margin = p->margin;
    memcpy(info->origin, p->origin, sizeof(info->origin));
    info->invalid_threshold = p->invalid_threshold;
    info->baked = p->rgb != NULL;
    info->basis = p->cube ? VDBGI_BASIS_AMBIENT_CUBE : VDBGI_BASIS_SCALAR;
    for (int k = 0; k < 3; k++) {
        info->ijk_min[k] = p->count ? INT32_MAX : 0;
        info->ijk_max[k] = p->count ? INT32_MIN : 0;
    }
    for (size_t n = 0; n < p->count; n++)
        for (int k = 0; k < 3; k++) {
            const int32_t c = p->ijk[3 * n + k];
            info->ijk_min[k] = c < info->ijk_min[k] ? c : info->ijk_min[k];
            info->ijk_max[k] = c > info->ijk_max[k] ? c : info->ijk_max[k];
        }
}

vdbgi_result vdbgi_probes_get(const vdbgi_probes *p, size_t index, int32_t ijk[3], float rgb[3],
                              float *backface)
{
    VDBGI_FAIL_IF(p->ctx, index >= p->count, VDBGI_ERR_INVALID_ARG,
                  "probe index %zu out of range (%zu probes)", index, p->count);
    if (ijk)
        memcpy(ijk, &p->ijk[3 * index], 3 * sizeof(int32_t));
    if (rgb)
        for (int k = 0; k < 3; k++)
            rgb[k] = p->rgb ? p->rgb[3 * index + k] : 0.0f;
    if (backface)
        *backface = p->backface ? p->backface[index] : 0.0f;
    return VDBGI_OK;
}

vdbgi_result vdbgi_probes_get_noise(const vdbgi_probes *p, size_t index, float *stderr_out,
                                    uint32_t *rays_out)
{
    VDBGI_FAIL_IF(p->ctx, index >= p->count, VDBGI_ERR_INVALID_ARG,
                  "probe index %zu out of range (%zu probes)", index, p->count);
    const vdbgi_meta *const m = vdbgi_meta_find(p, "rays");
    if (stderr_out)
        *stderr_out = p->stderr_ ? p->stderr_[index] : 0.0f;
    if (rays_out)
        *rays_out = p->rays ? p->rays[index]
                            : (m && m->type == VDBGI_META_INT && m->i > 0 ? (uint32_t)m->i : 0);
    return VDBGI_OK;
}

vdbgi_result vdbgi_probes_get_cube(const vdbgi_probes *p, size_t index, float cube[6][3])
{
    VDBGI_FAIL_IF(p->ctx, index >= p->count, VDBGI_ERR_INVALID_ARG,
                  "probe index %zu out of range (%zu probes)", index, p->count);
    VDBGI_FAIL_IF(p->ctx, !p->cube, VDBGI_ERR_INVALID_ARG,
                  "probes have no ambient cubes: bake with the ambient-cube basis");
    memcpy(cube, &p->cube[18 * index], 18 * sizeof(float));
    return VDBGI_OK;
}

vdbgi_result vdbgi_probes_sample(const vdbgi_probes *p, const float pos[3], float rgb[3])
{
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    VDBGI_FAIL_IF(p->ctx, !p->rgb, VDBGI_ERR_INVALID_ARG, "probes have no values");
    double t[3], fr[3];
    int32_t i0[3];
    for (int k = 0; k < 3; k++) {
        t[k] = ((double)pos[k] - p->origin[k]) / p->spacing;
        VDBGI_FAIL_IF(p->ctx, !(fabs(t[k]) < 2e9), VDBGI_ERR_INVALID_ARG,
                      "position is outside the lattice");
        i0[k] = (int32_t)floor(t[k]);
        fr[k] = t[k] - i0[k];
    }
    double acc[3] = {0.0, 0.0, 0.0}, wsum = 0.0;
    for (size_t n = 0; n < p->count; n++) {
        const int32_t *const c = &p->ijk[3 * n];
        const int32_t d[3] = {c[0] - i0[0], c[1] - i0[1], c[2] - i0[2]};
        if ((d[0] | d[1] | d[2]) & ~1 || p->backface[n] > p->invalid_threshold)
            continue; /* not one of the eight corners, or not to be trusted */
        const double w = (d[0] ? fr[0] : 1.0 - fr[0]) * (d[1] ? fr[1] : 1.0 - fr[1]) *
                         (d[2] ? fr[2] : 1.0 - fr[2]);
        for (int k = 0; k < 3; k++)
            acc[k] += w * p->rgb[3 * n + k];
        wsum += w;
    }
    VDBGI_FAIL_IF(p->ctx, !(wsum > 0.0), VDBGI_ERR_INVALID_ARG,
                  "no valid probe around (%g, %g, %g)", (double)pos[0], (double)pos[1],
                  (double)pos[2]);
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)(acc[k] / wsum);
    return VDBGI_OK;
}

/* ---- metadata ------------------------------------------------------------ */

static vdbgi_meta *meta_slot(vdbgi_probes *p, const char *name, vdbgi_meta_type type)
{
    vdbgi_meta *m = NULL;
    for (size_t i = 0; i < p->meta_count && !m; i++)
        if (strcmp(p->meta[i].name, name) == 0)
            m = &p->meta[i];
    if (!m) {
        if (p->meta_count == VDBGI_META_CAPACITY)
            return NULL; /* ours fit; a foreign file's extras are dropped */
        m = &p->meta[p->meta_count++];
        memset(m, 0, sizeof(*m));
        snprintf(m->name, sizeof(m->name), "%s", name);
    }
    m->type = type;
    return m;
}

void vdbgi_meta_set_string(vdbgi_probes *p, const char *name, const char *value)
{
    vdbgi_meta *const m = meta_slot(p, name, VDBGI_META_STRING);
    if (m) {
        snprintf(m->text, sizeof(m->text), "%s", value);
        snprintf(m->line, sizeof(m->line), "%s=%s", m->name, m->text);
    }
}

void vdbgi_meta_set_int(vdbgi_probes *p, const char *name, int64_t value)
{
    vdbgi_meta *const m = meta_slot(p, name, VDBGI_META_INT);
    if (m) {
        m->i = value;
        snprintf(m->line, sizeof(m->line), "%s=%lld", m->name, (long long)value);
    }
}

void vdbgi_meta_set_double(vdbgi_probes *p, const char *name, double value)
{
    vdbgi_meta *const m = meta_slot(p, name, VDBGI_META_DOUBLE);
    if (m) {
        m->d = value;
        snprintf(m->line, sizeof(m->line), "%s=%.9g", m->name, value);
    }
}

void vdbgi_meta_set_vec3(vdbgi_probes *p, const char *name, const float value[3])
{
    vdbgi_meta *const m = meta_slot(p, name, VDBGI_META_VEC3);
    if (m) {
        memcpy(m->v, value, sizeof(m->v));
        snprintf(m->line, sizeof(m->line), "%s=%.9g,%.9g,%.9g", m->name, (double)value[0],
                 (double)value[1], (double)value[2]);
    }
}

const vdbgi_meta *vdbgi_meta_find(const vdbgi_probes *p, const char *name)
{
    for (size_t i = 0; i < p->meta_count; i++)
        if (strcmp(p->meta[i].name, name) == 0)
            return &p->meta[i];
    return NULL;
}

const char *vdbgi_probes_metadata(const vdbgi_probes *p, size_t index)
{
    return index < p->meta_count ? p->meta[index].line : NULL;
}
