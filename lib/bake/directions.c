/*
 * directions.c: the estimator's direction sets: seed 000's spherical
 * Fibonacci set (a ladder of its sizes for adaptive bakes), its cosine-
 * weighted hemisphere, and the random rotation a probe's own stream gives
 * it, seeded from the probe alone.
 */
#include "estimate.h"
#include "util.h"

#include <math.h>

#define PI_F 3.14159265358979f

/*
 * Spherical Fibonacci set: z evenly spaced in (-1, 1), azimuth advancing by
 * the golden angle, so every direction stands for the same solid angle.
 */
void vdbgi_fibonacci_directions(int n, float *dirs)
{
    const double golden = PI_F * (3.0 - sqrt(5.0));
    for (int i = 0; i < n; i++) {
        const double z = 1.0 - (2.0 * i + 1.0) / n;
        const double r = sqrt(1.0 - z * z);
        const double phi = golden * i;
        dirs[3 * i + 0] = (float)(r * cos(phi));
        dirs[3 * i + 1] = (float)z;
        dirs[3 * i + 2] = (float)(r * sin(phi));
    }
}

uint64_t vdbgi_point_stream(int32_t i, int32_t j, int32_t k, uint64_t seed)
{
    uint64_t s = seed ^ ((uint64_t)(uint32_t)i * 0x8CB92BA72F3D8DD7ull) ^
                 ((uint64_t)(uint32_t)j * 0xAB8F3B2A1F7C5D93ull) ^
                 ((uint64_t)(uint32_t)k * 0xD1B54A32D192ED03ull);
    return vdbgi_splitmix64(&s);
}

/* Uniformly random rotation (Shoemake's quaternion from three uniforms). */
static void random_rotation(uint64_t stream, float m[9])
{
    const double u1 = vdbgi_uniform01(&stream), u2 = vdbgi_uniform01(&stream),
                 u3 = vdbgi_uniform01(&stream);
    const double a = sqrt(1.0 - u1), b = sqrt(u1);
    const double x = a * sin(2.0 * PI_F * u2), y = a * cos(2.0 * PI_F * u2);
    const double z = b * sin(2.0 * PI_F * u3), w = b * cos(2.0 * PI_F * u3);
    m[0] = (float)(1 - 2 * (y * y + z * z)), m[1] = (float)(2 * (x * y - z * w));
    m[2] = (float)(2 * (x * z + y * w)), m[3] = (float)(2 * (x * y + z * w));
    m[4] = (float)(1 - 2 * (x * x + z * z)), m[5] = (float)(2 * (y * z - x * w));
    m[6] = (float)(2 * (x * z - y * w)), m[7] = (float)(2 * (y * z + x * w));
    m[8] = (float)(1 - 2 * (x * x + y * y));
}

void vdbgi_directions_rotate(uint64_t stream, const float *base, int n, float *out)
{
    float m[9];
    random_rotation(stream, m);
    for (int i = 0; i < n; i++) {
        const float *const d = &base[3 * i];
        for (int r = 0; r < 3; r++)
            out[3 * i + r] = m[3 * r] * d[0] + m[3 * r + 1] * d[1] + m[3 * r + 2] * d[2];
    }
}

void vdbgi_hemisphere_directions(int n, float *dirs)
{
    const double golden = 3.14159265358979323846 * (3.0 - sqrt(5.0));
    for (int i = 0; i < n; i++) {
        const double r = sqrt((i + 0.5) / n), phi = golden * i;
        dirs[3 * i] = (float)(r * cos(phi));
        dirs[3 * i + 1] = (float)(r * sin(phi));
        dirs[3 * i + 2] = (float)sqrt(fmax(0.0, 1.0 - r * r));
    }
}

/*
 * The ladder of an adaptive point's second set: whole pilots up to
 * VDBGI_ADAPTIVE_FINE rays in all, then doublings of the whole.
 */
static int ladder_next(int size)
{
    const int B = VDBGI_ADAPTIVE_BATCH;
    return size + 2 * B <= VDBGI_ADAPTIVE_FINE ? size + B : 2 * (size + B) - B;
}

int vdbgi_adaptive_set(int n, int max_rays, int *offset)
{
    const int most = max_rays - VDBGI_ADAPTIVE_BATCH;
    int size = VDBGI_ADAPTIVE_BATCH, at = 0;
    while (size < n && size < most)
        at += size, size = ladder_next(size);
    *offset = at;
    return size;
}

vdbgi_result vdbgi_estimator_directions(vdbgi_context *ctx, const vdbgi_bake_params *bp,
                                        bool hemisphere, float **dirs, int *count)
{
    int total = bp->rays, largest = bp->rays;
    if (bp->adaptive) /* every set of the ladder, one after the other (the first the pilot) */
        largest = vdbgi_adaptive_set(bp->max_rays, bp->max_rays, &total), total += largest;
    float *const d = vdbgi_calloc(ctx, (size_t)total, 3 * sizeof(float));
    if (!d)
        return VDBGI_ERR_OUT_OF_MEMORY;
    void (*const set)(int, float *) =
        hemisphere ? vdbgi_hemisphere_directions : vdbgi_fibonacci_directions;
    if (bp->adaptive)
        for (int at = 0, size = VDBGI_ADAPTIVE_BATCH; at < total;
             at += size, size = ladder_next(size))
            set(size, &d[3 * at]);
    else
        set(total, d);
    *dirs = d;
    *count = largest;
    return VDBGI_OK;
}
