/* vdb_shim.h: C interface to the only code that includes OpenVDB. */
#ifndef VDBGI_VDB_SHIM_H
#define VDBGI_VDB_SHIM_H

#include "internal.h"

#ifdef __cplusplus
extern "C" {
#endif

/*
 * Active lattice points of an unsigned distance field of the triangles:
 * every ijk with distance(origin + spacing * ijk, mesh) <= margin, in VDB
 * tree order. *ijk_out (3 int32 per point) is allocated through ctx. Fails
 * with VDBGI_ERR_OUT_OF_MEMORY, stating count and memory, past max_count.
 */
vdbgi_result vdbgi_vdb_topology(vdbgi_context *ctx, const float *positions, size_t vertex_count,
                                const uint32_t *indices, size_t triangle_count,
                                const double origin[3], double spacing, double margin,
                                uint64_t max_count, int32_t **ijk_out, size_t *count_out);

/* Write probes (baked) as the "irradiance" and "validity" grids at path (no temp dance). */
vdbgi_result vdbgi_vdb_write(vdbgi_context *ctx, const char *path, const vdbgi_probes *probes);

/* Read "irradiance" (and "validity" if present) from path into new probes. */
vdbgi_result vdbgi_vdb_read(vdbgi_context *ctx, const char *path, vdbgi_probes **out);

/*
 * The filled field. Sources are the probes whose back-face fraction is at
 * most fp->invalid_threshold. The target region is every level-0 cell that
 * holds a probe, dilated by fp->margin_cells cells (26-neighbourhood), as
 * fine points, dilated again by fp->rim points. Rings of target points next
 * to already-valued points take the weighted mean of their valued 26
 * neighbours (weights by face, edge, corner), ring after ring, until the
 * target is covered or a ring is empty. Writes the valued points as leaves
 * into *field, the occupied cells (3 int32 each, sorted) into *cells_out,
 * and the target points left without a value into *unreached. Fails with
 * VDBGI_ERR_FORMAT when no probe is a source.
 */
vdbgi_result vdbgi_vdb_fill(vdbgi_context *ctx, const vdbgi_probes *probes,
                            const vdbgi_fill_params *fp, vdbgi_field *field, int32_t **cells_out,
                            size_t *cell_count, size_t *unreached);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_VDB_SHIM_H */
