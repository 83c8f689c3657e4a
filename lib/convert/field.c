/* field.c: the filled fine lattice as VDB-shaped leaves, with lookup by position. */
#include "field.h"

#include <math.h>
#include <string.h>

void vdbgi_field_free(vdbgi_field *f)
{
    if (f->ctx) {
        vdbgi_free(f->ctx, f->leaves);
        vdbgi_free(f->ctx, f->values);
        vdbgi_map_free(&f->index);
    }
    memset(f, 0, sizeof(*f));
}

const vdbgi_leaf *vdbgi_field_leaf(const vdbgi_field *f, const int32_t ijk[3])
{
    const int32_t o[3] = {ijk[0] & ~7, ijk[1] & ~7, ijk[2] & ~7};
    const long i = vdbgi_map_find(&f->index, o);
    return i < 0 ? NULL : &f->leaves[i];
}

const float *vdbgi_field_at(const vdbgi_field *f, const int32_t ijk[3], const vdbgi_leaf **cache)
{
    const vdbgi_leaf *l = cache ? *cache : NULL;
    if (!l || l->origin[0] != (ijk[0] & ~7) || l->origin[1] != (ijk[1] & ~7) ||
        l->origin[2] != (ijk[2] & ~7)) {
        l = vdbgi_field_leaf(f, ijk);
        if (cache && l)
            *cache = l;
    }
    if (!l)
        return NULL;
    const unsigned n = (unsigned)(((ijk[0] & 7) << 6) | ((ijk[1] & 7) << 3) | (ijk[2] & 7));
    if (!(l->mask[n >> 6] >> (n & 63) & 1))
        return NULL;
    return l->values + 3 * (size_t)f->channels * n;
}

vdbgi_fill_params vdbgi_fill_params_default(float invalid_threshold, vdbgi_fill fill, int threads)
{
    /* Level-0 cells of 4 probes, a rim of one point for the aprons,
       inverse-squared-distance weights for face, edge and corner neighbours, and the
       darkest fill unless the mean is asked for (docs/stability.md). */
    const vdbgi_fill_params fp = {.invalid_threshold = invalid_threshold,
                                  .cell_size = 4,
                                  .rim = 1,
                                  .filter_below = 1,
                                  .weights = {1.0f, 0.5f, 1.0f / 3.0f},
                                  .max_iterations = 1024,
                                  .darkest = fill != VDBGI_FILL_MEAN,
                                  .threads = threads};
    return fp;
}

/* The body of vdbgi_field_trilinear for ch3 floats a point; inlined with a constant
   ch3 for the scalar field, the converter's hot loop. */
static inline bool trilinear(const vdbgi_field *f, const double pos[3], float *out,
                             const vdbgi_leaf **cache, const int ch3)
{
    int32_t i0[3];
    double fr[3];
    for (int k = 0; k < 3; k++) {
        const double fl = floor(pos[k]);
        i0[k] = (int32_t)fl;
        fr[k] = pos[k] - fl;
    }
    double acc[3 * VDBGI_FIELD_MAX_CHANNELS], wsum = 0.0;
    for (int k = 0; k < ch3; k++)
        acc[k] = 0.0;
    for (int c = 0; c < 8; c++) {
        const double w = (c & 1 ? fr[0] : 1.0 - fr[0]) * (c & 2 ? fr[1] : 1.0 - fr[1]) *
                         (c & 4 ? fr[2] : 1.0 - fr[2]);
        if (w == 0.0)
            continue;
        const int32_t p[3] = {i0[0] + (c & 1), i0[1] + (c >> 1 & 1), i0[2] + (c >> 2 & 1)};
        const float *const v = vdbgi_field_at(f, p, cache);
        if (v) {
            for (int k = 0; k < ch3; k++)
                acc[k] += w * v[k];
            wsum += w;
        }
    }
    if (wsum <= 0.0)
        return false;
    for (int k = 0; k < ch3; k++)
        out[k] = (float)(acc[k] / wsum);
    return true;
}

bool vdbgi_field_trilinear(const vdbgi_field *f, const double pos[3], float *out,
                           const vdbgi_leaf **cache)
{
    return f->channels == 1 ? trilinear(f, pos, out, cache, 3)
                            : trilinear(f, pos, out, cache, 3 * f->channels);
}

int vdbgi_tree_order(const int32_t a[3], const int32_t b[3])
{
    /* Root keys, the two internal levels, leaves (OpenVDB's 5-4-3 tree), then points. */
    static const int32_t blocks[4] = {4096, 128, 8, 1};
    for (int level = 0; level < 4; level++)
        for (int k = 0; k < 3; k++) {
            const int32_t x = vdbgi_floor_div(a[k], blocks[level]);
            const int32_t y = vdbgi_floor_div(b[k], blocks[level]);
            if (x != y)
                return x < y ? -1 : 1;
        }
    return 0;
}
