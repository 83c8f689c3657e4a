/* encode.h: texel codecs (RGBM, RGB9E5, half float); pure functions, no state. */
#ifndef VDBGI_ENCODE_H
#define VDBGI_ENCODE_H

#include <stdbool.h>
#include <stdint.h>

/*
 * RGBM with multiplier range `range`: M = ceil(255 max(r,g,b)/range)/255,
 * rgb = round(255 c / (M range))/255. Rounding M up keeps every channel in
 * [0, 1], so decoding lands within half a step (M range / 510) of the input.
 * Negative and NaN channels encode as 0; colours brighter than range clamp
 * (the return value says so).
 */
bool vdbgi_rgbm_encode(const float rgb[3], float range, uint8_t out[4]);
void vdbgi_rgbm_decode(const uint8_t in[4], float range, float rgb[3]);

/*
 * RGB9E5 (EXT_texture_shared_exponent, WebGPU rgb9e5ufloat): 9-bit
 * mantissas, one 5-bit exponent, bias 15; r in bits 0-8, g 9-17, b 18-26,
 * exponent 27-31. Largest value 65408; relative error <= 2^-9 of the
 * largest channel. Negative and NaN channels encode as 0; larger values clamp
 * (the return value says so).
 */
bool vdbgi_rgb9e5_encode(const float rgb[3], uint32_t *out);
void vdbgi_rgb9e5_decode(uint32_t in, float rgb[3]);

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

/* IEEE 754 binary16, round to nearest even; overflow goes to infinity. */
/* The sRGB transfer function of a linear value clamped to [0, 1] (NaN gives 0), for 8-bit
   images people look at. */
float vdbgi_srgb_from_linear(float c);

uint16_t vdbgi_half_from_float(float f);
float vdbgi_half_to_float(uint16_t h);

#endif /* VDBGI_ENCODE_H */
