/* field.c: the filled fine lattice as VDB-shaped leaves, with lookup by position. */
#include "internal.h"

#include <math.h>
#include <string.h>

vdbgi_result vdbgi_field_alloc(vdbgi_context *ctx, size_t leaf_count, vdbgi_field *out)
{
    memset(out, 0, sizeof(*out));
    out->ctx = ctx;
    VDBGI_FAIL_IF(ctx, leaf_count >= UINT32_MAX / 4, VDBGI_ERR_OUT_OF_MEMORY,
                  "%zu leaves is more than a field can index", leaf_count);
    size_t size = 16;
    while (size < 2 * leaf_count)
        size *= 2;
    /* Not zeroed: the caller writes every field of every leaf (and zeroing 6 kB a leaf shows). */
    out->leaves = leaf_count > SIZE_MAX / sizeof(vdbgi_leaf)
                      ? NULL
                      : vdbgi_alloc(ctx, (leaf_count ? leaf_count : 1) * sizeof(vdbgi_leaf));
    out->table = vdbgi_calloc(ctx, size, sizeof(uint32_t));
    if (!out->leaves || !out->table) {
        vdbgi_field_free(out);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    out->leaf_count = leaf_count;
    out->table_size = size;
    return VDBGI_OK;
}

void vdbgi_field_free(vdbgi_field *f)
{
    if (f->ctx) {
        vdbgi_free(f->ctx, f->leaves);
        vdbgi_free(f->ctx, f->table);
    }
    memset(f, 0, sizeof(*f));
}

static size_t hash_origin(const int32_t o[3])
{
    /* Origins are multiples of 8: drop those bits, then mix. */
    uint64_t h = (uint64_t)(uint32_t)(o[0] >> 3) * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)(uint32_t)(o[1] >> 3) * 0xC2B2AE3D27D4EB4Full;
    h ^= (uint64_t)(uint32_t)(o[2] >> 3) * 0x165667B19E3779F9ull;
    return (size_t)(h ^ (h >> 29));
}

void vdbgi_field_index(vdbgi_field *f)
{
    const size_t mask = f->table_size - 1;
    memset(f->table, 0, f->table_size * sizeof(uint32_t));
    for (size_t i = 0; i < f->leaf_count; i++) {
        size_t slot = hash_origin(f->leaves[i].origin) & mask;
        while (f->table[slot])
            slot = (slot + 1) & mask;
        f->table[slot] = (uint32_t)i + 1;
    }
}

const vdbgi_leaf *vdbgi_field_leaf(const vdbgi_field *f, const int32_t ijk[3])
{
    const int32_t o[3] = {ijk[0] & ~7, ijk[1] & ~7, ijk[2] & ~7};
    const size_t mask = f->table_size - 1;
    for (size_t slot = hash_origin(o) & mask; f->table[slot]; slot = (slot + 1) & mask) {
        const vdbgi_leaf *const l = &f->leaves[f->table[slot] - 1];
        if (l->origin[0] == o[0] && l->origin[1] == o[1] && l->origin[2] == o[2])
            return l;
    }
    return NULL;
}

bool vdbgi_field_get(const vdbgi_field *f, const int32_t ijk[3], float rgb[3])
{
    return vdbgi_field_get_cached(f, ijk, rgb, NULL);
}

bool vdbgi_field_get_cached(const vdbgi_field *f, const int32_t ijk[3], float rgb[3],
                            const vdbgi_leaf **cache)
{
    const vdbgi_leaf *l = cache ? *cache : NULL;
    if (!l || l->origin[0] != (ijk[0] & ~7) || l->origin[1] != (ijk[1] & ~7) ||
        l->origin[2] != (ijk[2] & ~7)) {
        l = vdbgi_field_leaf(f, ijk);
        if (cache && l)
            *cache = l;
    }
    if (!l)
        return false;
    const unsigned n = (unsigned)(((ijk[0] & 7) << 6) | ((ijk[1] & 7) << 3) | (ijk[2] & 7));
    if (!(l->mask[n >> 6] >> (n & 63) & 1))
        return false;
    memcpy(rgb, l->rgb[n], 3 * sizeof(float));
    return true;
}

vdbgi_fill_params vdbgi_fill_params_default(float invalid_threshold, vdbgi_fill fill)
{
    /* Level-0 cells of 4 probes, the one-cell margin, a rim of one point for the aprons,
       inverse-squared-distance weights for face, edge and corner neighbours, and the
       darkest fill unless the mean is asked for (docs/stability.md). */
    const vdbgi_fill_params fp = {.invalid_threshold = invalid_threshold, .cell_size = 4,
                                  .margin_cells = 1, .rim = 1,
                                  .weights = {1.0f, 0.5f, 1.0f / 3.0f}, .max_iterations = 1024,
                                  .darkest = fill != VDBGI_FILL_MEAN};
    return fp;
}

bool vdbgi_field_trilinear(const vdbgi_field *f, const double pos[3], float rgb[3],
                           const vdbgi_leaf **cache)
{
    int32_t i0[3];
    double fr[3];
    for (int k = 0; k < 3; k++) {
        const double fl = floor(pos[k]);
        i0[k] = (int32_t)fl;
        fr[k] = pos[k] - fl;
    }
    double acc[3] = {0.0, 0.0, 0.0}, wsum = 0.0;
    for (int c = 0; c < 8; c++) {
        const double w = (c & 1 ? fr[0] : 1.0 - fr[0]) * (c & 2 ? fr[1] : 1.0 - fr[1]) *
                         (c & 4 ? fr[2] : 1.0 - fr[2]);
        if (w == 0.0)
            continue;
        const int32_t p[3] = {i0[0] + (c & 1), i0[1] + (c >> 1 & 1), i0[2] + (c >> 2 & 1)};
        float v[3];
        if (vdbgi_field_get_cached(f, p, v, cache)) {
            for (int k = 0; k < 3; k++)
                acc[k] += w * v[k];
            wsum += w;
        }
    }
    if (wsum <= 0.0)
        return false;
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)(acc[k] / wsum);
    return true;
}
