/*
 * atlas.c: bricks into atlas slots with their aprons or borders, encoded, and
 * the indirection to them. The compact layout also stitches each brick's
 * faces to the coarser bricks they touch (docs/format.md).
 */
#include "atlas.h"
#include "encode.h"

#include <math.h>
#include <string.h>

/* Atlas slots per axis: near-cubic, each at most 256 (a slot coordinate is one byte). */
vdbgi_result vdbgi_atlas_dims(vdbgi_context *ctx, size_t slots, vdbgi_layout layout,
                              uint32_t dims[3])
{
    const uint32_t b = (uint32_t)vdbgi_slot_texels(layout);
    uint32_t sx = (uint32_t)ceil(cbrt((double)slots));
    sx = sx > 256 ? 256 : sx;
    uint32_t sy = (uint32_t)ceil(sqrt((double)slots / sx));
    sy = sy > 256 ? 256 : sy;
    const uint64_t sz = (slots + (uint64_t)sx * sy - 1) / ((uint64_t)sx * sy);
    VDBGI_FAIL_IF(ctx, sz > 256, VDBGI_ERR_OUT_OF_MEMORY,
                  "%zu bricks do not fit an atlas of 256^3 slots (%u texels a side): raise eps or "
                  "the probe spacing",
                  slots, 256 * b);
    dims[0] = sx * b;
    dims[1] = sy * b;
    dims[2] = (uint32_t)sz * b;
    return VDBGI_OK;
}

/* Encode a brick's n^3 samples (x fastest) into its atlas slot; returns how many clamped. */
static size_t encode_brick(const vdbgi_volume *v, const float (*s)[3], uint32_t slot)
{
    size_t clamped_count = 0;
    const uint32_t n = (uint32_t)vdbgi_slot_texels(v->info.layout);
    const uint32_t *const d = v->info.atlas_dims;
    const uint32_t sx = d[0] / n, sy = d[1] / n;
    const uint32_t base[3] = {(slot % sx) * n, (slot / sx % sy) * n, (slot / (sx * sy)) * n};
    for (uint32_t z = 0; z < n; z++)
        for (uint32_t y = 0; y < n; y++)
            for (uint32_t x = 0; x < n; x++) {
                const size_t t = ((size_t)(base[2] + z) * d[1] + base[1] + y) * d[0] + base[0] + x;
                const float *const rgb = s[(z * n + y) * n + x];
                uint8_t *const out = &v->atlas[4 * t];
                bool clamped;
                if (v->info.encoding == VDBGI_ENCODING_RGB9E5) {
                    uint32_t w;
                    clamped = vdbgi_rgb9e5_encode(rgb, &w);
                    out[0] = (uint8_t)w, out[1] = (uint8_t)(w >> 8);
                    out[2] = (uint8_t)(w >> 16), out[3] = (uint8_t)(w >> 24);
                } else {
                    clamped = vdbgi_rgbm_encode(rgb, v->info.rgbm_range, out);
                }
                clamped_count += clamped;
            }
    return clamped_count;
}

/* Point every level-0 cell a brick covers at that brick's slot and level. */
static void mark_indirection(const vdbgi_volume *v, const vdbgi_brick *k, uint32_t slot)
{
    const uint32_t *const d = v->info.indirection_dims;
    const uint32_t n = (uint32_t)vdbgi_slot_texels(v->info.layout);
    const uint32_t sx = v->info.atlas_dims[0] / n, sy = v->info.atlas_dims[1] / n;
    const uint8_t texel[4] = {(uint8_t)(slot % sx), (uint8_t)(slot / sx % sy),
                              (uint8_t)(slot / (sx * sy)), (uint8_t)(k->level + 1)};
    const int32_t span = 1 << k->level;
    int32_t lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = k->key[a] * span - v->origin_cell[a];
        hi[a] = lo[a] + span;
        lo[a] = lo[a] < 0 ? 0 : lo[a];
        hi[a] = hi[a] > (int32_t)d[a] ? (int32_t)d[a] : hi[a];
    }
    for (int32_t z = lo[2]; z < hi[2]; z++)
        for (int32_t y = lo[1]; y < hi[1]; y++)
            for (int32_t x = lo[0]; x < hi[0]; x++)
                memcpy(&v->indirection[4 * (((size_t)z * d[1] + (size_t)y) * d[0] + (size_t)x)],
                       texel, 4);
}

enum { SLOT_MAX = VDBGI_BRICK_PADDED * VDBGI_BRICK_PADDED * VDBGI_BRICK_PADDED };
enum { COMPACT = VDBGI_BRICK_COMPACT * VDBGI_BRICK_COMPACT * VDBGI_BRICK_COMPACT };

typedef struct atlas_job {
    vdbgi_volume *v;
    const vdbgi_brick *bricks;
    float (*samples)[COMPACT][3]; /* compact: every brick's samples, stitched in place */
    int stage, level;             /* compact: which pass; the level being stitched */
    size_t begin, end;            /* kept bricks [begin, end) */
    size_t fallbacks, clamped;
} atlas_job;

/*
 * The coarsest brick whose cells touch fine lattice point p, if coarser than
 * level: its index (slot - 1) and level. A point on a cell face, edge or
 * corner touches two, four or eight cells.
 */
static bool coarser_brick_at(const vdbgi_volume *v, const int32_t p[3], int level, size_t *index,
                             int *coarse_level)
{
    const uint32_t *const d = v->info.indirection_dims;
    const uint32_t n = VDBGI_BRICK_COMPACT;
    const uint32_t sx = v->info.atlas_dims[0] / n, sy = v->info.atlas_dims[1] / n;
    int32_t c0[3];
    int two[3];
    for (int k = 0; k < 3; k++) {
        c0[k] = vdbgi_floor_div(p[k], VDBGI_BRICK) - v->origin_cell[k];
        two[k] = p[k] % VDBGI_BRICK == 0; /* on a face: the cell below touches it too */
    }
    int best = level;
    for (int c = 0; c < 8; c++) {
        int32_t cell[3];
        bool inside = true;
        for (int k = 0; k < 3; k++) {
            const int down = c >> k & 1;
            cell[k] = c0[k] - down;
            inside = inside && (!down || two[k]) && cell[k] >= 0 && cell[k] < (int32_t)d[k];
        }
        if (!inside)
            continue;
        const uint8_t *const t =
            &v->indirection[4 * (((size_t)cell[2] * d[1] + (size_t)cell[1]) * d[0] + cell[0])];
        if (t[3] == 0 || t[3] - 1 <= best)
            continue;
        best = t[3] - 1;
        *index = ((size_t)t[2] * sy + t[1]) * sx + t[0] - 1;
    }
    *coarse_level = best;
    return best > level;
}

/* A compact brick's face texels that touch a coarser brick take its interpolated value. */
static void stitch_brick(const atlas_job *job, size_t i)
{
    const vdbgi_brick *const k = &job->bricks[i];
    const int n = VDBGI_BRICK_COMPACT, span = 1 << k->level;
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++) {
                const int q[3] = {x, y, z};
                if (x % 4 && y % 4 && z % 4)
                    continue; /* inside: only faces meet other bricks */
                int32_t p[3];
                for (int a = 0; a < 3; a++)
                    p[a] = (k->key[a] * VDBGI_BRICK + q[a]) * span;
                size_t j = 0;
                int cl = 0;
                if (!coarser_brick_at(job->v, p, k->level, &j, &cl))
                    continue;
                const double pos[3] = {p[0], p[1], p[2]};
                vdbgi_brick_interpolate((const float(*)[3])job->samples[j], VDBGI_LAYOUT_COMPACT,
                                        job->bricks[j].key, cl, pos,
                                        job->samples[i][(z * n + y) * n + x]);
            }
}

enum { SEED_ALL, COMPACT_SAMPLE, COMPACT_STITCH, COMPACT_ENCODE };

static void *atlas_worker(void *arg)
{
    atlas_job *const job = arg;
    for (size_t i = job->begin; i < job->end; i++) {
        const vdbgi_brick *const k = &job->bricks[i];
        const uint32_t slot = (uint32_t)i + 1;
        switch (job->stage) {
        case SEED_ALL: {
            float s[SLOT_MAX][3];
            job->fallbacks += vdbgi_brick_samples(&job->v->filled, k->key, k->level, k->mean,
                                                  VDBGI_LAYOUT_SEED, s);
            job->clamped += encode_brick(job->v, (const float(*)[3])s, slot);
            mark_indirection(job->v, k, slot);
            break;
        }
        case COMPACT_SAMPLE:
            job->fallbacks += vdbgi_brick_samples(&job->v->filled, k->key, k->level, k->mean,
                                                  VDBGI_LAYOUT_COMPACT, job->samples[i]);
            mark_indirection(job->v, k, slot);
            break;
        case COMPACT_STITCH:
            if (k->level == job->level)
                stitch_brick(job, i);
            break;
        default: job->clamped += encode_brick(job->v, (const float(*)[3])job->samples[i], slot);
        }
    }
    return NULL;
}

/* One pass of the atlas over threads, each a contiguous run of bricks. */
static void run_pass(atlas_job *jobs, int n, size_t count, int stage, int level)
{
    for (int t = 0; t < n; t++) {
        jobs[t].begin = count * (size_t)t / (size_t)n;
        jobs[t].end = count * (size_t)(t + 1) / (size_t)n;
        jobs[t].stage = stage;
        jobs[t].level = level;
    }
    vdbgi_run_threads(n, atlas_worker, jobs, sizeof(jobs[0]));
}

vdbgi_result vdbgi_atlas_fill(vdbgi_volume *v, const vdbgi_brick *bricks, size_t count, int threads)
{
    enum { MAX_JOBS = 64 };
    atlas_job jobs[MAX_JOBS];
    const int n = threads > MAX_JOBS ? MAX_JOBS : threads;
    memset(jobs, 0, sizeof(jobs));
    for (int t = 0; t < n; t++) {
        jobs[t].v = v;
        jobs[t].bricks = bricks;
    }
    if (v->info.layout == VDBGI_LAYOUT_COMPACT) {
        /*
         * Every brick sampled and pointed at first; then faces stitched level by
         * level from the coarsest, each reading only coarser bricks, already final,
         * so the bytes do not depend on the split; then encoded.
         */
        float(*samples)[COMPACT][3] = vdbgi_alloc(v->ctx, (count ? count : 1) * sizeof(*samples));
        if (!samples)
            return VDBGI_ERR_OUT_OF_MEMORY;
        for (int t = 0; t < n; t++)
            jobs[t].samples = samples;
        run_pass(jobs, n, count, COMPACT_SAMPLE, 0);
        for (int level = (int)v->info.max_level - 1; level >= 0; level--)
            run_pass(jobs, n, count, COMPACT_STITCH, level);
        run_pass(jobs, n, count, COMPACT_ENCODE, 0);
        vdbgi_free(v->ctx, samples);
    } else {
        run_pass(jobs, n, count, SEED_ALL, 0);
    }
    for (int t = 0; t < n; t++) {
        v->info.fallback_count += jobs[t].fallbacks;
        v->info.clamped_count += jobs[t].clamped;
    }
    return VDBGI_OK;
}
