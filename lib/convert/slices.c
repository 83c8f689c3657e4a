/* slices.c: images of a plane through the baked, filled and bricked fields, and the atlas. */
#define _POSIX_C_SOURCE 200809L
#include "encode.h"
#include "field.h"
#include "image_shim.h"
#include "probes.h"
#include "util.h"
#include "volume.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

const float *vdbgi_level_colour(int level)
{
    /* A function, not a global table: sanitizers add symbols of their own beside global data. */
    static const float colour[5][3] = {{0.25f, 0.25f, 0.25f},
                                       {0.1f, 0.35f, 1.0f},
                                       {0.1f, 0.85f, 0.25f},
                                       {1.0f, 0.85f, 0.1f},
                                       {1.0f, 0.2f, 0.1f}};
    return colour[level < 0 || level > 3 ? 0 : level + 1];
}

/* Write name.exr (linear, scaled) and name.png (exposed, sRGB) from RGB pixels. */
static vdbgi_result write_pair(vdbgi_context *ctx, const char *dir, const char *name, int w, int h,
                               float *rgb, float scale, float exposure)
{
    char path[4096];
    const size_t n = (size_t)w * (size_t)h * 3;
    for (size_t i = 0; i < n; i++)
        rgb[i] *= scale;
    snprintf(path, sizeof(path), "%s/%s.exr", dir, name);
    VDBGI_TRY(vdbgi_image_write(ctx, path, w, h, 3, rgb, false));
    const float gain = exp2f(exposure);
    for (size_t i = 0; i < n; i++)
        rgb[i] = vdbgi_srgb_from_linear(rgb[i] * gain);
    snprintf(path, sizeof(path), "%s/%s.png", dir, name);
    return vdbgi_image_write(ctx, path, w, h, 3, rgb, false);
}

/* The atlas: its z layers in a grid, decoded. */
static vdbgi_result write_atlas(const vdbgi_volume *v, const char *dir, float exposure)
{
    vdbgi_context *const ctx = v->ctx;
    const uint32_t *const ad = v->info.atlas_dims;
    const uint32_t cols = (uint32_t)ceil(sqrt((double)ad[2]));
    const uint32_t rows = (ad[2] + cols - 1) / cols;
    const int aw = (int)(cols * ad[0]), ah = (int)(rows * ad[1]);
    float *const atlas = vdbgi_calloc(ctx, (size_t)aw * (size_t)ah, 3 * sizeof(float));
    if (!atlas)
        return VDBGI_ERR_OUT_OF_MEMORY;
    for (uint32_t z = 0; z < ad[2]; z++)
        for (uint32_t y = 0; y < ad[1]; y++)
            for (uint32_t x = 0; x < ad[0]; x++) {
                const uint8_t *const t = &v->tex.atlas[4 * (((size_t)z * ad[1] + y) * ad[0] + x)];
                float rgb[3];
                if (v->info.encoding == VDBGI_ENCODING_RGB9E5)
                    vdbgi_rgb9e5_decode(vdbgi_get_u32(t), rgb);
                else
                    vdbgi_rgbm_decode(t, v->info.rgbm_range, rgb);
                const size_t ox = (z % cols) * ad[0] + x, oy = (z / cols) * ad[1] + y;
                memcpy(&atlas[3 * (oy * (size_t)aw + ox)], rgb, sizeof(rgb));
            }
    const vdbgi_result r = write_pair(ctx, dir, "atlas", aw, ah, atlas, 1.0f, exposure);
    vdbgi_free(ctx, atlas);
    return r;
}

/* One pass over the plane fills the four images together (about 90 lines, kept whole). */
vdbgi_result vdbgi_volume_write_slices(const vdbgi_volume *v, const vdbgi_probes *probes,
                                       vdbgi_axis axis, double at, float exposure, const char *dir)
{
    vdbgi_context *const ctx = v->ctx;
    VDBGI_FAIL_IF(ctx, !v->filled || !v->filled->leaves || !probes || !probes->rgb,
                  VDBGI_ERR_INVALID_ARG, "slices need a volume built from baked probes");
    VDBGI_FAIL_IF(
        ctx, axis < VDBGI_AXIS_X || axis > VDBGI_AXIS_Z || !isfinite(at) || !isfinite(exposure),
        VDBGI_ERR_INVALID_ARG, "bad slice axis, position or exposure");
    VDBGI_FAIL_IF(ctx, !dir || !*dir, VDBGI_ERR_INVALID_ARG, "no slice directory given");
    VDBGI_FAIL_IF(ctx, mkdir(dir, 0777) != 0 && errno != EEXIST, VDBGI_ERR_IO,
                  "%s: cannot make directory: %s", dir, strerror(errno));

    /* Image axes: looking down -y for a y slice (x right, z down), else y up. */
    const int ua = axis == VDBGI_AXIS_X ? 2 : 0;
    const int va = axis == VDBGI_AXIS_Y ? 2 : 1;
    const bool flip_v = axis != VDBGI_AXIS_Y;
    const int32_t plane = (int32_t)lround((at - v->lattice_origin[axis]) / probes->spacing);
    const int32_t u0 = v->origin_cell[ua] * VDBGI_BRICK, v0 = v->origin_cell[va] * VDBGI_BRICK;
    const int w = (int)v->info.ind_dims[ua] * VDBGI_BRICK;
    const int h = (int)v->info.ind_dims[va] * VDBGI_BRICK;

    const size_t px = (size_t)w * (size_t)h;
    float *const baked = vdbgi_calloc(ctx, px, 3 * sizeof(float));
    float *const bricks = vdbgi_calloc(ctx, px, 3 * sizeof(float));
    float *const diff = vdbgi_calloc(ctx, px, 3 * sizeof(float));
    float *const levels = vdbgi_calloc(ctx, px, 3 * sizeof(float));
    vdbgi_result r = baked && bricks && diff && levels ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;

    /* Pixel of a lattice point, or -1 off the image. */
#define PIXEL(iu, iv)                                                                              \
    ((iu) < u0 || (iu) >= u0 + w || (iv) < v0 || (iv) >= v0 + h                                    \
         ? (ptrdiff_t)-1                                                                           \
         : (ptrdiff_t)((flip_v ? (size_t)(h - 1 - ((iv)-v0)) : (size_t)((iv)-v0)) * (size_t)w +    \
                       (size_t)((iu)-u0)))
    for (size_t i = 0; r == VDBGI_OK && i < probes->count; i++) {
        const int32_t *const c = &probes->ijk[3 * i];
        if (c[axis] != plane)
            continue;
        const ptrdiff_t p = PIXEL(c[ua], c[va]);
        if (p >= 0)
            memcpy(&baked[3 * p], &probes->rgb[3 * i], 3 * sizeof(float));
    }
    const vdbgi_volume_view view = vdbgi_volume_view_of(v);
    for (int iv = v0; r == VDBGI_OK && iv < v0 + h; iv++)
        for (int iu = u0; iu < u0 + w; iu++) {
            int32_t ijk[3];
            ijk[axis] = plane, ijk[ua] = iu, ijk[va] = iv;
            float pos[3], got[3];
            for (int k = 0; k < 3; k++)
                pos[k] = (float)(v->lattice_origin[k] + probes->spacing * ijk[k]);
            vdbgi_sampler_sample(&view, pos, got);
            const ptrdiff_t p = PIXEL(iu, iv);
            memcpy(&bricks[3 * p], got, sizeof(got));
            const float *const want = vdbgi_field_at(v->filled, ijk, NULL);
            if (want)
                for (int k = 0; k < 3; k++)
                    diff[3 * p + k] = fabsf(got[k] - want[k]);
            size_t cell[3];
            for (int k = 0; k < 3; k++)
                cell[k] = (size_t)(vdbgi_floor_div(ijk[k], VDBGI_BRICK) - v->origin_cell[k]);
            const uint32_t *const d = v->info.ind_dims;
            const int level =
                cell[axis] < d[axis]
                    ? vdbgi_cell_level(
                          &view,
                          &v->tex.indirection[4 * ((cell[2] * d[1] + cell[1]) * d[0] + cell[0])])
                    : -1;
            for (int k = 0; k < 3; k++)
                levels[3 * p + k] = vdbgi_srgb_from_linear(vdbgi_level_colour(level)[k]);
        }
#undef PIXEL
    if (r == VDBGI_OK)
        r = write_pair(ctx, dir, "baked", w, h, baked, 1.0f, exposure);
    if (r == VDBGI_OK)
        r = write_pair(ctx, dir, "bricks", w, h, bricks, 1.0f, exposure);
    if (r == VDBGI_OK)
        r = write_pair(ctx, dir, "difference", w, h, diff, 10.0f, exposure);
    if (r == VDBGI_OK) {
        char path[4096];
        snprintf(path, sizeof(path), "%s/levels.png", dir);
        r = vdbgi_image_write(ctx, path, w, h, 3, levels, false);
    }
    vdbgi_free(ctx, baked);
    vdbgi_free(ctx, bricks);
    vdbgi_free(ctx, diff);
    vdbgi_free(ctx, levels);
    VDBGI_TRY(r);

    return write_atlas(v, dir, exposure);
}
