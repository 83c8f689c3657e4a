/* vdb_shim.h: C interface to the code that includes OpenVDB (vdb_shim.cpp, vdb_read.cpp). */
#ifndef VDBGI_VDB_SHIM_H
#define VDBGI_VDB_SHIM_H

#include "context.h"
#include "lattice.h"
#include "meta.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A set of lattice points: OpenVDB's MaskGrid. One thread at a time per mask. */
typedef struct vdbgi_vdb_mask vdbgi_vdb_mask;
vdbgi_result vdbgi_vdb_mask_create(vdbgi_context *ctx, vdbgi_vdb_mask **out);
void vdbgi_vdb_mask_destroy(vdbgi_vdb_mask *mask);
/*
 * Add the points of the 8^3 leaf at origin (multiples of 8) whose bits are
 * set: point (x, y, z) of it is bit y * 8 + z of bits[x], OpenVDB's order.
 * Records no message (workers call it): VDBGI_ERR_OUT_OF_MEMORY or _BACKEND.
 */
vdbgi_result vdbgi_vdb_mask_add_leaf(vdbgi_vdb_mask *mask, const int32_t origin[3],
                                     const uint64_t bits[8]);
/* Add every point of from to mask. */
vdbgi_result vdbgi_vdb_mask_merge(vdbgi_context *ctx, vdbgi_vdb_mask *mask,
                                  const vdbgi_vdb_mask *from);
/*
 * The points as ijk triples in tree order into *ijk_out (allocated through
 * ctx, *count_out of them). Fails with VDBGI_ERR_OUT_OF_MEMORY, stating
 * count and memory, past max_count.
 */
vdbgi_result vdbgi_vdb_mask_points(vdbgi_context *ctx, const vdbgi_vdb_mask *mask,
                                   uint64_t max_count, int32_t **ijk_out, size_t *count_out);

/*
 * Merge the grids of the .vdb tiles (checked by the caller: one bake, disjoint
 * leaves) with OpenVDB's tree merge, drop the metadata named in drop, set
 * set's items, and write the whole at path (no temp dance); messages say name.
 */
vdbgi_result vdbgi_vdb_merge(vdbgi_context *ctx, const char *path, const char *name,
                             const char *const *tiles, size_t count, const char *const *drop,
                             size_t drop_count, const vdbgi_meta_store *set);

/* The name of the ambient cube's grid for side 0..5: +x -x +y -y +z -z (docs/format.md). */
const char *vdbgi_side_grid_name(int side);
/* The name of the L2 term's grid for term 1..8: irradiance_sh1 .. irradiance_sh8. */
const char *vdbgi_sh_grid_name(int term);

/*
 * Probes as they cross the shim: plain arrays that the caller (probes.c)
 * owns. vdbgi_vdb_write reads them; vdbgi_vdb_read calls make once, when it
 * knows the probe count and which per-probe grids the file holds, to set the
 * array pointers (NULL for an absent grid) and meta, or fail, which the
 * reader returns.
 */
typedef struct vdbgi_vdb_arrays {
    vdbgi_result (*make)(struct vdbgi_vdb_arrays *sink, size_t count, bool with_stderr,
                         bool with_rays, bool with_cube, bool with_sh);
    void *user;
    double spacing, origin[3];
    size_t count;    /* probes the arrays hold (set by the reader) */
    int32_t *ijk;    /* 3 per probe */
    float *rgb;      /* 3 per probe */
    float *backface; /* per probe; 0 where the file has no validity */
    float *stderr_;  /* per probe, or NULL */
    uint32_t *rays;  /* per probe, or NULL */
    float *cube;     /* 18 per probe, or NULL */
    uint16_t *sh;    /* 24 per probe, as vdbgi_probes holds them (vdbgi_term_encode), or NULL */
    vdbgi_meta_store *meta;
} vdbgi_vdb_arrays;

/* Write baked probes (their arrays, make unused) as the "irradiance" and "validity" grids
   and those beside them, with meta on each, at path (no temp dance); messages say name. */
vdbgi_result vdbgi_vdb_write(vdbgi_context *ctx, const char *path, const char *name,
                             const vdbgi_vdb_arrays *probes, const vdbgi_meta_store *meta);

/* Read "irradiance" (and the grids beside it, if present) from path into the sink's arrays. */
vdbgi_result vdbgi_vdb_read(vdbgi_context *ctx, const char *path, vdbgi_vdb_arrays *sink);

/*
 * The same file read a z range at a time: open checks every grid's bytes
 * once and gives the index box of the irradiance grid's leaves that hold a
 * probe (lo[0] > hi[0]: none); read puts the probes with z0 <= k < z1 into
 * the sink (perhaps none), with the whole read's checks, once it finds the
 * file as open left it.
 */
typedef struct vdbgi_vdb_regions vdbgi_vdb_regions;
vdbgi_result vdbgi_vdb_regions_open(vdbgi_context *ctx, const char *path, vdbgi_vdb_regions **out,
                                    int32_t lo[3], int32_t hi[3]);
vdbgi_result vdbgi_vdb_regions_read(vdbgi_vdb_regions *f, int32_t z0, int32_t z1,
                                    vdbgi_vdb_arrays *sink);
void vdbgi_vdb_regions_close(vdbgi_vdb_regions *f);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_VDB_SHIM_H */
