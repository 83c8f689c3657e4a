/* ktx2.h: a minimal KTX 2.0 writer for one uncompressed image (no mips, layers or faces). */
#ifndef VDBGI_KTX2_H
#define VDBGI_KTX2_H

#include "context.h"

/* The two formats vdbgi writes (VkFormat values). */
#define VDBGI_VK_FORMAT_R16G16B16A16_SFLOAT 97
#define VDBGI_VK_FORMAT_E5B9G9R9_UFLOAT_PACK32 123

/*
 * Encode a width x height x depth texture (depth 1 for 2D) of the given
 * VkFormat, texels x fastest, into a KTX 2.0 file in memory: identifier,
 * header, level index, a Basic Data Format Descriptor, one key/value
 * (KTXwriter) and the level. *out is allocated through ctx.
 */
vdbgi_result vdbgi_ktx2_encode(vdbgi_context *ctx, uint32_t vk_format, uint32_t width,
                               uint32_t height, uint32_t depth, const void *texels, uint8_t **out,
                               size_t *out_size);

#endif /* VDBGI_KTX2_H */
