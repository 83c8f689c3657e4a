/* map.h: the one hash map of lib/, from integer triples (lattice or block coordinates) to dense indices. */
#ifndef VDBGI_MAP_H
#define VDBGI_MAP_H

#include "context.h"

/*
 * Keys are numbered 0, 1, 2 ... in the order they are first inserted, so a
 * caller keeps its per-key data in arrays of its own and iterating keys
 * follows insertion order, never the hash. Grows as needed.
 */
typedef struct vdbgi_map {
    vdbgi_context *ctx;
    int32_t (*keys)[3];
    size_t count, capacity;
    uint32_t *table; /* open addressing: index + 1, 0 = empty */
    size_t table_size;
} vdbgi_map;

/* An empty map with room for capacity keys before it grows. */
vdbgi_result vdbgi_map_init(vdbgi_context *ctx, vdbgi_map *m, size_t capacity);
void vdbgi_map_free(vdbgi_map *m);
/* Index of key k, or -1. */
long vdbgi_map_find(const vdbgi_map *m, const int32_t k[3]);
/* Index of key k, inserted if new (*added says which). Fails only for memory. */
vdbgi_result vdbgi_map_insert(vdbgi_map *m, const int32_t k[3], size_t *index, bool *added);

#endif /* VDBGI_MAP_H */
