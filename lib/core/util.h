/* util.h: small helpers lib/ shares: random numbers, little-endian bytes, JSON text, quantiles. */
#ifndef VDBGI_UTIL_H
#define VDBGI_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* SplitMix64: the next number of the stream *state (Steele, Lea and Flood 2014). */
uint64_t vdbgi_splitmix64(uint64_t *state);
/* A double in [0, 1) from the top 53 bits of the next splitmix64. */
double vdbgi_uniform01(uint64_t *state);

/*
 * The probes' L2 terms as they are held (probes.h): each term's channel c as
 * its ratio to L0's channel c0, in an IEEE 754 half float (11 bits, rounded
 * to nearest even). Light that is nowhere negative keeps every ratio within
 * +-2 (docs/format.md's ranges), and the bake's noise is far above 2^-11, so
 * a probe's 24 terms take 48 bytes instead of 96. L0 under 1e-30 keeps no
 * terms (0). What no such light gives encodes for a reader to refuse: a
 * ratio beyond +-4 as +-infinity, a term that is not finite (or a negative
 * L0) as NaN.
 */
uint16_t vdbgi_term_encode(float c, float c0);
/* The term back: the ratio times c0 (a NaN ratio stays NaN; decode with c0 = 1 to test). */
float vdbgi_term_decode(uint16_t h, float c0);
/* A probe's 24 terms (c1..c8 x RGB) against its L0 c0[3], each as above. */
void vdbgi_terms_encode(const float c[24], const float c0[3], uint16_t out[24]);
void vdbgi_terms_decode(const uint16_t h[24], const float c0[3], float out[24]);

/* Little-endian stores and loads (file formats are little-endian whatever the host). */
void vdbgi_put_u16(uint8_t *p, uint16_t v);
void vdbgi_put_u32(uint8_t *p, uint32_t v);
void vdbgi_put_u64(uint8_t *p, uint64_t v);
void vdbgi_put_f32(uint8_t *p, float f);
uint16_t vdbgi_get_u16(const uint8_t *p);
uint32_t vdbgi_get_u32(const uint8_t *p);
float vdbgi_get_f32(const uint8_t *p);

/* s as a JSON string, quotes included: quotes, backslashes and control characters escaped. */
void vdbgi_json_string(FILE *f, const char *s);

/* The q-quantile (0..1) of a[0..n-1], n >= 1, as the element at floor(q (n - 1)); reorders a. */
double vdbgi_quantile(double *a, size_t n, double q);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_UTIL_H */
