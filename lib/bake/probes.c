/* probes.c: the probe object: its arrays, its file, its lookups and its metadata lines. */
#include "probes.h"
#include "estimate.h"
#include "map.h"
#include "util.h"
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
    vdbgi_free(p->ctx, p->sh);
    vdbgi_free(p->ctx, p->stderr_);
    vdbgi_free(p->ctx, p->rays);
    vdbgi_free(p->ctx, p);
}

/* What write_vdb writes, and the name its messages give. */
typedef struct vdb_job {
    const vdbgi_probes *probes;
    const char *path; /* for messages: the name the user gave */
} vdb_job;

static vdbgi_result write_vdb(vdbgi_context *ctx, const char *tmp, const void *user)
{
    const vdb_job *const job = user;
    const vdbgi_probes *const p = job->probes;
    const vdbgi_vdb_arrays arrays = {.spacing = p->spacing,
                                     .origin = {p->origin[0], p->origin[1], p->origin[2]},
                                     .count = p->count,
                                     .ijk = p->ijk,
                                     .rgb = p->rgb,
                                     .backface = p->backface,
                                     .stderr_ = p->stderr_,
                                     .rays = p->rays,
                                     .cube = p->cube,
                                     .sh = p->sh};
    return vdbgi_vdb_write(ctx, tmp, job->path, &arrays, &p->meta);
}

vdbgi_result vdbgi_probes_write(const vdbgi_probes *p, const char *path)
{
    VDBGI_FAIL_IF(p->ctx, !p->rgb, VDBGI_ERR_INVALID_ARG, "probes have no values: bake them first");
    const vdb_job job = {p, path};
    return vdbgi_write_atomic(p->ctx, path, write_vdb, &job);
}

/* The probes object the .vdb reader's values go into, made when it knows their count. */
typedef struct read_target {
    vdbgi_context *ctx;
    vdbgi_probes *p;
} read_target;

static vdbgi_result make_probes(vdbgi_vdb_arrays *sink, size_t count, bool with_stderr,
                                bool with_rays, bool with_cube, bool with_sh)
{
    read_target *const t = sink->user;
    VDBGI_TRY(vdbgi_probes_alloc(t->ctx, count, true, &t->p));
    vdbgi_probes *const p = t->p;
    const size_t n = count ? count : 1;
    if ((with_stderr && !(p->stderr_ = vdbgi_calloc(t->ctx, n, sizeof(float)))) ||
        (with_rays && !(p->rays = vdbgi_calloc(t->ctx, n, sizeof(uint32_t)))) ||
        (with_cube && !(p->cube = vdbgi_calloc(t->ctx, n, 18 * sizeof(float)))) ||
        (with_sh && !(p->sh = vdbgi_calloc(t->ctx, n, 24 * sizeof(uint16_t)))))
        return VDBGI_ERR_OUT_OF_MEMORY;
    sink->ijk = p->ijk, sink->rgb = p->rgb, sink->backface = p->backface;
    sink->stderr_ = p->stderr_, sink->rays = p->rays, sink->cube = p->cube, sink->sh = p->sh;
    sink->meta = &p->meta;
    return VDBGI_OK;
}

/*
 * The probes a read put into target, parsed and checked (settings from the
 * metadata, values in range) into *out; r is the read's result. A region of
 * a file (whole false) may hold none.
 */
static vdbgi_result take_read(vdbgi_context *ctx, const char *path, vdbgi_result r,
                              read_target *target, const vdbgi_vdb_arrays *sink, bool whole,
                              vdbgi_probes **out)
{
    vdbgi_probes *const p = target->p;
    if (r != VDBGI_OK) {
        vdbgi_probes_destroy(p);
        return r;
    }
    p->count = sink->count;
    p->spacing = sink->spacing;
    memcpy(p->origin, sink->origin, sizeof(p->origin));
    if (p->count == 0 && whole) {
        vdbgi_probes_destroy(p);
        return vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid 'irradiance' holds no probes", path);
    }
    const vdbgi_meta *m = vdbgi_meta_find(&p->meta, "invalid_threshold");
    if (m && m->type == VDBGI_META_DOUBLE)
        p->invalid_threshold = (float)m->d;
    m = vdbgi_meta_find(&p->meta, "margin");
    if (m && m->type == VDBGI_META_DOUBLE)
        p->margin = m->d;
    /* The settings are parsed here, once; nothing after compares their text. */
    m = vdbgi_meta_find(&p->meta, "sampling");
    p->sampling = m && m->type == VDBGI_META_STRING && strcmp(m->text, "random") == 0
                      ? VDBGI_SAMPLING_RANDOM
                      : VDBGI_SAMPLING_FIBONACCI;
    m = vdbgi_meta_find(&p->meta, "rays");
    p->adaptive = m && m->type == VDBGI_META_INT && m->i == VDBGI_META_RAYS_ADAPTIVE;
    if (!vdbgi_meta_find(&p->meta, "sampling"))
        p->sampling = VDBGI_SAMPLING_RANDOM; /* not ours: assume independent noise */
    /* What OpenVDB reads as any float: irradiance is finite and >= 0, validity a fraction. */
    for (size_t i = 0; i < p->count; i++) {
        const float *const c = &p->rgb[3 * i];
        const float *const q = p->cube ? &p->cube[18 * i] : c;
        bool ok = p->backface[i] >= 0.0f && p->backface[i] <= 1.0f;
        for (int k = 0; k < (p->cube ? 18 : 3); k++)
            ok = ok && q[k] >= 0.0f && isfinite(q[k]);
        for (int k = 0; k < 3; k++)
            ok = ok && c[k] >= 0.0f && isfinite(c[k]);
        const int32_t *const ijk = &p->ijk[3 * i];
        if (!ok) {
            vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                       "%s: probe %d,%d,%d holds a negative or non-finite value (%g,%g,%g, "
                       "validity %g)",
                       path, ijk[0], ijk[1], ijk[2], (double)c[0], (double)c[1], (double)c[2],
                       (double)p->backface[i]);
            vdbgi_probes_destroy(p);
            return VDBGI_ERR_FORMAT;
        }
        /* The L2 terms are signed, but no light that is nowhere negative gives one beyond
           twice its L0 (vdbgi_term_encode held the ratio, or told what it could not hold;
           L0 is checked first, as the ratios are to it). */
        int bad_term = 0;
        bool nan_term = false;
        for (int k = 0; p->sh && k < 24 && !bad_term; k++) {
            const float ratio = vdbgi_term_decode(p->sh[24 * i + k], 1.0f);
            bad_term = isfinite(ratio) ? 0 : 1 + k / 3;
            nan_term = isnan(ratio);
        }
        if (bad_term) {
            vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: probe %d,%d,%d: L2 term %d is %s", path, ijk[0],
                       ijk[1], ijk[2], bad_term,
                       nan_term ? "not finite"
                                : "more than 4 times its L0, which no non-negative light gives");
            vdbgi_probes_destroy(p);
            return VDBGI_ERR_FORMAT;
        }
        p->invalid_count += p->backface[i] > p->invalid_threshold;
    }
    *out = p;
    return VDBGI_OK;
}

vdbgi_result vdbgi_probes_read(vdbgi_context *ctx, const char *path, vdbgi_probes **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_TRY(vdbgi_input_check(ctx, path));
    read_target target = {ctx, NULL};
    vdbgi_vdb_arrays sink = {.make = make_probes, .user = &target};
    const vdbgi_result r = vdbgi_vdb_read(ctx, path, &sink);
    return take_read(ctx, path, r, &target, &sink, true, out);
}

struct vdbgi_probe_file {
    vdbgi_context *ctx;
    vdbgi_vdb_regions *regions;
    int32_t lo[3], hi[3]; /* the irradiance grid's leaves */
    char path[];
};

vdbgi_result vdbgi_probe_file_open(vdbgi_context *ctx, const char *path, vdbgi_probe_file **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_TRY(vdbgi_input_check(ctx, path));
    vdbgi_probe_file *const f = vdbgi_calloc(ctx, 1, sizeof(*f) + strlen(path) + 1);
    if (!f)
        return VDBGI_ERR_OUT_OF_MEMORY;
    f->ctx = ctx;
    strcpy(f->path, path);
    const vdbgi_result r = vdbgi_vdb_regions_open(ctx, path, &f->regions, f->lo, f->hi);
    if (r == VDBGI_OK && f->lo[0] > f->hi[0])
        vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: grid 'irradiance' holds no probes", path);
    if (r != VDBGI_OK || f->lo[0] > f->hi[0]) {
        vdbgi_probe_file_close(f);
        return r != VDBGI_OK ? r : VDBGI_ERR_FORMAT;
    }
    *out = f;
    return VDBGI_OK;
}

void vdbgi_probe_file_extent(const vdbgi_probe_file *f, int32_t lo[3], int32_t hi[3])
{
    memcpy(lo, f->lo, sizeof(f->lo));
    memcpy(hi, f->hi, sizeof(f->hi));
}

vdbgi_result vdbgi_probe_file_read(vdbgi_probe_file *f, int32_t z0, int32_t z1, vdbgi_probes **out)
{
    VDBGI_FAIL_IF(f->ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_FAIL_IF(f->ctx, z0 >= z1, VDBGI_ERR_INVALID_ARG, "an empty z range (%d..%d)", z0, z1);
    read_target target = {f->ctx, NULL};
    vdbgi_vdb_arrays sink = {.make = make_probes, .user = &target};
    const vdbgi_result r = vdbgi_vdb_regions_read(f->regions, z0, z1, &sink);
    return take_read(f->ctx, f->path, r, &target, &sink, false, out);
}

void vdbgi_probe_file_close(vdbgi_probe_file *f)
{
    if (!f)
        return;
    vdbgi_vdb_regions_close(f->regions);
    vdbgi_free(f->ctx, f);
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
    info->basis = p->cube ? VDBGI_BASIS_AMBIENT_CUBE : p->sh ? VDBGI_BASIS_SH2 : VDBGI_BASIS_SCALAR;
    info->tile_index = p->tile_count > 1 ? p->tile_index : 0;
    info->tile_count = p->tile_count > 1 ? p->tile_count : 0;
    info->tile_x[0] = p->tile_count > 1 ? p->tile_x[0] : 0;
    info->tile_x[1] = p->tile_count > 1 ? p->tile_x[1] : 0;
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
    const vdbgi_meta *const m = vdbgi_meta_find(&p->meta, "rays");
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

const char *vdbgi_probes_metadata(const vdbgi_probes *p, size_t index)
{
    return index < p->meta.count ? p->meta.items[index].line : NULL;
}

size_t vdbgi_probes_copy(const vdbgi_probes *p, int32_t *ijk, float *rgb, float *backface,
                         size_t capacity)
{
    if (!ijk && !rgb && !backface)
        return p->count;
    if (capacity < p->count || ((rgb || backface) && !p->rgb))
        return 0;
    if (ijk)
        memcpy(ijk, p->ijk, p->count * 3 * sizeof(int32_t));
    if (rgb)
        memcpy(rgb, p->rgb, p->count * 3 * sizeof(float));
    if (backface)
        memcpy(backface, p->backface, p->count * sizeof(float));
    return p->count;
}

vdbgi_result vdbgi_probes_get_sh2(const vdbgi_probes *p, size_t index, float sh[VDBGI_SH2_TERMS][3])
{
    VDBGI_FAIL_IF(p->ctx, index >= p->count, VDBGI_ERR_INVALID_ARG,
                  "probe index %zu out of range (%zu probes)", index, p->count);
    VDBGI_FAIL_IF(p->ctx, !p->sh, VDBGI_ERR_INVALID_ARG,
                  "probes have no L2 terms: bake with the sh2 basis");
    memcpy(sh[0], &p->rgb[3 * index], 3 * sizeof(float));
    vdbgi_terms_decode(&p->sh[24 * index], &p->rgb[3 * index], sh[1]);
    return VDBGI_OK;
}

void vdbgi_sh2_eval(const float sh[VDBGI_SH2_TERMS][3], const float n[3], float rgb[3])
{
    float t[8];
    vdbgi_sh2_terms(n, t);
    for (int k = 0; k < 3; k++) {
        float e = sh[0][k];
        for (int i = 0; i < 8; i++)
            e += sh[i + 1][k] * t[i];
        rgb[k] = e > 0.0f ? e : 0.0f;
    }
}

/* An ambient cube's E / pi for unit normal n: each axis's facing side, weighted by n_a^2. */
static void cube_eval(const float cube[18], const float n[3], float rgb[3])
{
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    for (int a = 0; a < 3; a++) {
        const float *const side = &cube[3 * (2 * a + (n[a] < 0.0f))];
        for (int k = 0; k < 3; k++)
            rgb[k] += n[a] * n[a] * side[k];
    }
}

/* Probe p's basis terms, c0 first: 3, 3 + 18 (cube) or 3 + 24 (L2) floats. */
static int gather_terms(const vdbgi_probes *p, size_t i, float *out)
{
    memcpy(out, &p->rgb[3 * i], 3 * sizeof(float));
    if (p->cube) {
        memcpy(&out[3], &p->cube[18 * i], 18 * sizeof(float));
        return 21;
    }
    if (p->sh) {
        vdbgi_terms_decode(&p->sh[24 * i], &p->rgb[3 * i], &out[3]);
        return 27;
    }
    return 3;
}

/* One point of vdbgi_probes_sample_points: false when none of its eight probes is valid. */
static bool sample_one(const vdbgi_probes *p, const vdbgi_map *index, const float pos[3],
                       const float *normal, float bias, float rgb[3])
{
    double fr[3], at[3];
    int32_t i0[3];
    for (int k = 0; k < 3; k++) {
        at[k] = (double)pos[k] + (normal ? (double)bias * normal[k] : 0.0);
        const double t = (at[k] - p->origin[k]) / p->spacing;
        if (!(fabs(t) < VDBGI_MAX_INDEX))
            return false;
        i0[k] = (int32_t)floor(t);
        fr[k] = t - i0[k];
    }
    double acc[27] = {0.0}, wsum = 0.0;
    int terms = 3;
    for (int c = 0; c < 8; c++) {
        const int32_t ijk[3] = {i0[0] + (c & 1), i0[1] + (c >> 1 & 1), i0[2] + (c >> 2)};
        const long n = vdbgi_map_find(index, ijk);
        if (n < 0 || p->backface[n] > p->invalid_threshold)
            continue;
        double w = (c & 1 ? fr[0] : 1.0 - fr[0]) * (c >> 1 & 1 ? fr[1] : 1.0 - fr[1]) *
                   (c >> 2 ? fr[2] : 1.0 - fr[2]);
        if (normal && bias > 0.0f) {
            /* A probe behind the surface sees the other side of it: weigh it down (DDGI's
               backface weight), never to nothing, so a point between probes still reads. */
            double d[3], len = 1e-12, facing = 0.0;
            for (int k = 0; k < 3; k++) {
                d[k] = p->origin[k] + p->spacing * ijk[k] - at[k];
                len += d[k] * d[k];
            }
            for (int k = 0; k < 3; k++)
                facing += d[k] * normal[k];
            const double half = 0.5 * (facing / sqrt(len) + 1.0);
            w *= half * half + 0.05;
        }
        float v[27];
        terms = gather_terms(p, (size_t)n, v);
        for (int t = 0; t < terms; t++)
            acc[t] += w * v[t];
        wsum += w;
    }
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    if (!(wsum > 0.0))
        return false;
    float v[27];
    for (int t = 0; t < terms; t++)
        v[t] = (float)(acc[t] / wsum);
    if (normal && terms == 21)
        cube_eval(&v[3], normal, rgb);
    else if (normal && terms == 27)
        vdbgi_sh2_eval((const float(*)[3])v, normal, rgb);
    else
        memcpy(rgb, v, 3 * sizeof(float));
    return true;
}

vdbgi_result vdbgi_probes_sample_points(const vdbgi_probes *p, size_t count, const float *pos,
                                        const float *normals, float normal_bias, float *rgb,
                                        unsigned char *valid)
{
    VDBGI_FAIL_IF(p->ctx, !p->rgb, VDBGI_ERR_INVALID_ARG, "probes have no values");
    VDBGI_FAIL_IF(p->ctx, count && (!pos || !rgb), VDBGI_ERR_INVALID_ARG,
                  "no positions or output given");
    VDBGI_FAIL_IF(p->ctx, !(fabsf(normal_bias) <= 4.0f * (float)p->spacing), VDBGI_ERR_INVALID_ARG,
                  "normal bias must be within 4 spacings (got %g m)", (double)normal_bias);
    vdbgi_map index;
    VDBGI_TRY(vdbgi_map_init(p->ctx, &index, p->count));
    vdbgi_result r = VDBGI_OK;
    for (size_t i = 0; r == VDBGI_OK && i < p->count; i++) {
        size_t at;
        bool added;
        r = vdbgi_map_insert(&index, &p->ijk[3 * i], &at, &added);
        if (r == VDBGI_OK && !added) /* the lookup numbers probes by first insertion */
            r = vdbgi_fail(p->ctx, VDBGI_ERR_INVALID_ARG, "probe %zu repeats a lattice point", i);
    }
    for (size_t i = 0; r == VDBGI_OK && i < count; i++) {
        const bool ok = sample_one(p, &index, &pos[3 * i], normals ? &normals[3 * i] : NULL,
                                   normal_bias, &rgb[3 * i]);
        if (valid)
            valid[i] = ok;
    }
    vdbgi_map_free(&index);
    return r;
}
