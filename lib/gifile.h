/* gifile.h: the .gi container (docs/format.md) around a volume's two textures. */
#ifndef VDBGI_GIFILE_H
#define VDBGI_GIFILE_H

#include "volume.h"

#define VDBGI_GI_HEADER_SIZE 112
/*
 * The newest version read: 1 is the seed layout, 2 adds the layout field, 4
 * stores the compact layout packed (docs/format.md); 3 was an older compact
 * layout, refused.
 */
#define VDBGI_GI_VERSION 4
/*
 * The layout field's values for the compact layout: 3 is written, where the
 * lookup must read a column's lowest brick below it (docs/format.md), so that
 * a reader without that rule refuses the file; 2, written before the rule, is
 * read alike (its columns still start with the bricks the rule leaves out, and
 * only what positions below them read changes, from black to their bottom
 * plane); 1 was an older form, refused.
 */
#define VDBGI_GI_LAYOUT_COMPACT 3
#define VDBGI_GI_LAYOUT_COMPACT_2 2
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
