/* band.h: the lattice points within the margin of a triangle soup, computed exactly. */
#ifndef VDBGI_BAND_H
#define VDBGI_BAND_H

#include "context.h"

#include <stdint.h>

typedef struct vdbgi_band_desc {
    const float *positions;  /* xyz per vertex, metres */
    const uint32_t *indices; /* three per triangle */
    size_t triangle_count;
    double origin[3], spacing; /* point ijk sits at origin + spacing * ijk */
    double margin;             /* metres, >= 0 */
    int64_t x_range[2];        /* only points with x_range[0] <= i < x_range[1] */
    uint64_t max_count;        /* refused (out of memory) past this many points */
    int threads;               /* 0: one a core */
} vdbgi_band_desc;

/*
 * Every lattice point whose distance to some triangle is at most the margin
 * (plus a millionth of a spacing, for points exactly at it), as ijk triples
 * into *ijk_out (vdbgi_alloc'd, *count_out of them) in OpenVDB's tree order.
 * The set depends on each point and each triangle alone, never on which
 * other triangles are given or on the thread count.
 */
vdbgi_result vdbgi_band_points(vdbgi_context *ctx, const vdbgi_band_desc *desc, int32_t **ijk_out,
                               size_t *count_out);

#endif
