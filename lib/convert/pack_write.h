/* pack_write.h: the compact layout's writer, the converter's half of packed.h. */
#ifndef VDBGI_PACK_WRITE_H
#define VDBGI_PACK_WRITE_H

#include "coarsen.h"
#include "packed.h"

/*
 * The converter's half: bricks (in any order; sorted here into scan order)
 * sampled from v->filled, each stored point encoded once, and a point no
 * receiver can read (no valid probe within one step, and read by level-0
 * bricks only) given the value the decoder predicts, which costs the file
 * almost nothing. Writes the payload (levels, the placement table, then
 * four planes of residuals)
 * into *payload (payload_size bytes, the caller frees it) and builds v's
 * textures from it exactly as vdbgi_pack_rebuild does for a reader.
 */
vdbgi_result vdbgi_pack_write(vdbgi_volume *v, vdbgi_brick *bricks, size_t count,
                              const vdbgi_probes *probes, int threads, uint8_t **payload,
                              size_t *payload_size);

/*
 * The same in passes, for a conversion region by region: create sorts the
 * bricks (kept by the writer until destroy) and makes the plan; values
 * takes the stored points of the owner cells holding lattice z0 <= k < z1
 * from a field valid there, and the valid probes it is given (INT32_MIN,
 * INT32_MAX: all); finish, once every point has its value, writes the
 * payload and builds v's textures as vdbgi_pack_write does.
 */
typedef struct vdbgi_pack_writer vdbgi_pack_writer;
vdbgi_result vdbgi_pack_writer_create(vdbgi_volume *v, vdbgi_brick *bricks, size_t count,
                                      int threads, vdbgi_pack_writer **out);
void vdbgi_pack_writer_values(vdbgi_pack_writer *w, const vdbgi_field *filled,
                              const vdbgi_probes *probes, int32_t z0, int32_t z1);
vdbgi_result vdbgi_pack_writer_finish(vdbgi_pack_writer *w, uint8_t **payload,
                                      size_t *payload_size);
void vdbgi_pack_writer_destroy(vdbgi_pack_writer *w);

#endif /* VDBGI_PACK_WRITE_H */
