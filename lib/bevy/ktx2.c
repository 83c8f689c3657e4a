/*
 * ktx2.c: KTX 2.0 files (Khronos KTX File Format Specification 2.0) for one
 * uncompressed level, written by hand since no Debian package writes them.
 * Layout: identifier (12 bytes), header (36), index (32), one level index
 * entry (24), the Data Format Descriptor, the key/value data, padding to the
 * texel size, the level. Tested against the npm package ktx-parse.
 */
#include "ktx2.h"
#include "util.h"

#include <stdio.h>
#include <string.h>

static const uint8_t ktx2_identifier[12] = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                            '0',  0xBB, '\r', '\n', 0x1A, '\n'};

/* One sample of a Basic Data Format Descriptor block (16 bytes). */
static void put_sample(uint8_t *p, uint16_t bit_offset, uint8_t bit_length, uint8_t channel,
                       uint32_t lower, uint32_t upper)
{
    vdbgi_put_u16(p, bit_offset);
    p[2] = (uint8_t)(bit_length - 1); /* stored as length - 1 */
    p[3] = channel;                   /* channel id | qualifier bits */
    vdbgi_put_u32(p + 4, 0);          /* sample position 0,0,0,0 */
    vdbgi_put_u32(p + 8, lower);
    vdbgi_put_u32(p + 12, upper);
}

/* Khronos Data Format constants used below. */
enum {
    DF_MODEL_RGBSDA = 1,
    DF_PRIMARIES_BT709 = 1,
    DF_TRANSFER_LINEAR = 1,
    DF_CHANNEL_R = 0,
    DF_CHANNEL_G = 1,
    DF_CHANNEL_B = 2,
    DF_CHANNEL_A = 15,
    DF_QUALIFIER_EXPONENT = 0x20,
    DF_QUALIFIER_SIGNED = 0x40,
    DF_QUALIFIER_FLOAT = 0x80
};

/* Write the DFD (its total size, then one basic block) into p; returns its size. */
static uint32_t write_dfd(uint8_t *p, uint32_t vk_format)
{
    const bool rgb9e5 = vk_format == VDBGI_VK_FORMAT_E5B9G9R9_UFLOAT_PACK32;
    const uint32_t samples = rgb9e5 ? 6 : 4;
    const uint32_t block = 24 + 16 * samples;
    vdbgi_put_u32(p, 4 + block);
    uint8_t *const b = p + 4;
    vdbgi_put_u32(b, 0);     /* vendor 0 (Khronos), descriptor type 0 (basic) */
    vdbgi_put_u16(b + 4, 2); /* version 2 (KDF 1.3) */
    vdbgi_put_u16(b + 6, (uint16_t)block);
    b[8] = DF_MODEL_RGBSDA;
    b[9] = DF_PRIMARIES_BT709;
    b[10] = DF_TRANSFER_LINEAR;
    b[11] = 0;                /* alpha straight */
    vdbgi_put_u32(b + 12, 0); /* texel block 1 x 1 x 1 x 1 */
    memset(b + 16, 0, 8);
    b[16] = rgb9e5 ? 4 : 8; /* bytes of plane 0: one texel */
    uint8_t *s = b + 24;
    if (rgb9e5) {
        /* Per channel a 9-bit mantissa (1.0 = 256 at exponent 15, upper 8448 as the
           Khronos tools write) and the shared 5-bit exponent (bias 15). */
        static const uint8_t channel[3] = {DF_CHANNEL_R, DF_CHANNEL_G, DF_CHANNEL_B};
        for (int c = 0; c < 3; c++) {
            put_sample(s, (uint16_t)(9 * c), 9, channel[c], 0, 8448);
            put_sample(s + 16, 27, 5, channel[c] | DF_QUALIFIER_EXPONENT, 15, 31);
            s += 32;
        }
    } else {
        /* Four signed half floats; float samples' limits are -1.0f and 1.0f. */
        static const uint8_t channel[4] = {DF_CHANNEL_R, DF_CHANNEL_G, DF_CHANNEL_B, DF_CHANNEL_A};
        for (int c = 0; c < 4; c++, s += 16)
            put_sample(s, (uint16_t)(16 * c), 16,
                       channel[c] | DF_QUALIFIER_FLOAT | DF_QUALIFIER_SIGNED, 0xBF800000u,
                       0x3F800000u);
    }
    return 4 + block;
}

static size_t align_up(size_t v, size_t a)
{
    return (v + a - 1) / a * a;
}

vdbgi_result vdbgi_ktx2_encode(vdbgi_context *ctx, uint32_t vk_format, uint32_t width,
                               uint32_t height, uint32_t depth, const void *texels, uint8_t **out,
                               size_t *out_size)
{
    *out = NULL;
    *out_size = 0;
    VDBGI_FAIL_IF(ctx,
                  vk_format != VDBGI_VK_FORMAT_R16G16B16A16_SFLOAT &&
                      vk_format != VDBGI_VK_FORMAT_E5B9G9R9_UFLOAT_PACK32,
                  VDBGI_ERR_INVALID_ARG, "ktx2: unsupported VkFormat %u", vk_format);
    VDBGI_FAIL_IF(ctx, !width || !height || !depth, VDBGI_ERR_INVALID_ARG,
                  "ktx2: empty texture %ux%ux%u", width, height, depth);
    const uint32_t texel_size = vk_format == VDBGI_VK_FORMAT_E5B9G9R9_UFLOAT_PACK32 ? 4 : 8;
    const size_t level_size = (size_t)width * height * depth * texel_size;

    static const char kv_key[] = "KTXwriter";
    char kv_value[64];
    snprintf(kv_value, sizeof(kv_value), "vdbgi %s", vdbgi_version_string());
    const uint32_t kv_length = (uint32_t)(sizeof(kv_key) + strlen(kv_value) + 1);

    /* identifier 12 + header 36 + index 32 = 80, then one 24-byte level index entry. */
    const size_t dfd_offset = 80 + 24;
    const size_t dfd_size = 4 + 24 + 16 * (texel_size == 4 ? 6 : 4);
    const size_t kvd_offset = dfd_offset + dfd_size;
    const size_t kvd_size = align_up(4 + kv_length, 4);
    /* The level starts at a multiple of lcm(texel size, 4). */
    const size_t level_offset = align_up(kvd_offset + kvd_size, texel_size);
    const size_t total = level_offset + level_size;
    uint8_t *const f = vdbgi_calloc(ctx, total, 1);
    if (!f)
        return VDBGI_ERR_OUT_OF_MEMORY;

    memcpy(f, ktx2_identifier, 12);
    vdbgi_put_u32(f + 12, vk_format);
    vdbgi_put_u32(f + 16, texel_size == 4 ? 4 : 2); /* typeSize: bytes of the format's data type */
    vdbgi_put_u32(f + 20, width);
    vdbgi_put_u32(f + 24, height);
    vdbgi_put_u32(f + 28, depth == 1 ? 0 : depth); /* 0 marks a 2D texture */
    vdbgi_put_u32(f + 32, 0);                      /* layerCount: not an array */
    vdbgi_put_u32(f + 36, 1);                      /* faceCount */
    vdbgi_put_u32(f + 40, 1);                      /* levelCount */
    vdbgi_put_u32(f + 44, 0);                      /* supercompressionScheme: none */
    vdbgi_put_u32(f + 48, (uint32_t)dfd_offset);
    vdbgi_put_u32(f + 52, (uint32_t)dfd_size);
    vdbgi_put_u32(f + 56, (uint32_t)kvd_offset);
    vdbgi_put_u32(f + 60, (uint32_t)kvd_size);
    vdbgi_put_u64(f + 64, 0); /* no supercompression global data */
    vdbgi_put_u64(f + 72, 0);
    vdbgi_put_u64(f + 80, level_offset);
    vdbgi_put_u64(f + 88, level_size);
    vdbgi_put_u64(f + 96, level_size); /* uncompressed length */
    write_dfd(f + dfd_offset, vk_format);
    vdbgi_put_u32(f + kvd_offset, kv_length);
    memcpy(f + kvd_offset + 4, kv_key, sizeof(kv_key));
    memcpy(f + kvd_offset + 4 + sizeof(kv_key), kv_value, strlen(kv_value) + 1);
    memcpy(f + level_offset, texels, level_size);
    *out = f;
    *out_size = total;
    return VDBGI_OK;
}
