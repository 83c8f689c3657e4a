/* gifile.h: the .gi container (docs/format.md) around a volume's two textures. */
#ifndef VDBGI_GIFILE_H
#define VDBGI_GIFILE_H

#include "volume.h"

#define VDBGI_GI_HEADER_SIZE 112
/*
 * The versions (docs/format.md has the table): 1 the seed layout's textures,
 * 2 either layout's textures, 5 the compact layout packed with its bricks'
 * places. 3 and 4 were older compact forms, refused.
 */
#define VDBGI_GI_VERSION 5
/*
 * The layout field holds vdbgi_layout's numbers (1 seed, 2 compact). Two
 * older values are still read in version 2: 0 for the seed layout, and 3 for
 * the compact one (written while 2 meant the compact layout before the lift,
 * which is read alike: only what positions below a column's lowest brick
 * read differs).
 */
#define VDBGI_GI_LAYOUT_SEED_OLD 0
#define VDBGI_GI_LAYOUT_COMPACT_OLD 3
/* Version 5: each brick's first atlas texel, three u16 a brick. */
#define VDBGI_PLACEMENT_BYTES 6
/* Version 5: the most atlas texels a brick may bring (a brick is 125; a file's atlas is bounded). */
#define VDBGI_ATLAS_TEXELS_PER_BRICK 500
/* The compact atlas's largest side: a brick's first texel is 4 r + (a's two bits) <= 1023. */
#define VDBGI_ATLAS_MAX 1024

/* Allocate v->raw for v->info's texture sizes and point indirection and atlas into it. */
vdbgi_result vdbgi_gifile_alloc(vdbgi_volume *v);
/* The compact layout's file: its header (written later) and payload, into v->packed. */
vdbgi_result vdbgi_gifile_pack(vdbgi_volume *v, const uint8_t *payload, size_t size);
/*
 * Write the header into v->raw and gzip the whole into v->file, in three
 * steps: begin allocates, run compresses (it allocates nothing and touches no
 * context, so it may run on another thread beside other work), end keeps the
 * result or reports the failure. end also frees what begin took.
 */
typedef struct vdbgi_gzip_job {
    struct libdeflate_compressor *compressor;
    const uint8_t *in;
    size_t in_size;
    uint8_t *out;
    size_t capacity, written;
} vdbgi_gzip_job;

vdbgi_result vdbgi_gifile_encode_begin(vdbgi_volume *v, vdbgi_gzip_job *job);
void vdbgi_gifile_encode_run(vdbgi_gzip_job *job);
vdbgi_result vdbgi_gifile_encode_end(vdbgi_volume *v, vdbgi_gzip_job *job);

#endif /* VDBGI_GIFILE_H */
