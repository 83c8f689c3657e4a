/*
 * test_encode.c: the texel codecs keep their stated bounds: RGBM decodes
 * within one step of its input and flags what clamps; RGB9E5 within 2^-9 of
 * the largest channel and exact where representable; half floats round to
 * nearest even exactly as the compiler's _Float16 does; bevy-baked-gi's 8-bit
 * shared exponent picks the most precise exponent and stays within half a step.
 */
#include "check.h"
#include "encode.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rng = 0x9E3779B97F4A7C15ull;

static double uniform(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

/* A colour whose channels spread over 1e-4 .. hi on a log scale. */
static void random_colour(float c[3], double hi)
{
    for (int k = 0; k < 3; k++)
        c[k] = (float)(1e-4 * pow(hi / 1e-4, uniform()));
}

static void rgbm_decodes_within_one_step(void)
{
    for (int i = 0; i < 200000; i++) {
        float c[3], d[3];
        uint8_t t[4];
        random_colour(c, 8.0);
        const bool clamped = vdbgi_rgbm_encode(c, 8.0f, t);
        vdbgi_rgbm_decode(t, 8.0f, d);
        const float step = (float)t[3] / 255.0f * 8.0f / 255.0f;
        CHECK(!clamped);
        for (int k = 0; k < 3; k++) {
            /* Round to nearest: half a step; a float of slack for the products. */
            CHECK(fabsf(d[k] - c[k]) <= 0.5f * step * 1.0001f + 1e-7f);
        }
        /* M was rounded up: the largest channel used its full range. */
        const float mx = fmaxf(c[0], fmaxf(c[1], c[2]));
        CHECK((float)t[3] / 255.0f * 8.0f >= mx * 0.99999f);
        if (check_test_failures)
            break;
    }
}

static void rgbm_clamps_above_its_range_and_zeroes_bad_input(void)
{
    const float big[3] = {16.0f, 4.0f, 0.5f};
    uint8_t t[4];
    float d[3];
    CHECK(vdbgi_rgbm_encode(big, 8.0f, t));
    vdbgi_rgbm_decode(t, 8.0f, d);
    CHECK_NEAR(d[0], 8.0, 1e-6);
    CHECK_NEAR(d[1], 4.0, 8.0 / 255 / 2 + 1e-6);
    const float zero[3] = {0, 0, 0}, bad[3] = {NAN, -1.0f, -INFINITY};
    CHECK(!vdbgi_rgbm_encode(zero, 8.0f, t));
    CHECK(t[0] == 0 && t[1] == 0 && t[2] == 0 && t[3] == 0);
    CHECK(!vdbgi_rgbm_encode(bad, 8.0f, t));
    CHECK(t[0] == 0 && t[1] == 0 && t[2] == 0 && t[3] == 0);
    /* The tiniest colour still gets one step of M rather than vanishing. */
    const float tiny[3] = {1e-6f, 0.0f, 0.0f};
    vdbgi_rgbm_encode(tiny, 8.0f, t);
    CHECK(t[3] == 1);
}

static void rgb9e5_is_within_its_precision(void)
{
    for (int i = 0; i < 200000; i++) {
        float c[3], d[3];
        uint32_t w;
        random_colour(c, 1e4);
        CHECK(!vdbgi_rgb9e5_encode(c, &w));
        vdbgi_rgb9e5_decode(w, d);
        const float mx = fmaxf(c[0], fmaxf(c[1], c[2]));
        for (int k = 0; k < 3; k++)
            CHECK(fabsf(d[k] - c[k]) <= mx * (1.0f / 512.0f) + ldexpf(1.0f, -24));
        if (check_test_failures)
            break;
    }
}

static void rgb9e5_is_exact_where_representable_and_clamps(void)
{
    /* Values with <= 9 significant bits and a shared exponent round-trip exactly. */
    const float exact[][3] = {{1.0f, 0.5f, 0.25f},
                              {0.0f, 0.0f, 0.0f},
                              {511.0f, 3.0f, 0.0f},
                              {65408.0f, 128.0f, 256.0f},
                              {0.001953125f, 0.0f, 0.0009765625f}};
    for (size_t i = 0; i < sizeof(exact) / sizeof(exact[0]); i++) {
        uint32_t w;
        float d[3];
        vdbgi_rgb9e5_encode(exact[i], &w);
        vdbgi_rgb9e5_decode(w, d);
        CHECK(memcmp(d, exact[i], sizeof(d)) == 0);
    }
    /* 1.0 is 256 x 2^(16 - 15 - 9): mantissa 256, exponent 16. */
    const float one[3] = {1.0f, 1.0f, 1.0f};
    uint32_t w;
    vdbgi_rgb9e5_encode(one, &w);
    CHECK(w == (256u | 256u << 9 | 256u << 18 | 16u << 27));
    const float over[3] = {1e6f, 1.0f, NAN};
    float d[3];
    CHECK(vdbgi_rgb9e5_encode(over, &w));
    vdbgi_rgb9e5_decode(w, d);
    CHECK(d[0] == 65408.0f && d[2] == 0.0f);
    /* Rounding that carries into the next power of two bumps the exponent. */
    const float carry[3] = {511.75f, 0.0f, 0.0f};
    vdbgi_rgb9e5_encode(carry, &w);
    vdbgi_rgb9e5_decode(w, d);
    CHECK(d[0] == 512.0f);
}

static void half_matches_the_compilers_float16(void)
{
#if defined(__FLT16_MAX__)
    /* Every half decodes to the value _Float16 holds, and encodes back to itself. */
    for (uint32_t h = 0; h < 65536; h++) {
        _Float16 ref;
        const uint16_t bits = (uint16_t)h;
        memcpy(&ref, &bits, 2);
        const float f = vdbgi_half_to_float(bits);
        if (isnan((float)ref)) {
            CHECK(isnan(f));
            continue;
        }
        CHECK(f == (float)ref);
        CHECK(vdbgi_half_from_float(f) == bits);
    }
    /* Arbitrary floats round as the compiler rounds. */
    for (int i = 0; i < 1000000; i++) {
        uint32_t x = (uint32_t)(uniform() * 4294967296.0);
        float f;
        memcpy(&f, &x, 4);
        if (isnan(f))
            continue;
        const _Float16 ref = (_Float16)f;
        uint16_t bits;
        memcpy(&bits, &ref, 2);
        if (vdbgi_half_from_float(f) != bits) {
            fprintf(stderr, "half(%a): got %04x, want %04x\n", (double)f, vdbgi_half_from_float(f),
                    bits);
            CHECK(0);
            break;
        }
    }
#else
    CHECK(vdbgi_half_from_float(1.0f) == 0x3C00 && vdbgi_half_to_float(0x3C00) == 1.0f);
#endif
    CHECK(vdbgi_half_from_float(65520.0f) == 0x7C00);
    CHECK(vdbgi_half_from_float(-0.0f) == 0x8000);
}

static void sharedexp8_keeps_the_most_precision(void)
{
    for (int i = 0; i < 200000; i++) {
        float c[3], d[3];
        uint8_t t[4];
        random_colour(c, 1e4);
        CHECK(!vdbgi_sharedexp8_encode(c, t));
        vdbgi_sharedexp8_decode(t, d);
        const float mx = fmaxf(c[0], fmaxf(c[1], c[2]));
        const float step = ldexpf(1.0f, (int)t[3] - 128) / 255.0f;
        /* The smallest exponent that holds the largest channel: one more and it would not. */
        CHECK(mx <= ldexpf(1.0f, (int)t[3] - 128) && mx > ldexpf(1.0f, (int)t[3] - 129));
        for (int k = 0; k < 3; k++)
            CHECK(fabsf(d[k] - c[k]) <= 0.5f * step * 1.0001f);
        if (check_test_failures)
            break;
    }
    const float zero[3] = {0, 0, 0}, bad[3] = {NAN, -2.0f, -0.0f}, one[3] = {1.0f, 0.5f, 0.25f};
    uint8_t t[4];
    float d[3];
    vdbgi_sharedexp8_encode(zero, t);
    CHECK(t[0] == 0 && t[1] == 0 && t[2] == 0 && t[3] == 0);
    vdbgi_sharedexp8_encode(bad, t);
    CHECK(t[0] == 0 && t[1] == 0 && t[2] == 0 && t[3] == 0);
    vdbgi_sharedexp8_encode(one, t);
    CHECK(t[3] == 128 && t[0] == 255); /* 1.0 = 2^0 x 255/255 */
    vdbgi_sharedexp8_decode(t, d);
    CHECK(d[0] == 1.0f);
    const float huge[3] = {1e38f, 0.0f, 0.0f};
    CHECK(!vdbgi_sharedexp8_encode(huge, t) && t[3] == 255);
    const float inf[3] = {INFINITY, 1.0f, 0.0f};
    CHECK(vdbgi_sharedexp8_encode(inf, t));
}

static void half_keeps_its_precision_from_1e_minus4_to_1e4(void)
{
    for (int i = 0; i < 100000; i++) {
        float c[3];
        random_colour(c, 1e4);
        const float back = vdbgi_half_to_float(vdbgi_half_from_float(c[0]));
        /* Normal halves (>= 2^-14) hold 11 significant bits; below, a fixed 2^-25 step. */
        CHECK(fabsf(back - c[0]) <= fmaxf(c[0] * ldexpf(1.0f, -11), ldexpf(1.0f, -25)));
        if (check_test_failures)
            break;
    }
    CHECK(vdbgi_half_from_float(0.0f) == 0);
}

int main(void)
{
    RUN(rgbm_decodes_within_one_step);
    RUN(rgbm_clamps_above_its_range_and_zeroes_bad_input);
    RUN(rgb9e5_is_within_its_precision);
    RUN(rgb9e5_is_exact_where_representable_and_clamps);
    RUN(half_matches_the_compilers_float16);
    RUN(sharedexp8_keeps_the_most_precision);
    RUN(half_keeps_its_precision_from_1e_minus4_to_1e4);
    return CHECK_EXIT();
}
