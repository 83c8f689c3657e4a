/* map.c: open-addressing hash map from int32 triples to insertion indices. */
#include "map.h"

#include <string.h>

static size_t hash_key(const int32_t k[3])
{
    uint64_t h = (uint64_t)(uint32_t)k[0] * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t)(uint32_t)k[1] * 0xC2B2AE3D27D4EB4Full;
    h ^= (uint64_t)(uint32_t)k[2] * 0x165667B19E3779F9ull;
    /* Leaf origins are multiples of 8: fold the high bits down so the low ones vary. */
    return (size_t)(h ^ (h >> 31));
}

static bool same_key(const int32_t a[3], const int32_t b[3])
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

vdbgi_result vdbgi_map_init(vdbgi_context *ctx, vdbgi_map *m, size_t capacity)
{
    memset(m, 0, sizeof(*m));
    m->ctx = ctx;
    VDBGI_FAIL_IF(ctx, capacity >= UINT32_MAX / 4, VDBGI_ERR_OUT_OF_MEMORY,
                  "%zu keys are more than a map can index", capacity);
    m->capacity = capacity ? capacity : 16;
    m->table_size = 16;
    while (m->table_size < 2 * m->capacity)
        m->table_size *= 2;
    m->keys = vdbgi_calloc(ctx, m->capacity, sizeof(*m->keys));
    m->table = vdbgi_calloc(ctx, m->table_size, sizeof(uint32_t));
    if (!m->keys || !m->table) {
        vdbgi_map_free(m);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    return VDBGI_OK;
}

void vdbgi_map_free(vdbgi_map *m)
{
    if (m->ctx) {
        vdbgi_free(m->ctx, m->keys);
        vdbgi_free(m->ctx, m->table);
    }
    memset(m, 0, sizeof(*m));
}

long vdbgi_map_find(const vdbgi_map *m, const int32_t k[3])
{
    if (m->table_size == 0) /* never initialised: an empty field, say */
        return -1;
    const size_t mask = m->table_size - 1;
    for (size_t s = hash_key(k) & mask; m->table[s]; s = (s + 1) & mask)
        if (same_key(m->keys[m->table[s] - 1], k))
            return (long)m->table[s] - 1;
    return -1;
}

static void place(vdbgi_map *m, size_t index)
{
    const size_t mask = m->table_size - 1;
    size_t s = hash_key(m->keys[index]) & mask;
    while (m->table[s])
        s = (s + 1) & mask;
    m->table[s] = (uint32_t)index + 1;
}

static vdbgi_result grow(vdbgi_map *m)
{
    vdbgi_context *const ctx = m->ctx;
    VDBGI_FAIL_IF(ctx, m->capacity >= UINT32_MAX / 8, VDBGI_ERR_OUT_OF_MEMORY,
                  "%zu keys are more than a map can index", m->capacity);
    const size_t capacity = 2 * m->capacity, table_size = 2 * m->table_size;
    int32_t(*const keys)[3] = vdbgi_calloc(ctx, capacity, sizeof(*keys));
    uint32_t *const table = vdbgi_calloc(ctx, table_size, sizeof(uint32_t));
    if (!keys || !table) {
        vdbgi_free(ctx, keys);
        vdbgi_free(ctx, table);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    memcpy(keys, m->keys, m->count * sizeof(*keys));
    vdbgi_free(ctx, m->keys);
    vdbgi_free(ctx, m->table);
    m->keys = keys;
    m->table = table;
    m->capacity = capacity;
    m->table_size = table_size;
    for (size_t i = 0; i < m->count; i++)
        place(m, i);
    return VDBGI_OK;
}

vdbgi_result vdbgi_map_insert(vdbgi_map *m, const int32_t k[3], size_t *index, bool *added)
{
    const long found = vdbgi_map_find(m, k);
    if (added)
        *added = found < 0;
    if (found >= 0) {
        *index = (size_t)found;
        return VDBGI_OK;
    }
    if (m->count == m->capacity)
        VDBGI_TRY(grow(m));
    const size_t i = m->count++;
    memcpy(m->keys[i], k, sizeof(m->keys[i]));
    place(m, i);
    *index = i;
    return VDBGI_OK;
}
