/* volume_stats.h: sums over the lattice that do not depend on how it is read, and the
   error figures of a conversion, shared by the whole build and the build by regions. */
#ifndef VDBGI_VOLUME_STATS_H
#define VDBGI_VOLUME_STATS_H

#include "probes.h"
#include "volume.h"

/*
 * A sum over the lattice adds each VDBGI_REGION_STEP-point z slab's terms in
 * probe order, then the slabs in z order. A region is whole slabs, and its
 * probes come in the whole read's order, so a conversion region by region
 * adds exactly what the whole one does.
 */
typedef struct vdbgi_slab_sums {
    int32_t first; /* the first slab's index */
    size_t count;
    int width; /* doubles a slab */
    double *v;
} vdbgi_slab_sums;

vdbgi_result vdbgi_slab_sums_init(vdbgi_context *ctx, vdbgi_slab_sums *s, const int32_t z[2],
                                  int width);

void vdbgi_slab_sums_total(const vdbgi_slab_sums *s, double *out);

/*
 * The colour sums' doubles a slab: the valid probes' r, g and b; then, for probes with L2
 * terms, what version 8 would change in their readings (vdbgi_stats_add_colours): the
 * squared channel differences and the channels read, each summed over VDBGI_LUMA2_NORMALS
 * normals.
 */
#define VDBGI_COLOUR_SUMS 5
#define VDBGI_LUMA2_NORMALS 14

/* What the conversion needs of the whole lattice before it fills any of it. */
typedef struct vdbgi_lattice_stats {
    size_t probes, valid;
    int32_t lo[3], hi[3];           /* every probe's index */
    int32_t cell_lo[3], cell_hi[3]; /* the valid probes' cells */
    vdbgi_slab_sums colour;         /* the valid probes' colours */
} vdbgi_lattice_stats;

void vdbgi_stats_init(vdbgi_lattice_stats *st);

/* Counts and extents. */
void vdbgi_stats_add(vdbgi_lattice_stats *st, const vdbgi_probes *p);

/* The valid probes' colours into st->colour (VDBGI_COLOUR_SUMS a slab), allocated once
   vdbgi_build_check_extent bounds its slabs. */
void vdbgi_stats_add_colours(vdbgi_lattice_stats *st, const vdbgi_probes *p);

/* The z range of the valid probes' cells, which the sums over them cover. */
void vdbgi_stats_valid_z(const vdbgi_lattice_stats *st, int32_t z[2]);

/* The error figures, summed as they come (a region's probes, or all). */
typedef struct vdbgi_error_sums {
    vdbgi_slab_sums sq; /* squared channel errors */
    double worst;
    size_t n;
    /* The largest errors seen, a min-heap of at most top_cap: once every valid probe is in,
       its root is the one vdbgi_quantile's 0.99 picks. */
    double *top;
    size_t top_count, top_cap;
} vdbgi_error_sums;

vdbgi_result vdbgi_error_sums_init(vdbgi_context *ctx, vdbgi_error_sums *e, const int32_t z[2],
                                   size_t valid);

void vdbgi_error_sums_free(vdbgi_context *ctx, vdbgi_error_sums *e);

/*
 * The shader's view of the valid probes p against their values (which the
 * fill kept): sampled over threads, summed on one in probe order, so the
 * figures do not depend on the thread count.
 */
vdbgi_result vdbgi_error_measure(vdbgi_volume *v, const vdbgi_probes *p, int threads,
                                 vdbgi_error_sums *e);

void vdbgi_error_figures(vdbgi_volume_info *info, const vdbgi_error_sums *e);

#endif /* VDBGI_VOLUME_STATS_H */
