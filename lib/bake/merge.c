/*
 * merge.c: the tiles of one bake into the whole (gi-merge): each tile read
 * and checked against the first (same bake, same tiling, its own range),
 * the set checked (none missing; their slabs covering the tiles' span with
 * no gap and no overlap), then OpenVDB's tree merge (vdb_shim.cpp) writes
 * the whole.
 */
#include "probes.h"
#include "util.h"
#include "vdb_shim.h"

#include <stdio.h>
#include <string.h>

/* Settings that differ from tile to tile of one bake, or that OpenVDB writes per file. */
static bool per_tile(const char *name)
{
    static const char *const keys[] = {"probes",     "invalid_probes", "bake_seconds",
                                       "tile_index", "tile_x_begin",   "tile_x_end"};
    for (size_t k = 0; k < sizeof(keys) / sizeof(keys[0]); k++)
        if (strcmp(name, keys[k]) == 0)
            return true;
    return strncmp(name, "file_", 5) == 0;
}

/* Whether a and b are the same bake: else false, and the first setting in which they differ
   (either way) into why, as "a's line against b's line". */
static bool same_bake(const vdbgi_meta_store *a, const vdbgi_meta_store *b, char *why,
                      size_t why_size)
{
    for (int pass = 0; pass < 2; pass++) {
        const vdbgi_meta_store *const x = pass ? b : a, *const y = pass ? a : b;
        for (size_t m = 0; m < x->count; m++) {
            const vdbgi_meta *const mx = &x->items[m];
            if (per_tile(mx->name))
                continue;
            const vdbgi_meta *const my = vdbgi_meta_find(y, mx->name);
            if (!my || strcmp(mx->line, my->line) != 0) {
                snprintf(why, why_size, "%s against %s",
                         pass ? (my ? my->line : mx->name) : mx->line,
                         pass ? mx->line : (my ? my->line : "none"));
                return false;
            }
        }
    }
    return true;
}

typedef struct tile_seen {
    const char *path; /* NULL until given */
    int64_t x[2];
} tile_seen;

typedef struct merge_job {
    const char *const *paths;
    size_t count;
    const char *name;
    const vdbgi_meta_store *set;
} merge_job;

static vdbgi_result write_merged(vdbgi_context *ctx, const char *tmp, const void *user)
{
    static const char *const drop[] = {"tile_index", "tile_count",    "tile_x_begin",
                                       "tile_x_end", "tiles_x_begin", "tiles_x_end"};
    const merge_job *const job = user;
    return vdbgi_vdb_merge(ctx, tmp, job->name, job->paths, job->count, drop,
                           sizeof(drop) / sizeof(drop[0]), job->set);
}

/* The integer setting name of p, or fail naming path. */
static vdbgi_result tile_int(vdbgi_context *ctx, const vdbgi_probes *p, const char *path,
                             const char *name, int64_t *out)
{
    const vdbgi_meta *const m = vdbgi_meta_find(&p->meta, name);
    VDBGI_FAIL_IF(ctx, !m || m->type != VDBGI_META_INT, VDBGI_ERR_FORMAT,
                  "%s: not a tile of a bake (no %s): bake tiles with gi-bake --tile I/N", path,
                  name);
    *out = m->i;
    return VDBGI_OK;
}

/* Read and check tile number i of paths against the first, into seen and the sums. */
static vdbgi_result take_tile(vdbgi_context *ctx, const char *path, vdbgi_meta_store *first,
                              const char **first_path, tile_seen **seen, int64_t *tiles,
                              int64_t span[2], size_t sums[2], double *seconds)
{
    vdbgi_probes *p = NULL;
    VDBGI_TRY(vdbgi_probes_read(ctx, path, &p));
    int64_t index = 0, count = 0, x0 = 0, x1 = 0, s0 = 0, s1 = 0;
    vdbgi_result r = tile_int(ctx, p, path, "tile_index", &index);
    if (r == VDBGI_OK)
        r = tile_int(ctx, p, path, "tile_count", &count);
    if (r == VDBGI_OK)
        r = tile_int(ctx, p, path, "tile_x_begin", &x0);
    if (r == VDBGI_OK)
        r = tile_int(ctx, p, path, "tile_x_end", &x1);
    if (r == VDBGI_OK)
        r = tile_int(ctx, p, path, "tiles_x_begin", &s0);
    if (r == VDBGI_OK)
        r = tile_int(ctx, p, path, "tiles_x_end", &s1);
    char why[600];
    if (r == VDBGI_OK && !*first_path) {
        if (count < 2 || count > VDBGI_MAX_TILES)
            r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: a tile of %lld tiles", path,
                           (long long)count);
        else if (!(*seen = vdbgi_calloc(ctx, (size_t)count, sizeof(tile_seen))))
            r = VDBGI_ERR_OUT_OF_MEMORY;
        else
            *first = p->meta, *first_path = path, *tiles = count, span[0] = s0, span[1] = s1;
    } else if (r == VDBGI_OK && !same_bake(first, &p->meta, why, sizeof(why))) {
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: not a tile of the same bake as %s: %s", path,
                       *first_path, why);
    }
    if (r == VDBGI_OK && !(index >= 0 && index < *tiles))
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: tile %lld of %lld does not exist", path,
                       (long long)index + 1, (long long)*tiles);
    if (r == VDBGI_OK && (*seen)[index].path)
        r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s: tile %lld of %lld, given twice (also %s)", path,
                       (long long)index + 1, (long long)*tiles, (*seen)[index].path);
    for (size_t i = 0; r == VDBGI_OK && i < p->count; i++)
        if (p->ijk[3 * i] < x0 || p->ijk[3 * i] >= x1)
            r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT,
                           "%s: holds probe %d,%d,%d, outside its tile's i range %lld..%lld", path,
                           p->ijk[3 * i], p->ijk[3 * i + 1], p->ijk[3 * i + 2], (long long)x0,
                           (long long)x1 - 1);
    if (r == VDBGI_OK) {
        (*seen)[index] = (tile_seen){path, {x0, x1}};
        sums[0] += p->count;
        sums[1] += p->invalid_count;
        const vdbgi_meta *const s = vdbgi_meta_find(&p->meta, "bake_seconds");
        *seconds += s && s->type == VDBGI_META_DOUBLE ? s->d : 0.0;
    }
    vdbgi_probes_destroy(p);
    return r;
}

vdbgi_result vdbgi_probes_merge(vdbgi_context *ctx, const char *const *paths, size_t count,
                                const char *path)
{
    VDBGI_FAIL_IF(ctx, !paths || count == 0 || !path, VDBGI_ERR_INVALID_ARG,
                  "no tiles or no output given");
    vdbgi_meta_store *const first = vdbgi_calloc(ctx, 1, sizeof(*first));
    if (!first)
        return VDBGI_ERR_OUT_OF_MEMORY;
    const char *first_path = NULL;
    tile_seen *seen = NULL;
    int64_t tiles = 0, span[2] = {0, 0};
    size_t sums[2] = {0, 0};
    double seconds = 0.0;
    vdbgi_result r = VDBGI_OK;
    for (size_t i = 0; r == VDBGI_OK && i < count; i++)
        r = take_tile(ctx, paths[i], first, &first_path, &seen, &tiles, span, sums, &seconds);
    for (int64_t t = 0; r == VDBGI_OK && t < tiles; t++)
        if (!seen[t].path)
            r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "tile %lld of %lld is missing", (long long)t + 1,
                           (long long)tiles);
    /* The slabs, in tile order, cover the tiles' span without a gap or an overlap. */
    for (int64_t t = 0; r == VDBGI_OK && t <= tiles; t++) {
        const int64_t end = t == 0 ? span[0] : seen[t - 1].x[1];
        const int64_t begin = t == tiles ? span[1] : seen[t].x[0];
        if (end > begin)
            r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "%s and %s overlap (i %lld..%lld and %lld..%lld)",
                           seen[t - 1].path, seen[t].path, (long long)seen[t - 1].x[0],
                           (long long)seen[t - 1].x[1] - 1, (long long)seen[t].x[0],
                           (long long)seen[t].x[1] - 1);
        else if (end < begin)
            r = vdbgi_fail(ctx, VDBGI_ERR_FORMAT, "no tile holds lattice i %lld..%lld",
                           (long long)end, (long long)begin - 1);
    }
    if (r == VDBGI_OK) {
        vdbgi_meta_store set = {0};
        vdbgi_meta_set_int(&set, "probes", (int64_t)sums[0]);
        vdbgi_meta_set_int(&set, "invalid_probes", (int64_t)sums[1]);
        vdbgi_meta_set_double(&set, "bake_seconds", seconds);
        const merge_job job = {paths, count, path, &set};
        r = vdbgi_write_atomic(ctx, path, write_merged, &job);
    }
    vdbgi_free(ctx, seen);
    vdbgi_free(ctx, first);
    return r;
}
