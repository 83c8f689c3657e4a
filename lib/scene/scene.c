/* scene.c: the triangle soup: building it, albedo at a hit, points on its surfaces. */
#include "scene.h"
#include "util.h"
#include "vdbgi_bench.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void scene_free_arrays(vdbgi_scene *s)
{
    vdbgi_context *const ctx = s->ctx;
    vdbgi_free(ctx, s->positions);
    vdbgi_free(ctx, s->uvs);
    vdbgi_free(ctx, s->uvs1);
    vdbgi_free(ctx, s->colors);
    vdbgi_free(ctx, s->indices);
    vdbgi_free(ctx, s->tris);
    vdbgi_free(ctx, s->materials);
    for (size_t i = 0; s->textures && i < s->texture_count; i++)
        vdbgi_free(ctx, s->textures[i].rgba);
    vdbgi_free(ctx, s->textures);
    vdbgi_free(ctx, s->name);
}

void vdbgi_scene_destroy(vdbgi_scene *scene)
{
    if (!scene)
        return;
    scene_free_arrays(scene);
    vdbgi_free(scene->ctx, scene);
}

vdbgi_result vdbgi_scene_alloc(vdbgi_context *ctx, const char *name, size_t vertex_count,
                               size_t triangle_capacity, size_t material_count,
                               size_t texture_count, vdbgi_scene **out)
{
    *out = NULL;
    vdbgi_scene *const s = vdbgi_calloc(ctx, 1, sizeof(*s));
    if (!s)
        return VDBGI_ERR_OUT_OF_MEMORY;
    s->ctx = ctx;
    s->vertex_count = vertex_count;
    s->material_count = material_count;
    s->texture_count = texture_count;
    /* Embree reads vertices with 16-byte loads: one spare vertex keeps the last in bounds. */
    s->positions = vdbgi_calloc(ctx, vertex_count + 1, 3 * sizeof(float));
    s->uvs = vdbgi_calloc(ctx, vertex_count, 2 * sizeof(float));
    s->uvs1 = vdbgi_calloc(ctx, vertex_count ? vertex_count : 1, 2 * sizeof(float));
    s->colors = vdbgi_calloc(ctx, vertex_count, 3 * sizeof(float));
    s->indices = vdbgi_calloc(ctx, triangle_capacity, 3 * sizeof(uint32_t));
    s->tris = vdbgi_calloc(ctx, triangle_capacity, sizeof(vdbgi_tri));
    s->materials = vdbgi_calloc(ctx, material_count, sizeof(vdbgi_material));
    s->textures = vdbgi_calloc(ctx, texture_count, sizeof(vdbgi_texture));
    s->name = vdbgi_strdup(ctx, name);
    if (!s->positions || !s->uvs || !s->uvs1 || !s->colors || !s->indices || !s->tris ||
        !s->materials || !s->textures || !s->name) {
        vdbgi_scene_destroy(s);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    for (size_t i = 0; i < vertex_count * 3; i++)
        s->colors[i] = 1.0f;
    for (size_t m = 0; m < material_count; m++)
        s->materials[m].texture = s->materials[m].emissive_texture = -1;
    *out = s;
    return VDBGI_OK;
}

/* Append triangle (a, b, c) if it is finite and has area; returns what happened. */
vdbgi_tri_status vdbgi_scene_add_triangle(vdbgi_scene *s, uint32_t a, uint32_t b, uint32_t c,
                                          uint32_t material)
{
    const float *const p0 = &s->positions[3 * a];
    const float *const p1 = &s->positions[3 * b];
    const float *const p2 = &s->positions[3 * c];
    for (int k = 0; k < 3; k++) {
        if (!isfinite(p0[k]) || !isfinite(p1[k]) || !isfinite(p2[k]))
            return VDBGI_TRI_NONFINITE;
    }
    const float e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const float e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
    const float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0.0f) || !isfinite(len))
        return VDBGI_TRI_DEGENERATE;
    const size_t t = s->triangle_count++;
    s->indices[3 * t + 0] = a;
    s->indices[3 * t + 1] = b;
    s->indices[3 * t + 2] = c;
    for (int k = 0; k < 3; k++)
        s->tris[t].normal[k] = n[k] / len;
    s->tris[t].material = material;
    return VDBGI_TRI_KEPT;
}

/*
 * Most triangles have one albedo everywhere (no texture, equal vertex
 * colours): work it out once, so a hit on them costs one record read.
 */
static void classify_triangles(vdbgi_scene *s)
{
    for (size_t t = 0; t < s->triangle_count; t++) {
        vdbgi_tri *const tri = &s->tris[t];
        const vdbgi_material *const mat = &s->materials[tri->material];
        const float *const c0 = &s->colors[3 * s->indices[3 * t]];
        const float *const c1 = &s->colors[3 * s->indices[3 * t + 1]];
        const float *const c2 = &s->colors[3 * s->indices[3 * t + 2]];
        const bool varies = mat->texture >= 0 || memcmp(c0, c1, 3 * sizeof(float)) != 0 ||
                            memcmp(c0, c2, 3 * sizeof(float)) != 0;
        const bool emits =
            mat->emissive[0] > 0.0f || mat->emissive[1] > 0.0f || mat->emissive[2] > 0.0f;
        tri->flags = (mat->double_sided ? VDBGI_TRI_DOUBLE_SIDED : 0u) |
                     (varies ? VDBGI_TRI_VARIES : 0u) | (emits ? VDBGI_TRI_EMISSIVE : 0u);
        for (int k = 0; k < 3; k++)
            tri->albedo[k] = mat->base[k] * c0[k];
    }
}

vdbgi_result vdbgi_scene_finish(vdbgi_scene *s, size_t nonfinite_count)
{
    vdbgi_context *const ctx = s->ctx;
    if (nonfinite_count)
        vdbgi_log(ctx, VDBGI_LOG_WARNING, "%s: skipped %zu triangles with non-finite vertices",
                  s->name, nonfinite_count);
    VDBGI_FAIL_IF(ctx, s->triangle_count == 0, VDBGI_ERR_FORMAT,
                  "%s: no triangles to trace (%zu skipped as non-finite or zero-area)", s->name,
                  s->skipped_count);
    VDBGI_FAIL_IF(ctx, s->triangle_count > UINT32_MAX / 3, VDBGI_ERR_FORMAT,
                  "%s: %zu triangles is more than one scene can hold", s->name, s->triangle_count);
    float max_abs = 0.0f;
    for (int k = 0; k < 3; k++) {
        s->bounds_min[k] = INFINITY;
        s->bounds_max[k] = -INFINITY;
    }
    for (size_t t = 0; t < s->triangle_count * 3; t++) {
        const float *const p = &s->positions[3 * s->indices[t]];
        for (int k = 0; k < 3; k++) {
            s->bounds_min[k] = fminf(s->bounds_min[k], p[k]);
            s->bounds_max[k] = fmaxf(s->bounds_max[k], p[k]);
            max_abs = fmaxf(max_abs, fabsf(p[k]));
        }
    }
    s->ray_offset = VDBGI_RAY_OFFSET_REL * fmaxf(max_abs, VDBGI_RAY_OFFSET_MIN_MAGNITUDE);
    /* Offsets are local, but geometry 5 km out is coarse there (ulps of 0.5 mm): say so. */
    if (s->ray_offset > 0.05f)
        vdbgi_log(ctx, VDBGI_LOG_WARNING,
                  "%s: geometry reaches %g m from the origin, where rays leave surfaces up to "
                  "%g m off (1e-5 of the coordinates) and detail is lost: keep what matters "
                  "near the origin",
                  s->name, (double)max_abs, (double)s->ray_offset);
    classify_triangles(s);
    return VDBGI_OK;
}

vdbgi_result vdbgi_scene_create(vdbgi_context *ctx, const vdbgi_mesh_desc *meshes,
                                size_t mesh_count, vdbgi_scene **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_FAIL_IF(ctx, !meshes && mesh_count, VDBGI_ERR_INVALID_ARG, "no meshes given");
    size_t vertex_count = 0, triangle_count = 0;
    for (size_t m = 0; m < mesh_count; m++) {
        const vdbgi_mesh_desc *const d = &meshes[m];
        VDBGI_FAIL_IF(ctx, (d->vertex_count && !d->positions) || (d->triangle_count && !d->indices),
                      VDBGI_ERR_INVALID_ARG, "mesh %zu: missing positions or indices", m);
        for (size_t i = 0; i < d->triangle_count * 3; i++)
            VDBGI_FAIL_IF(ctx, d->indices[i] >= d->vertex_count, VDBGI_ERR_INVALID_ARG,
                          "mesh %zu: index %u out of range (%zu vertices)", m, d->indices[i],
                          d->vertex_count);
        for (int k = 0; k < 3; k++) {
            VDBGI_FAIL_IF(ctx, !(d->albedo[k] >= 0.0f && d->albedo[k] <= 1.0f),
                          VDBGI_ERR_INVALID_ARG, "mesh %zu: albedo must be in [0, 1] (got %g)", m,
                          (double)d->albedo[k]);
            VDBGI_FAIL_IF(ctx, !(d->emissive[k] >= 0.0f && d->emissive[k] <= VDBGI_MAX_EMISSION),
                          VDBGI_ERR_INVALID_ARG, "mesh %zu: emissive must be in [0, %g] (got %g)",
                          m, (double)VDBGI_MAX_EMISSION, (double)d->emissive[k]);
        }
        vertex_count += d->vertex_count;
        triangle_count += d->triangle_count;
    }
    VDBGI_FAIL_IF(ctx, vertex_count > UINT32_MAX, VDBGI_ERR_INVALID_ARG,
                  "%zu vertices is more than one scene can hold", vertex_count);
    vdbgi_scene *s = NULL;
    VDBGI_TRY(vdbgi_scene_alloc(ctx, "memory", vertex_count, triangle_count, mesh_count, 0, &s));
    size_t base = 0, nonfinite = 0;
    for (size_t m = 0; m < mesh_count; m++) {
        const vdbgi_mesh_desc *const d = &meshes[m];
        memcpy(&s->positions[3 * base], d->positions, d->vertex_count * 3 * sizeof(float));
        vdbgi_material *const mat = &s->materials[m];
        memcpy(mat->base, d->albedo, sizeof(mat->base));
        memcpy(mat->emissive, d->emissive, sizeof(mat->emissive));
        mat->texture = mat->emissive_texture = -1;
        mat->double_sided = d->double_sided != 0;
        for (size_t t = 0; t < d->triangle_count; t++) {
            const uint32_t *const i = &d->indices[3 * t];
            const vdbgi_tri_status st =
                vdbgi_scene_add_triangle(s, (uint32_t)base + i[0], (uint32_t)base + i[1],
                                         (uint32_t)base + i[2], (uint32_t)m);
            nonfinite += st == VDBGI_TRI_NONFINITE;
            s->skipped_count += st != VDBGI_TRI_KEPT;
        }
        base += d->vertex_count;
    }
    const vdbgi_result r = vdbgi_scene_finish(s, nonfinite);
    if (r != VDBGI_OK) {
        vdbgi_scene_destroy(s);
        return r;
    }
    *out = s;
    return VDBGI_OK;
}

/* ---- assimp ------------------------------------------------------------- */

void vdbgi_scene_get_info(const vdbgi_scene *scene, vdbgi_scene_info *info)
{
    memset(info, 0, sizeof(*info));
    info->triangle_count = scene->triangle_count;
    info->skipped_triangle_count = scene->skipped_count;
    info->material_count = scene->material_count;
    for (size_t i = 0; i < scene->texture_count; i++)
        info->texture_count += scene->textures[i].rgba != NULL;
    memcpy(info->bounds_min, scene->bounds_min, sizeof(info->bounds_min));
    memcpy(info->bounds_max, scene->bounds_max, sizeof(info->bounds_max));
    info->ray_offset = scene->ray_offset;
    info->name = scene->name;
    info->light_count = scene->light_count;
    info->keep_box_count = scene->keep_box_count;
    info->keep_node_count = scene->keep_node_count;
}

/* ---- punctual lights ------------------------------------------------------ */

static bool finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* Why light l cannot be added, or NULL. */
static const char *light_refusal(const vdbgi_light *l)
{
    if (l->type != VDBGI_LIGHT_DIRECTIONAL && l->type != VDBGI_LIGHT_POINT &&
        l->type != VDBGI_LIGHT_SPOT)
        return "an unknown type";
    for (int k = 0; k < 3; k++)
        if (!(l->color[k] >= 0.0f && l->color[k] <= VDBGI_MAX_EMISSION))
            return isnan(l->color[k])   ? "a colour or intensity that is not a number"
                   : l->color[k] < 0.0f ? "a negative colour or intensity"
                                        : "a colour times intensity above 1e6";
    if (!finite3(l->position) || !finite3(l->direction))
        return "a position or direction that is not finite";
    const float *const d = l->direction;
    if (l->type != VDBGI_LIGHT_POINT && !(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 0.0f))
        return "no direction";
    if (!(l->range >= 0.0f) || isinf(l->range))
        return "a range that is negative or not finite";
    if (l->type == VDBGI_LIGHT_SPOT) {
        if (!(l->inner_cone >= 0.0f && l->outer_cone <= 1.5707964f))
            return "cone angles outside 0..pi/2";
        if (!(l->outer_cone >= l->inner_cone))
            return "an outer cone angle below its inner one";
    }
    return NULL;
}

vdbgi_result vdbgi_scene_add_lights(vdbgi_scene *scene, const vdbgi_light *lights, size_t count)
{
    vdbgi_context *const ctx = scene->ctx;
    VDBGI_FAIL_IF(ctx, count && !lights, VDBGI_ERR_INVALID_ARG, "no lights given");
    VDBGI_FAIL_IF(ctx, count > VDBGI_MAX_LIGHTS - scene->light_count, VDBGI_ERR_INVALID_ARG,
                  "%zu lights: at most %d are traced", scene->light_count + count,
                  VDBGI_MAX_LIGHTS);
    for (size_t i = 0; i < count; i++) {
        const char *const why = light_refusal(&lights[i]);
        VDBGI_FAIL_IF(ctx, why, VDBGI_ERR_INVALID_ARG, "light %zu%s%.*s%s has %s", i,
                      lights[i].name[0] ? " (" : "", (int)sizeof(lights[i].name), lights[i].name,
                      lights[i].name[0] ? ")" : "", why);
    }
    for (size_t i = 0; i < count; i++) {
        vdbgi_light *const l = &scene->lights[scene->light_count++];
        *l = lights[i];
        l->name[sizeof(l->name) - 1] = '\0';
        const float *const d = l->direction;
        const float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int k = 0; k < 3 && len > 0.0f; k++)
            l->direction[k] /= len;
    }
    return VDBGI_OK;
}

size_t vdbgi_scene_get_lights(const vdbgi_scene *scene, const vdbgi_light **lights)
{
    *lights = scene->lights;
    return scene->light_count;
}

size_t vdbgi_scene_keep_boxes(const vdbgi_scene *scene, const double (**boxes)[6])
{
    *boxes = (const double(*)[6])scene->keep_boxes;
    return scene->keep_box_count;
}

/* ---- albedo at a hit ----------------------------------------------------- */

/* Bilinear, repeat-wrapped, texel centres at half-integers; v = 1 is row 0. */
static void texture_sample(const vdbgi_texture *t, float u, float v, float rgb[3])
{
    const float x = u * (float)t->width - 0.5f;
    const float y = (1.0f - v) * (float)t->height - 0.5f;
    const float fx0 = floorf(x), fy0 = floorf(y);
    const float fx = x - fx0, fy = y - fy0;
    long x0 = (long)fx0 % t->width, y0 = (long)fy0 % t->height;
    x0 += x0 < 0 ? t->width : 0;
    y0 += y0 < 0 ? t->height : 0;
    const long x1 = (x0 + 1) % t->width, y1 = (y0 + 1) % t->height;
    const float *const a = &t->rgba[4 * ((size_t)y0 * t->width + x0)];
    const float *const b = &t->rgba[4 * ((size_t)y0 * t->width + x1)];
    const float *const c = &t->rgba[4 * ((size_t)y1 * t->width + x0)];
    const float *const d = &t->rgba[4 * ((size_t)y1 * t->width + x1)];
    for (int k = 0; k < 3; k++) {
        const float top = a[k] + (b[k] - a[k]) * fx;
        const float bottom = c[k] + (d[k] - c[k]) * fx;
        rgb[k] = top + (bottom - top) * fy;
    }
}

/* rgb times texture `texture` at triangle prim's barycentrics (u, v), through its first UV set. */
static void times_texture(const vdbgi_scene *scene, uint32_t prim, float u, float v, int texture,
                          float rgb[3])
{
    const uint32_t *const idx = &scene->indices[3 * prim];
    const float w = 1.0f - u - v;
    const float *const t0 = &scene->uvs[2 * idx[0]];
    const float *const t1 = &scene->uvs[2 * idx[1]];
    const float *const t2 = &scene->uvs[2 * idx[2]];
    float tex[3];
    texture_sample(&scene->textures[texture], w * t0[0] + u * t1[0] + v * t2[0],
                   w * t0[1] + u * t1[1] + v * t2[1], tex);
    for (int k = 0; k < 3; k++)
        rgb[k] *= tex[k];
}

void vdbgi_scene_albedo(const vdbgi_scene *scene, uint32_t prim, float u, float v, float rgb[3])
{
    const vdbgi_tri *const tri = &scene->tris[prim];
    if (!(tri->flags & VDBGI_TRI_VARIES)) {
        memcpy(rgb, tri->albedo, 3 * sizeof(float));
        return;
    }
    const vdbgi_material *const mat = &scene->materials[tri->material];
    const uint32_t *const idx = &scene->indices[3 * prim];
    const float w = 1.0f - u - v;
    const float *const c0 = &scene->colors[3 * idx[0]];
    const float *const c1 = &scene->colors[3 * idx[1]];
    const float *const c2 = &scene->colors[3 * idx[2]];
    for (int k = 0; k < 3; k++)
        rgb[k] = mat->base[k] * (w * c0[k] + u * c1[k] + v * c2[k]);
    if (mat->texture >= 0)
        times_texture(scene, prim, u, v, mat->texture, rgb);
}

float vdbgi_scene_offset(const vdbgi_scene *scene, uint32_t prim)
{
    const uint32_t *const idx = &scene->indices[3 * (size_t)prim];
    float m = VDBGI_RAY_OFFSET_MIN_MAGNITUDE;
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++)
            m = fmaxf(m, fabsf(scene->positions[3 * (size_t)idx[c] + (size_t)k]));
    return VDBGI_RAY_OFFSET_REL * m;
}

float vdbgi_scene_hit_point(const vdbgi_scene *scene, uint32_t prim, float u, float v, float p[3])
{
    const uint32_t *const idx = &scene->indices[3 * (size_t)prim];
    const float *const a = &scene->positions[3 * (size_t)idx[0]];
    const float *const b = &scene->positions[3 * (size_t)idx[1]];
    const float *const c = &scene->positions[3 * (size_t)idx[2]];
    const float w = 1.0f - u - v;
    for (int k = 0; k < 3; k++)
        p[k] = w * a[k] + u * b[k] + v * c[k];
    return vdbgi_scene_offset(scene, prim);
}

void vdbgi_scene_emission(const vdbgi_scene *scene, uint32_t prim, float u, float v, float rgb[3])
{
    const vdbgi_material *const mat = &scene->materials[scene->tris[prim].material];
    memcpy(rgb, mat->emissive, 3 * sizeof(float));
    if (mat->emissive_texture >= 0)
        times_texture(scene, prim, u, v, mat->emissive_texture, rgb);
}

/* ---- receivers ------------------------------------------------------------ */

void vdbgi_scene_triangle_cross(const vdbgi_scene *scene, size_t t, double c[3])
{
    const float *const p0 = &scene->positions[3 * scene->indices[3 * t]];
    const float *const p1 = &scene->positions[3 * scene->indices[3 * t + 1]];
    const float *const p2 = &scene->positions[3 * scene->indices[3 * t + 2]];
    const double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const double e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    c[0] = e1[1] * e2[2] - e1[2] * e2[1];
    c[1] = e1[2] * e2[0] - e1[0] * e2[2];
    c[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

double vdbgi_scene_triangle_area(const vdbgi_scene *scene, size_t t)
{
    double c[3];
    vdbgi_scene_triangle_cross(scene, t, c);
    return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

/* count points spread by area: triangles and barycentrics into prims and uv. */
static vdbgi_result spread(const vdbgi_scene *scene, size_t point_count, uint64_t seed,
                           uint32_t *prims, double *uv)
{
    vdbgi_context *const ctx = scene->ctx;
    /* Cumulative areas, then a binary search per point. */
    double *const cdf = vdbgi_calloc(ctx, scene->triangle_count, sizeof(double));
    if (!cdf)
        return VDBGI_ERR_OUT_OF_MEMORY;
    double total = 0.0;
    for (size_t t = 0; t < scene->triangle_count; t++) {
        total += vdbgi_scene_triangle_area(scene, t);
        cdf[t] = total;
    }
    uint64_t state = seed;
    for (size_t i = 0; i < point_count; i++) {
        const double target = vdbgi_uniform01(&state) * total;
        size_t lo = 0, hi = scene->triangle_count - 1;
        while (lo < hi) {
            const size_t mid = lo + (hi - lo) / 2;
            if (cdf[mid] < target)
                lo = mid + 1;
            else
                hi = mid;
        }
        /* Uniform on the triangle: fold the unit square's upper half back. */
        double u = vdbgi_uniform01(&state), v = vdbgi_uniform01(&state);
        if (u + v > 1.0)
            u = 1.0 - u, v = 1.0 - v;
        prims[i] = (uint32_t)lo;
        uv[2 * i] = u, uv[2 * i + 1] = v;
    }
    vdbgi_free(ctx, cdf);
    return VDBGI_OK;
}

vdbgi_result vdbgi_scene_sample_surface(const vdbgi_scene *scene, size_t point_count, float offset,
                                        uint64_t seed, float *points)
{
    vdbgi_context *const ctx = scene->ctx;
    VDBGI_FAIL_IF(ctx, point_count && !points, VDBGI_ERR_INVALID_ARG, "no output given");
    VDBGI_FAIL_IF(ctx, !isfinite(offset), VDBGI_ERR_INVALID_ARG, "offset must be finite");
    uint32_t *const prims = vdbgi_calloc(ctx, point_count ? point_count : 1, sizeof(uint32_t));
    double *const uv = vdbgi_calloc(ctx, point_count ? point_count : 1, 2 * sizeof(double));
    vdbgi_result r =
        prims && uv ? spread(scene, point_count, seed, prims, uv) : VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; r == VDBGI_OK && i < point_count; i++) {
        const double u = uv[2 * i], v = uv[2 * i + 1];
        const uint32_t *const idx = &scene->indices[3 * (size_t)prims[i]];
        const float *const p0 = &scene->positions[3 * idx[0]];
        const float *const p1 = &scene->positions[3 * idx[1]];
        const float *const p2 = &scene->positions[3 * idx[2]];
        for (int k = 0; k < 3; k++)
            points[3 * i + k] = (float)((1.0 - u - v) * p0[k] + u * p1[k] + v * p2[k]) +
                                offset * scene->tris[prims[i]].normal[k];
    }
    vdbgi_free(ctx, prims);
    vdbgi_free(ctx, uv);
    return r;
}

vdbgi_result vdbgi_scene_sample_triangles(const vdbgi_scene *scene, size_t count, uint64_t seed,
                                          uint32_t *prims, float *uv)
{
    vdbgi_context *const ctx = scene->ctx;
    VDBGI_FAIL_IF(ctx, count && (!prims || !uv), VDBGI_ERR_INVALID_ARG, "no output given");
    double *const d = vdbgi_calloc(ctx, count ? count : 1, 2 * sizeof(double));
    const vdbgi_result r = d ? spread(scene, count, seed, prims, d) : VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; r == VDBGI_OK && i < 2 * count; i++)
        uv[i] = (float)d[i];
    vdbgi_free(ctx, d);
    return r;
}
