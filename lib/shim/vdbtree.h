/* vdbtree.h: a walk over the bytes of one VDB tree, checked before OpenVDB reads them. */
#ifndef VDBGI_VDBTREE_H
#define VDBGI_VDBTREE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* How a grid stored its tree: the stream's compression flags and its value type's sizes. */
typedef struct vdbgi_vdb_tree_format {
    uint32_t compression; /* OpenVDB's io::COMPRESS_* bits: 1 zip, 2 active mask, 4 blosc */
    size_t value_size;    /* bytes of one value in memory (and of backgrounds and tiles) */
    size_t saved_size;    /* bytes of one voxel value as stored (half floats: smaller) */
    int32_t max_index;    /* no node may reach beyond +-max_index */
} vdbgi_vdb_tree_format;

/* What a walk found: leaves, their active voxels, active tiles, and the index box of the
   leaves holding any voxel (inclusive; meaningless when active is 0). */
typedef struct vdbgi_vdb_tree_counts {
    size_t leaves, active, tiles;
    int32_t leaf_min[3], leaf_max[3];
} vdbgi_vdb_tree_counts;

/*
 * Do buf[0..topology) and buf[topology..size) hold a 5-4-3 tree's topology and
 * leaf buffers as OpenVDB 10 reads them (file format 222 and later), with
 * every count, mask and chunk size consistent and inside the bytes? OpenVDB
 * 10 trusts a chunk's stored size and copies that many bytes into a buffer
 * sized by the mask (one flipped byte corrupted the heap); it also allocates
 * whatever size a chunk claims. On false, why says what is wrong; on true,
 * *counts (if not NULL) says what the tree holds.
 */
bool vdbgi_vdb_tree_check(const uint8_t *buf, size_t topology, size_t size,
                          const vdbgi_vdb_tree_format *f, vdbgi_vdb_tree_counts *counts, char *why,
                          size_t why_size);

#ifdef __cplusplus
}
#endif

#endif /* VDBGI_VDBTREE_H */
