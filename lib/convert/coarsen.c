/*
 * coarsen.c: per-block colour statistics over the filled field, level by
 * level, and the top-down choice of one coarse brick or eight finer ones.
 */
#include "coarsen.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

typedef struct block_stats {
    float lo[3], hi[3];
    double sum[3];
    uint32_t count; /* filled points summed */
    float noise;    /* largest standard error of a valid probe in the block */
} block_stats;

/* The blocks of one pyramid level: the map numbers them, stats[i] is block i's. */
typedef struct level_map {
    vdbgi_map map;
    block_stats *stats;
} level_map;

/* Room for capacity blocks: a level never holds more blocks than there are cells. */
static vdbgi_result level_init(vdbgi_context *ctx, level_map *m, size_t capacity)
{
    m->stats = vdbgi_calloc(ctx, capacity ? capacity : 1, sizeof(*m->stats));
    const vdbgi_result r = vdbgi_map_init(ctx, &m->map, capacity);
    return m->stats ? r : VDBGI_ERR_OUT_OF_MEMORY;
}

static void level_free(vdbgi_context *ctx, level_map *m)
{
    vdbgi_free(ctx, m->stats);
    vdbgi_map_free(&m->map);
    m->stats = NULL;
}

static long level_find(const level_map *m, const int32_t k[3])
{
    return vdbgi_map_find(&m->map, k);
}

/* Index of block k, inserted with empty stats if new (the map has room: see level_init). */
static size_t level_insert(level_map *m, const int32_t k[3])
{
    size_t i;
    bool added;
    vdbgi_map_insert(&m->map, k, &i, &added);
    if (added) {
        block_stats *const st = &m->stats[i];
        for (int c = 0; c < 3; c++) {
            st->lo[c] = INFINITY;
            st->hi[c] = -INFINITY;
            st->sum[c] = 0.0;
        }
        st->count = 0;
        st->noise = 0.0f;
    }
    return i;
}

static void stats_merge(block_stats *into, const block_stats *from)
{
    for (int c = 0; c < 3; c++) {
        into->lo[c] = fminf(into->lo[c], from->lo[c]);
        into->hi[c] = fmaxf(into->hi[c], from->hi[c]);
        into->sum[c] += from->sum[c];
    }
    into->count += from->count;
    into->noise = fmaxf(into->noise, from->noise);
}

/* Largest channel range; 0 for a block with no filled point (it reads its fallback). */
static float stats_range(const block_stats *st)
{
    if (!st->count)
        return 0.0f;
    float r = 0.0f;
    for (int c = 0; c < 3; c++)
        r = fmaxf(r, st->hi[c] - st->lo[c]);
    return r;
}

typedef struct builder {
    vdbgi_context *ctx;
    const vdbgi_probes *probes;
    const vdbgi_field *filled;
    const vdbgi_coarsen_params *cp;
    level_map levels[4];
    vdbgi_brick *kept;
    size_t kept_count, kept_capacity;
} builder;

/* The mean of block st, or the fallback for a block with no filled point. */
static void block_mean(const builder *b, const block_stats *st, float mean[3])
{
    for (int c = 0; c < 3; c++)
        mean[c] = st->count ? (float)(st->sum[c] / st->count) : b->cp->fallback[c];
}

/*
 * The values of a level-L brick, x fastest. Seed layout: 6^3, probe q (-1..4
 * per axis, -1 and 4 the apron) at fine position origin + (q + 0.5) 2^L - 0.5,
 * the centre of its 2^L block (the shader's convention). Compact layout: 5^3,
 * probe q (0..4, 4 the border) at origin + q 2^L, a lattice point. Points the
 * fill did not reach take the block's mean, which is within the block's range
 * of every filled point.
 */
size_t vdbgi_brick_samples(const vdbgi_field *filled, const int32_t key[3], int level,
                           const float mean[3], vdbgi_layout layout, float out[][3])
{
    size_t fallbacks = 0;
    const vdbgi_leaf *cache = NULL;
    const int span = 1 << level, n = vdbgi_slot_texels(layout);
    const double shift = layout == VDBGI_LAYOUT_COMPACT ? 0.0 : 0.5 * span - 0.5 - span;
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++) {
                const int q[3] = {x, y, z};
                double pos[3];
                for (int k = 0; k < 3; k++)
                    pos[k] = (double)key[k] * VDBGI_BRICK * span + q[k] * span + shift;
                float *const v = out[(z * n + y) * n + x];
                bool valued;
                if (layout == VDBGI_LAYOUT_COMPACT) {
                    /* A lattice point: what the trilinear read gives there, without weights. */
                    const int32_t p[3] = {(int32_t)pos[0], (int32_t)pos[1], (int32_t)pos[2]};
                    const float *const f = vdbgi_field_at(filled, p, &cache);
                    if ((valued = f != NULL))
                        memcpy(v, f, 3 * sizeof(float));
                } else {
                    float all[3 * VDBGI_FIELD_MAX_CHANNELS]; /* L0 first, then any terms */
                    if ((valued = vdbgi_field_trilinear(filled, pos, all, &cache)))
                        memcpy(v, all, 3 * sizeof(float));
                }
                if (!valued) {
                    memcpy(v, mean, 3 * sizeof(float));
                    fallbacks++;
                }
            }
    return fallbacks;
}

/*
 * Does the coarse brick reproduce the filled points it draws within
 * tolerance: every one (INTERP), or in the root mean square of each point's
 * largest channel error (RMSE, Unreal's rule)? The shader keeps a block's brick up to the next block's
 * first probe, so the probes one step past the block's far faces are tested
 * too: with both ends of that last step within tolerance, and the next
 * block's brick exact or within its own tolerance at that probe, the jump
 * where the bricks meet stays within the two tolerances (docs/stability.md,
 * level seams). The near faces need no extra points: the block's first probe
 * is its own.
 */
static bool interpolation_fits(const builder *b, const int32_t key[3], int level,
                               const float mean[3], float noise)
{
    float s[VDBGI_BRICK_PADDED * VDBGI_BRICK_PADDED * VDBGI_BRICK_PADDED][3];
    vdbgi_brick_samples(b->filled, key, level, mean, b->cp->layout, s);
    const int span = 1 << level, n = VDBGI_BRICK * span;
    const level_map *const cells = &b->levels[0];
    const vdbgi_leaf *cache = NULL;
    const float tolerance = b->cp->tolerance + noise;
    const bool rmse = b->cp->criterion == VDBGI_CRITERION_RMSE;
    double sum = 0.0;
    size_t count = 0;
    for (int z = 0; z <= n; z++)
        for (int y = 0; y <= n; y++)
            for (int x = 0; x <= n; x++) {
                const int32_t p[3] = {key[0] * n + x, key[1] * n + y, key[2] * n + z};
                const int32_t cell[3] = {vdbgi_floor_div(p[0], VDBGI_BRICK),
                                         vdbgi_floor_div(p[1], VDBGI_BRICK),
                                         vdbgi_floor_div(p[2], VDBGI_BRICK)};
                if (level_find(cells, cell) < 0)
                    continue; /* no brick there: nothing is drawn */
                float got[3];
                const float *const want = vdbgi_field_at(b->filled, p, &cache);
                if (!want)
                    continue;
                const double pos[3] = {p[0], p[1], p[2]};
                vdbgi_brick_interpolate(s, b->cp->layout, key, level, pos, got);
                float worst = 0.0f;
                for (int k = 0; k < 3; k++)
                    worst = fmaxf(worst, fabsf(got[k] - want[k]));
                if (!rmse && worst > tolerance)
                    return false;
                sum += (double)worst * worst;
                count++;
            }
    return !rmse || count == 0 || sqrt(sum / (double)count) <= tolerance;
}

/*
 * The range criterion in the compact layout: a coarse brick there stands its
 * last probes on the next blocks' first ones (its + border), so the block's
 * own range says nothing about the step into them. The range of the block
 * together with the filled points on its + faces bounds every value the
 * brick interpolates.
 */
static float range_with_far_faces(const builder *b, const block_stats *st, const int32_t key[3],
                                  int level)
{
    block_stats all = *st;
    const int n = VDBGI_BRICK << level;
    const vdbgi_leaf *cache = NULL;
    for (int z = 0; z <= n; z++)
        for (int y = 0; y <= n; y++)
            for (int x = 0; x <= n; x++) {
                if (x < n && y < n && z < n) {
                    x = n - 1; /* inside: skip to the + face of this row */
                    continue;
                }
                const int32_t p[3] = {key[0] * n + x, key[1] * n + y, key[2] * n + z};
                const float *const v = vdbgi_field_at(b->filled, p, &cache);
                if (!v)
                    continue;
                for (int c = 0; c < 3; c++) {
                    all.lo[c] = fminf(all.lo[c], v[c]);
                    all.hi[c] = fmaxf(all.hi[c], v[c]);
                }
                all.count++;
            }
    return stats_range(&all);
}

/*
 * Kept bricks go into the region of b->kept reserved for their root block:
 * bricks are disjoint and each holds a cell, so a root never keeps more
 * bricks than it has cells, and the region is sized to that.
 */
static vdbgi_result keep(builder *b, const int32_t key[3], int level, const float mean[3])
{
    if (b->kept_count == b->kept_capacity)
        return vdbgi_fail(b->ctx, VDBGI_ERR_BACKEND, "internal error: more bricks than cells");
    vdbgi_brick *const k = &b->kept[b->kept_count++];
    memcpy(k->key, key, sizeof(k->key));
    k->level = level;
    memcpy(k->mean, mean, sizeof(k->mean));
    return VDBGI_OK;
}

/* Seed 000's visit(): one coarse brick if flat enough, else the eight children that exist. */
static vdbgi_result visit(builder *b, const int32_t key[3], int level)
{
    const long i = level_find(&b->levels[level], key);
    if (i < 0)
        return VDBGI_OK; /* empty air: no brick */
    const block_stats *const st = &b->levels[level].stats[i];
    float mean[3];
    block_mean(b, st, mean);
    if (level == 0)
        return keep(b, key, level, mean);
    /*
     * Sampling noise spreads a flat field over about +-sigmas standard errors,
     * so that much of the range (twice: both ends) is not the light's doing.
     */
    const float noise = b->cp->sigmas * st->noise;
    /*
     * A flat block is not enough for the interpolation criterion: its brick's apron
     * reaches half a coarse texel into the neighbours, and a flat block beside a
     * shadow edge would draw the edge into its own probes (docs/stability.md).
     */
    bool coarse;
    if (b->cp->criterion != VDBGI_CRITERION_RANGE)
        coarse = interpolation_fits(b, key, level, mean, noise);
    else if (b->cp->layout == VDBGI_LAYOUT_COMPACT)
        coarse = range_with_far_faces(b, st, key, level) - 2.0f * noise <= b->cp->tolerance;
    else
        coarse = stats_range(st) - 2.0f * noise <= b->cp->tolerance;
    if (coarse)
        return keep(b, key, level, mean);
    for (int c = 0; c < 8; c++) {
        const int32_t child[3] = {2 * key[0] + (c & 1), 2 * key[1] + (c >> 1 & 1),
                                  2 * key[2] + (c >> 2 & 1)};
        VDBGI_TRY(visit(b, child, level - 1));
    }
    return VDBGI_OK;
}

static int compare_keys(const void *a, const void *b)
{
    const int32_t *const x = a, *const y = b;
    for (int k = 2; k >= 0; k--)
        if (x[k] != y[k])
            return x[k] < y[k] ? -1 : 1;
    return 0;
}

/* Level-0 stats from the filled leaves (a leaf holds 2^3 cells), then coarser levels. */
static vdbgi_result build_pyramid(builder *b, const int32_t *cells, size_t cell_count)
{
    vdbgi_context *const ctx = b->ctx;
    for (int l = 0; l <= b->cp->max_level; l++)
        VDBGI_TRY(level_init(ctx, &b->levels[l], cell_count));
    for (size_t c = 0; c < cell_count; c++)
        level_insert(&b->levels[0], &cells[3 * c]);
    const vdbgi_field *const f = b->filled;
    for (size_t li = 0; li < f->leaf_count; li++) {
        const vdbgi_leaf *const leaf = &f->leaves[li];
        for (int sub = 0; sub < 8; sub++) {
            const int ox = (sub & 1) * 4, oy = (sub >> 1 & 1) * 4, oz = (sub >> 2 & 1) * 4;
            /* Leaf origins are multiples of 8, so this division is exact. */
            const int32_t ck[3] = {(leaf->origin[0] + ox) / 4, (leaf->origin[1] + oy) / 4,
                                   (leaf->origin[2] + oz) / 4};
            const long ci = level_find(&b->levels[0], ck);
            if (ci < 0)
                continue; /* rim points: filled for filtering, not part of any cell */
            block_stats *const st = &b->levels[0].stats[ci];
            for (int x = ox; x < ox + 4; x++)
                for (int y = oy; y < oy + 4; y++)
                    for (int z = oz; z < oz + 4; z++) {
                        const unsigned n = (unsigned)(x << 6 | y << 3 | z);
                        if (!(leaf->mask[n >> 6] >> (n & 63) & 1))
                            continue;
                        const float *const v = leaf->values + 3 * (size_t)f->channels * n;
                        for (int k = 0; k < 3; k++) {
                            st->lo[k] = fminf(st->lo[k], v[k]);
                            st->hi[k] = fmaxf(st->hi[k], v[k]);
                            st->sum[k] += v[k];
                        }
                        st->count++;
                    }
        }
    }
    /* Each cell's noise: the largest standard error among its valid probes. */
    const vdbgi_probes *const p = b->probes;
    for (size_t n = 0; p->stderr_ && n < p->count; n++) {
        if (p->backface[n] > p->invalid_threshold)
            continue;
        const int32_t ck[3] = {vdbgi_floor_div(p->ijk[3 * n], 4),
                               vdbgi_floor_div(p->ijk[3 * n + 1], 4),
                               vdbgi_floor_div(p->ijk[3 * n + 2], 4)};
        const long ci = level_find(&b->levels[0], ck);
        if (ci >= 0)
            b->levels[0].stats[ci].noise = fmaxf(b->levels[0].stats[ci].noise, p->stderr_[n]);
    }
    for (int l = 1; l <= b->cp->max_level; l++) {
        const level_map *const fine = &b->levels[l - 1];
        for (size_t i = 0; i < fine->map.count; i++) {
            const int32_t parent[3] = {vdbgi_floor_div(fine->map.keys[i][0], 2),
                                       vdbgi_floor_div(fine->map.keys[i][1], 2),
                                       vdbgi_floor_div(fine->map.keys[i][2], 2)};
            const size_t pi = level_insert(&b->levels[l], parent);
            stats_merge(&b->levels[l].stats[pi], &fine->stats[i]);
        }
    }
    return VDBGI_OK;
}

/*
 * Coarsen every root block over all cores. Roots are handed out one at a
 * time; each writes its bricks into its own region of b->kept, and the
 * regions are joined in z, y, x order of the roots afterwards, so the brick
 * order, hence the file, does not depend on the threads.
 */
typedef struct coarsen_job {
    const builder *b;
    const int32_t (*roots)[3];
    builder *parts; /* one per root: the builder with that root's region as kept */
    size_t count;
    atomic_size_t *next;
    vdbgi_result result;
} coarsen_job;

static void *coarsen_worker(void *arg)
{
    coarsen_job *const job = arg;
    for (size_t i; job->result == VDBGI_OK && (i = atomic_fetch_add(job->next, 1)) < job->count;)
        job->result = visit(&job->parts[i], job->roots[i], job->b->cp->max_level);
    return NULL;
}

static vdbgi_result coarsen(builder *b)
{
    vdbgi_context *const ctx = b->ctx;
    const vdbgi_map *const top = &b->levels[b->cp->max_level].map;
    const vdbgi_map *const cells = &b->levels[0].map;
    const size_t n = top->count;
    int32_t(*roots)[3] = vdbgi_calloc(ctx, n ? n : 1, sizeof(*roots));
    size_t *const cells_under = vdbgi_calloc(ctx, n ? n : 1, sizeof(size_t)); /* by top index */
    builder *const parts = vdbgi_calloc(ctx, n ? n : 1, sizeof(*parts));
    b->kept = vdbgi_calloc(ctx, cells->count ? cells->count : 1, sizeof(*b->kept));
    vdbgi_result r = VDBGI_OK;
    if (!roots || !cells_under || !parts || !b->kept) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto done;
    }
    /* Each root's region: as many bricks as it has level-0 cells, roots in z, y, x order. */
    memcpy(roots, top->keys, n * sizeof(*roots));
    qsort(roots, n, sizeof(*roots), compare_keys);
    for (size_t c = 0; c < cells->count; c++) {
        int32_t root[3];
        for (int k = 0; k < 3; k++)
            root[k] = vdbgi_floor_div(cells->keys[c][k], 1 << b->cp->max_level);
        const long ti = vdbgi_map_find(top, root);
        if (ti >= 0) /* always: the pyramid holds every cell's ancestors */
            cells_under[ti]++;
    }
    size_t sum = 0;
    for (size_t i = 0; i < n; i++) {
        const size_t count = cells_under[vdbgi_map_find(top, roots[i])]; /* roots are top's keys */
        parts[i] = *b;
        parts[i].kept = b->kept + sum;
        parts[i].kept_count = 0;
        parts[i].kept_capacity = count;
        sum += count;
    }
    enum { MAX_JOBS = 64 };
    coarsen_job jobs[MAX_JOBS];
    atomic_size_t next = 0;
    int t_count = b->cp->threads;
    t_count = t_count > MAX_JOBS ? MAX_JOBS : t_count;
    for (int t = 0; t < t_count; t++)
        jobs[t] = (coarsen_job){
            .b = b, .roots = (const int32_t(*)[3])roots, .parts = parts, .count = n, .next = &next};
    vdbgi_run_threads(t_count, coarsen_worker, jobs, sizeof(jobs[0]));
    for (int t = 0; t < t_count && r == VDBGI_OK; t++)
        r = jobs[t].result;
    /* Join the regions in root order. */
    b->kept_count = 0;
    for (size_t i = 0; r == VDBGI_OK && i < n; i++) {
        memmove(b->kept + b->kept_count, parts[i].kept, parts[i].kept_count * sizeof(*b->kept));
        b->kept_count += parts[i].kept_count;
    }
done:
    vdbgi_free(ctx, roots);
    vdbgi_free(ctx, cells_under);
    vdbgi_free(ctx, parts);
    return r;
}

vdbgi_result vdbgi_coarsen(vdbgi_context *ctx, const vdbgi_field *filled,
                           const vdbgi_probes *probes, const int32_t *cells, size_t cell_count,
                           const vdbgi_coarsen_params *cp, vdbgi_brick **bricks,
                           size_t *brick_count)
{
    *bricks = NULL;
    *brick_count = 0;
    builder b = {.ctx = ctx, .probes = probes, .filled = filled, .cp = cp};
    vdbgi_result r = build_pyramid(&b, cells, cell_count);
    if (r == VDBGI_OK)
        r = coarsen(&b);
    for (int l = 0; l < 4; l++)
        level_free(ctx, &b.levels[l]);
    if (r != VDBGI_OK) {
        vdbgi_free(ctx, b.kept);
        return r;
    }
    *bricks = b.kept;
    *brick_count = b.kept_count;
    return VDBGI_OK;
}
