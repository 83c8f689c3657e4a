/*
 * sampler.c: the lookup of seed 000's gi-volume.ts, step by step in float32
 * (and its one change for the compact layout, docs/format.md),
 * with the texture units' NEAREST and LINEAR filtering (clamp-to-edge,
 * texel centres at +0.5) done by hand; and a brick's trilinear reconstruction
 * from its samples, which the compact layout's seams and the coarsening share.
 * Depends on nothing else in lib/.
 */
#include "sampler.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

/*
 * One atlas texel as the texture unit sees it after format conversion; term
 * 0..7 reads that L2 term's three snorm8 ratios instead.
 */
static void fetch(const vdbgi_volume_view *v, int x, int y, int z, int term, float out[4])
{
    const size_t i = ((size_t)z * v->atlas_dims[1] + (size_t)y) * v->atlas_dims[0] + (size_t)x;
    if (term >= 0) {
        for (int k = 0; k < 3; k++)
            out[k] = fmaxf((float)v->sh[24 * i + 3 * term + k] / 127.0f, -1.0f);
        out[3] = 0.0f;
        return;
    }
    const uint8_t *const t = &v->atlas[4 * i];
    if (v->encoding == 1) {
        /* rgb9e5ufloat is decoded before filtering. */
        const uint32_t w =
            (uint32_t)t[0] | (uint32_t)t[1] << 8 | (uint32_t)t[2] << 16 | (uint32_t)t[3] << 24;
        const float scale = ldexpf(1.0f, (int)(w >> 27) - 15 - 9);
        for (int k = 0; k < 3; k++)
            out[k] = (float)((w >> (9 * k)) & 511u) * scale;
        out[3] = 1.0f;
    } else {
        for (int k = 0; k < 4; k++)
            out[k] = (float)t[k] / 255.0f; /* unorm8 */
    }
}

/* LINEAR filtering at normalised coordinate uvw (texture-unit convention), of fetch's term. */
static void sample_linear(const vdbgi_volume_view *v, const float uvw[3], int term, float out[4])
{
    int i0[3], i1[3];
    float f[3];
    for (int k = 0; k < 3; k++) {
        const int dim = (int)v->atlas_dims[k];
        const float t = uvw[k] * (float)dim - 0.5f;
        const float fl = floorf(t);
        f[k] = t - fl;
        i0[k] = clampi((int)fl, 0, dim - 1);
        i1[k] = clampi((int)fl + 1, 0, dim - 1);
    }
    memset(out, 0, 4 * sizeof(float));
    for (int c = 0; c < 8; c++) {
        const int x = c & 1 ? i1[0] : i0[0], y = c & 2 ? i1[1] : i0[1], z = c & 4 ? i1[2] : i0[2];
        const float w = (c & 1 ? f[0] : 1.0f - f[0]) * (c & 2 ? f[1] : 1.0f - f[1]) *
                        (c & 4 ? f[2] : 1.0f - f[2]);
        float t[4];
        fetch(v, x, y, z, term, t);
        for (int k = 0; k < 4; k++)
            out[k] += w * t[k];
    }
}

/* Indirection texel (x, y, z), x fastest. */
static const uint8_t *ind_texel(const vdbgi_volume_view *v, int x, int y, int z)
{
    return &v->indirection[4 *
                           (((size_t)z * v->ind_dims[1] + (size_t)y) * v->ind_dims[0] + (size_t)x)];
}

static bool empty_cell(const vdbgi_volume_view *v, int x, int y, int z)
{
    const uint8_t *const t = ind_texel(v, x, y, z);
    return !(t[0] | t[1] | t[2] | t[3]);
}

/* The lowest cell of column (x, z) that holds a brick, or -1. */
static int column_bottom(const vdbgi_volume_view *v, int x, int z)
{
    for (int y = 0; y < (int)v->ind_dims[1]; y++)
        if (!empty_cell(v, x, y, z))
            return y;
    return -1;
}

int vdbgi_cell_level(const vdbgi_volume_view *v, const uint8_t texel[4])
{
    if (v->layout == 2)
        return texel[0] | texel[1] | texel[2] | texel[3] ? texel[3] & 3 : -1;
    return (int)texel[3] - 1;
}

/* Where the lookup reads the atlas for world position pos: normalised texture coordinates. */
static void atlas_coordinates(const vdbgi_volume_view *v, const float pos[3], float uvw[3])
{
    float p[3], base[3], ind[4];
    /* const p = box.mul(giRes).sub(0.5); const baseBrick = p.div(BRICK).floor() */
    for (int k = 0; k < 3; k++) {
        const float box = (pos[k] - v->box_min[k]) / (v->box_max[k] - v->box_min[k]);
        const float gi_res = (float)(v->ind_dims[k] * VDBGI_BRICK);
        p[k] = box * gi_res - 0.5f;
        base[k] = floorf(p[k] / (float)VDBGI_BRICK);
    }
    /* giIndNode.sample(baseBrick.add(0.5).div(giIndDims)), NEAREST */
    int it[3];
    for (int k = 0; k < 3; k++) {
        const float u = (base[k] + 0.5f) / (float)v->ind_dims[k];
        it[k] = clampi((int)floorf(u * (float)v->ind_dims[k]), 0, (int)v->ind_dims[k] - 1);
    }
    const bool compact = v->layout == 2;
    /*
     * Compact: below its column's lowest brick a position reads that brick, at
     * its bottom plane (q.y clamped below): the runtime's columns give the run's
     * first cell (docs/format.md). Only an empty cell, or one below the box,
     * can lie below the run.
     */
    if (compact && (base[1] < 0.0f || empty_cell(v, it[0], it[1], it[2]))) {
        const int ymin = column_bottom(v, it[0], it[2]);
        if (ymin >= 0 && base[1] < (float)ymin) {
            base[1] = (float)ymin;
            it[1] = ymin;
        }
    }
    const uint8_t *const texel = ind_texel(v, it[0], it[1], it[2]);
    for (int k = 0; k < 4; k++)
        ind[k] = (float)texel[k] / 255.0f;
    /*
     * Seed: level = ind.a * 255 - 1 (max 0), slot = ind.rgb * 255. Compact:
     * a holds the level in bits 0-1 and each axis's texel mod 4 above; the
     * brick's first texel is rgb * 4 plus those.
     */
    float b[4];
    for (int k = 0; k < 4; k++)
        b[k] = floorf(ind[k] * 255.0f + 0.5f);
    const float level = compact ? fmodf(b[3], 4.0f) : fmaxf(b[3] - 1.0f, 0.0f);
    const float span = exp2f(level);
    for (int k = 0; k < 3; k++) {
        const float origin_cell = floorf(base[k] / span) * span * (float)VDBGI_BRICK;
        float atlas_texel;
        if (compact) {
            /* Probe q of the brick stands at origin_cell + q span, q = 0..4. */
            const float low = fmodf(floorf(b[3] / exp2f((float)(2 + 2 * k))), 4.0f);
            const float q = (p[k] - origin_cell) / span;
            atlas_texel = b[k] * 4.0f + low + (k == 1 ? fmaxf(q, 0.0f) : q);
        } else {
            const float q = (p[k] - origin_cell + 0.5f) / span - 0.5f;
            atlas_texel = b[k] * (float)VDBGI_BRICK_PADDED + 1.0f + q;
        }
        uvw[k] = (atlas_texel + 0.5f) / (float)v->atlas_dims[k];
    }
}

/* The atlas's colour at uvw: irr = sample.rgb * sample.a * RANGE for RGBM; RGB9E5 is linear. */
static void colour_at(const vdbgi_volume_view *v, const float uvw[3], float rgb[3])
{
    float s[4];
    sample_linear(v, uvw, -1, s);
    for (int k = 0; k < 3; k++)
        rgb[k] = v->encoding == 1 ? s[k] : s[k] * s[3] * v->rgbm_range;
}

void vdbgi_sampler_sample(const vdbgi_volume_view *v, const float pos[3], float rgb[3])
{
    float uvw[3];
    atlas_coordinates(v, pos, uvw);
    colour_at(v, uvw, rgb);
}

void vdbgi_sampler_sample_normal(const vdbgi_volume_view *v, const float pos[3], const float n[3],
                                 float rgb[3])
{
    float uvw[3];
    atlas_coordinates(v, pos, uvw);
    colour_at(v, uvw, rgb);
    if (!v->sh)
        return;
    /* The eight polynomials of the normal (estimate.c's vdbgi_sh2_terms, in float32 here). */
    const float x = n[0], y = n[1], z = n[2];
    const float poly[8] = {x, y, z, x * y, y * z, 3.0f * z * z - 1.0f, x * z, x * x - y * y};
    /* encode.c's vdbgi_sh_ratio_range, the format's constants: this file depends on no other. */
    static const float range[8] = {2.0f, 2.0f, 2.0f, 1.875f, 1.875f, 0.625f, 1.875f, 0.9375f};
    float sum[3] = {1.0f, 1.0f, 1.0f};
    for (int t = 0; t < 8; t++) {
        float r[4];
        sample_linear(v, uvw, t, r);
        for (int k = 0; k < 3; k++)
            sum[k] += r[k] * range[t] * poly[t];
    }
    for (int k = 0; k < 3; k++)
        rgb[k] = fmaxf(rgb[k] * sum[k], 0.0f);
}

void vdbgi_brick_interpolate(const float s[][3], uint32_t layout, const int32_t key[3], int level,
                             const double pos[3], float rgb[3])
{
    vdbgi_brick_interpolate_n(s[0], 3, layout, key, level, pos, rgb);
}

void vdbgi_brick_interpolate_n(const float *s, int channels, uint32_t layout, const int32_t key[3],
                               int level, const double pos[3], float *out)
{
    const float span = (float)(1 << level);
    const int n = vdbgi_slot_texels(layout);
    int i0[3];
    float fr[3];
    for (int k = 0; k < 3; k++) {
        const float origin = (float)key[k] * VDBGI_BRICK * span;
        /* texel units: seed probes sit half a texel in, behind the apron */
        const float t = layout == 2 /* compact */
                            ? ((float)pos[k] - origin) / span
                            : ((float)pos[k] - origin + 0.5f) / span - 0.5f + 1.0f;
        const float fl = floorf(t);
        i0[k] = (int)fl;
        fr[k] = t - fl;
        if (i0[k] > n - 2) { /* the far face itself, or a guard past it */
            i0[k] = n - 2;
            fr[k] = 1.0f;
        }
    }
    for (int k = 0; k < channels; k++)
        out[k] = 0.0f;
    for (int c = 0; c < 8; c++) {
        const float w = (c & 1 ? fr[0] : 1.0f - fr[0]) * (c & 2 ? fr[1] : 1.0f - fr[1]) *
                        (c & 4 ? fr[2] : 1.0f - fr[2]);
        const int x = i0[0] + (c & 1), y = i0[1] + (c >> 1 & 1), z = i0[2] + (c >> 2 & 1);
        const float *const v = &s[(size_t)channels * (size_t)((z * n + y) * n + x)];
        for (int k = 0; k < channels; k++)
            out[k] += w * v[k];
    }
}
