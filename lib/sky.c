/*
 * sky.c: an environment map, equirectangular, as the radiance of the rays
 * that leave the scene. Decoded through the image module like textures;
 * read with bilinear filtering, wrapped around the horizon.
 */
#include "context.h"
#include "image_shim.h"
#include "scene.h"
#include "util.h"

#include <math.h>
#include <string.h>

#define PI_D 3.14159265358979323846

struct vdbgi_sky {
    vdbgi_context *ctx;
    int width, height;
    float *rgb; /* 3 floats a texel, intensity applied, row 0 towards +y */
    float cos_rot, sin_rot;
    uint64_t hash;
};

static uint64_t fnv1a(uint64_t h, const void *data, size_t size)
{
    const unsigned char *const p = data;
    for (size_t i = 0; i < size; i++)
        h = (h ^ p[i]) * 0x100000001B3ull;
    return h;
}

vdbgi_result vdbgi_sky_load(vdbgi_context *ctx, const char *path, float intensity, float rotation,
                            vdbgi_sky **out)
{
    VDBGI_FAIL_IF(ctx, !out || !path, VDBGI_ERR_INVALID_ARG, "no sky map or output given");
    *out = NULL;
    VDBGI_FAIL_IF(ctx, !(intensity > 0.0f) || !(intensity <= VDBGI_MAX_EMISSION),
                  VDBGI_ERR_INVALID_ARG, "sky map intensity must be in (0, 1e6] (got %g)",
                  (double)intensity);
    VDBGI_FAIL_IF(ctx, !isfinite(rotation), VDBGI_ERR_INVALID_ARG,
                  "sky map rotation must be finite degrees (got %g)", (double)rotation);
    VDBGI_TRY(vdbgi_input_check(ctx, path));
    vdbgi_image img;
    VDBGI_TRY(vdbgi_image_decode(ctx, path, NULL, 0, NULL, &img));
    vdbgi_result r = VDBGI_OK;
    vdbgi_sky *s = NULL;
    if (img.width != 2 * img.height) {
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                       "%s: a sky map is equirectangular, twice as wide as high (got %d x %d)",
                       path, img.width, img.height);
        goto fail;
    }
    s = vdbgi_calloc(ctx, 1, sizeof(*s));
    const size_t texels = (size_t)img.width * (size_t)img.height;
    if (!s || !(s->rgb = vdbgi_calloc(ctx, texels, 3 * sizeof(float)))) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto fail;
    }
    size_t bad = 0;
    for (size_t i = 0; i < texels; i++)
        for (int k = 0; k < 3; k++) {
            const float v = img.rgba[4 * i + (size_t)k] * intensity;
            bad += !(v >= 0.0f && v <= VDBGI_MAX_EMISSION);
            s->rgb[3 * i + (size_t)k] = v;
        }
    if (bad) {
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                       "%s: %zu sky map values are negative, not finite or above 1e6", path, bad);
        goto fail;
    }
    s->ctx = ctx;
    s->width = img.width;
    s->height = img.height;
    const double a = rotation * PI_D / 180.0;
    s->cos_rot = (float)cos(a);
    s->sin_rot = (float)sin(a);
    uint64_t h = 0xCBF29CE484222325ull;
    h = fnv1a(h, &s->width, sizeof(s->width));
    h = fnv1a(h, &s->height, sizeof(s->height));
    h = fnv1a(h, s->rgb, texels * 3 * sizeof(float));
    s->hash = fnv1a(h, &rotation, sizeof(rotation));
    vdbgi_free(ctx, img.rgba);
    *out = s;
    return VDBGI_OK;
fail:
    vdbgi_free(ctx, img.rgba);
    if (s)
        vdbgi_free(ctx, s->rgb);
    vdbgi_free(ctx, s);
    return r;
}

void vdbgi_sky_destroy(vdbgi_sky *sky)
{
    if (!sky)
        return;
    vdbgi_free(sky->ctx, sky->rgb);
    vdbgi_free(sky->ctx, sky);
}

uint64_t vdbgi_sky_hash(const vdbgi_sky *sky)
{
    return sky ? sky->hash : 0;
}

void vdbgi_sky_radiance(const vdbgi_sky *s, const float d[3], float rgb[3])
{
    /* Turn the direction back by the rotation: the map turns by it about +y. */
    const float x = s->cos_rot * d[0] + s->sin_rot * d[2];
    const float z = -s->sin_rot * d[0] + s->cos_rot * d[2];
    const float y = fminf(fmaxf(d[1], -1.0f), 1.0f);
    /* u = 0.5 looks down -z, u grows towards +x; v = 0 is straight up. */
    const double u = 0.5 + atan2((double)x, (double)-z) / (2.0 * PI_D);
    const double v = acos((double)y) / PI_D;
    const double fx = u * s->width - 0.5, fy = v * s->height - 0.5;
    const double x0 = floor(fx), y0 = floor(fy);
    const float ax = (float)(fx - x0), ay = (float)(fy - y0);
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    for (int c = 0; c < 4; c++) {
        long xi = (long)x0 + (c & 1), yi = (long)y0 + (c >> 1);
        xi = ((xi % s->width) + s->width) % s->width; /* around the horizon */
        yi = yi < 0 ? 0 : yi >= s->height ? s->height - 1 : yi;
        const float w = (c & 1 ? ax : 1.0f - ax) * (c >> 1 ? ay : 1.0f - ay);
        const float *const t = &s->rgb[3 * ((size_t)yi * (size_t)s->width + (size_t)xi)];
        for (int k = 0; k < 3; k++)
            rgb[k] += w * t[k];
    }
}
