/* textures.c: the runtime textures' one allocation. */
#include "textures.h"

#include <string.h>

void vdbgi_textures_adopt(vdbgi_textures *t, uint8_t *block, const uint32_t ind_dims[3],
                          const uint32_t atlas_dims[3])
{
    memcpy(t->ind_dims, ind_dims, sizeof(t->ind_dims));
    memcpy(t->atlas_dims, atlas_dims, sizeof(t->atlas_dims));
    t->indirection = block;
    t->atlas = block + 4 * vdbgi_texels(ind_dims);
}

vdbgi_result vdbgi_textures_alloc(vdbgi_context *ctx, vdbgi_textures *t, const uint32_t ind_dims[3],
                                  const uint32_t atlas_dims[3])
{
    const size_t ind = 4 * vdbgi_texels(ind_dims), atlas = 4 * vdbgi_texels(atlas_dims);
    VDBGI_FAIL_IF(ctx, ind > UINT32_MAX || atlas > UINT32_MAX, VDBGI_ERR_OUT_OF_MEMORY,
                  "textures of %zu + %zu bytes exceed the format's 4 GiB", ind, atlas);
    uint8_t *const block = vdbgi_calloc(ctx, ind + atlas, 1);
    if (!block)
        return VDBGI_ERR_OUT_OF_MEMORY;
    vdbgi_textures_free(ctx, t);
    vdbgi_textures_adopt(t, block, ind_dims, atlas_dims);
    return VDBGI_OK;
}

vdbgi_result vdbgi_textures_alloc_sh(vdbgi_context *ctx, vdbgi_textures *t)
{
    int8_t *const sh = vdbgi_calloc(ctx, vdbgi_texels(t->atlas_dims), 24);
    if (!sh)
        return VDBGI_ERR_OUT_OF_MEMORY;
    vdbgi_free(ctx, t->sh);
    t->sh = sh;
    return VDBGI_OK;
}

void vdbgi_textures_free(vdbgi_context *ctx, vdbgi_textures *t)
{
    vdbgi_free(ctx, t->sh);
    vdbgi_free(ctx, t->indirection);
    memset(t, 0, sizeof(*t));
}
