/*
 * bevy.c: Bevy irradiance volumes: baked ambient cubes resampled onto a dense
 * voxel grid, written in seed 001's 3D layout (KTX2) or seed 002's 2D cell
 * layout (RGBA8 PNG), with a JSON sidecar saying where the volume goes.
 */
#define _POSIX_C_SOURCE 200809L
#include "encode.h"
#include "field.h"
#include "image_shim.h"
#include "ktx2.h"
#include "probes.h"
#include "util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct vdbgi_bevy {
    vdbgi_context *ctx;
    int res[3];
    double box_min[3], box_max[3];
    float *cube; /* 18 floats per voxel, vdbgi_side order */
};

/* Texture limits: WebGPU guarantees 2048 texels a side in 3D and 8192 in 2D. */
#define KTX2_MAX 2048
#define PNG_MAX 8192

static size_t voxel_count(const int res[3])
{
    return (size_t)res[0] * (size_t)res[1] * (size_t)res[2];
}

static vdbgi_result check_grid(vdbgi_context *ctx, const int res[3], const double lo[3],
                               const double hi[3])
{
    for (int k = 0; k < 3; k++) {
        VDBGI_FAIL_IF(ctx, res[k] < 1, VDBGI_ERR_INVALID_ARG,
                      "volume resolution must be at least 1 on every axis (got %d,%d,%d)", res[0],
                      res[1], res[2]);
        VDBGI_FAIL_IF(ctx, !isfinite(lo[k]) || !isfinite(hi[k]) || !(hi[k] > lo[k]),
                      VDBGI_ERR_INVALID_ARG, "volume box must have a positive size on every axis");
    }
    /* Seed 001's texture is (Rx, 2Ry, 3Rz); seed 002's is 3Rx x 2RyRz. */
    VDBGI_FAIL_IF(ctx,
                  res[0] > KTX2_MAX || 2 * res[1] > KTX2_MAX || 3 * res[2] > KTX2_MAX ||
                      2 * (long long)res[1] * res[2] > PNG_MAX,
                  VDBGI_ERR_INVALID_ARG,
                  "volume resolution %dx%dx%d needs textures of %dx%dx%d (3D, limit %d) and "
                  "%dx%lld (2D, limit %d) texels: lower it",
                  res[0], res[1], res[2], res[0], 2 * res[1], 3 * res[2], KTX2_MAX, 3 * res[0],
                  2 * (long long)res[1] * res[2], PNG_MAX);
    return VDBGI_OK;
}

static vdbgi_result bevy_alloc(vdbgi_context *ctx, const int res[3], const double lo[3],
                               const double hi[3], vdbgi_bevy **out)
{
    *out = NULL;
    VDBGI_TRY(check_grid(ctx, res, lo, hi));
    vdbgi_bevy *const b = vdbgi_calloc(ctx, 1, sizeof(*b));
    if (!b)
        return VDBGI_ERR_OUT_OF_MEMORY;
    b->ctx = ctx;
    memcpy(b->res, res, sizeof(b->res));
    memcpy(b->box_min, lo, sizeof(b->box_min));
    memcpy(b->box_max, hi, sizeof(b->box_max));
    if (!(b->cube = vdbgi_calloc(ctx, voxel_count(res), 18 * sizeof(float)))) {
        vdbgi_free(ctx, b);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    *out = b;
    return VDBGI_OK;
}

void vdbgi_bevy_destroy(vdbgi_bevy *b)
{
    if (b) {
        vdbgi_free(b->ctx, b->cube);
        vdbgi_free(b->ctx, b);
    }
}

vdbgi_result vdbgi_bevy_create(vdbgi_context *ctx, const float *cube, const int resolution[3],
                               const double box_min[3], const double box_max[3], vdbgi_bevy **out)
{
    VDBGI_FAIL_IF(ctx, !out || !cube || !resolution || !box_min || !box_max, VDBGI_ERR_INVALID_ARG,
                  "missing volume data");
    VDBGI_TRY(bevy_alloc(ctx, resolution, box_min, box_max, out));
    memcpy((*out)->cube, cube, voxel_count(resolution) * 18 * sizeof(float));
    return VDBGI_OK;
}

void vdbgi_bevy_get_info(const vdbgi_bevy *b, vdbgi_bevy_info *info)
{
    memset(info, 0, sizeof(*info));
    memcpy(info->resolution, b->res, sizeof(info->resolution));
    for (int k = 0; k < 3; k++) {
        info->box_min[k] = b->box_min[k];
        info->box_max[k] = b->box_max[k];
        info->center[k] = 0.5 * (b->box_min[k] + b->box_max[k]);
        info->size[k] = b->box_max[k] - b->box_min[k];
    }
    info->ktx2_texels = voxel_count(b->res) * 6;
}

/* ---- resampling ---------------------------------------------------------------- */

/* The volume's box (inside the baked bounds) and resolution, from desc's defaults. */
static vdbgi_result resolve_grid(vdbgi_context *ctx, const vdbgi_probes *p,
                                 const vdbgi_bevy_desc *desc, double lo[3], double hi[3],
                                 int res[3])
{
    /* The baked bounds: the probes' box and half a spacing around it. */
    vdbgi_probes_info pi;
    vdbgi_probes_get_info(p, &pi);
    const bool box_given = desc->box_is_set || desc->box_min[0] != 0.0 || desc->box_min[1] != 0.0 ||
                           desc->box_min[2] != 0.0 || desc->box_max[0] != 0.0 ||
                           desc->box_max[1] != 0.0 || desc->box_max[2] != 0.0;
    for (int k = 0; k < 3; k++) {
        const double blo = p->origin[k] + p->spacing * (pi.ijk_min[k] - 0.5);
        const double bhi = p->origin[k] + p->spacing * (pi.ijk_max[k] + 0.5);
        lo[k] = box_given ? desc->box_min[k] : blo;
        hi[k] = box_given ? desc->box_max[k] : bhi;
        const double slack = 1e-6 * (bhi - blo);
        VDBGI_FAIL_IF(ctx, lo[k] < blo - slack || hi[k] > bhi + slack, VDBGI_ERR_INVALID_ARG,
                      "volume box %g..%g on %c reaches outside the baked bounds %g..%g", lo[k],
                      hi[k], "xyz"[k], blo, bhi);
    }
    const bool res_given = desc->resolution[0] || desc->resolution[1] || desc->resolution[2];
    const double voxel = desc->voxel_size != 0.0 ? desc->voxel_size : 4.0 * p->spacing;
    VDBGI_FAIL_IF(ctx, !res_given && (!(voxel > 0.0) || !isfinite(voxel)), VDBGI_ERR_INVALID_ARG,
                  "voxel size must be > 0 (got %g)", desc->voxel_size);
    for (int k = 0; k < 3; k++) {
        const double cells = res_given ? desc->resolution[k] : ceil((hi[k] - lo[k]) / voxel);
        res[k] = cells > 1e6 ? 1000000 : (int)cells;
        res[k] = !res_given && res[k] < 1 ? 1 : res[k];
    }
    return VDBGI_OK;
}

vdbgi_result vdbgi_bevy_build(vdbgi_context *ctx, const vdbgi_probes *p,
                              const vdbgi_bevy_desc *desc, vdbgi_bevy **out)
{
    VDBGI_FAIL_IF(ctx, !out || !p, VDBGI_ERR_INVALID_ARG, "no probes or output given");
    *out = NULL;
    VDBGI_FAIL_IF(ctx, !p->cube, VDBGI_ERR_INVALID_ARG,
                  "the probes have no ambient cubes: bake with --basis ambient-cube");
    VDBGI_FAIL_IF(ctx, p->count == 0, VDBGI_ERR_FORMAT, "the grid holds no probes");
    const vdbgi_bevy_desc none = {0};
    if (!desc)
        desc = &none;
    VDBGI_FAIL_IF(ctx, desc->fill < VDBGI_FILL_AUTO || desc->fill > VDBGI_FILL_DARKEST,
                  VDBGI_ERR_INVALID_ARG, "unknown fill %d", (int)desc->fill);
    VDBGI_FAIL_IF(ctx, desc->threads < 0, VDBGI_ERR_INVALID_ARG,
                  "thread count must be >= 0 (got %d)", desc->threads);

    double lo[3], hi[3];
    int res[3];
    VDBGI_TRY(resolve_grid(ctx, p, desc, lo, hi, res));
    vdbgi_bevy *b = NULL;
    VDBGI_TRY(bevy_alloc(ctx, res, lo, hi, &b));

    /*
     * The converter's fill from valid probes, all six sides at once (one choice of
     * neighbour a probe), then trilinear at voxel centres. Voxels with no filled point
     * around them (the box reaches past the baked shell) take the same rings on the
     * voxel grid.
     */
    const size_t n = voxel_count(res);
    unsigned char *const valued = vdbgi_calloc(ctx, n, 1);
    vdbgi_result r = valued ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    vdbgi_fill_params fp =
        vdbgi_fill_params_default(p->invalid_threshold, desc->fill, desc->threads);
    /* A voxel 4 probes wide filters across solids' insides, which bricks never read:
       fill a cell around every cell holding a valid probe, as the converter once did. */
    fp.margin_cells = 1;
    const vdbgi_fill_input in = {.count = p->count,
                                 .ijk = p->ijk,
                                 .values = p->cube,
                                 .backface = p->backface,
                                 .channels = 6};
    vdbgi_field field = {0};
    int32_t *cells = NULL;
    size_t cell_count = 0, unreached = 0;
    if (r == VDBGI_OK)
        r = vdbgi_field_fill(ctx, &in, &fp, &field, &cells, &cell_count, NULL, NULL, &unreached);
    size_t any = 0;
    const vdbgi_leaf *cache = NULL;
    for (int z = 0; z < res[2] && r == VDBGI_OK; z++)
        for (int y = 0; y < res[1]; y++)
            for (int x = 0; x < res[0]; x++) {
                const int v[3] = {x, y, z};
                double pos[3];
                for (int k = 0; k < 3; k++) {
                    const double world = lo[k] + (v[k] + 0.5) * (hi[k] - lo[k]) / res[k];
                    pos[k] = (world - p->origin[k]) / p->spacing;
                }
                const size_t i = ((size_t)z * res[1] + y) * res[0] + x;
                valued[i] = vdbgi_field_trilinear(&field, pos, &b->cube[18 * i], &cache);
                any += valued[i];
            }
    vdbgi_free(ctx, cells);
    vdbgi_field_free(&field);
    if (r == VDBGI_OK)
        r = any ? vdbgi_fill_dense(ctx, res, 6, b->cube, valued, &fp)
                : vdbgi_fail(ctx, VDBGI_ERR_INVALID_ARG, "no baked probe lies inside the box");
    vdbgi_free(ctx, valued);
    if (r != VDBGI_OK) {
        vdbgi_bevy_destroy(b);
        return r;
    }
    *out = b;
    return VDBGI_OK;
}

/* ---- writing ------------------------------------------------------------------- */

/* Axis and sign of each vdbgi_side. */
static int side_axis(int side)
{
    return side / 2;
}

static bool side_positive(int side)
{
    return side % 2 == 0;
}

vdbgi_result vdbgi_bevy_write_ktx2(const vdbgi_bevy *b, const char *path, vdbgi_bevy_format format,
                                   size_t *clamped_count_out)
{
    vdbgi_context *const ctx = b->ctx;
    VDBGI_FAIL_IF(ctx, format != VDBGI_BEVY_RGBA16F && format != VDBGI_BEVY_RGB9E5,
                  VDBGI_ERR_INVALID_ARG, "unknown Bevy texture format %d", (int)format);
    const int *const r = b->res;
    const uint32_t w = (uint32_t)r[0], h = 2u * (uint32_t)r[1], d = 3u * (uint32_t)r[2];
    const size_t texel_size = format == VDBGI_BEVY_RGB9E5 ? 4 : 8;
    uint8_t *const texels = vdbgi_calloc(ctx, (size_t)w * h * d, texel_size);
    if (!texels)
        return VDBGI_ERR_OUT_OF_MEMORY;
    size_t clamped_count = 0;
    for (int z = 0; z < r[2]; z++)
        for (int y = 0; y < r[1]; y++)
            for (int x = 0; x < r[0]; x++)
                for (int side = 0; side < 6; side++) {
                    /* Seed 001: s = x; t = y (+Ry for +X +Y +Z); p = z (+Rz Y, +2Rz Z). */
                    const size_t s = (size_t)x;
                    const size_t t = (size_t)y + (side_positive(side) ? (size_t)r[1] : 0);
                    const size_t pz = (size_t)z + (size_t)side_axis(side) * (size_t)r[2];
                    const size_t i = ((size_t)z * r[1] + y) * r[0] + x;
                    const float *const c = &b->cube[18 * i + 3 * side];
                    uint8_t *const out = &texels[((pz * h + t) * w + s) * texel_size];
                    if (format == VDBGI_BEVY_RGB9E5) {
                        uint32_t v;
                        clamped_count += vdbgi_rgb9e5_encode(c, &v);
                        vdbgi_put_u32(out, v);
                    } else {
                        const float rgba[4] = {c[0], c[1], c[2], 1.0f};
                        for (int k = 0; k < 4; k++) {
                            /* Half floats: NaN and negatives to 0, beyond 65504 clamped. */
                            float f = rgba[k] > 0.0f ? rgba[k] : 0.0f;
                            clamped_count += k < 3 && f > 65504.0f;
                            f = f > 65504.0f ? 65504.0f : f;
                            const uint16_t hbits = vdbgi_half_from_float(f);
                            vdbgi_put_u16(out + 2 * k, hbits);
                        }
                    }
                }
    uint8_t *file = NULL;
    size_t size = 0;
    vdbgi_result res =
        vdbgi_ktx2_encode(ctx,
                          format == VDBGI_BEVY_RGB9E5 ? VDBGI_VK_FORMAT_E5B9G9R9_UFLOAT_PACK32
                                                      : VDBGI_VK_FORMAT_R16G16B16A16_SFLOAT,
                          w, h, d, texels, &file, &size);
    vdbgi_free(ctx, texels);
    if (res == VDBGI_OK)
        res = vdbgi_write_bytes_atomic(ctx, path, file, size);
    vdbgi_free(ctx, file);
    if (res == VDBGI_OK && clamped_count_out)
        *clamped_count_out = clamped_count;
    return res;
}

vdbgi_result vdbgi_bevy_write_baked_gi(const vdbgi_bevy *b, const char *path,
                                       size_t *clamped_count_out)
{
    vdbgi_context *const ctx = b->ctx;
    const int *const r = b->res;
    /* One row of cells per (z, y): width 3Rx, height 2 Ry Rz. */
    const int w = 3 * r[0], h = 2 * r[1] * r[2];
    float *const px = vdbgi_calloc(ctx, (size_t)w * (size_t)h, 4 * sizeof(float));
    if (!px)
        return VDBGI_ERR_OUT_OF_MEMORY;
    size_t clamped_count = 0;
    for (int z = 0; z < r[2]; z++)
        for (int y = 0; y < r[1]; y++)
            for (int x = 0; x < r[0]; x++) {
                const size_t i = ((size_t)z * r[1] + y) * r[0] + x;
                /* Seed 002: cell i at (3 (i mod w/3), 2 floor(i / (w/3))), w/3 = Rx. */
                const size_t cx = 3 * (i % (size_t)r[0]), cy = 2 * (i / (size_t)r[0]);
                for (int side = 0; side < 6; side++) {
                    uint8_t t[4];
                    clamped_count += vdbgi_sharedexp8_encode(&b->cube[18 * i + 3 * side], t);
                    const size_t tx = cx + (size_t)side_axis(side);
                    const size_t ty = cy + (side_positive(side) ? 0 : 1);
                    float *const o = &px[4 * (ty * (size_t)w + tx)];
                    for (int k = 0; k < 4; k++)
                        o[k] = (float)t[k] / 255.0f; /* bytes exactly: /255 then *255 rounds back */
                }
            }
    const vdbgi_result res = vdbgi_image_write(ctx, path, w, h, 4, px, true);
    vdbgi_free(ctx, px);
    if (res == VDBGI_OK && clamped_count_out)
        *clamped_count_out = clamped_count;
    return res;
}

typedef struct json_job {
    const vdbgi_bevy *b;
    const char *path, *texture, *layout;
} json_job;

static vdbgi_result write_json(vdbgi_context *ctx, const char *tmp, const void *user)
{
    const json_job *const job = user;
    vdbgi_bevy_info info;
    vdbgi_bevy_get_info(job->b, &info);
    FILE *const f = fopen(tmp, "w");
    VDBGI_FAIL_IF(ctx, !f, VDBGI_ERR_IO, "%s: cannot write", job->path);
    fputs("{\n  \"texture\": ", f);
    vdbgi_json_string(f, job->texture);
    fputs(",\n  \"layout\": ", f);
    vdbgi_json_string(f, job->layout);
    fprintf(
        f,
        ",\n  \"resolution\": [%d, %d, %d],\n"
        "  \"box_min\": [%.9g, %.9g, %.9g],\n  \"box_max\": [%.9g, %.9g, %.9g],\n"
        "  \"transform\": {\"translation\": [%.9g, %.9g, %.9g], \"scale\": [%.9g, %.9g, %.9g]}\n"
        "}\n",
        info.resolution[0], info.resolution[1], info.resolution[2], info.box_min[0],
        info.box_min[1], info.box_min[2], info.box_max[0], info.box_max[1], info.box_max[2],
        info.center[0], info.center[1], info.center[2], info.size[0], info.size[1], info.size[2]);
    const bool ok = !ferror(f);
    VDBGI_FAIL_IF(ctx, (fclose(f) != 0) | !ok, VDBGI_ERR_IO, "%s: cannot write", job->path);
    return VDBGI_OK;
}

vdbgi_result vdbgi_bevy_write_json(const vdbgi_bevy *b, const char *path, const char *texture,
                                   const char *layout)
{
    const json_job job = {b, path, texture ? texture : "", layout ? layout : ""};
    return vdbgi_write_atomic(b->ctx, path, write_json, &job);
}
