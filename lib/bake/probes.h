/* probes.h: the probe object: lattice, per-probe values, metadata; resolved bake settings. */
#ifndef VDBGI_PROBES_H
#define VDBGI_PROBES_H

#include "lattice.h"
#include "meta.h"

/* The .vdb's "rays" of an adaptive bake, whose count varies by probe. */
#define VDBGI_META_RAYS_ADAPTIVE (-1)

#ifdef __cplusplus
extern "C" {
#endif

struct vdbgi_probes {
    vdbgi_context *ctx;
    double spacing, margin, origin[3];
    size_t count;
    int32_t *ijk;    /* 3 per probe */
    float *rgb;      /* 3 per probe, NULL until baked or read */
    float *backface; /* per probe */
    float *cube;     /* 18 per probe (6 sides x RGB, vdbgi_side order), or NULL */
    uint16_t *sh;    /* 24 per probe (L2 terms c1..c8 x RGB, VDBGI_SH2_TERMS) as ratios to rgb
                        in half floats (vdbgi_term_encode), or NULL */
    float *stderr_;  /* per probe: standard error of the value, or NULL (not baked) */
    uint32_t *rays;  /* per probe: rays traced, or NULL (every probe had desc->rays) */
    float invalid_threshold;
    size_t invalid_count;
    /* A tile of a lattice (vdbgi_place_desc): its index of tile_count (0: the whole lattice),
       the leaf-aligned range of i it keeps, and the range every tile's together cover. */
    int tile_index, tile_count;
    int32_t tile_x[2], tile_span[2];
    vdbgi_sampling sampling; /* how the directions were chosen (read from the metadata) */
    bool adaptive;           /* rays in batches until a noise target */
    vdbgi_meta_store meta;
};

vdbgi_result vdbgi_probes_alloc(vdbgi_context *ctx, size_t count, bool with_values,
                                vdbgi_probes **out);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_PROBES_H */
