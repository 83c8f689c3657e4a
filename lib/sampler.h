/* sampler.h: seed 000's runtime lookup on the CPU, on plain texture bytes. */
#ifndef VDBGI_SAMPLER_H
#define VDBGI_SAMPLER_H

#include <stdint.h>

/* The two textures and the uniforms the shader is given. */
typedef struct vdbgi_volume_view {
    uint32_t encoding; /* 0 RGBM (rgba8), 1 RGB9E5 (uint32 little-endian) */
    float rgbm_range;
    float box_min[3], box_max[3];
    uint32_t ind_dims[3]; /* rgba8 texels, x fastest */
    const uint8_t *indirection;
    uint32_t atlas_dims[3]; /* 4-byte texels, x fastest */
    const uint8_t *atlas;
} vdbgi_volume_view;

/* 6^3 texels per brick: 4^3 probes and a one-texel apron. */
#define VDBGI_BRICK 4
#define VDBGI_BRICK_PADDED 6

void vdbgi_sampler_sample(const vdbgi_volume_view *v, const float pos[3], float rgb[3]);

#endif /* VDBGI_SAMPLER_H */
