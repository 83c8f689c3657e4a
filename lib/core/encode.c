/* encode.c: RGBM, RGB9E5 and half-float codecs, exact to their stated bounds. */
#include "encode.h"

#include <math.h>
#include <string.h>

static float sanitise(float c)
{
    return c > 0.0f ? c : 0.0f; /* NaN fails the comparison too */
}

/* min(c, 1) for c that is not NaN; fminf is a call into libm without -ffast-math. */
static float at_most_one(float c)
{
    return c < 1.0f ? c : 1.0f;
}

int vdbgi_rgbm_encode(const float rgb[3], float range, uint8_t out[4])
{
    const float c[3] = {sanitise(rgb[0]), sanitise(rgb[1]), sanitise(rgb[2])};
    const float mx = fmaxf(c[0], fmaxf(c[1], c[2]));
    const bool clamped = mx > range;
    if (!(mx > 0.0f)) {
        memset(out, 0, 4);
        return false;
    }
    /* Round M up (never below one step) so that c / (M range) <= 1 for every channel. */
    float m8 = ceilf(at_most_one(mx / range) * 255.0f);
    m8 = m8 < 1.0f ? 1.0f : m8;
    const float scale = m8 / 255.0f * range;
    for (int k = 0; k < 3; k++)
        out[k] = (uint8_t)lrintf(at_most_one(c[k] / scale) * 255.0f);
    out[3] = (uint8_t)m8;
    return clamped;
}

void vdbgi_rgbm_decode(const uint8_t in[4], float range, float rgb[3])
{
    const float m = (float)in[3] / 255.0f * range;
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)in[k] / 255.0f * m;
}

#define RGB9E5_BITS 9
#define RGB9E5_BIAS 15
#define RGB9E5_MAX_EXP 31
#define RGB9E5_MAX 65408.0f /* (511/512) * 2^(31 - 15) */

int vdbgi_rgb9e5_encode(const float rgb[3], uint32_t *out)
{
    float c[3];
    bool clamped = false;
    for (int k = 0; k < 3; k++) {
        c[k] = sanitise(rgb[k]);
        clamped |= c[k] > RGB9E5_MAX;
        c[k] = fminf(c[k], RGB9E5_MAX);
    }
    const float mx = fmaxf(c[0], fmaxf(c[1], c[2]));
    /* The spec's floor(log2(max)), via frexp (exact, unlike log2f near powers of two). */
    int e2 = 0;
    frexpf(mx, &e2);
    int exp = (mx > 0.0f ? e2 - 1 : -RGB9E5_BIAS - 1);
    if (exp < -RGB9E5_BIAS - 1)
        exp = -RGB9E5_BIAS - 1;
    exp += 1 + RGB9E5_BIAS;
    double denom = ldexp(1.0, exp - RGB9E5_BIAS - RGB9E5_BITS);
    if (floor(mx / denom + 0.5) == (double)(1 << RGB9E5_BITS)) {
        exp += 1; /* rounding carried into the next power of two */
        denom *= 2.0;
    }
    uint32_t m[3];
    for (int k = 0; k < 3; k++)
        m[k] = (uint32_t)floor(c[k] / denom + 0.5);
    *out = m[0] | m[1] << 9 | m[2] << 18 | (uint32_t)exp << 27;
    return clamped;
}

void vdbgi_rgb9e5_decode(uint32_t in, float rgb[3])
{
    const int exp = (int)(in >> 27);
    const float scale = ldexpf(1.0f, exp - RGB9E5_BIAS - RGB9E5_BITS);
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)((in >> (9 * k)) & 511u) * scale;
}

bool vdbgi_sharedexp8_encode(const float rgb[3], uint8_t out[4])
{
    const float c[3] = {sanitise(rgb[0]), sanitise(rgb[1]), sanitise(rgb[2])};
    const float mx = fmaxf(c[0], fmaxf(c[1], c[2]));
    memset(out, 0, 4);
    if (!(mx > 0.0f))
        return false;
    /* mx = m 2^e2 with m in [0.5, 1): 2^e2 holds it, or 2^(e2-1) if m is exactly 0.5. */
    int e2 = 0;
    const float m = frexpf(mx, &e2);
    int e = 128 + (m == 0.5f ? e2 - 1 : e2);
    const bool clamped = e > 255 || !isfinite(mx);
    e = e < 0 ? 0 : (e > 255 ? 255 : e);
    const double scale = ldexp(1.0, e - 128);
    for (int k = 0; k < 3; k++) {
        const double v = (double)c[k] / scale * 255.0;
        out[k] = (uint8_t)(v >= 255.0 ? 255 : (long)floor(v + 0.5));
    }
    out[3] = (uint8_t)e;
    return clamped;
}

void vdbgi_sharedexp8_decode(const uint8_t in[4], float rgb[3])
{
    const float scale = ldexpf(1.0f, (int)in[3] - 128) / 255.0f;
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)in[k] * scale;
}

float vdbgi_srgb_from_linear(float c)
{
    c = c > 0.0f ? (c < 1.0f ? c : 1.0f) : 0.0f;
    return c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
}

uint16_t vdbgi_half_from_float(float f)
{
    uint32_t x;
    memcpy(&x, &f, 4);
    const uint32_t sign = (x >> 16) & 0x8000u;
    const uint32_t abs = x & 0x7FFFFFFFu;
    if (abs > 0x7F800000u) /* NaN: keep it a quiet NaN */
        return (uint16_t)(sign | 0x7E00u);
    if (abs >= 0x477FF000u) /* rounds to at least 65520: infinity */
        return (uint16_t)(sign | 0x7C00u);
    if (abs < 0x38800000u) {                    /* below 2^-14: subnormal or zero */
        const float a = fabsf(f) * 16777216.0f; /* in units of 2^-24, rounded to even */
        return (uint16_t)(sign | (uint32_t)lrintf(a));
    }
    /* Normal: rebias the exponent, round the 13 dropped bits to nearest even. */
    const uint32_t mant = abs & 0x7FFFFFu;
    uint32_t h = ((abs >> 23) - 112u) << 10 | mant >> 13;
    const uint32_t rest = mant & 0x1FFFu;
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u)))
        h++;
    return (uint16_t)(sign | h);
}

float vdbgi_half_to_float(uint16_t h)
{
    const uint32_t sign = (uint32_t)(h & 0x8000u) << 16;
    const uint32_t exp = (h >> 10) & 0x1Fu, mant = h & 0x3FFu;
    float f;
    if (exp == 0) {
        f = ldexpf((float)mant, -24);
        uint32_t x;
        memcpy(&x, &f, 4);
        x |= sign;
        memcpy(&f, &x, 4);
        return f;
    }
    const uint32_t x =
        sign | (exp == 31 ? 0x7F800000u | mant << 13 : (exp + 112u) << 23 | mant << 13);
    memcpy(&f, &x, 4);
    return f;
}

/*
 * With stored c_k = w_k mean(L p_k) and c_0 = mean(L), L >= 0: |c_k| <= w_k
 * max|p_k| c_0. The weights are estimate.c's vdbgi_sh2_weights; the term
 * bounds 1 (x, y, z), 1/2 (xy, yz, xz), 2 (3z^2 - 1) and 1 (x^2 - y^2).
 */
float vdbgi_sh_ratio_range(int term)
{
    static const float range[8] = {2.0f, 2.0f, 2.0f, 1.875f, 1.875f, 0.625f, 1.875f, 0.9375f};
    return range[term];
}

int8_t vdbgi_sh_ratio_encode(float term_value, float l0, int term, int step)
{
    if (!(l0 > 0.0f) || !isfinite(term_value))
        return 0;
    float r = term_value / l0 / vdbgi_sh_ratio_range(term);
    r = r > 1.0f ? 1.0f : r < -1.0f ? -1.0f : r;
    const long most = 127 / step * step;
    const long q = step * lrintf(r * 127.0f / (float)step);
    return (int8_t)(q > most ? most : q < -most ? -most : q);
}
