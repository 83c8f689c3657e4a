/*
 * packed.h: the compact layout's file (.gi version 5, docs/format.md): each
 * kept brick's level in one byte a cell, and every probe value the bricks
 * read stored once; the runtime textures (placement, borders, stitched seams)
 * rebuilt from them, by the converter and the reader alike. The converter's
 * half, which writes them, is pack_write.h.
 */
#ifndef VDBGI_PACKED_H
#define VDBGI_PACKED_H

#include "volume.h"

/*
 * The bricks a level array describes, in scan order, and which lattice
 * points their texels read unstitched: those, and only those, the file
 * stores. Points are owned by the level-0 cell holding them; the owner grid
 * reaches 2 cells past the indirection, as far as a position inside it reads.
 */
typedef struct vdbgi_pack_plan {
    uint32_t dims[3];      /* indirection cells */
    uint32_t grid[3];      /* cells owning stored points: dims + 2 */
    size_t brick_count;    /* bricks, in the order the level bytes list them */
    int32_t (*key)[3];     /* per brick: block index at its level, relative to cell 0 */
    uint8_t *level;        /* per brick */
    uint16_t (*origin)[3]; /* per brick: its first atlas texel */
    int32_t *cell_brick;   /* per indirection cell: the brick covering it, or -1 */
    uint32_t (*stitch)[4]; /* per brick: bit t, texel t takes a coarser brick's value */
    uint64_t *mask;        /* per owner cell: bit (z*4 + y)*4 + x, point stored */
    uint32_t *offset;      /* per owner cell: index of its first stored point */
    size_t points;         /* stored points */
    uint32_t per_level[4];
} vdbgi_pack_plan;

/*
 * From one level byte a cell (level + 1, or 0 for an empty cell; x fastest):
 * the bricks, their places in the atlas, v's indirection, v->info's brick
 * counts, v->raw allocated, and the stored points. The places are a file's
 * placement table (VDBGI_PLACEMENT_BYTES a brick, into v->info's atlas
 * size) or, with placement NULL, the converter's choice: slabs of same-level
 * neighbours sharing their borders, packed in layers, which sets the atlas
 * size. A level array or table no converter writes (a level above
 * max_level, a coarse block whose cells disagree, with expect, a reader's
 * header, other bricks than it counts: refused before anything is
 * allocated; a brick outside the atlas or overlapping another's points) is
 * VDBGI_ERR_FORMAT, with what is wrong after `name: `. The stored points are
 * found on `threads` threads; the plan is the same for any.
 */
vdbgi_result vdbgi_pack_plan_make(vdbgi_volume *v, const uint8_t *levels, const uint8_t *placement,
                                  const vdbgi_volume_info *expect, const char *name, int threads,
                                  vdbgi_pack_plan *plan);
void vdbgi_pack_plan_free(vdbgi_context *ctx, vdbgi_pack_plan *plan);

/*
 * The reader's half: v's atlas from the plan and the payload's planes
 * (after its level bytes): stored texels copied, stitched ones interpolated
 * from their coarser brick and encoded (a texel two bricks share gets the
 * same bytes from both), over threads; *clamped gets how many of those
 * clamped.
 */
vdbgi_result vdbgi_pack_rebuild(vdbgi_volume *v, const vdbgi_pack_plan *plan, const uint8_t *planes,
                                int threads, size_t *clamped);

/*
 * A reader's whole job on a version 5 body, v->payload (v->info from the
 * header): the plan, checked against the header, and the textures rebuilt.
 */
vdbgi_result vdbgi_pack_read(vdbgi_volume *v, const char *name);

#endif /* VDBGI_PACKED_H */
