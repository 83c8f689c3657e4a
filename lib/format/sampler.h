/* sampler.h: seed 000's runtime lookup on the CPU, on plain texture bytes; a brick's
   reconstruction from its samples. */
#ifndef VDBGI_SAMPLER_H
#define VDBGI_SAMPLER_H

#include <stdint.h>

/* The two textures and the uniforms the shader is given. */
typedef struct vdbgi_volume_view {
    uint32_t encoding; /* 0 RGBM (rgba8), 1 RGB9E5 (uint32 little-endian) */
    uint32_t layout;   /* vdbgi_layout's: 1 seed 000's 6^3 slots, 2 compact (5^3 bricks) */
    float rgbm_range;
    float box_min[3], box_max[3];
    uint32_t ind_dims[3]; /* rgba8 texels, x fastest */
    const uint8_t *indirection;
    uint32_t atlas_dims[3]; /* 4-byte texels, x fastest */
    const uint8_t *atlas;
    const int8_t *sh; /* NULL, or the L2 terms: 24 snorm8 a texel (textures.h) */
} vdbgi_volume_view;

/* 4^3 probes a brick: 6^3 texels with a one-texel apron (seed), or 5^3 with a + border. */
#define VDBGI_BRICK 4
#define VDBGI_BRICK_PADDED 6
#define VDBGI_BRICK_COMPACT 5

/* Texels per brick edge in an atlas slot of the given layout. */
static inline int vdbgi_slot_texels(uint32_t layout)
{
    return layout == 2 ? VDBGI_BRICK_COMPACT : VDBGI_BRICK_PADDED;
}

void vdbgi_sampler_sample(const vdbgi_volume_view *v, const float pos[3], float rgb[3]);
/*
 * With the normal n: L0 and, where the view has L2 terms, their ratios read
 * with the same trilinear weights, then E(n) / pi = L0 (1 + sum r_k p_k(n)),
 * at least 0 (docs/format.md, "Version 6"). Without terms, vdbgi_sampler_sample.
 */
void vdbgi_sampler_sample_normal(const vdbgi_volume_view *v, const float pos[3], const float n[3],
                                 float rgb[3]);

/*
 * The level of the brick an indirection texel points at, or -1 where the
 * cell has none: seed, a = level + 1 (0 empty); compact, a & 3 unless the
 * texel is 0, 0, 0, 0.
 */
int vdbgi_cell_level(const vdbgi_volume_view *v, const uint8_t texel[4]);

/*
 * Trilinear reconstruction from a brick's samples s (the layout's texels of
 * it, x fastest) at fine lattice position pos: what a coarse brick gives a
 * point, for the coarsening's test and the compact layout's stitched seams.
 */
void vdbgi_brick_interpolate(const float s[][3], uint32_t layout, const int32_t key[3], int level,
                             const double pos[3], float rgb[3]);
/* The same for samples of `channels` floats each (L2 terms: 24), channel by channel. */
void vdbgi_brick_interpolate_n(const float *s, int channels, uint32_t layout, const int32_t key[3],
                               int level, const double pos[3], float *out);

#endif /* VDBGI_SAMPLER_H */
