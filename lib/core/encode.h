/* encode.h: texel codecs (RGBM, RGB9E5, half float); pure functions, no state. */
#ifndef VDBGI_ENCODE_H
#define VDBGI_ENCODE_H

#include "vdbgi.h"

#include <stdbool.h>
#include <stdint.h>

/* RGBM and RGB9E5, the .gi texels: declared in vdbgi.h (tools that write texels use them). */

/*
 * bevy-baked-gi's 8-bit shared exponent (seed 002): C = 2^(a - 128) (r, g, b) / 255
 * with bytes r, g, b, a. The exponent is the smallest that holds the largest
 * channel, which keeps the most precision: decoding lands within half a step,
 * 2^(a-128)/510, that is within 1/255 of the largest channel. Negative and NaN
 * channels encode as 0; zero is (0, 0, 0, 0); beyond 2^127 clamps (the
 * return value says so).
 */
bool vdbgi_sharedexp8_encode(const float rgb[3], uint8_t out[4]);
void vdbgi_sharedexp8_decode(const uint8_t in[4], float rgb[3]);

/*
 * An L2 term as the .gi stores it (docs/format.md, "Version 6"): its ratio
 * to L0, term / l0, in 127ths of the term's largest possible ratio
 * (vdbgi_sh_ratio_range; radiance is never negative, so no honest ratio
 * exceeds it), rounded to even to a multiple of step (1, 2, 4 ...; 1 keeps
 * every byte) within +-127; 0 where l0 is not positive. A reader decodes it
 * as a snorm8 texel: max(q / 127, -1) times the range (sampler.c).
 */
float vdbgi_sh_ratio_range(int term);
int8_t vdbgi_sh_ratio_encode(float term_value, float l0, int term, int step);

/* Rec. 709's luminance of a linear colour: .gi version 8's one ratio for terms 4-8. */
static inline float vdbgi_luminance(const float c[3])
{
    return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2];
}

/* IEEE 754 binary16, round to nearest even; overflow goes to infinity. */
/* The sRGB transfer function of a linear value clamped to [0, 1] (NaN gives 0), for 8-bit
   images people look at. */
float vdbgi_srgb_from_linear(float c);

uint16_t vdbgi_half_from_float(float f);
float vdbgi_half_to_float(uint16_t h);

#endif /* VDBGI_ENCODE_H */
