/* texels.c: conservative rasterisation of the charts into sample points, and dilation. */
#include "texels.h"
#include "util.h"

#include <math.h>
#include <string.h>

void vdbgi_texels_free(vdbgi_texels *t)
{
    if (!t || !t->ctx)
        return;
    vdbgi_free(t->ctx, t->tri);
    vdbgi_free(t->ctx, t->pos);
    memset(t, 0, sizeof(*t));
}

static double cross2(const double a[2], const double b[2], const double c[2])
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Does the triangle touch the closed square [x, x+1] x [y, y+1]? Separating axes. */
static bool touches(const double t[3][2], double x, double y)
{
    const double sq[4][2] = {{x, y}, {x + 1, y}, {x + 1, y + 1}, {x, y + 1}};
    for (int e = 0; e < 3; e++) {
        const double *a = t[e], *b = t[(e + 1) % 3];
        const double ax = a[1] - b[1], ay = b[0] - a[0];
        double tl = INFINITY, th = -INFINITY, sl = INFINITY, sh = -INFINITY;
        for (int k = 0; k < 3; k++) {
            const double d = ax * t[k][0] + ay * t[k][1];
            tl = fmin(tl, d), th = fmax(th, d);
        }
        for (int k = 0; k < 4; k++) {
            const double d = ax * sq[k][0] + ay * sq[k][1];
            sl = fmin(sl, d), sh = fmax(sh, d);
        }
        if (th < sl || sh < tl)
            return false;
    }
    return true; /* the square's own axes: the caller's box already overlaps */
}

/* The point of the triangle nearest c, as barycentrics; 0 distance when c is inside. */
static double nearest(const double t[3][2], const double c[2], double bary[3])
{
    const double area = cross2(t[0], t[1], t[2]);
    const double w0 = cross2(t[1], t[2], c) / area, w1 = cross2(t[2], t[0], c) / area;
    const double w2 = 1.0 - w0 - w1;
    if (w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0) {
        bary[0] = w0, bary[1] = w1, bary[2] = w2;
        return 0.0;
    }
    double best = INFINITY;
    for (int e = 0; e < 3; e++) {
        const double *a = t[e], *b = t[(e + 1) % 3];
        const double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
        double s = l2 > 0.0 ? ((c[0] - a[0]) * dx + (c[1] - a[1]) * dy) / l2 : 0.0;
        s = s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
        const double px = a[0] + s * dx - c[0], py = a[1] + s * dy - c[1];
        const double d2 = px * px + py * py;
        if (d2 < best) {
            best = d2;
            bary[e] = 1.0 - s, bary[(e + 1) % 3] = s, bary[(e + 2) % 3] = 0.0;
        }
    }
    /* A hair inside, towards the centroid: the point belongs to this triangle alone. */
    for (int k = 0; k < 3; k++)
        bary[k] = bary[k] * (1.0 - 1e-4) + 1e-4 / 3.0;
    return sqrt(best);
}

vdbgi_result vdbgi_texels_build(vdbgi_context *ctx, const vdbgi_scene *s, const vdbgi_unwrap *u,
                                vdbgi_texels *out)
{
    memset(out, 0, sizeof(*out));
    VDBGI_FAIL_IF(ctx, u->triangle_count != s->triangle_count, VDBGI_ERR_INVALID_ARG,
                  "the unwrap is of another scene (%zu triangles, the scene has %zu)",
                  u->triangle_count, s->triangle_count);
    const size_t size = (size_t)u->size, texels = size * size * u->page_count;
    out->ctx = ctx;
    out->size = u->size;
    out->page_count = u->page_count;
    out->tri = vdbgi_alloc(ctx, texels * sizeof(*out->tri));
    out->pos = vdbgi_calloc(ctx, texels, 3 * sizeof(*out->pos));
    float *const score = vdbgi_alloc(ctx, texels * sizeof(*score));
    if (!out->tri || !out->pos || !score) {
        vdbgi_free(ctx, score);
        vdbgi_texels_free(out);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    for (size_t i = 0; i < texels; i++)
        out->tri[i] = -1, score[i] = INFINITY;
    for (size_t t = 0; t < s->triangle_count; t++) {
        double tri[3][2];
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 2; a++) {
                tri[k][a] = u->uv[6 * t + 2 * (size_t)k + (size_t)a];
                lo[a] = fmin(lo[a], tri[k][a]), hi[a] = fmax(hi[a], tri[k][a]);
            }
        if (cross2(tri[0], tri[1], tri[2]) == 0.0)
            continue; /* no area in the atlas: nothing to sample (unwrap never makes one) */
        const size_t page = (size_t)u->page[u->chart[t]] * size * size;
        for (long y = (long)fmax(0.0, floor(lo[1])); y <= (long)floor(hi[1]) && y < (long)size; y++)
            for (long x = (long)fmax(0.0, floor(lo[0])); x <= (long)floor(hi[0]) && x < (long)size;
                 x++) {
                if (!touches(tri, (double)x, (double)y))
                    continue;
                const double c[2] = {x + 0.5, y + 0.5};
                double b[3];
                const float d = (float)nearest(tri, c, b);
                const size_t i = page + (size_t)y * size + (size_t)x;
                if (!(d < score[i]))
                    continue;
                score[i] = d;
                out->tri[i] = (int32_t)t;
                /*
                 * On the triangle, pulled towards its centroid by two ray offsets (at
                 * most half the way): a point on an edge lies in the plane of the face
                 * beyond it, and its rays would start on that face.
                 */
                double p[3], g[3], len = 0.0;
                for (int k = 0; k < 3; k++) {
                    p[k] = g[k] = 0.0;
                    for (int v = 0; v < 3; v++) {
                        const double corner =
                            s->positions[3 * (size_t)s->indices[3 * t + (size_t)v] + (size_t)k];
                        p[k] += b[v] * corner;
                        g[k] += corner / 3.0;
                    }
                    len += (g[k] - p[k]) * (g[k] - p[k]);
                }
                len = sqrt(len);
                const double off = vdbgi_scene_offset(s, (uint32_t)t);
                const double pull = len > 0.0 ? fmin(2.0 * off, 0.5 * len) / len : 0.0;
                for (int k = 0; k < 3; k++)
                    out->pos[3 * i + (size_t)k] = (float)(p[k] + pull * (g[k] - p[k]));
            }
    }
    for (size_t i = 0; i < texels; i++) {
        out->sample_count += out->tri[i] >= 0;
        out->centre_count += score[i] == 0.0f;
    }
    vdbgi_free(ctx, score);
    return VDBGI_OK;
}

/* Queue texel i's neighbours on its page that are neither kept nor queued yet. */
static void queue_neighbours(size_t i, size_t size, const unsigned char *keep,
                             unsigned char *queued, size_t *list, size_t *count)
{
    const size_t page = i / (size * size), y = i / size % size, x = i % size;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            const long xx = (long)x + dx, yy = (long)y + dy;
            if ((dx || dy) && xx >= 0 && yy >= 0 && xx < (long)size && yy < (long)size) {
                const size_t j = (page * size + (size_t)yy) * size + (size_t)xx;
                if (!keep[j] && !queued[j]) {
                    queued[j] = 1;
                    list[(*count)++] = j;
                }
            }
        }
}

vdbgi_result vdbgi_texels_dilate(const vdbgi_texels *t, float *values, int channels,
                                 unsigned char *keep, int rings)
{
    const size_t size = (size_t)t->size, texels = size * size * t->page_count;
    const size_t nch = (size_t)channels;
    /*
     * Ring by ring, only the texels next to what is kept: the first ring's
     * candidates are the neighbours of the kept texels, each later ring's
     * the neighbours of the ring before (every other texel is as far from a
     * kept one as it was).
     */
    size_t *const cand = vdbgi_alloc(t->ctx, (texels ? texels : 1) * sizeof(*cand));
    size_t *const next = vdbgi_alloc(t->ctx, (texels ? texels : 1) * sizeof(*next));
    unsigned char *const queued = vdbgi_calloc(t->ctx, texels ? texels : 1, 1);
    float *const sum = vdbgi_alloc(t->ctx, (texels ? texels : 1) * nch * sizeof(*sum));
    if (!cand || !next || !queued || !sum) {
        vdbgi_free(t->ctx, cand);
        vdbgi_free(t->ctx, next);
        vdbgi_free(t->ctx, queued);
        vdbgi_free(t->ctx, sum);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    size_t count = 0;
    for (size_t i = 0; rings > 0 && i < texels; i++)
        if (keep[i] == 1)
            queue_neighbours(i, size, keep, queued, cand, &count);
    for (int ring = 0; ring < rings && count > 0; ring++) {
        for (size_t c = 0; c < count; c++) {
            const size_t i = cand[c];
            const size_t page = i / (size * size), y = i / size % size, x = i % size;
            int n = 0;
            float *const acc = &sum[c * nch];
            memset(acc, 0, nch * sizeof(*acc));
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    const long xx = (long)x + dx, yy = (long)y + dy;
                    if ((dx || dy) && xx >= 0 && yy >= 0 && xx < (long)size && yy < (long)size) {
                        const size_t j = (page * size + (size_t)yy) * size + (size_t)xx;
                        if (keep[j] == 1) {
                            for (size_t k = 0; k < nch; k++)
                                acc[k] += values[j * nch + k];
                            n++;
                        }
                    }
                }
            for (size_t k = 0; k < nch; k++)
                acc[k] /= (float)n; /* n > 0: a candidate touches a kept texel */
        }
        /* Applied after the scan: a ring reads only what the rings before it made. */
        for (size_t c = 0; c < count; c++) {
            memcpy(&values[cand[c] * nch], &sum[c * nch], nch * sizeof(*sum));
            keep[cand[c]] = 1;
        }
        size_t n_next = 0;
        for (size_t c = 0; ring + 1 < rings && c < count; c++)
            queue_neighbours(cand[c], size, keep, queued, next, &n_next);
        memcpy(cand, next, n_next * sizeof(*cand));
        count = n_next;
    }
    vdbgi_free(t->ctx, cand);
    vdbgi_free(t->ctx, next);
    vdbgi_free(t->ctx, queued);
    vdbgi_free(t->ctx, sum);
    return VDBGI_OK;
}
