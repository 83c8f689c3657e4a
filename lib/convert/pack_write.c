/*
 * pack_write.c: the converter's half of the compact file: each stored
 * point's value from the filled field, the residuals against the predictor,
 * and the payload (level bytes, placement, residual planes); the textures
 * are then rebuilt from the values exactly as a reader rebuilds them.
 */
#include "pack_write.h"
#include "encode.h"
#include "gifile.h"
#include "pack_common.h"
#include "util.h"

#include <stdlib.h>
#include <string.h>

/*
 * Slot order: by each brick's first cell, z, then y, then x, as the reader
 * lists them (absolute cells: the indirection's corner shifts all alike).
 */
static int brick_order(const void *pa, const void *pb)
{
    const vdbgi_brick *a = pa, *b = pb;
    for (int k = 2; k >= 0; k--) {
        const int32_t ca = a->key[k] * (1 << a->level), cb = b->key[k] * (1 << b->level);
        if (ca != cb)
            return ca < cb ? -1 : 1;
    }
    return 0;
}

/* Valid probes, a bit each, into bits over the owner grid. */
static void valid_bits(const vdbgi_volume *v, const vdbgi_pack_plan *pl, const vdbgi_probes *pr,
                       uint64_t *bits)
{
    for (size_t i = 0; i < pr->count; i++) {
        if (pr->backface[i] > pr->invalid_threshold)
            continue;
        int32_t p[3];
        size_t c;
        int bit;
        for (int k = 0; k < 3; k++)
            p[k] = pr->ijk[3 * i + k] - v->origin_cell[k] * VDBGI_BRICK;
        if (grid_slot(pl, p, &c, &bit))
            bits[c] |= UINT64_C(1) << bit;
    }
}

/*
 * The valid bits grown by one point along an axis: a cell's 4^3 bits are
 * x fastest (1 bit), then y (4), then z (16); the neighbour cells' faces
 * carry in. Three passes grow them to the 26 neighbours.
 */
static void grow(const vdbgi_pack_plan *pl, const uint64_t *in, uint64_t *out, int axis)
{
    static const uint64_t low_face[3] = {UINT64_C(0x1111111111111111), UINT64_C(0x000F000F000F000F),
                                         UINT64_C(0xFFFF)};
    const int step = axis == 0 ? 1 : axis == 1 ? 4 : 16;
    const uint64_t low = low_face[axis], high = low << (3 * step);
    const size_t stride = axis == 0   ? 1
                          : axis == 1 ? pl->grid[0]
                                      : (size_t)pl->grid[0] * pl->grid[1];
    for (int32_t z = 0; z < (int32_t)pl->grid[2]; z++)
        for (int32_t y = 0; y < (int32_t)pl->grid[1]; y++)
            for (int32_t x = 0; x < (int32_t)pl->grid[0]; x++) {
                const int32_t c[3] = {x, y, z};
                const size_t i = cell_index(pl->grid, c);
                const uint64_t m = in[i];
                uint64_t g = m | (m << step & ~low) | (m >> step & ~high);
                if (c[axis] > 0)
                    g |= in[i - stride] >> (3 * step) & low;
                if (c[axis] + 1 < (int32_t)pl->grid[axis])
                    g |= in[i + stride] << (3 * step) & high;
                out[i] = g;
            }
}

/*
 * The first brick (in brick order) whose unstitched texel stands at stored
 * point p. Its block holds one of the cells that touch p (a brick's +
 * border lies in the next cell), which may lie past the indirection when a
 * coarse block does: each such cell is looked up at each level's block.
 */
static size_t first_reader(const vdbgi_pack_plan *pl, const int32_t p[3])
{
    size_t first = SIZE_MAX;
    for (int c = 0; c < 8; c++) {
        int32_t cell[3];
        if (!touching_cell(p, c, cell))
            continue;
        for (int level = 0; level < 4; level++) {
            const int32_t key[3] = {cell[0] >> level, cell[1] >> level, cell[2] >> level};
            const int32_t b = brick_with_key(pl, key, level);
            if (b < 0 || (size_t)b >= first)
                continue;
            const int32_t span = 1 << level;
            bool on = true;
            int t = 0;
            for (int k = 2; k >= 0 && on; k--) {
                const int32_t q = p[k] - key[k] * VDBGI_BRICK * span;
                on = q % span == 0 && q >= 0 && q <= VDBGI_BRICK * span;
                t = t * N + q / span;
            }
            size_t j;
            int cl;
            if (on && !stitched(pl, (size_t)b, t, &j, &cl))
                first = (size_t)b;
        }
    }
    return first;
}

/*
 * A point's 24 term bytes (docs/format.md, "Version 6"), from the filled field's 27 numbers
 * f (NULL, a fallback point: none, flat): each term's ratio to L0 per channel. Version 8
 * gives terms 4-8 the ratio of their luminance (Rec. 709) in all three channels: the first
 * band's colours carry where coloured light comes from, the second its shape.
 */
static void term_bytes(const vdbgi_volume *v, const float *f, uint8_t sh[VDBGI_SH_BYTES])
{
    const int step = 1 << (8 - v->info.term_bits);
    for (int k = 0; k < VDBGI_SH_BYTES; k++) {
        const int term = k / 3;
        if (!f)
            sh[k] = 0;
        else if (v->version >= 8 && term >= 3)
            sh[k] = (uint8_t)vdbgi_sh_ratio_encode(vdbgi_luminance(&f[3 + 3 * term]),
                                                   vdbgi_luminance(f), term, step);
        else
            sh[k] = (uint8_t)vdbgi_sh_ratio_encode(f[3 + k], f[k % 3], term, step);
    }
}

/*
 * A band of owner-cell planes z0 <= cz < z1 for one thread of the converter's
 * passes over the stored points; i0 is its first point's index. The points
 * of a band are written by its thread alone, so the bytes do not depend on
 * the threads.
 */
typedef struct band_job {
    const vdbgi_volume *v;
    const vdbgi_field *filled;
    const vdbgi_pack_plan *pl;
    const vdbgi_brick *bricks;
    size_t count;
    uint8_t *values; /* 4 bytes a point */
    uint8_t *sh;     /* VDBGI_SH_BYTES a point, or NULL: the L2 terms */
    uint8_t *out;    /* the residual planes */
    int32_t z0, z1;
    size_t i0;
    size_t clamped, fallback;
} band_job;

/* Each point's value: the filled field at its lattice point or, where the
 * fill left none, the block mean of the first brick (in brick order) that
 * reads it. Storage order keeps the field's leaves at hand. */
static void *values_worker(void *arg)
{
    band_job *const job = arg;
    const vdbgi_volume *const v = job->v;
    const vdbgi_leaf *cache = NULL;
    FOR_EACH_POINT_IN(job->pl, job->z0, job->z1, job->i0, p, i, {
        const int32_t at[3] = {p[0] + VDBGI_BRICK * v->origin_cell[0],
                               p[1] + VDBGI_BRICK * v->origin_cell[1],
                               p[2] + VDBGI_BRICK * v->origin_cell[2]};
        const float *f = vdbgi_field_at(job->filled, at, &cache);
        const bool valued = f != NULL;
        if (!f) { /* every stored point has a reader: the plan stored it for one */
            static const float none[3];
            const size_t b = first_reader(job->pl, p);
            f = b < job->count ? job->bricks[b].mean : none;
            job->fallback++;
        }
        job->clamped += encode_texel(v, f, &job->values[4 * i]);
        if (job->sh)
            term_bytes(v, valued ? f : NULL, &job->sh[VDBGI_SH_BYTES * i]);
    });
    return NULL;
}

/* Each point's residual against its prediction from values that are final. */
static void *residual_worker(void *arg)
{
    band_job *const job = arg;
    const size_t n = job->pl->points;
    const bool rgbm = job->v->info.encoding == VDBGI_ENCODING_RGBM;
    FOR_EACH_POINT_IN(job->pl, job->z0, job->z1, job->i0, p, i, {
        int64_t nb[4];
        neighbours(job->pl, p, nb);
        for (int o = 0; o < 4; o++) {
            const int k = byte_order(rgbm, o);
            const uint8_t pred = predict(job->values, nb, k, rgbm && k < 3, job->values[4 * i + 3]);
            job->out[k * n + i] = (uint8_t)(job->values[4 * i + k] - pred);
        }
        if (job->sh) {
            uint8_t e[VDBGI_SH_BYTES];
            term_residuals(job->v->version, job->sh, nb, i, e);
            for (int j = 0; j < vdbgi_term_bytes(job->v->version); j++)
                job->out[(4 + (size_t)j) * n + i] = e[vdbgi_term_byte(job->v->version, j)];
        }
    });
    return NULL;
}

/* The number of stored points before owner-cell plane z (every one for z past the grid). */
static size_t points_before(const vdbgi_pack_plan *pl, int32_t z)
{
    const size_t plane_cells = (size_t)pl->grid[0] * pl->grid[1];
    return z < (int32_t)pl->grid[2] ? pl->offset[(size_t)z * plane_cells] : pl->points;
}

/*
 * Bands of about equal numbers of points over the planes z0 <= z < z1, one
 * a thread (at most MAX_JOBS), into jobs; returns how many.
 */
static int split_bands(const vdbgi_pack_plan *pl, int32_t z0, int32_t z1, int threads,
                       band_job *jobs, const band_job *proto)
{
    const int32_t planes = z1 - z0;
    int nt = job_count(threads);
    nt = nt > planes ? (planes > 0 ? planes : 1) : nt;
    const size_t first = points_before(pl, z0), points = points_before(pl, z1) - first;
    int32_t z = z0;
    for (int t = 0; t < nt; t++) {
        jobs[t] = *proto;
        jobs[t].z0 = z;
        jobs[t].i0 = points_before(pl, z);
        const size_t until = first + points * (size_t)(t + 1) / (size_t)nt;
        while (z < z1 && (t == nt - 1 || points_before(pl, z) < until))
            z++;
        jobs[t].z1 = z;
    }
    return nt;
}

/* One level byte a cell (level + 1, 0 for none) for the bricks, in v's indirection; NULL: out of memory. */
static uint8_t *level_bytes(const vdbgi_volume *v, const vdbgi_brick *bricks, size_t count)
{
    const uint32_t *const d = v->info.ind_dims;
    uint8_t *const levels = vdbgi_calloc(v->ctx, (size_t)d[0] * d[1] * d[2], 1);
    for (size_t b = 0; levels && b < count; b++) {
        const int32_t span = 1 << bricks[b].level;
        int32_t lo[3], hi[3];
        for (int k = 0; k < 3; k++) {
            lo[k] = bricks[b].key[k] * span - v->origin_cell[k];
            hi[k] = lo[k] + span < (int32_t)d[k] ? lo[k] + span : (int32_t)d[k];
        }
        for (int32_t z = lo[2]; z < hi[2]; z++)
            for (int32_t y = lo[1]; y < hi[1]; y++)
                for (int32_t x = lo[0]; x < hi[0]; x++) {
                    const int32_t c[3] = {x, y, z};
                    levels[cell_index(d, c)] = (uint8_t)(bricks[b].level + 1);
                }
    }
    return levels;
}

/*
 * A point no receiver reads takes the prediction itself: its residual is
 * zero, which gzip all but drops. Such a point is read by level-0 bricks
 * only (coarse_read marks the others) and has no valid probe among its 26
 * neighbours (valid, grown into near over the three axes; valid is used up).
 * Its prediction depends on the points before it, so these go in storage
 * order, on one thread. Returns how many.
 */
static size_t predict_unread(const vdbgi_volume *v, const vdbgi_pack_plan *pl, uint8_t *values,
                             uint8_t *sh, uint8_t *coarse_read, uint64_t *valid, uint64_t *near)
{
    for (size_t b = 0; b < pl->brick_count; b++)
        for (int t = 0; pl->level[b] && t < TEXELS; t++) {
            size_t j;
            int cl;
            int32_t p[3];
            texel_point(pl, b, t, p);
            const int64_t i = stitched(pl, b, t, &j, &cl) ? -1 : point_index(pl, p);
            if (i >= 0)
                coarse_read[i] = 1;
        }
    grow(pl, valid, near, 0);
    grow(pl, near, valid, 1);
    grow(pl, valid, near, 2);
    const bool rgbm = v->info.encoding == VDBGI_ENCODING_RGBM;
    size_t unread = 0;
    FOR_EACH_POINT(pl, p, i, {
        size_t c = 0;
        int own = 0;
        grid_slot(pl, p, &c, &own); /* every stored point is in the grid */
        if (!coarse_read[i] && !(near[c] >> own & 1u)) {
            unread++;
            int64_t nb[4];
            neighbours(pl, p, nb);
            for (int o = 0; o < 4; o++) {
                const int k = byte_order(rgbm, o);
                values[4 * i + k] = predict(values, nb, k, rgbm && k < 3, values[4 * i + 3]);
            }
            static const uint8_t none[VDBGI_SH_BYTES];
            if (sh)
                term_undo_residuals(v->version, sh, nb, i, none);
        }
    });
    return unread;
}

/* What a compact volume's writing holds between its passes (packed.h). */
struct vdbgi_pack_writer {
    vdbgi_volume *v;
    vdbgi_brick *bricks;
    size_t count;
    int threads;
    vdbgi_pack_plan pl;
    uint8_t *levels, *values, *sh, *coarse_read, *out;
    uint64_t *valid, *near;
    size_t clamped;
};

void vdbgi_pack_writer_destroy(vdbgi_pack_writer *w)
{
    if (!w)
        return;
    vdbgi_context *const ctx = w->v->ctx;
    vdbgi_pack_plan_free(ctx, &w->pl);
    vdbgi_free(ctx, w->levels);
    vdbgi_free(ctx, w->values);
    vdbgi_free(ctx, w->sh);
    vdbgi_free(ctx, w->coarse_read);
    vdbgi_free(ctx, w->out);
    vdbgi_free(ctx, w->valid);
    vdbgi_free(ctx, w->near);
    vdbgi_free(ctx, w);
}

vdbgi_result vdbgi_pack_writer_create(vdbgi_volume *v, vdbgi_brick *bricks, size_t count,
                                      int threads, vdbgi_pack_writer **out)
{
    vdbgi_context *const ctx = v->ctx;
    *out = NULL;
    vdbgi_pack_writer *const w = vdbgi_calloc(ctx, 1, sizeof(*w));
    if (!w)
        return VDBGI_ERR_OUT_OF_MEMORY;
    *w = (vdbgi_pack_writer){.v = v, .bricks = bricks, .count = count, .threads = threads};
    qsort(bricks, count, sizeof(*bricks), brick_order);
    if (!(w->levels = level_bytes(v, bricks, count))) {
        vdbgi_free(ctx, w);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    vdbgi_result r = vdbgi_pack_plan_make(v, w->levels, NULL, NULL, "converter", threads, &w->pl);
    if (r != VDBGI_OK) {
        vdbgi_free(ctx, w->levels);
        vdbgi_free(ctx, w);
        return r;
    }
    const uint32_t *const d = v->info.ind_dims;
    const size_t cells = (size_t)d[0] * d[1] * d[2], n = w->pl.points;
    const bool with_sh = v->info.basis == VDBGI_BASIS_SH2;
    const size_t point_bytes = 4 + (with_sh ? (size_t)vdbgi_term_bytes(v->version) : 0);
    const size_t grid_cells = (size_t)w->pl.grid[0] * w->pl.grid[1] * w->pl.grid[2];
    w->values = vdbgi_calloc(ctx, 4 * (n ? n : 1), 1);
    w->sh = with_sh ? vdbgi_calloc(ctx, n ? n : 1, VDBGI_SH_BYTES) : NULL;
    w->coarse_read = vdbgi_calloc(ctx, n ? n : 1, 1); /* 1: a coarse brick reads the point */
    w->out = vdbgi_alloc(ctx, cells + VDBGI_PLACEMENT_BYTES * count + point_bytes * n);
    w->valid = vdbgi_calloc(ctx, grid_cells ? grid_cells : 1, sizeof(*w->valid));
    w->near = vdbgi_alloc(ctx, (grid_cells ? grid_cells : 1) * sizeof(*w->near));
    if (!w->values || (with_sh && !w->sh) || !w->coarse_read || !w->out || !w->valid || !w->near) {
        vdbgi_pack_writer_destroy(w);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    *out = w;
    return VDBGI_OK;
}

/* Bands over the planes z0 <= z < z1 for w's passes (reading filled, if any), into jobs. */
static int writer_bands(const vdbgi_pack_writer *w, const vdbgi_field *filled, int32_t z0,
                        int32_t z1, band_job *jobs)
{
    const uint32_t *const d = w->v->info.ind_dims;
    const size_t cells = (size_t)d[0] * d[1] * d[2];
    const band_job proto = {.v = w->v,
                            .filled = filled,
                            .pl = &w->pl,
                            .bricks = w->bricks,
                            .count = w->count,
                            .values = w->values,
                            .sh = w->sh,
                            .out = w->out + cells + VDBGI_PLACEMENT_BYTES * w->count};
    return split_bands(&w->pl, z0, z1, w->threads, jobs, &proto);
}

void vdbgi_pack_writer_values(vdbgi_pack_writer *w, const vdbgi_field *filled,
                              const vdbgi_probes *probes, int32_t z0, int32_t z1)
{
    vdbgi_volume *const v = w->v;
    const vdbgi_pack_plan *const pl = &w->pl;
    /* The owner-cell planes holding lattice z0 <= k < z1, within the grid. */
    const int32_t base = v->origin_cell[2], planes = (int32_t)pl->grid[2];
    int32_t c0 = z0 == INT32_MIN ? 0 : vdbgi_floor_div(z0, VDBGI_BRICK) - base;
    int32_t c1 = z1 == INT32_MAX ? planes : vdbgi_floor_div(z1, VDBGI_BRICK) - base;
    c0 = c0 < 0 ? 0 : c0 > planes ? planes : c0;
    c1 = c1 < c0 ? c0 : c1 > planes ? planes : c1;
    valid_bits(v, pl, probes, w->valid);
    band_job jobs[MAX_JOBS];
    const int bands = writer_bands(w, filled, c0, c1, jobs);
    vdbgi_run_threads(bands, values_worker, jobs, sizeof(jobs[0]));
    for (int t = 0; t < bands; t++) {
        w->clamped += jobs[t].clamped;
        v->info.fallback_count += jobs[t].fallback;
    }
}

vdbgi_result vdbgi_pack_writer_finish(vdbgi_pack_writer *w, uint8_t **payload, size_t *payload_size)
{
    vdbgi_volume *const v = w->v;
    vdbgi_context *const ctx = v->ctx;
    const vdbgi_pack_plan *const pl = &w->pl;
    const uint32_t *const d = v->info.ind_dims;
    const size_t cells = (size_t)d[0] * d[1] * d[2], n = pl->points, count = w->count;
    const size_t point_bytes = 4 + (w->sh ? (size_t)vdbgi_term_bytes(v->version) : 0);
    memcpy(w->out, w->levels, cells);
    for (size_t b = 0; b < count; b++)
        for (int k = 0; k < 3; k++)
            vdbgi_put_u16(w->out + cells + 2 * (k * count + b), pl->origin[b][k]);
    const size_t unread =
        predict_unread(v, pl, w->values, w->sh, w->coarse_read, w->valid, w->near);
    band_job jobs[MAX_JOBS];
    const int bands = writer_bands(w, NULL, 0, (int32_t)pl->grid[2], jobs);
    vdbgi_run_threads(bands, residual_worker, jobs, sizeof(jobs[0]));
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "%zu stored points, %zu of them read by no receiver", n,
              unread);
    size_t stitched_clamps = 0;
    VDBGI_TRY(vdbgi_pack_rebuild_values(v, pl, w->values, (const int8_t *)w->sh, w->threads,
                                        &stitched_clamps));
    v->info.clamped_count += w->clamped + stitched_clamps;
    v->info.stored_points = n;
    *payload = w->out;
    *payload_size = cells + VDBGI_PLACEMENT_BYTES * count + point_bytes * n;
    w->out = NULL;
    return VDBGI_OK;
}

vdbgi_result vdbgi_pack_write(vdbgi_volume *v, vdbgi_brick *bricks, size_t count,
                              const vdbgi_probes *probes, int threads, uint8_t **payload,
                              size_t *payload_size)
{
    *payload = NULL;
    *payload_size = 0;
    vdbgi_pack_writer *w = NULL;
    VDBGI_TRY(vdbgi_pack_writer_create(v, bricks, count, threads, &w));
    vdbgi_pack_writer_values(w, v->filled, probes, INT32_MIN, INT32_MAX);
    const vdbgi_result r = vdbgi_pack_writer_finish(w, payload, payload_size);
    vdbgi_pack_writer_destroy(w);
    return r;
}
