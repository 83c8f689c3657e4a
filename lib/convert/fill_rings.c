/*
 * fill_rings.c: the fill's spread, ring by ring from the valued points: each
 * ring's points found by dilating the leaves' masks, each point's value from
 * its neighbours valued before its ring, over threads.
 */
#include "fill_grid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct ring_job {
    const vdbgi_fill_grid *g;
    const vdbgi_fill_params *fp;
    const vdbgi_fill_point *points;
    size_t begin, end;
} ring_job;

/*
 * The value of one point from its neighbours valued before this ring: the
 * weighted mean, or for an invalid probe between two valued face neighbours
 * its darkest neighbour. Sums in double, in a fixed neighbour order, so the
 * result does not depend on how the ring is split over threads.
 */
static void fill_point(const vdbgi_fill_grid *g, const vdbgi_fill_params *fp, vdbgi_fill_point p)
{
    const vdbgi_fill_leaf *const leaf = &g->leaves[p.leaf];
    const int ch3 = 3 * g->channels;
    const int x = (int)(p.n >> 6), y = (int)(p.n >> 3 & 7), z = (int)(p.n & 7);
    const float w[4] = {0.0f, fp->weights[0], fp->weights[1], fp->weights[2]};
    const bool invalid_probe = fill_bit(leaf->invalid, p.n);
    double sum[3 * VDBGI_FIELD_MAX_CHANNELS] = {0.0}, wsum = 0.0;
    const float *dark = NULL;
    float best = INFINITY;
    uint32_t valued = 0; /* bit (dx+1) + 3(dy+1) + 9(dz+1) */
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                const int k = abs(dx) + abs(dy) + abs(dz);
                const int nx = x + dx + 8, ny = y + dy + 8, nz = z + dz + 8;
                const int32_t l = leaf->nb[nx / 8 + 3 * (ny / 8) + 9 * (nz / 8)];
                const unsigned n = (unsigned)((nx & 7) << 6 | (ny & 7) << 3 | (nz & 7));
                if (!k || l < 0 || !fill_bit(g->leaves[l].filled, n))
                    continue;
                const float *const c = fill_grid_value(g, (size_t)l, n);
                for (int i = 0; i < ch3; i++)
                    sum[i] += (double)c[i] * w[k];
                wsum += w[k];
                if (invalid_probe) {
                    valued |= 1u << ((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1));
                    /* Darkest by the sum of the judged channels' r + g + b; the first
                       of equals, in this fixed order. */
                    float s = 0.0f;
                    for (int i = 0; i < 3 * g->judged; i += 3)
                        s += c[i] + c[i + 1] + c[i + 2];
                    if (s < best) {
                        best = s;
                        dark = c;
                    }
                }
            }
    /*
     * A probe inside a thin wall is shared by the cells on both sides of it: when
     * two of its face neighbours on one axis are both valued, its darkest neighbour
     * keeps light from crossing (docs/stability.md). A probe under a floor, valued
     * from one side only, takes the weighted mean, and so does one inside a convex
     * corner, whose valued neighbours are diagonal. Face pairs: -x/+x are bits
     * 12/14, -y/+y 10/16, -z/+z 4/22.
     */
    const bool across = ((valued >> 12 & valued >> 14) | (valued >> 10 & valued >> 16) |
                         (valued >> 4 & valued >> 22)) &
                        1u;
    float *const out = fill_grid_value(g, p.leaf, p.n);
    for (int i = 0; i < ch3; i++)
        out[i] = fp->darkest && across ? dark[i] : (float)(sum[i] / wsum);
}

static void *ring_worker(void *arg)
{
    const ring_job *const job = arg;
    for (size_t i = job->begin; i < job->end; i++)
        fill_point(job->g, job->fp, job->points[i]);
    return NULL;
}

/* Values for every point of a ring, over threads: each writes only its own points. */
static void fill_ring(const vdbgi_fill_grid *g, const vdbgi_fill_params *fp,
                      const vdbgi_fill_point *points, size_t count)
{
    enum { MAX_JOBS = 64 };
    ring_job jobs[MAX_JOBS];
    int n = fp->threads > 0 ? fp->threads : vdbgi_core_count();
    n = n > MAX_JOBS ? MAX_JOBS : n;
    /* A thread start costs about what a few thousand points do. */
    if ((size_t)n > count / 4096 + 1)
        n = (int)(count / 4096 + 1);
    for (int t = 0; t < n; t++)
        jobs[t] = (ring_job){g, fp, points, count * (size_t)t / (size_t)n,
                             count * (size_t)(t + 1) / (size_t)n};
    vdbgi_run_threads(n, ring_worker, jobs, sizeof(jobs[0]));
}

/*
 * Dilate each leaf's mask by one point along one axis (the masks of the 27
 * leaves around it from nb): bit n of a leaf is point x << 6 | y << 3 | z,
 * so word x holds its 8 x 8 y-z plane, y steps by 8 bits and z by 1. Three
 * passes, z then y then x, reach the 26 neighbours.
 */
static void dilate(const vdbgi_fill_grid *g, const uint64_t (*in)[8], uint64_t (*out)[8], int axis)
{
    static const uint64_t z0 = UINT64_C(0x0101010101010101), z7 = z0 << 7;
    const int below = axis == 0 ? 4 : axis == 1 ? 10 : 12; /* nb index of the -axis leaf */
    const int above = 26 - below;
    for (size_t l = 0; l < g->map.count; l++) {
        const uint64_t *const m = in[l];
        const int32_t lo = g->leaves[l].nb[below], hi = g->leaves[l].nb[above];
        for (int w = 0; w < 8; w++) {
            uint64_t d = m[w];
            if (axis == 0) { /* z, within each byte */
                d |= (m[w] << 1 & ~z0) | (m[w] >> 1 & ~z7);
                if (lo >= 0)
                    d |= in[lo][w] >> 7 & z0;
                if (hi >= 0)
                    d |= (in[hi][w] & z0) << 7;
            } else if (axis == 1) { /* y, by bytes */
                d |= m[w] << 8 | m[w] >> 8;
                if (lo >= 0)
                    d |= in[lo][w] >> 56;
                if (hi >= 0)
                    d |= in[hi][w] << 56;
            } else { /* x, by words */
                d |= w > 0 ? m[w - 1] : lo >= 0 ? in[lo][7] : 0;
                d |= w < 7 ? m[w + 1] : hi >= 0 ? in[hi][0] : 0;
            }
            out[l][w] = d;
        }
    }
}

vdbgi_result vdbgi_fill_spread(vdbgi_fill_grid *g, const vdbgi_fill_params *fp, size_t *unreached)
{
    vdbgi_context *const ctx = g->ctx;
    const size_t leaf_count = g->map.count;
    size_t remaining = 0, filled = 0;
    for (size_t l = 0; l < leaf_count; l++) {
        remaining += fill_popcount512(g->leaves[l].target);
        filled += fill_popcount512(g->leaves[l].filled);
    }
    remaining -= filled; /* every filled point is a target point */
    vdbgi_fill_point *const ring = vdbgi_calloc(ctx, remaining ? remaining : 1, sizeof(*ring));
    uint64_t(*a)[8] = vdbgi_alloc(ctx, (leaf_count ? leaf_count : 1) * sizeof(*a));
    uint64_t(*b)[8] = vdbgi_alloc(ctx, (leaf_count ? leaf_count : 1) * sizeof(*b));
    if (!ring || !a || !b) {
        vdbgi_free(ctx, ring);
        vdbgi_free(ctx, a);
        vdbgi_free(ctx, b);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    for (int iter = 0; iter < fp->max_iterations && remaining > 0; iter++) {
        for (size_t l = 0; l < leaf_count; l++)
            memcpy(a[l], g->leaves[l].filled, sizeof(a[l]));
        dilate(g, (const uint64_t(*)[8])a, b, 0);
        dilate(g, (const uint64_t(*)[8])b, a, 1);
        dilate(g, (const uint64_t(*)[8])a, b, 2);
        size_t count = 0;
        for (size_t l = 0; l < leaf_count; l++)
            for (int w = 0; w < 8; w++) {
                uint64_t m = b[l][w] & g->leaves[l].target[w] & ~g->leaves[l].filled[w];
                for (; m; m &= m - 1)
                    ring[count++] =
                        (vdbgi_fill_point){(uint32_t)l, (unsigned)(w << 6 | __builtin_ctzll(m))};
            }
        if (count == 0)
            break; /* what is left cannot be reached from any source */
        fill_ring(g, fp, ring, count);
        for (size_t i = 0; i < count; i++)
            fill_set_bit(g->leaves[ring[i].leaf].filled, ring[i].n);
        remaining -= count;
    }
    vdbgi_free(ctx, ring);
    vdbgi_free(ctx, a);
    vdbgi_free(ctx, b);
    if (fp->core_z[0] < fp->core_z[1]) { /* a region's: its own points only */
        remaining = 0;
        for (size_t l = 0; l < leaf_count; l++) {
            uint64_t left[8];
            for (int w = 0; w < 8; w++)
                left[w] = g->leaves[l].target[w] & ~g->leaves[l].filled[w];
            remaining +=
                vdbgi_mask_count_z(left, g->leaves[l].origin[2], fp->core_z[0], fp->core_z[1]);
        }
    }
    *unreached = remaining;
    return VDBGI_OK;
}
