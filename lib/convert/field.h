/* field.h: the filled fine lattice in VDB-shaped leaves, and the fill that makes it. */
#ifndef VDBGI_FIELD_H
#define VDBGI_FIELD_H

#include "map.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VDBGI_LEAF_DIM 8
#define VDBGI_LEAF_VOXELS 512
/* Colours a point may carry: 1 (irradiance), 6 (ambient-cube sides), 9 (L0 and the L2 terms). */
#define VDBGI_FIELD_MAX_CHANNELS 9
/* Cells any fill may have however sparse its probes: 64 k, 4 M points. */
#define VDBGI_FILL_SPARSE_CELLS 65536

/* One leaf: point (x, y, z) of the leaf is number x*64 + y*8 + z (VDB's order). */
typedef struct vdbgi_leaf {
    int32_t origin[3]; /* multiple of 8, fine-lattice index */
    uint64_t mask[8];  /* bit n of word n/64: point n holds a value */
    float *values;     /* 512 points of channels x RGB floats, inside the field's block */
} vdbgi_leaf;

typedef struct vdbgi_field {
    vdbgi_context *ctx;
    int channels;
    vdbgi_leaf *leaves; /* in OpenVDB's tree order (see vdbgi_tree_order) */
    size_t leaf_count;
    float *values;
    vdbgi_map index; /* leaf origin -> leaf */
} vdbgi_field;

void vdbgi_field_free(vdbgi_field *f);
/* The leaf holding fine point ijk, or NULL. */
const vdbgi_leaf *vdbgi_field_leaf(const vdbgi_field *f, const int32_t ijk[3]);
/*
 * The colours (3 * channels floats) at fine point ijk, or NULL where the
 * field holds none. cache remembers the last leaf: start it at NULL, one per
 * thread; NULL for none.
 */
const float *vdbgi_field_at(const vdbgi_field *f, const int32_t ijk[3], const vdbgi_leaf **cache);
/*
 * The field at fine position pos (lattice units, may be fractional):
 * trilinear over the 8 lattice points around it, renormalised over those
 * that hold a value, into out (3 * channels floats). False when none does.
 */
bool vdbgi_field_trilinear(const vdbgi_field *f, const double pos[3], float *out,
                           const vdbgi_leaf **cache);

/*
 * OpenVDB's iteration order of voxels (and leaves) in its default tree: by
 * 4096-blocks, then 128-blocks, then 8-blocks, then points, each x-major.
 * Kept so that sums over the field add in the order they always have.
 */
int vdbgi_tree_order(const int32_t a[3], const int32_t b[3]);

/* How the fill spreads valid values (docs/converter.md). */
typedef struct vdbgi_fill_params {
    float invalid_threshold; /* back-face fraction above which a probe is not a source */
    int cell_size;           /* fine probes per level-0 brick cell edge (4) */
    int margin_cells;        /* 0: the cells whose filter reads a source; k > 0: the cells
                                holding one and k cells around them (Bevy: 1) */
    int rim;                 /* points beyond a cell's + faces that its filter reads, and
                                around the cells, points the fill reaches (1) */
    int filter_below;        /* points below a cell's - faces that its filter reads: 1 with
                                the seed layout's apron, 0 with the compact layout */
    bool lift;               /* also list the cells whose filter reads sources only on
                                their top face (the compact layout's lift, docs/format.md) */
    float weights[3];        /* weight of a face, edge and corner neighbour */
    int max_iterations;      /* rings of spreading before giving up */
    bool darkest;            /* invalid probes take their darkest valued neighbour, not the
                                mean: a probe inside a wall then leaks no light to the dark side */
    int threads;             /* 0: all cores */
    int32_t core_z[2];       /* a region's fill: the points unreached counts are those with
                                core_z[0] <= z < core_z[1] (equal: every point) */
} vdbgi_fill_params;

/* The points of a leaf mask (leaf origin z oz) with z0 <= z < z1. */
static inline size_t vdbgi_mask_count_z(const uint64_t mask[8], int32_t oz, int32_t z0, int32_t z1)
{
    size_t n = 0;
    for (int w = 0; w < 8; w++)
        for (uint64_t m = mask[w]; m; m &= m - 1) {
            const int32_t z = oz + (__builtin_ctzll(m) & 7);
            n += z >= z0 && z < z1;
        }
    return n;
}

/*
 * The fill's refusal of a lattice too sparse to fill: more than
 * VDBGI_FILL_SPARSE_CELLS cells of cell_size^3 points, and more than allowed
 * (what the sources could reach). VDBGI_OK when it is not.
 */
vdbgi_result vdbgi_fill_check_sparse(vdbgi_context *ctx, size_t sources, size_t cells,
                                     int cell_size, size_t allowed);

/* The converter's fill for a (checked) vdbgi_fill choice: what bricks and Bevy both use. */
vdbgi_fill_params vdbgi_fill_params_default(float invalid_threshold, vdbgi_fill fill, int threads);

/* Points to fill from: count lattice points with channels colours each. */
typedef struct vdbgi_fill_input {
    size_t count;
    const int32_t *ijk;    /* 3 per point */
    const float *values;   /* 3 * channels per point */
    const float *backface; /* per point; a point above the threshold is no source */
    int channels;          /* 1..VDBGI_FIELD_MAX_CHANNELS */
    bool signed_terms;     /* channels past the first are signed terms (L2): the first
                              alone says which neighbour is darkest */
} vdbgi_fill_input;

/*
 * The filled field. Sources are the points whose back-face fraction is at
 * most fp->invalid_threshold. The target region is every level-0 cell whose
 * points, or the points beyond its faces its filter reads (fp->rim above,
 * fp->filter_below below), include a source (or, with
 * fp->margin_cells k > 0, every cell that holds one, dilated by k cells), as
 * fine points, dilated again by fp->rim points. Rings of target points next
 * to already-valued points take the weighted mean of their valued 26
 * neighbours (weights by face, edge, corner), ring after ring, until the
 * target is covered or a ring is empty. An invalid point with valued face
 * neighbours on both sides of one axis takes instead its darkest valued
 * neighbour (fp->darkest), darkest by the sum over all channels (the first
 * alone with in->signed_terms): one choice
 * of neighbour a point, applied to every channel. Writes the field, the
 * occupied cells (3 int32 each, in tree order) into *cells_out, with
 * fp->lift and top_only_out not NULL those of them whose filter reads sources
 * only on their top face into *top_only_out (in no set order), and the target
 * points left without a value into *unreached. Fails with
 * VDBGI_ERR_FORMAT when no point is a source.
 */
vdbgi_result vdbgi_field_fill(vdbgi_context *ctx, const vdbgi_fill_input *in,
                              const vdbgi_fill_params *fp, vdbgi_field *field, int32_t **cells_out,
                              size_t *cell_count, int32_t **top_only_out, size_t *top_only_count,
                              size_t *unreached);

/*
 * The same rings over a dense box of res[0] x res[1] x res[2] points (x
 * fastest): points with valued[i] set are the sources, every other point of
 * the box is a target; values (3 * channels floats a point) and valued are
 * updated in place. Weights and ring count from fp; no darkest choice.
 */
vdbgi_result vdbgi_fill_dense(vdbgi_context *ctx, const int res[3], int channels, float *values,
                              unsigned char *valued, const vdbgi_fill_params *fp);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_FIELD_H */
