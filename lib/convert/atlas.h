/* atlas.h: the runtime layout of kept bricks: atlas slots, aprons or borders, indirection,
   encoding. */
#ifndef VDBGI_ATLAS_H
#define VDBGI_ATLAS_H

#include "coarsen.h"
#include "volume.h"

/* Atlas texel dimensions for slots bricks of the layout: near-cubic, at most 256 slots an axis. */
vdbgi_result vdbgi_atlas_dims(vdbgi_context *ctx, size_t slots, vdbgi_layout layout,
                              uint32_t dims[3]);

/*
 * Sample, encode and point at every brick (brick i in slot i + 1; slot 0 is
 * black) into v's atlas and indirection in seed 000's layout, over threads:
 * bricks own disjoint slots and cells, so the bytes do not depend on the
 * split. Adds the texels that took a block mean and the clamped ones to
 * v->info. (The compact layout: vdbgi_pack_write.)
 */
vdbgi_result vdbgi_atlas_fill(vdbgi_volume *v, const vdbgi_brick *bricks, size_t count,
                              int threads);

#endif /* VDBGI_ATLAS_H */
