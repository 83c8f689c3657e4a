/*
 * atlas.c: seed 000's layout: bricks into atlas slots with their aprons,
 * encoded, and the indirection to them. The compact layout's textures are
 * rebuilt from its packed file instead (packed.c).
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
    /*
     * In integers: the smallest sx with sx^3 >= slots, then the smallest sy
     * with sx sy^2 >= slots. (glibc's cbrt(27) is 3.0000000000000004, so a
     * floating ceil gave 4 where a reader's cube root gives 3.)
     */
    uint64_t sx = 1, sy = 1;
    while (sx < 256 && sx * sx * sx < slots)
        sx++;
    while (sy < 256 && sx * sy * sy < slots)
        sy++;
    const uint64_t sz = (slots + sx * sy - 1) / (sx * sy);
    VDBGI_FAIL_IF(ctx, sz > 256, VDBGI_ERR_OUT_OF_MEMORY,
                  "%zu bricks do not fit an atlas of 256^3 slots (%u texels a side): raise eps or "
                  "the probe spacing",
                  slots, 256 * b);
    dims[0] = (uint32_t)sx * b;
    dims[1] = (uint32_t)sy * b;
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
                uint8_t *const out = &v->tex.atlas[4 * t];
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
    const uint32_t *const d = v->info.ind_dims;
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
                memcpy(&v->tex.indirection[4 * (((size_t)z * d[1] + (size_t)y) * d[0] + (size_t)x)],
                       texel, 4);
}

enum { SLOT_MAX = VDBGI_BRICK_PADDED * VDBGI_BRICK_PADDED * VDBGI_BRICK_PADDED };

typedef struct atlas_job {
    vdbgi_volume *v;
    const vdbgi_brick *bricks;
    size_t begin, end; /* kept bricks [begin, end) */
    size_t fallbacks, clamped;
} atlas_job;

static void *atlas_worker(void *arg)
{
    atlas_job *const job = arg;
    for (size_t i = job->begin; i < job->end; i++) {
        const vdbgi_brick *const k = &job->bricks[i];
        const uint32_t slot = (uint32_t)i + 1;
        float s[SLOT_MAX][3];
        job->fallbacks +=
            vdbgi_brick_samples(job->v->filled, k->key, k->level, k->mean, VDBGI_LAYOUT_SEED, s);
        job->clamped += encode_brick(job->v, (const float(*)[3])s, slot);
        mark_indirection(job->v, k, slot);
    }
    return NULL;
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
        jobs[t].begin = count * (size_t)t / (size_t)n;
        jobs[t].end = count * (size_t)(t + 1) / (size_t)n;
    }
    vdbgi_run_threads(n, atlas_worker, jobs, sizeof(jobs[0]));
    for (int t = 0; t < n; t++) {
        v->info.fallback_count += jobs[t].fallbacks;
        v->info.clamped_count += jobs[t].clamped;
    }
    return VDBGI_OK;
}
