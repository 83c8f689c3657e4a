/* volume_access.c: what a volume gives its users: the sampler's view, samples, its
   figures, and copies of its textures (the indirection as the runtime's columns). */
#include "gifile.h"
#include "volume.h"

#include <string.h>

vdbgi_volume_view vdbgi_volume_view_of(const vdbgi_volume *v)
{
    vdbgi_volume_view view;
    memset(&view, 0, sizeof(view));
    view.encoding = (uint32_t)v->info.encoding;
    view.layout = (uint32_t)v->info.layout;
    view.rgbm_range = v->info.rgbm_range;
    for (int k = 0; k < 3; k++) {
        view.box_min[k] = v->info.box_min[k];
        view.box_max[k] = v->info.box_max[k];
        view.ind_dims[k] = v->info.ind_dims[k];
        view.atlas_dims[k] = v->info.atlas_dims[k];
    }
    view.indirection = v->tex.indirection;
    view.atlas = v->tex.atlas;
    view.sh = v->tex.sh;
    return view;
}

void vdbgi_volume_sample(const vdbgi_volume *v, const float pos[3], float rgb[3])
{
    const vdbgi_volume_view view = vdbgi_volume_view_of(v);
    vdbgi_sampler_sample(&view, pos, rgb);
}

void vdbgi_volume_sample_normal(const vdbgi_volume *v, const float pos[3], const float n[3],
                                float rgb[3])
{
    const vdbgi_volume_view view = vdbgi_volume_view_of(v);
    vdbgi_sampler_sample_normal(&view, pos, n, rgb);
}

/* Column (x, z)'s run: the cells from its lowest to its highest that are not 0,0,0,0. */
static uint32_t column_run(const vdbgi_volume *v, uint32_t x, uint32_t z, uint32_t *ymin)
{
    const uint32_t *const d = v->info.ind_dims;
    uint32_t lo = d[1], hi = 0;
    for (uint32_t y = 0; y < d[1]; y++) {
        const uint8_t *const t = &v->tex.indirection[4 * (((size_t)z * d[1] + y) * d[0] + x)];
        if (t[0] | t[1] | t[2] | t[3]) {
            lo = lo == d[1] ? y : lo;
            hi = y;
        }
    }
    *ymin = lo == d[1] ? 0 : lo;
    return lo == d[1] ? 0 : hi - lo + 1;
}

size_t vdbgi_volume_columns(const vdbgi_volume *v, uint8_t *out, size_t capacity, uint32_t dims[2])
{
    const uint32_t *const d = v->info.ind_dims;
    const size_t n = (size_t)d[0] * d[2];
    size_t total = 2 * n;
    uint32_t ymin;
    for (uint32_t z = 0; z < d[2]; z++)
        for (uint32_t x = 0; x < d[0]; x++)
            total += column_run(v, x, z, &ymin);
    dims[0] = dims[1] = 0;
    if (total > (size_t)VDBGI_COLUMNS_ROW * VDBGI_COLUMNS_ROW)
        return 0;
    const size_t rows = (total + VDBGI_COLUMNS_ROW - 1) / VDBGI_COLUMNS_ROW;
    dims[0] = (uint32_t)((total + rows - 1) / rows);
    dims[1] = (uint32_t)rows;
    const size_t size = 4 * (size_t)dims[0] * dims[1];
    if (!out)
        return size;
    if (capacity < size)
        return 0;
    memset(out, 0, size);
    size_t offset = 0;
    for (uint32_t z = 0; z < d[2]; z++)
        for (uint32_t x = 0; x < d[0]; x++) {
            const uint32_t count = column_run(v, x, z, &ymin);
            uint8_t *const head = &out[8 * ((size_t)z * d[0] + x)];
            const uint8_t h[8] = {(uint8_t)ymin,           (uint8_t)(ymin >> 8),
                                  (uint8_t)count,          (uint8_t)(count >> 8),
                                  (uint8_t)offset,         (uint8_t)(offset >> 8),
                                  (uint8_t)(offset >> 16), 0};
            memcpy(head, h, sizeof(h));
            for (uint32_t k = 0; k < count; k++)
                memcpy(&out[4 * (2 * n + offset + k)],
                       &v->tex.indirection[4 * (((size_t)z * d[1] + ymin + k) * d[0] + x)], 4);
            offset += count;
        }
    return size;
}

void vdbgi_volume_get_info(const vdbgi_volume *v, vdbgi_volume_info *info)
{
    *info = v->info;
    info->columns_size = vdbgi_volume_columns(v, NULL, 0, info->columns_dims);
    info->sh_size = v->info.basis == VDBGI_BASIS_SH2
                        ? v->info.atlas_size / 4 * (size_t)vdbgi_term_bytes(v->version)
                        : 0;
}

size_t vdbgi_volume_copy_columns(const vdbgi_volume *v, void *buffer, size_t capacity)
{
    uint32_t dims[2];
    return vdbgi_volume_columns(v, buffer, capacity, dims);
}

/* meshoptimizer's way: a NULL buffer asks the size, a short one gets nothing. */
static size_t copy_bytes(const void *src, size_t size, void *buffer, size_t capacity)
{
    if (!buffer)
        return size;
    if (capacity < size)
        return 0;
    memcpy(buffer, src, size);
    return size;
}

size_t vdbgi_volume_copy_indirection(const vdbgi_volume *v, void *buffer, size_t capacity)
{
    return copy_bytes(v->tex.indirection, v->info.indirection_size, buffer, capacity);
}

size_t vdbgi_volume_copy_atlas(const vdbgi_volume *v, void *buffer, size_t capacity)
{
    return copy_bytes(v->tex.atlas, v->info.atlas_size, buffer, capacity);
}
