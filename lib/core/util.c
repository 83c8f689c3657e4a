/* util.c: random numbers, little-endian bytes, JSON text and quantiles for the rest of lib/. */
#include "util.h"

#include <math.h>
#include <string.h>

uint64_t vdbgi_splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double vdbgi_uniform01(uint64_t *state)
{
    return (double)(vdbgi_splitmix64(state) >> 11) * (1.0 / 9007199254740992.0);
}

void vdbgi_put_u16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8);
}

void vdbgi_put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16),
    p[3] = (uint8_t)(v >> 24);
}

void vdbgi_put_u64(uint8_t *p, uint64_t v)
{
    vdbgi_put_u32(p, (uint32_t)v);
    vdbgi_put_u32(p + 4, (uint32_t)(v >> 32));
}

void vdbgi_put_f32(uint8_t *p, float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    vdbgi_put_u32(p, v);
}

uint16_t vdbgi_get_u16(const uint8_t *p)
{
    return (uint16_t)(p[0] | p[1] << 8);
}

uint32_t vdbgi_get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/*
 * _Float16 (GCC 12 and later, Clang 15 and later, on x86-64 and AArch64) converts with
 * IEEE rounding (libgcc's routines without F16C).
 */
static uint16_t half_bits(float f)
{
    const _Float16 h = (_Float16)f;
    uint16_t bits;
    memcpy(&bits, &h, sizeof(bits));
    return bits;
}

uint16_t vdbgi_term_encode(float c, float c0)
{
    enum { HALF_NAN = 0x7E00, HALF_INF = 0x7C00, HALF_SIGN = 0x8000 };
    const float bound = 4.0f;
    if (!isfinite(c) || !isfinite(c0))
        return HALF_NAN;
    if (c0 >= 0.0f && c0 < 1e-30f) /* no light to speak of (or floats that underflowed) */
        return 0;
    if (c0 < 0.0f) /* no light gives it: the reader refuses the L0 first */
        return HALF_NAN;
    const float r = c / c0;
    if (fabsf(r) > bound)
        return r < 0.0f ? HALF_SIGN | HALF_INF : HALF_INF;
    return half_bits(r);
}

float vdbgi_term_decode(uint16_t bits, float c0)
{
    _Float16 h;
    memcpy(&h, &bits, sizeof(h));
    return (float)h * c0;
}

void vdbgi_terms_encode(const float c[24], const float c0[3], uint16_t out[24])
{
    for (int k = 0; k < 24; k++)
        out[k] = vdbgi_term_encode(c[k], c0[k % 3]);
}

void vdbgi_terms_decode(const uint16_t h[24], const float c0[3], float out[24])
{
    for (int k = 0; k < 24; k++)
        out[k] = vdbgi_term_decode(h[k], c0[k % 3]);
}

float vdbgi_get_f32(const uint8_t *p)
{
    const uint32_t v = vdbgi_get_u32(p);
    float f;
    memcpy(&f, &v, 4);
    return f;
}

void vdbgi_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        const unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

/* Hoare-partition quickselect with the middle element as pivot: deterministic. */
double vdbgi_quantile(double *a, size_t n, double q)
{
    const size_t k = (size_t)(q * (double)(n - 1));
    size_t lo = 0, hi = n - 1;
    while (lo < hi) {
        const double pivot = a[lo + (hi - lo) / 2];
        size_t i = lo, j = hi;
        while (i <= j) {
            while (a[i] < pivot)
                i++;
            while (a[j] > pivot)
                j--;
            if (i <= j) {
                const double t = a[i];
                a[i] = a[j], a[j] = t;
                i++;
                if (j == 0)
                    break;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break;
    }
    return a[k];
}
