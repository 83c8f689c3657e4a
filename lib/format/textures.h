/*
 * textures.h: the runtime textures as one small object: the indirection (4
 * bytes a level-0 cell) and the atlas (4 bytes a texel), x fastest, in one
 * allocation. A layout fills them (atlas.c, packed.c); the file code never
 * sees them but as bytes.
 */
#ifndef VDBGI_TEXTURES_H
#define VDBGI_TEXTURES_H

#include "context.h"

typedef struct vdbgi_textures {
    uint32_t ind_dims[3];   /* cells */
    uint32_t atlas_dims[3]; /* texels */
    uint8_t *indirection;   /* 4 x cells bytes, then the atlas's: one block */
    uint8_t *atlas;
    int8_t *sh; /* L2 terms, or NULL: 24 a texel (term-major, RGB), a ratio to L0 in 127ths
                   of the term's range (docs/format.md, "Version 6"); a block of its own */
} vdbgi_textures;

static inline size_t vdbgi_texels(const uint32_t d[3])
{
    return (size_t)d[0] * d[1] * d[2];
}

/*
 * Zeroed textures of those sizes (an empty cell and texel are 0, 0, 0, 0),
 * replacing what t held. VDBGI_ERR_OUT_OF_MEMORY past what the format's
 * sizes (u32 bytes each) can say.
 */
vdbgi_result vdbgi_textures_alloc(vdbgi_context *ctx, vdbgi_textures *t, const uint32_t ind_dims[3],
                                  const uint32_t atlas_dims[3]);

/*
 * Textures over a block already holding the indirection's bytes, then the
 * atlas's (as a .gi of textures stores them): t takes the block, which must
 * come from ctx's allocator and hold both.
 */
void vdbgi_textures_adopt(vdbgi_textures *t, uint8_t *block, const uint32_t ind_dims[3],
                          const uint32_t atlas_dims[3]);

/* The L2 terms' texels (zeroed) beside t's atlas, replacing any. */
vdbgi_result vdbgi_textures_alloc_sh(vdbgi_context *ctx, vdbgi_textures *t);
void vdbgi_textures_free(vdbgi_context *ctx, vdbgi_textures *t);

#endif /* VDBGI_TEXTURES_H */
