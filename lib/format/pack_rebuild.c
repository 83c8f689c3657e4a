/*
 * pack_rebuild.c: the compact layout's atlas filled by its plan (packed.c):
 * each stored point's bytes copied into every texel that holds it, each
 * stitched texel interpolated and encoded as a reader does, and the L2
 * terms' residual planes undone into bytes (docs/format.md, "Version 5"
 * and "Version 6").
 */
#include "encode.h"
#include "gifile.h"
#include "pack_common.h"
#include "util.h"

#include <math.h>
#include <string.h>

/*
 * What one rebuild pass reads and writes: each stored point's bytes (from
 * values), copied into the atlas texels, or
 * for a stitched texel interpolated and encoded. The L0 colours are the
 * volume's encoding; the L2 terms' 24 bytes are signed 127ths, which
 * interpolate as numbers (docs/format.md, "Version 6").
 */
typedef struct texel_codec {
    const uint8_t *values; /* bytes() a stored point */
    uint8_t *atlas;        /* bytes() a texel */
    bool terms;            /* the 24 int8 of the L2 terms, not a 4-byte colour */
} texel_codec;

/* Bytes a point or texel holds, and floats a sample of it: a colour's 4 and 3, or 24. */
static size_t codec_bytes(const texel_codec *tc)
{
    return tc->terms ? VDBGI_SH_BYTES : 4;
}

static int codec_channels(const texel_codec *tc)
{
    return tc->terms ? VDBGI_SH_BYTES : 3;
}

static uint8_t *atlas_texel(const vdbgi_volume *v, const vdbgi_pack_plan *pl, const texel_codec *tc,
                            size_t b, int t)
{
    const uint32_t *const d = v->info.atlas_dims;
    const uint16_t *const o = pl->origin[b];
    const size_t x = o[0] + (size_t)(t % N), y = o[1] + (size_t)(t / N % N),
                 z = o[2] + (size_t)(t / (N * N));
    return &tc->atlas[codec_bytes(tc) * ((z * d[1] + y) * d[0] + x)];
}

static void decode_any(const vdbgi_volume *v, const texel_codec *tc, const uint8_t *in, float *out)
{
    if (!tc->terms) {
        decode_texel(v, in, out);
        return;
    }
    for (int k = 0; k < VDBGI_SH_BYTES; k++) {
        const int8_t q = (int8_t)in[k];
        out[k] = q < -127 ? -127.0f : (float)q; /* snorm8: -128 reads as -1 */
    }
}

static bool encode_any(const vdbgi_volume *v, const texel_codec *tc, const float *in, uint8_t *out)
{
    if (!tc->terms)
        return encode_texel(v, in, out);
    for (int k = 0; k < VDBGI_SH_BYTES; k++) {
        const float q = in[k] > 127.0f ? 127.0f : in[k] < -127.0f ? -127.0f : in[k];
        out[k] = (uint8_t)(int8_t)lrintf(q); /* float32, to nearest even */
    }
    return false;
}

/* One thread's share of the rebuild: the bricks whose first texel lies in rows y_begin..y_end. */
typedef struct rebuild_job {
    const vdbgi_volume *v;
    const vdbgi_pack_plan *pl;
    const texel_codec *tc;
    float *fs; /* coarse bricks' samples, by cidx: TEXELS x channels floats each */
    const int32_t *cidx;
    int level; /* the coarse level whose samples to compute, or -1: write the atlas */
    uint32_t y_begin, y_end;
    size_t clamped;
} rebuild_job;

static void *rebuild_worker(void *arg)
{
    rebuild_job *const job = arg;
    const vdbgi_pack_plan *const pl = job->pl;
    const texel_codec *const tc = job->tc;
    const int ch = codec_channels(tc);
    const int32_t *const cidx = job->cidx;
    const size_t bytes = codec_bytes(tc);
    /* Coarse brick c's sample t. */
#define SAMPLE(c, t) (&job->fs[((size_t)(c)*TEXELS + (size_t)(t)) * (size_t)ch])
    for (size_t b = 0; b < pl->brick_count; b++) {
        if (pl->origin[b][1] < job->y_begin || pl->origin[b][1] >= job->y_end ||
            (job->level >= 0 && pl->level[b] != job->level))
            continue;
        for (int t = 0; t < TEXELS; t++) {
            size_t j;
            int cl;
            int32_t p[3];
            texel_point(pl, b, t, p);
            const bool stitch = stitched(pl, b, t, &j, &cl);
            const double pos[3] = {p[0], p[1], p[2]};
            if (job->level >= 0) { /* a coarse brick's samples */
                if (stitch) {
                    vdbgi_brick_interpolate_n(SAMPLE(cidx[j], 0), ch, VDBGI_LAYOUT_COMPACT,
                                              pl->key[j], cl, pos, SAMPLE(cidx[b], t));
                } else {
                    const int64_t i = point_index(pl, p);
                    static const uint8_t zero[VDBGI_SH_BYTES];
                    decode_any(job->v, tc, i >= 0 ? &tc->values[bytes * (size_t)i] : zero,
                               SAMPLE(cidx[b], t));
                }
                continue;
            }
            uint8_t *const out = atlas_texel(job->v, pl, tc, b, t);
            if (!stitch) {
                const int64_t i = point_index(pl, p);
                if (i >= 0)
                    memcpy(out, &tc->values[bytes * (size_t)i], bytes);
                continue;
            }
            float got[VDBGI_SH_BYTES];
            if (cidx[b] >= 0)
                memcpy(got, SAMPLE(cidx[b], t), (size_t)ch * sizeof(float));
            else
                vdbgi_brick_interpolate_n(SAMPLE(cidx[j], 0), ch, VDBGI_LAYOUT_COMPACT, pl->key[j],
                                          cl, pos, got);
            job->clamped += encode_any(job->v, tc, got, out);
        }
    }
#undef SAMPLE
    return NULL;
}

/*
 * One pass of the rebuild. Coarse bricks' samples are kept as floats,
 * coarsest level first, so a stitched texel interpolates exactly what the
 * converter's stitching always did: the coarser brick's values, its own
 * stitched ones unrounded. Threads take whole layers of the atlas: bricks
 * that share texels lie in one layer, and write the same bytes there.
 */
static vdbgi_result rebuild_pass(vdbgi_volume *v, const vdbgi_pack_plan *pl, const texel_codec *tc,
                                 int threads, size_t *clamped_out)
{
    vdbgi_context *const ctx = v->ctx;
    const size_t count = pl->brick_count;
    size_t coarse = 0;
    int32_t *const cidx = vdbgi_alloc(ctx, (count ? count : 1) * sizeof(*cidx));
    if (!cidx)
        return VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t b = 0; b < count; b++)
        cidx[b] = pl->level[b] ? (int32_t)coarse++ : -1;
    float *const fs = vdbgi_alloc(ctx, (coarse ? coarse : 1) * TEXELS * (size_t)codec_channels(tc) *
                                           sizeof(float));
    if (!fs) {
        vdbgi_free(ctx, cidx);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    rebuild_job jobs[MAX_JOBS];
    const uint32_t layers = v->info.atlas_dims[1] / N;
    int nt = job_count(threads);
    nt = (uint32_t)nt > layers ? (int)layers : nt;
    for (int level = (int)v->info.max_level; level >= -1; level--) {
        if (level == 0)
            continue;
        for (int t = 0; t < nt; t++)
            jobs[t] = (rebuild_job){.v = v,
                                    .pl = pl,
                                    .tc = tc,
                                    .fs = fs,
                                    .cidx = cidx,
                                    .level = level,
                                    .y_begin = N * (uint32_t)((uint64_t)layers * t / nt),
                                    .y_end = N * (uint32_t)((uint64_t)layers * (t + 1) / nt)};
        vdbgi_run_threads(nt, rebuild_worker, jobs, sizeof(jobs[0]));
        for (int t = 0; t < nt; t++)
            *clamped_out += jobs[t].clamped;
    }
    vdbgi_free(ctx, fs);
    vdbgi_free(ctx, cidx);
    return VDBGI_OK;
}

vdbgi_result vdbgi_pack_rebuild_values(vdbgi_volume *v, const vdbgi_pack_plan *pl,
                                       const uint8_t *values, const int8_t *sh, int threads,
                                       size_t *clamped_out)
{
    *clamped_out = 0;
    const texel_codec l0 = {.values = values, .atlas = v->tex.atlas};
    VDBGI_TRY(rebuild_pass(v, pl, &l0, threads, clamped_out));
    if (!sh)
        return VDBGI_OK;
    VDBGI_TRY(vdbgi_textures_alloc_sh(v->ctx, &v->tex));
    const texel_codec terms = {
        .values = (const uint8_t *)sh, .atlas = (uint8_t *)v->tex.sh, .terms = true};
    return rebuild_pass(v, pl, &terms, threads, clamped_out);
}

/*
 * The stored points of owner-cell layer z (the first is point i0), their values and L2
 * terms (sh, or NULL) from their residuals' planes, in storage order: each predicted from
 * neighbours before it. The terms' planes hold vdbgi_term_byte's bytes; version 8 stores
 * no green or blue residual of terms 4-8: they are 0, so those bytes copy red's.
 * Called a layer at a time, not once for all: V8 runs a WebAssembly function in its
 * baseline code until the call after it has optimised it (not inside a running loop), so
 * the reader built for the browser's worker (web/wasm) gets the optimised loop only from
 * a function it calls many times; noinline keeps it one.
 */
static __attribute__((noinline)) void undo_residuals(const vdbgi_pack_plan *pl, uint32_t version,
                                                     bool rgbm, const uint8_t *planes,
                                                     uint8_t *values, uint8_t *sh, int32_t z,
                                                     size_t i0)
{
    const size_t n = pl->points;
    const uint8_t *const term_planes = planes + 4 * n;
    FOR_EACH_POINT_IN(pl, z, z + 1, i0, p, i, {
        int64_t nb[4];
        neighbours(pl, p, nb);
        for (int o = 0; o < 4; o++) {
            const int k = byte_order(rgbm, o);
            values[4 * i + k] = (uint8_t)(planes[k * n + i] +
                                          predict(values, nb, k, rgbm && k < 3, values[4 * i + 3]));
        }
        if (sh) {
            uint8_t e[VDBGI_SH_BYTES] = {0};
            for (int j = 0; j < vdbgi_term_bytes(version); j++)
                e[vdbgi_term_byte(version, j)] = term_planes[(size_t)j * n + i];
            term_undo_residuals(version, sh, nb, i, e);
        }
    });
}

vdbgi_result vdbgi_pack_rebuild(vdbgi_volume *v, const vdbgi_pack_plan *pl, const uint8_t *planes,
                                int threads, size_t *clamped)
{
    const size_t n = pl->points;
    const bool with_sh = v->info.basis == VDBGI_BASIS_SH2;
    uint8_t *const values = vdbgi_calloc(v->ctx, n ? n : 1, 4);
    uint8_t *const sh = with_sh ? vdbgi_calloc(v->ctx, n ? n : 1, VDBGI_SH_BYTES) : NULL;
    if (!values || (with_sh && !sh)) {
        vdbgi_free(v->ctx, values);
        vdbgi_free(v->ctx, sh);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    const bool rgbm = v->info.encoding == VDBGI_ENCODING_RGBM;
    for (int32_t z = 0; z < (int32_t)pl->grid[2]; z++) {
        const int32_t first[3] = {0, 0, z};
        undo_residuals(pl, v->version, rgbm, planes, values, sh, z,
                       pl->offset[cell_index(pl->grid, first)]);
    }
    const vdbgi_result r =
        vdbgi_pack_rebuild_values(v, pl, values, (const int8_t *)sh, threads, clamped);
    vdbgi_free(v->ctx, values);
    vdbgi_free(v->ctx, sh);
    return r;
}

vdbgi_result vdbgi_pack_read(vdbgi_volume *v, const char *name)
{
    const vdbgi_volume_info header = v->info;
    const uint8_t *const levels = v->payload, *const placement =
                                                  levels + header.indirection_size / 4;
    vdbgi_pack_plan pl;
    VDBGI_TRY(vdbgi_pack_plan_make(v, levels, placement, &header, name, vdbgi_core_count(), &pl));
    vdbgi_result r = VDBGI_OK;
    if (pl.points != header.stored_points)
        r = vdbgi_fail(v->ctx, VDBGI_ERR_FORMAT,
                       "%s: the bricks read %zu points, the header says %zu are stored", name,
                       pl.points, header.stored_points);
    else
        r = vdbgi_pack_rebuild(v, &pl, placement + VDBGI_PLACEMENT_BYTES * pl.brick_count,
                               vdbgi_core_count(), &v->info.clamped_count);
    vdbgi_pack_plan_free(v->ctx, &pl);
    return r;
}
