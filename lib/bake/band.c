/*
 * band.c: which lattice points lie within the margin of a triangle, exactly.
 *
 * A point belongs when its distance to the nearest triangle is at most the
 * margin, each distance computed in double from the triangle itself. Being
 * a property of the point and each triangle alone, the set does not depend
 * on which other triangles are given: a tile that holds every triangle
 * reaching its slab finds exactly the whole lattice's points in it (OpenVDB's
 * mesh-to-volume propagates each voxel's nearest triangle from its
 * neighbours, which drops or adds points when the set of triangles changes).
 */
#include "band.h"
#include "vdb_shim.h"

#include <math.h>
#include <string.h>

typedef struct tri {
    double a[3], b[3], c[3];
    bool flat; /* no area: its distance is its edges' */
} tri;

static double dot3(const double u[3], const double v[3])
{
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
}

static void sub3(const double u[3], const double v[3], double out[3])
{
    out[0] = u[0] - v[0], out[1] = u[1] - v[1], out[2] = u[2] - v[2];
}

static double segment_distance2(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3];
    sub3(b, a, ab);
    sub3(p, a, ap);
    const double len2 = dot3(ab, ab);
    double t = len2 > 0.0 ? dot3(ap, ab) / len2 : 0.0;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    const double d[3] = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
    return dot3(d, d);
}

static double at_distance2(const double p[3], const double a[3], const double d[3], double t)
{
    const double q[3] = {a[0] + t * d[0] - p[0], a[1] + t * d[1] - p[1], a[2] + t * d[2] - p[2]};
    return dot3(q, q);
}

/*
 * Squared distance from p to the triangle: the closest point found by
 * Voronoi region (Ericson, Real-Time Collision Detection, 5.1.5). For a
 * triangle with area every denominator below is a squared edge length or
 * twice its squared area, so none is zero.
 */
static double triangle_distance2(const tri *t, const double p[3])
{
    if (t->flat) {
        const double ab = segment_distance2(p, t->a, t->b);
        const double bc = segment_distance2(p, t->b, t->c);
        const double ca = segment_distance2(p, t->c, t->a);
        return fmin(ab, fmin(bc, ca));
    }
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    sub3(t->b, t->a, ab);
    sub3(t->c, t->a, ac);
    sub3(p, t->a, ap);
    const double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0)
        return dot3(ap, ap);
    sub3(p, t->b, bp);
    const double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0.0 && d4 <= d3)
        return dot3(bp, bp);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
        return at_distance2(p, t->a, ab, d1 / (d1 - d3));
    sub3(p, t->c, cp);
    const double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0.0 && d5 <= d6)
        return dot3(cp, cp);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
        return at_distance2(p, t->a, ac, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        double bc[3];
        sub3(t->c, t->b, bc);
        return at_distance2(p, t->b, bc, (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    const double s = 1.0 / (va + vb + vc), v = vb * s, w = vc * s;
    const double q[3] = {t->a[0] + ab[0] * v + ac[0] * w - p[0],
                         t->a[1] + ab[1] * v + ac[1] * w - p[1],
                         t->a[2] + ab[2] * v + ac[2] * w - p[2]};
    return dot3(q, q);
}

typedef struct job {
    const vdbgi_band_desc *d;
    size_t first, end; /* triangles */
    vdbgi_vdb_mask *mask;
    vdbgi_result result; /* without a message: workers share no context */
} job;

/* The lattice points of one triangle's box, [lo, hi] inclusive, in index space. */
typedef struct box {
    int64_t lo[3], hi[3];
} box;

/* Distance from the triangle to the points of b is more than the margin for all of them. */
static bool box_is_far(const job *j, const tri *t, const box *b)
{
    const vdbgi_band_desc *d = j->d;
    double c[3], r2 = 0.0;
    for (int k = 0; k < 3; k++) {
        c[k] = d->origin[k] + d->spacing * 0.5 * (double)(b->lo[k] + b->hi[k]);
        const double h = 0.5 * d->spacing * (double)(b->hi[k] - b->lo[k]);
        r2 += h * h;
    }
    const double reach = d->margin + sqrt(r2) + d->spacing; /* a spacing of slack for rounding */
    return triangle_distance2(t, c) > reach * reach;
}

/* The points of b (inside one 8^3 leaf) within the margin, into the mask. */
static vdbgi_result add_leaf(job *j, const tri *t, const box *b, double limit2)
{
    const vdbgi_band_desc *d = j->d;
    uint64_t bits[8] = {0};
    bool any = false;
    for (int64_t x = b->lo[0]; x <= b->hi[0]; x++) {
        for (int64_t y = b->lo[1]; y <= b->hi[1]; y++) {
            for (int64_t z = b->lo[2]; z <= b->hi[2]; z++) {
                const double p[3] = {d->origin[0] + d->spacing * (double)x,
                                     d->origin[1] + d->spacing * (double)y,
                                     d->origin[2] + d->spacing * (double)z};
                if (triangle_distance2(t, p) <= limit2) {
                    bits[x & 7] |= (uint64_t)1 << ((y & 7) * 8 + (z & 7));
                    any = true;
                }
            }
        }
    }
    if (!any)
        return VDBGI_OK;
    const int32_t leaf[3] = {(int32_t)(b->lo[0] & ~(int64_t)7), (int32_t)(b->lo[1] & ~(int64_t)7),
                             (int32_t)(b->lo[2] & ~(int64_t)7)};
    return vdbgi_vdb_mask_add_leaf(j->mask, leaf, bits);
}

/*
 * The box split in halves along its longest side in leaves until each part
 * lies in one leaf, dropping every part the triangle is too far from: the
 * work follows the triangle's surface, not its box's volume.
 */
static vdbgi_result visit(job *j, const tri *t, const box *b, double limit2)
{
    if (box_is_far(j, t, b))
        return VDBGI_OK;
    int longest = -1;
    int64_t most = 0;
    for (int k = 0; k < 3; k++) {
        const int64_t leaves = (b->hi[k] >> 3) - (b->lo[k] >> 3);
        if (leaves > most)
            most = leaves, longest = k;
    }
    if (longest < 0)
        return add_leaf(j, t, b, limit2);
    const int64_t cut =
        ((b->lo[longest] >> 3) + (most + 1) / 2) * 8; /* first point of the upper half */
    box lower = *b, upper = *b;
    lower.hi[longest] = cut - 1;
    upper.lo[longest] = cut;
    VDBGI_TRY(visit(j, t, &lower, limit2));
    return visit(j, t, &upper, limit2);
}

static void *run_job(void *arg)
{
    job *const j = arg;
    const vdbgi_band_desc *d = j->d;
    /* A millionth of a spacing keeps points at exactly the margin (common where geometry lines
       up with the lattice) whatever the rounding of the distance. */
    const double limit = d->margin + 1e-6 * d->spacing, limit2 = limit * limit;
    for (size_t i = j->first; i < j->end && j->result == VDBGI_OK; i++) {
        const uint32_t *const idx = &d->indices[3 * i];
        tri t;
        double *const v[3] = {t.a, t.b, t.c};
        box b;
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++)
                v[c][k] = d->positions[3 * (size_t)idx[c] + (size_t)k];
        for (int k = 0; k < 3; k++) {
            const double lo = fmin(t.a[k], fmin(t.b[k], t.c[k])) - limit - d->origin[k];
            const double hi = fmax(t.a[k], fmax(t.b[k], t.c[k])) + limit - d->origin[k];
            b.lo[k] = (int64_t)ceil(lo / d->spacing);
            b.hi[k] = (int64_t)floor(hi / d->spacing);
        }
        b.lo[0] = b.lo[0] > d->x_range[0] ? b.lo[0] : d->x_range[0];
        b.hi[0] = b.hi[0] < d->x_range[1] - 1 ? b.hi[0] : d->x_range[1] - 1;
        if (b.lo[0] > b.hi[0] || b.lo[1] > b.hi[1] || b.lo[2] > b.hi[2])
            continue;
        double ab[3], ac[3];
        sub3(t.b, t.a, ab);
        sub3(t.c, t.a, ac);
        const double n[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
                             ab[0] * ac[1] - ab[1] * ac[0]};
        t.flat = !(dot3(n, n) > 1e-24 * dot3(ab, ab) * dot3(ac, ac));
        j->result = visit(j, &t, &b, limit2);
    }
    return NULL;
}

vdbgi_result vdbgi_band_points(vdbgi_context *ctx, const vdbgi_band_desc *d, int32_t **ijk_out,
                               size_t *count_out)
{
    *ijk_out = NULL;
    *count_out = 0;
    /* Each thread a run of consecutive triangles (neighbours share leaves) and a mask of its
       own; the union of the masks is the same whatever the count. */
    int threads = d->threads;
    if (threads <= 0) {
        threads = vdbgi_core_count();
        if ((size_t)threads > d->triangle_count / 256 + 1) /* a thread's start costs more */
            threads = (int)(d->triangle_count / 256 + 1);
    }
    threads = threads > 64 ? 64 : threads;
    job jobs[64];
    memset(jobs, 0, sizeof(jobs));
    vdbgi_result r = VDBGI_OK;
    for (int k = 0; k < threads && r == VDBGI_OK; k++) {
        jobs[k].d = d;
        jobs[k].first = d->triangle_count * (size_t)k / (size_t)threads;
        jobs[k].end = d->triangle_count * (size_t)(k + 1) / (size_t)threads;
        r = vdbgi_vdb_mask_create(ctx, &jobs[k].mask);
    }
    if (r == VDBGI_OK)
        vdbgi_run_threads(threads, run_job, jobs, sizeof(job));
    for (int k = 0; k < threads && r == VDBGI_OK; k++)
        if (jobs[k].result != VDBGI_OK)
            r = vdbgi_fail(ctx, jobs[k].result, "openvdb: %s while placing probes",
                           jobs[k].result == VDBGI_ERR_OUT_OF_MEMORY ? "out of memory"
                                                                     : "a failure");
    for (int k = 1; k < threads && r == VDBGI_OK; k++)
        r = vdbgi_vdb_mask_merge(ctx, jobs[0].mask, jobs[k].mask);
    if (r == VDBGI_OK)
        r = vdbgi_vdb_mask_points(ctx, jobs[0].mask, d->max_count, ijk_out, count_out);
    for (int k = 0; k < threads; k++)
        vdbgi_vdb_mask_destroy(jobs[k].mask);
    return r;
}
