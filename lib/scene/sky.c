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
    float *rgb; /* 3 floats a texel, intensity applied, row 0 towards +y; the sun taken out */
    float cos_rot, sin_rot;
    uint64_t hash;
    bool has_sun;
    float sun_dir[3]; /* world, towards the sun */
    float sun_rgb[3]; /* the irradiance it gives a surface facing it */
};

/* Texels brighter than this many times the map's mean radiance (without them) are its sun. */
#define SUN_THRESHOLD 50.0
/* ... if they hold this much of the map's light, within this angle of their centre. */
#define SUN_MIN_SHARE 0.01
#define SUN_MAX_RADIUS_DEG 5.0

/* Texel (x, y)'s direction in the map's frame (the inverse of vdbgi_sky_radiance's). */
static void texel_direction(const vdbgi_sky *s, int x, int y, double d[3])
{
    const double theta = (y + 0.5) / s->height * PI_D;
    const double phi = ((x + 0.5) / s->width - 0.5) * 2.0 * PI_D;
    d[0] = sin(theta) * sin(phi);
    d[1] = cos(theta);
    d[2] = -sin(theta) * cos(phi);
}

static double luminance(const float *c)
{
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

/*
 * Take the map's sun out as a directional lamp: the texels far brighter than
 * the mean keep SUN_THRESHOLD times the mean, and the rest of their light,
 * summed, shines from their light-weighted centre, with a shadow ray, where
 * uniform rays would find it a few times in a thousand (docs/lights.md). Only
 * when they are one compact patch that holds a share of the light worth it.
 */
static void extract_sun(vdbgi_sky *s)
{
    const int w = s->width, h = s->height;
    const double texel = (2.0 * PI_D / w) * (PI_D / h); /* dphi dtheta; times sin(theta) */
    /* The mean, then the mean of what lies under 50 times it: the sun's own light must not
       raise the bar it is measured against. */
    double power = 0.0, limit = INFINITY;
    for (int pass = 0; pass < 2; pass++) {
        double below = 0.0, solid = 0.0;
        for (int y = 0; y < h; y++) {
            const double omega = texel * sin((y + 0.5) / h * PI_D);
            for (int x = 0; x < w; x++) {
                const double l = luminance(&s->rgb[3 * ((size_t)y * (size_t)w + (size_t)x)]);
                if (pass == 0)
                    power += l * omega;
                if (l <= limit)
                    below += l * omega, solid += omega;
            }
        }
        limit = solid > 0.0 ? SUN_THRESHOLD * below / solid : INFINITY;
    }
    double moved = 0.0, centre[3] = {0.0, 0.0, 0.0}, e[3] = {0.0, 0.0, 0.0};
    for (int y = 0; y < h; y++) {
        const double omega = texel * sin((y + 0.5) / h * PI_D);
        for (int x = 0; x < w; x++) {
            const float *const c = &s->rgb[3 * ((size_t)y * (size_t)w + (size_t)x)];
            const double l = luminance(c);
            if (!(l > limit))
                continue;
            double d[3];
            texel_direction(s, x, y, d);
            const double share = (l - limit) / l * omega;
            for (int k = 0; k < 3; k++) {
                centre[k] += (l - limit) * omega * d[k];
                e[k] += c[k] * share;
            }
            moved += (l - limit) * omega;
        }
    }
    const double len = sqrt(centre[0] * centre[0] + centre[1] * centre[1] + centre[2] * centre[2]);
    if (!(moved > SUN_MIN_SHARE * power) || !(len > 0.0))
        return;
    for (int k = 0; k < 3; k++)
        centre[k] /= len;
    const double cos_max = cos(SUN_MAX_RADIUS_DEG * PI_D / 180.0);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double d[3];
            texel_direction(s, x, y, d);
            if (luminance(&s->rgb[3 * ((size_t)y * (size_t)w + (size_t)x)]) > limit &&
                d[0] * centre[0] + d[1] * centre[1] + d[2] * centre[2] < cos_max)
                return; /* bright light spread wide: a sky, not a sun */
        }
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
        float *const c = &s->rgb[3 * i];
        const double l = luminance(c);
        if (l > limit)
            for (int k = 0; k < 3; k++)
                c[k] = (float)(c[k] * (limit / l));
    }
    /* Into the world: the map turns by the rotation about +y. */
    const double cr = s->cos_rot, sr = s->sin_rot;
    s->sun_dir[0] = (float)(cr * centre[0] - sr * centre[2]);
    s->sun_dir[1] = (float)centre[1];
    s->sun_dir[2] = (float)(sr * centre[0] + cr * centre[2]);
    for (int k = 0; k < 3; k++)
        s->sun_rgb[k] = (float)e[k];
    s->has_sun = true;
}

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
    extract_sun(s);
    uint64_t h = 0xCBF29CE484222325ull;
    h = fnv1a(h, &s->width, sizeof(s->width));
    h = fnv1a(h, &s->height, sizeof(s->height));
    h = fnv1a(h, s->rgb, texels * 3 * sizeof(float));
    h = fnv1a(h, s->sun_dir, sizeof(s->sun_dir));
    h = fnv1a(h, s->sun_rgb, sizeof(s->sun_rgb));
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

int vdbgi_sky_sun(const vdbgi_sky *sky, float dir[3], float rgb[3])
{
    if (!sky || !sky->has_sun)
        return 0;
    memcpy(dir, sky->sun_dir, sizeof(sky->sun_dir));
    memcpy(rgb, sky->sun_rgb, sizeof(sky->sun_rgb));
    return 1;
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
