/* volume_build.h: the steps of a conversion that the whole build (volume.c) and the
   build by regions (volume_regions.c) share. */
#ifndef VDBGI_VOLUME_BUILD_H
#define VDBGI_VOLUME_BUILD_H

#include "coarsen.h"
#include "volume_stats.h"

int vdbgi_build_report(const vdbgi_convert_desc *desc, float done);

/*
 * The indirection's size from the valid probes alone, before the fill spends
 * memory on a lattice the texture limit refuses anyway: the same cells
 * vdbgi_build_place_indirection will count (the valid probes' cells, one cell of margin,
 * the corner aligned to 8 cells).
 */
vdbgi_result vdbgi_build_check_extent(vdbgi_context *ctx, const vdbgi_lattice_stats *st);

/* The indirection covers the occupied cells from a corner aligned to level-3 blocks. */
vdbgi_result vdbgi_build_place_indirection(vdbgi_volume *v, const int32_t *cells, size_t cell_count,
                                           double spacing);

/*
 * The lift (docs/format.md): drop each level-0 brick that is the lowest of its
 * column and whose cell's filter reads valid probes only on its top face
 * (top_only, from the fill); the lookup reads the brick above it at its bottom
 * plane there. Done after coarsening, so that the coarse bricks and their tests
 * see every occupied cell as before, and a cell that a coarse brick covers, or
 * that has any brick below it, keeps what it has. The dropped cells leave cells.
 */
vdbgi_result vdbgi_build_lift_bricks(vdbgi_context *ctx, vdbgi_brick *bricks, size_t *brick_count,
                                     int32_t *cells, size_t *cell_count, const int32_t *top_only,
                                     size_t top_count);

/* Log a step's time and report progress; VDBGI_ERR_CANCELLED if the caller asks to stop. */
vdbgi_result vdbgi_build_step_done(vdbgi_context *ctx, const vdbgi_convert_desc *desc, float done,
                                   double *t, const char *what);

/* What a conversion settled before it reads any value. */
typedef struct vdbgi_build_plan {
    vdbgi_coarsen_params cp;
    vdbgi_fill_params fp;
    bool terms; /* L2 terms go through with L0 */
} vdbgi_build_plan;

/*
 * desc resolved against probes like (a read of them: their settings) and
 * the lattice's statistics (checked by vdbgi_build_check_extent), and the volume started.
 */
vdbgi_result vdbgi_build_start(vdbgi_context *ctx, const vdbgi_probes *like,
                               const vdbgi_lattice_stats *st, const vdbgi_convert_desc *desc,
                               vdbgi_build_plan *bp, vdbgi_volume **out);

/*
 * The probes p filled into *field, L2 terms with L0 as one field of nine
 * colours a point, with the cells the fill occupied (tree order) and those
 * it reads on their top face only; unreached counts the points of
 * bp->fp.core_z.
 */
vdbgi_result vdbgi_build_fill(vdbgi_context *ctx, const vdbgi_probes *p, const vdbgi_build_plan *bp,
                              vdbgi_field *field, int32_t **cells, size_t *cell_count,
                              int32_t **top_only, size_t *top_count, size_t *unreached);

/* The field's points with z0 <= z < z1. */
size_t vdbgi_build_points_within(const vdbgi_field *f, int32_t z0, int32_t z1);

#endif /* VDBGI_VOLUME_BUILD_H */
