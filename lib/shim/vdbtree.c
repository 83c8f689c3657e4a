/*
 * vdbtree.c: the layout of a VDB tree (OpenVDB 10's Tree, RootNode,
 * InternalNode and LeafNode readTopology/readBuffers, and io::readCompressedValues),
 * walked over bytes in memory and checked, before OpenVDB reads the same bytes.
 *
 * Topology: a buffer count (1); the root's background, tile count, child count,
 * its tiles (origin, value, active byte) and children (origin, then the node);
 * an internal node's child mask, value mask, compressed tile values, then its
 * children in mask order; a leaf's value mask. Then the buffers: for every leaf
 * in the same order, its value mask again and its compressed voxel values.
 * Compressed values: a metadata byte, up to two inactive values, a selection
 * mask, then a chunk of either every value or (with active-mask compression)
 * the active ones: raw, or an int64 size and that many zip or blosc bytes
 * (a size <= 0: -size raw bytes).
 */
#include "vdbtree.h"

#include "util.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

enum { COMPRESS_ZIP = 1, COMPRESS_ACTIVE_MASK = 2, COMPRESS_BLOSC = 4 };
enum { ROOT_CHILD_DIM = 4096, LEAF_VALUES = 512, LEAF_MASK_BYTES = LEAF_VALUES / 8 };
enum { BLOSC_HEADER = 16 };

typedef struct cursor {
    const uint8_t *buf;
    size_t pos, end;
} cursor;

/* The topology cursor and, one leaf behind, the buffer cursor: no leaf list kept. */
typedef struct walk {
    cursor topo, data;
    const vdbgi_vdb_tree_format *f;
    char *why;
    size_t why_size;
    vdbgi_vdb_tree_counts counts;
} walk;

static bool fail(walk *w, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->why, w->why_size, fmt, ap);
    va_end(ap);
    return false;
}

/* The next n bytes of c, or false with the reason. */
static bool take(walk *w, cursor *c, uint64_t n, const uint8_t **p)
{
    if (n > c->end - c->pos)
        return fail(w, "%s ends inside a node", c == &w->topo ? "its topology" : "its data");
    *p = c->buf + c->pos;
    c->pos += (size_t)n;
    return true;
}

static size_t count_on(const uint8_t *mask, size_t bytes)
{
    size_t n = 0;
    for (size_t i = 0; i < bytes; i++)
        n += (size_t)__builtin_popcount(mask[i]);
    return n;
}

/* io::readData: count values of the saved size, raw, zipped or blosc'd. */
static bool chunk(walk *w, cursor *c, size_t count)
{
    const uint64_t bytes = (uint64_t)count * w->f->saved_size;
    const uint8_t *p = NULL;
    if (count == 0 && w->f->saved_size != w->f->value_size)
        return true; // io::HalfReader reads nothing at all for no values, not even a size
    if (!(w->f->compression & (COMPRESS_ZIP | COMPRESS_BLOSC)))
        return take(w, c, bytes, &p);
    if (!take(w, c, 8, &p))
        return false;
    const uint64_t stored = (uint64_t)vdbgi_get_u32(p) | (uint64_t)vdbgi_get_u32(p + 4) << 32;
    const int64_t n = (int64_t)stored;
    if (n <= 0) {
        if (0 - stored != bytes) // OpenVDB 10 copies -n bytes before it compares
            return fail(w, "a raw chunk says %llu bytes where its mask makes %llu",
                        (unsigned long long)(0 - stored), (unsigned long long)bytes);
        return take(w, c, bytes, &p);
    }
    if (stored > c->end - c->pos) // allocated by OpenVDB before it reads
        return fail(w, "a compressed chunk of %llu bytes runs past the grid's end",
                    (unsigned long long)stored);
    if ((w->f->compression & COMPRESS_BLOSC) &&
        (stored < BLOSC_HEADER || vdbgi_get_u32(c->buf + c->pos + 4) != bytes ||
         vdbgi_get_u32(c->buf + c->pos + 12) != stored))
        // Blosc trusts its header's sizes: they must be the chunk's and the mask's.
        return fail(w, "a blosc chunk's header disagrees with its size or its mask");
    return take(w, c, stored, &p);
}

/* io::readCompressedValues for a node of count values under value mask `mask`. */
static bool values(walk *w, cursor *c, size_t count, const uint8_t *mask)
{
    const uint8_t *p = NULL;
    if (!take(w, c, 1, &p))
        return false;
    const int meta = p[0];
    // 0 none, 1 minus background, 2 one inactive value, 3 mask, 4 mask and one value,
    // 5 mask and two values, 6 every value stored.
    if (meta > 6)
        return fail(w, "unknown value metadata %d", meta);
    const int inactive = meta == 2 || meta == 4 ? 1 : meta == 5 ? 2 : 0;
    if (!take(w, c, (uint64_t)inactive * w->f->value_size, &p))
        return false;
    if (meta >= 3 && meta <= 5 && !take(w, c, count / 8, &p))
        return false;
    const bool active_only = (w->f->compression & COMPRESS_ACTIVE_MASK) && meta != 6;
    return chunk(w, c, active_only ? count_on(mask, count / 8) : count);
}

/* A leaf: its mask in the topology, then its mask again and its values in the buffers. */
static bool leaf(walk *w, const int32_t o[3])
{
    const uint8_t *mask = NULL, *again = NULL;
    if (!take(w, &w->topo, LEAF_MASK_BYTES, &mask) || !take(w, &w->data, LEAF_MASK_BYTES, &again))
        return false;
    // OpenVDB counts the topology's mask and skips this copy: both must agree.
    if (memcmp(mask, again, LEAF_MASK_BYTES) != 0)
        return fail(w, "a leaf's mask differs between its topology and its data");
    vdbgi_vdb_tree_counts *const n = &w->counts;
    const size_t on = count_on(mask, LEAF_MASK_BYTES);
    for (int k = 0; on && k < 3; k++) {
        if (n->active == 0 || o[k] < n->leaf_min[k])
            n->leaf_min[k] = o[k];
        if (n->active == 0 || o[k] + 7 > n->leaf_max[k])
            n->leaf_max[k] = o[k] + 7;
    }
    n->leaves++;
    n->active += on;
    return values(w, &w->data, LEAF_VALUES, mask);
}

/*
 * An internal node of 2^(3 log2dim) slots at origin o: 5 holds nodes of 4,
 * 4 holds leaves. Slot n's child lies n >> 2 log2dim children along x,
 * (n >> log2dim) mod 2^log2dim along y and n mod 2^log2dim along z
 * (OpenVDB's offsetToLocalCoord).
 */
static bool internal(walk *w, int log2dim, const int32_t o[3])
{
    const size_t slots = (size_t)1 << (3 * log2dim), bytes = slots / 8;
    const uint8_t *child = NULL, *value = NULL;
    if (!take(w, &w->topo, bytes, &child) || !take(w, &w->topo, bytes, &value))
        return false;
    for (size_t i = 0; i < bytes; i++)
        if (child[i] & value[i])
            return fail(w, "a node marks one slot both child and active tile");
    w->counts.tiles += count_on(value, bytes);
    if (!values(w, &w->topo, slots, value))
        return false;
    const int child_log2 = log2dim == 5 ? 7 : 3; /* 128 or 8 points a child */
    const size_t dim_mask = ((size_t)1 << log2dim) - 1;
    for (size_t i = 0; i < slots; i++)
        if (child[i >> 3] >> (i & 7) & 1) {
            const int32_t c[3] = {o[0] + (int32_t)((i >> 2 * log2dim) << child_log2),
                                  o[1] + (int32_t)((i >> log2dim & dim_mask) << child_log2),
                                  o[2] + (int32_t)((i & dim_mask) << child_log2)};
            if (!(log2dim == 5 ? internal(w, 4, c) : leaf(w, c)))
                return false;
        }
    return true;
}

/* Is a < b in OpenVDB's Coord order (x, then y, then z)? The root's table is sorted so. */
static bool coord_less(const int32_t a[3], const int32_t b[3])
{
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k];
    return false;
}

static bool root(walk *w)
{
    const vdbgi_vdb_tree_format *f = w->f;
    const uint8_t *p = NULL;
    if (!take(w, &w->topo, 4, &p))
        return false;
    if (vdbgi_get_u32(p) != 1)
        return fail(w, "it has %u buffers where OpenVDB reads 1", vdbgi_get_u32(p));
    if (!take(w, &w->topo, f->value_size + 8, &p))
        return false;
    const uint32_t tiles = vdbgi_get_u32(p + f->value_size);
    const uint32_t children = vdbgi_get_u32(p + f->value_size + 4);
    if (!take(w, &w->topo, (uint64_t)tiles * (12 + f->value_size + 1), &p))
        return false;
    for (uint32_t t = 0; t < tiles; t++) /* origin, value, then the active byte */
        w->counts.tiles += p[t * (12 + f->value_size + 1) + 12 + f->value_size] != 0;
    int32_t prev[3] = {0, 0, 0};
    for (uint32_t n = 0; n < children; n++) {
        if (!take(w, &w->topo, 12, &p))
            return false;
        int32_t o[3];
        for (int k = 0; k < 3; k++) {
            o[k] = (int32_t)vdbgi_get_u32(p + 4 * k);
            // An unaligned origin is rounded by OpenVDB: two could land on one slot.
            if (o[k] % ROOT_CHILD_DIM != 0)
                return fail(w, "a node's origin %d is not a multiple of %d", o[k], ROOT_CHILD_DIM);
            if (o[k] < -f->max_index - ROOT_CHILD_DIM || o[k] > f->max_index)
                return fail(w, "a node at %d lies beyond index +-%d", o[k], f->max_index);
        }
        // OpenVDB keeps a duplicate's last copy and leaks the first; its buffers are read
        // in sorted order, so file order must be that order.
        if (n > 0 && !coord_less(prev, o))
            return fail(w, "its top-level nodes are not in ascending order");
        memcpy(prev, o, sizeof prev);
        if (!internal(w, 5, o))
            return false;
    }
    return true;
}

bool vdbgi_vdb_tree_check(const uint8_t *buf, size_t topology, size_t size,
                          const vdbgi_vdb_tree_format *f, vdbgi_vdb_tree_counts *counts, char *why,
                          size_t why_size)
{
    walk w = {{buf, 0, topology}, {buf, topology, size}, f, why, why_size, {0}};
    if (topology > size)
        return fail(&w, "its topology ends past its data");
    if (!root(&w))
        return false;
    if (w.topo.pos != topology)
        return fail(&w, "its topology ends %zu bytes before its data starts",
                    topology - w.topo.pos);
    if (w.data.pos != size)
        return fail(&w, "its data ends %zu bytes before the grid does", size - w.data.pos);
    if (counts)
        *counts = w.counts;
    return true;
}
