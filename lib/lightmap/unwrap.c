/*
 * unwrap.c: charts, their planes and smallest boxes, and the packing
 * (docs/lightmap.md). Everything here is a pure function of the scene and
 * the parameters: no threads, no randomness.
 */
#include "unwrap.h"
#include "map.h"
#include "util.h"

#include <math.h>
#include <stdlib.h>
/* Debian's libstb-dev: the packer compiled in here, its functions static to this file. */
#define STB_RECT_PACK_IMPLEMENTATION
#define STBRP_STATIC
#include <stb_rect_pack.h>
#include <string.h>

/* Welded vertices: positions equal to the bit, whatever mesh they came from. */
static vdbgi_result weld(vdbgi_context *ctx, const vdbgi_scene *s, uint32_t **out)
{
    vdbgi_map m;
    VDBGI_TRY(vdbgi_map_init(ctx, &m, s->vertex_count));
    uint32_t *const id = vdbgi_alloc(ctx, (s->vertex_count ? s->vertex_count : 1) * sizeof(*id));
    vdbgi_result r = id ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t v = 0; r == VDBGI_OK && v < s->vertex_count; v++) {
        int32_t k[3];
        memcpy(k, &s->positions[3 * v], sizeof(k));
        size_t index;
        bool added;
        r = vdbgi_map_insert(&m, k, &index, &added);
        id[v] = (uint32_t)index;
    }
    vdbgi_map_free(&m);
    if (r != VDBGI_OK) {
        vdbgi_free(ctx, id);
        return r;
    }
    *out = id;
    return VDBGI_OK;
}

/*
 * Each triangle's neighbour across each edge, or UINT32_MAX where the edge
 * is open or shared by more than two triangles (a chart never crosses a
 * non-manifold edge).
 */
static vdbgi_result neighbours(vdbgi_context *ctx, const vdbgi_scene *s, const uint32_t *id,
                               uint32_t *across)
{
    vdbgi_map m;
    VDBGI_TRY(vdbgi_map_init(ctx, &m, 3 * s->triangle_count));
    const size_t n = 3 * s->triangle_count;
    uint32_t(*users)[3] = vdbgi_alloc(ctx, (n ? n : 1) * sizeof(*users)); /* two + a count */
    vdbgi_result r = users ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    for (size_t t = 0; r == VDBGI_OK && t < s->triangle_count; t++)
        for (int e = 0; e < 3; e++) {
            uint32_t a = id[s->indices[3 * t + e]], b = id[s->indices[3 * t + (e + 1) % 3]];
            if (a > b) {
                const uint32_t c = a;
                a = b, b = c;
            }
            const int32_t k[3] = {(int32_t)a, (int32_t)b, 0};
            size_t i;
            bool added;
            if ((r = vdbgi_map_insert(&m, k, &i, &added)) != VDBGI_OK)
                break;
            if (added)
                users[i][2] = 0;
            if (users[i][2] < 2)
                users[i][users[i][2]] = (uint32_t)(3 * t + (size_t)e);
            users[i][2]++;
            across[3 * t + (size_t)e] = (uint32_t)i; /* the edge, for now */
        }
    for (size_t te = 0; r == VDBGI_OK && te < n; te++) {
        const uint32_t *const u = users[across[te]];
        across[te] = u[2] == 2 ? (u[0] == te ? u[1] : u[0]) / 3 : UINT32_MAX;
    }
    vdbgi_free(ctx, users);
    vdbgi_map_free(&m);
    return r;
}

/* An orthonormal basis of the plane with normal n. */
static void plane_basis(const float n[3], double u[3], double v[3])
{
    const double a[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    u[0] = a[1] * n[2] - a[2] * n[1];
    u[1] = a[2] * n[0] - a[0] * n[2];
    u[2] = a[0] * n[1] - a[1] * n[0];
    const double l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int k = 0; k < 3; k++)
        u[k] /= l;
    v[0] = n[1] * u[2] - n[2] * u[1];
    v[1] = n[2] * u[0] - n[0] * u[2];
    v[2] = n[0] * u[1] - n[1] * u[0];
}

static double cross2(const double o[2], const double a[2], const double b[2])
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

static int by_xy(const void *pa, const void *pb)
{
    const double *a = pa, *b = pb;
    return a[0] < b[0] ? -1 : a[0] > b[0] ? 1 : a[1] < b[1] ? -1 : a[1] > b[1] ? 1 : 0;
}

/*
 * The rotation (cos, sin) that gives 2D points their smallest bounding box:
 * one of its sides lies along an edge of their convex hull (Freeman and
 * Shapira), so the hull's edges are all the candidates. pts is sorted and
 * overwritten by the hull.
 */
static void smallest_box(double (*pts)[2], size_t n, double *c, double *s)
{
    *c = 1.0, *s = 0.0;
    if (n < 3)
        return;
    qsort(pts, n, sizeof(*pts), by_xy);
    double(*h)[2] = pts + n; /* the hull: at most n + 1 points after them (caller allocated) */
    size_t k = 0;
    for (size_t i = 0; i < n; i++) { /* Andrew's monotone chain: lower hull */
        while (k >= 2 && cross2(h[k - 2], h[k - 1], pts[i]) <= 0.0)
            k--;
        memcpy(h[k++], pts[i], sizeof(*h));
    }
    for (size_t i = n - 1, lower = k + 1; i-- > 0;) { /* upper hull */
        while (k >= lower && cross2(h[k - 2], h[k - 1], pts[i]) <= 0.0)
            k--;
        memcpy(h[k++], pts[i], sizeof(*h));
    }
    double best = INFINITY;
    for (size_t e = 0; e + 1 < k; e++) {
        double dx = h[e + 1][0] - h[e][0], dy = h[e + 1][1] - h[e][1];
        const double l = sqrt(dx * dx + dy * dy);
        if (!(l > 0.0))
            continue;
        dx /= l, dy /= l;
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (size_t i = 0; i + 1 < k; i++) {
            const double x = h[i][0] * dx + h[i][1] * dy, y = -h[i][0] * dy + h[i][1] * dx;
            lo[0] = fmin(lo[0], x), hi[0] = fmax(hi[0], x);
            lo[1] = fmin(lo[1], y), hi[1] = fmax(hi[1], y);
        }
        const double area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
        if (area < best * (1.0 - 1e-9)) { /* ties keep the first edge: deterministic */
            best = area;
            *c = dx, *s = dy;
        }
    }
}

/* Triangles by chart (a counting sort): order[first[c] .. first[c + 1]). */
static void sort_by_chart(const uint32_t *chart, size_t n, size_t charts, uint32_t *first,
                          uint32_t *order, uint32_t *next)
{
    memset(first, 0, (charts + 1) * sizeof(*first));
    for (size_t t = 0; t < n; t++)
        first[chart[t] + 1]++;
    for (size_t c = 0; c < charts; c++)
        first[c + 1] += first[c];
    memcpy(next, first, charts * sizeof(*next));
    for (size_t t = 0; t < n; t++)
        order[next[chart[t]]++] = (uint32_t)t;
}

/* A corner on its chart's plane, turned: frame holds the basis (u, v) and the rotation. */
static void project(const double frame[8], const float x[3], double out[2])
{
    const double a = x[0] * frame[0] + x[1] * frame[1] + x[2] * frame[2];
    const double b = x[0] * frame[3] + x[1] * frame[4] + x[2] * frame[5];
    out[0] = a * frame[6] + b * frame[7];
    out[1] = -a * frame[7] + b * frame[6];
}

static const float *corner(const vdbgi_scene *s, uint32_t t, int k)
{
    return &s->positions[3 * (size_t)s->indices[3 * (size_t)t + k]];
}

/* The chart's frame (plane of its first triangle, smallest-box rotation) and its box. */
static void place(const vdbgi_scene *s, const uint32_t *tris, size_t count, double (*pts)[2],
                  double frame[8], double box[4])
{
    plane_basis(s->tris[tris[0]].normal, &frame[0], &frame[3]);
    frame[6] = 1.0, frame[7] = 0.0;
    size_t m = 0;
    for (size_t i = 0; i < count; i++)
        for (int k = 0; k < 3; k++)
            project(frame, corner(s, tris[i], k), pts[m++]);
    smallest_box(pts, m, &frame[6], &frame[7]);
    box[0] = box[1] = INFINITY, box[2] = box[3] = -INFINITY;
    for (size_t i = 0; i < count; i++)
        for (int k = 0; k < 3; k++) {
            double p[2];
            project(frame, corner(s, tris[i], k), p);
            box[0] = fmin(box[0], p[0]), box[2] = fmax(box[2], p[0]);
            box[1] = fmin(box[1], p[1]), box[3] = fmax(box[3], p[1]);
        }
}

/*
 * Count, in hit (w x h texels), the texel centres strictly inside triangle t
 * (texel units, either winding; none if it has no area): true if one of them
 * was counted before, where another triangle covers it too. *covered (if not
 * NULL) grows by the centres counted.
 */
static bool covers_again(const double t[3][2], uint8_t *hit, size_t w, size_t h, size_t *covered)
{
    const double area = cross2(t[0], t[1], t[2]);
    if (area == 0.0)
        return false;
    const double sign = area > 0.0 ? 1.0 : -1.0, eps = 1e-9 * fabs(area);
    const size_t x0 = (size_t)fmax(0.0, floor(fmin(t[0][0], fmin(t[1][0], t[2][0])))),
                 y0 = (size_t)fmax(0.0, floor(fmin(t[0][1], fmin(t[1][1], t[2][1]))));
    const double x1 = fmax(t[0][0], fmax(t[1][0], t[2][0])),
                 y1 = fmax(t[0][1], fmax(t[1][1], t[2][1]));
    for (size_t y = y0; y < h && (double)y <= y1; y++)
        for (size_t x = x0; x < w && (double)x <= x1; x++) {
            const double c[2] = {x + 0.5, y + 0.5};
            if (!(sign * cross2(t[0], t[1], c) > eps && sign * cross2(t[1], t[2], c) > eps &&
                  sign * cross2(t[2], t[0], c) > eps))
                continue;
            if (covered)
                ++*covered;
            if (hit[y * w + x]++)
                return true;
        }
    return false;
}

/* Does the chart, laid out at density, cover some texel centre with two triangles? */
static vdbgi_result folds(vdbgi_context *ctx, const vdbgi_scene *s, const uint32_t *tris,
                          size_t count, const double frame[8], const double box[4], double density,
                          bool *fold)
{
    const size_t w = (size_t)ceil((box[2] - box[0]) * density) + 2,
                 h = (size_t)ceil((box[3] - box[1]) * density) + 2;
    uint8_t *const hit = vdbgi_calloc(ctx, w * h, 1);
    if (!hit)
        return VDBGI_ERR_OUT_OF_MEMORY;
    *fold = false;
    for (size_t i = 0; i < count && !*fold; i++) {
        double t[3][2];
        for (int k = 0; k < 3; k++) {
            project(frame, corner(s, tris[i], k), t[k]);
            t[k][0] = (t[k][0] - box[0]) * density, t[k][1] = (t[k][1] - box[1]) * density;
        }
        *fold = covers_again(t, hit, w, h, NULL);
    }
    vdbgi_free(ctx, hit);
    return VDBGI_OK;
}

void vdbgi_unwrap_free(vdbgi_unwrap *u)
{
    if (!u || !u->ctx)
        return;
    vdbgi_free(u->ctx, u->uv);
    vdbgi_free(u->ctx, u->chart);
    vdbgi_free(u->ctx, u->page);
    vdbgi_free(u->ctx, u->density);
    vdbgi_free(u->ctx, u->rect);
    memset(u, 0, sizeof(*u));
}

/* Grow every chart: a breadth-first flood over shared edges, in triangle order. */
static size_t grow_charts(const vdbgi_scene *s, const uint32_t *across, float cos_max,
                          uint32_t *chart, uint32_t *queue)
{
    const size_t n = s->triangle_count;
    for (size_t t = 0; t < n; t++)
        chart[t] = UINT32_MAX;
    size_t charts = 0;
    for (size_t seed = 0; seed < n; seed++) {
        if (chart[seed] != UINT32_MAX)
            continue;
        const float *const sn = s->tris[seed].normal;
        size_t head = 0, tail = 0;
        chart[seed] = (uint32_t)charts;
        queue[tail++] = (uint32_t)seed;
        while (head < tail) {
            const uint32_t t = queue[head++];
            for (int e = 0; e < 3; e++) {
                const uint32_t o = across[3 * (size_t)t + (size_t)e];
                if (o == UINT32_MAX || chart[o] != UINT32_MAX)
                    continue;
                const float *const on = s->tris[o].normal;
                if (on[0] * sn[0] + on[1] * sn[1] + on[2] * sn[2] < cos_max)
                    continue;
                chart[o] = (uint32_t)charts;
                queue[tail++] = o;
            }
        }
        charts++;
    }
    return charts;
}

/* The work arrays of one unwrap, per triangle or per chart (splitting may add charts). */
typedef struct unwrap_work {
    uint32_t *first, *order, *queue; /* each chart's triangles: order[first[c] .. first[c + 1]] */
    double (*pts)[2];                /* a chart's points, then their hull */
    double (*box)[4], (*frame)[8];   /* each chart's smallest box, on its plane */
    int (*wh)[2];                    /* each chart's texels, gutters included */
    stbrp_rect *rects;
    stbrp_node *nodes;
} unwrap_work;

/*
 * Each chart on the plane of its first triangle, turned to its smallest
 * box. A chart that covers a texel centre twice there (a spiral ramp folds
 * over itself) gives the second half of its triangles to a new chart, until
 * none does. Returns the chart count in *charts.
 */
static vdbgi_result place_charts(vdbgi_unwrap *u, const vdbgi_scene *s, unwrap_work *w,
                                 size_t *charts)
{
    const double gutter = u->gutter, texel = u->texel;
    for (;;) {
        sort_by_chart(u->chart, u->triangle_count, *charts, w->first, w->order, w->queue);
        const size_t before = *charts;
        for (size_t c = 0; c < before; c++) {
            const uint32_t *const tris = &w->order[w->first[c]];
            const uint32_t count = w->first[c + 1] - w->first[c];
            place(s, tris, count, w->pts, w->frame[c], w->box[c]);
            /* A chart larger than an atlas (gutters included) shrinks to fit one. */
            const double room = u->size - 2 * gutter - 1;
            const double want =
                fmax(w->box[c][2] - w->box[c][0], w->box[c][3] - w->box[c][1]) / texel;
            const double exact = want > room ? room / want / texel : 1.0 / texel;
            /* Rounded down to a float: rounded up, a chart that fills the atlas overflows it. */
            float density = (float)exact;
            if ((double)density > exact)
                density = nextafterf(density, 0.0f);
            u->density[c] = density;
            bool fold = false;
            if (count > 1)
                VDBGI_TRY(folds(u->ctx, s, tris, count, w->frame[c], w->box[c], density, &fold));
            if (fold) {
                for (uint32_t i = w->first[c] + count / 2; i < w->first[c + 1]; i++)
                    u->chart[w->order[i]] = (uint32_t)*charts;
                ++*charts;
            }
        }
        if (*charts == before)
            return VDBGI_OK;
    }
}

/*
 * The smallest atlas edge, a multiple of VDBGI_ATLAS_STEP texels below
 * u->size, on which every chart fits one page; u->size when none does. The
 * search starts where the charts' area and widest side allow and packs each
 * candidate whole (the packer places by skyline, so a fit is not a matter of
 * area alone).
 */
static int smallest_fit(const vdbgi_unwrap *u, unwrap_work *w)
{
    const size_t charts = u->chart_count;
    double area = 0.0;
    int widest = 0;
    for (size_t c = 0; c < charts; c++) {
        area += (double)w->wh[c][0] * w->wh[c][1];
        widest = w->wh[c][0] > widest ? w->wh[c][0] : widest;
        widest = w->wh[c][1] > widest ? w->wh[c][1] : widest;
    }
    const double least = fmax(sqrt(area), (double)widest);
    for (int size = VDBGI_ATLAS_STEP * (int)ceil(least / VDBGI_ATLAS_STEP); size < u->size;
         size += VDBGI_ATLAS_STEP) {
        stbrp_context pack;
        stbrp_init_target(&pack, size, size, w->nodes, size);
        for (size_t c = 0; c < charts; c++)
            w->rects[c] = (stbrp_rect){.id = (int)c, .w = w->wh[c][0], .h = w->wh[c][1]};
        if (stbrp_pack_rects(&pack, w->rects, (int)charts))
            return size;
    }
    return u->size;
}

/* Pages: pack what is left into a fresh atlas until nothing is; each triangle's uv from its chart's place. */
static vdbgi_result pack_pages(vdbgi_unwrap *u, const vdbgi_scene *s, unwrap_work *w)
{
    const size_t charts = u->chart_count;
    const int size = u->size, gutter = (int)u->gutter;
    size_t left = charts;
    for (size_t c = 0; c < charts; c++)
        u->page[c] = UINT32_MAX;
    while (left > 0) {
        stbrp_context pack;
        stbrp_init_target(&pack, size, size, w->nodes, size);
        size_t k = 0;
        for (size_t c = 0; c < charts; c++)
            if (u->page[c] == UINT32_MAX)
                w->rects[k++] = (stbrp_rect){.id = (int)c, .w = w->wh[c][0], .h = w->wh[c][1]};
        stbrp_pack_rects(&pack, w->rects, (int)k);
        size_t placed = 0;
        for (size_t i = 0; i < k; i++) {
            const stbrp_rect *const rc = &w->rects[i];
            if (!rc->was_packed)
                continue;
            const size_t c = (size_t)rc->id;
            u->page[c] = (uint32_t)u->page_count;
            const int32_t rect[4] = {rc->x, rc->y, rc->w, rc->h};
            memcpy(&u->rect[4 * c], rect, sizeof(rect));
            placed++;
            for (uint32_t j = w->first[c]; j < w->first[c + 1]; j++) {
                const size_t t = w->order[j];
                for (int q = 0; q < 3; q++) {
                    double pp[2];
                    project(w->frame[c], corner(s, (uint32_t)t, q), pp);
                    u->uv[6 * t + 2 * q] =
                        (float)(rc->x + gutter + 0.5 + (pp[0] - w->box[c][0]) * u->density[c]);
                    u->uv[6 * t + 2 * q + 1] =
                        (float)(rc->y + gutter + 0.5 + (pp[1] - w->box[c][1]) * u->density[c]);
                }
            }
        }
        /* Cannot happen: every chart fits an empty atlas. */
        VDBGI_FAIL_IF(u->ctx, placed == 0, VDBGI_ERR_BACKEND, "rectangle packing placed nothing");
        left -= placed;
        u->page_count++;
    }
    return VDBGI_OK;
}

vdbgi_result vdbgi_unwrap_build(vdbgi_context *ctx, const vdbgi_scene *s,
                                const vdbgi_unwrap_params *params, vdbgi_unwrap *u)
{
    const vdbgi_unwrap_params none = {0};
    const vdbgi_unwrap_params *const p = params ? params : &none;
    memset(u, 0, sizeof(*u));
    const float texel = p->texel == 0.0f ? 0.25f : p->texel;
    const int size = p->size == 0 ? 1024 : p->size;
    const float angle = p->max_angle == 0.0f ? 15.0f : p->max_angle;
    const int gutter = p->gutter == 0 ? 2 : p->gutter;
    VDBGI_FAIL_IF(ctx, !(texel > 0.0f) || !isfinite(texel), VDBGI_ERR_INVALID_ARG,
                  "texel size must be > 0 metres (got %g)", (double)p->texel);
    VDBGI_FAIL_IF(ctx, size < 16 || size > 16384, VDBGI_ERR_INVALID_ARG,
                  "atlas size must be 16..16384 texels (got %d)", p->size);
    VDBGI_FAIL_IF(ctx, !(angle > 0.0f && angle < 90.0f), VDBGI_ERR_INVALID_ARG,
                  "chart angle must be in (0, 90) degrees (got %g)", (double)p->max_angle);
    VDBGI_FAIL_IF(ctx, gutter < 1 || gutter > size / 8, VDBGI_ERR_INVALID_ARG,
                  "gutter must be 1..%d texels (got %d)", size / 8, p->gutter);
    VDBGI_FAIL_IF(ctx, s->triangle_count == 0, VDBGI_ERR_FORMAT, "the scene has no triangles");
    const size_t n = s->triangle_count;
    u->ctx = ctx;
    u->triangle_count = n;
    u->size = size;
    u->texel = texel;
    u->gutter = (float)gutter;
    uint32_t *id = NULL, *across = NULL;
    unwrap_work w = {0};
    u->uv = vdbgi_alloc(ctx, 6 * n * sizeof(*u->uv));
    u->chart = vdbgi_alloc(ctx, n * sizeof(*u->chart));
    across = vdbgi_alloc(ctx, 3 * n * sizeof(*across));
    w.queue = vdbgi_alloc(ctx, n * sizeof(*w.queue));
    vdbgi_result r = u->uv && u->chart && across && w.queue ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK && (r = weld(ctx, s, &id)) == VDBGI_OK)
        r = neighbours(ctx, s, id, across);
    if (r != VDBGI_OK)
        goto done;
    size_t charts = grow_charts(s, across, cosf(angle * 3.14159265f / 180.0f), u->chart, w.queue);
    /* Per-chart arrays for as many charts as triangles: splitting may add charts. */
    w.first = vdbgi_alloc(ctx, (n + 1) * sizeof(*w.first));
    w.order = vdbgi_alloc(ctx, n * sizeof(*w.order));
    w.pts = vdbgi_alloc(ctx, (6 * n + 1) * sizeof(*w.pts)); /* points, then their hull */
    w.box = vdbgi_alloc(ctx, n * sizeof(*w.box));
    w.frame = vdbgi_alloc(ctx, n * sizeof(*w.frame));
    w.rects = vdbgi_alloc(ctx, n * sizeof(*w.rects));
    w.wh = vdbgi_alloc(ctx, n * sizeof(*w.wh));
    w.nodes = vdbgi_alloc(ctx, (size_t)size * sizeof(*w.nodes));
    u->page = vdbgi_alloc(ctx, n * sizeof(*u->page));
    u->density = vdbgi_alloc(ctx, n * sizeof(*u->density));
    u->rect = vdbgi_alloc(ctx, 4 * n * sizeof(*u->rect));
    if (!w.first || !w.order || !w.pts || !w.box || !w.frame || !w.rects || !w.wh || !w.nodes ||
        !u->page || !u->density || !u->rect) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto done;
    }
    if ((r = place_charts(u, s, &w, &charts)) != VDBGI_OK)
        goto done;
    u->chart_count = charts;
    for (size_t c = 0; c < charts; c++) {
        /* Its footprint's texels, conservatively: the extent from half a texel in, plus one. */
        w.wh[c][0] = (int)ceil((w.box[c][2] - w.box[c][0]) * u->density[c]) + 2 * gutter + 1;
        w.wh[c][1] = (int)ceil((w.box[c][3] - w.box[c][1]) * u->density[c]) + 2 * gutter + 1;
        u->chart_texels += (double)(w.wh[c][0] - 2 * gutter) * (w.wh[c][1] - 2 * gutter);
    }
    if (p->size == 0) /* by default, an atlas no larger than the charts need */
        u->size = smallest_fit(u, &w);
    r = pack_pages(u, s, &w);
done:
    vdbgi_free(ctx, id);
    vdbgi_free(ctx, across);
    vdbgi_free(ctx, w.queue);
    vdbgi_free(ctx, w.first);
    vdbgi_free(ctx, w.order);
    vdbgi_free(ctx, w.pts);
    vdbgi_free(ctx, w.box);
    vdbgi_free(ctx, w.frame);
    vdbgi_free(ctx, w.rects);
    vdbgi_free(ctx, w.wh);
    vdbgi_free(ctx, w.nodes);
    if (r != VDBGI_OK)
        vdbgi_unwrap_free(u);
    return r;
}

vdbgi_result vdbgi_unwrap_from_uv1(vdbgi_context *ctx, const vdbgi_scene *s,
                                   const vdbgi_unwrap_params *params, vdbgi_unwrap *u, bool *usable,
                                   const char **why)
{
    memset(u, 0, sizeof(*u));
    *usable = false;
    const int size = params && params->size ? params->size : 1024;
    const size_t n = s->triangle_count;
    if (s->uv1_count != s->vertex_count || n == 0) {
        *why = "not every mesh has one";
        return VDBGI_OK;
    }
    u->ctx = ctx;
    u->triangle_count = n;
    u->size = size;
    u->texel = 0.0f; /* unknown: the set's own */
    u->gutter = (float)(params && params->gutter ? params->gutter : 2);
    u->uv = vdbgi_alloc(ctx, 6 * n * sizeof(*u->uv));
    u->chart = vdbgi_calloc(ctx, n, sizeof(*u->chart));
    u->page = vdbgi_calloc(ctx, 1, sizeof(*u->page));
    u->rect = vdbgi_calloc(ctx, 4, sizeof(*u->rect));
    u->density = vdbgi_calloc(ctx, 1, sizeof(*u->density));
    uint8_t *const hit = vdbgi_calloc(ctx, (size_t)size * (size_t)size, 1);
    if (!u->uv || !u->chart || !u->page || !u->density || !u->rect || !hit) {
        vdbgi_free(ctx, hit);
        vdbgi_unwrap_free(u);
        return VDBGI_ERR_OUT_OF_MEMORY;
    }
    u->chart_count = u->page_count = 1;
    u->rect[2] = u->rect[3] = size;
    *why = NULL;
    size_t bare = 0; /* triangles that cover no texel centre */
    for (size_t t = 0; t < n && !*why; t++) {
        double tri[3][2];
        for (int k = 0; k < 3; k++) {
            const float *const uv = &s->uvs1[2 * (size_t)s->indices[3 * t + (size_t)k]];
            if (!(uv[0] >= 0.0f && uv[0] <= 1.0f && uv[1] >= 0.0f && uv[1] <= 1.0f)) {
                *why = "a corner lies outside [0, 1]";
                break;
            }
            tri[k][0] = (double)uv[0] * size;
            tri[k][1] = (1.0 - (double)uv[1]) * size;
            u->uv[6 * t + 2 * (size_t)k] = (float)tri[k][0];
            u->uv[6 * t + 2 * (size_t)k + 1] = (float)tri[k][1];
        }
        if (*why)
            break;
        const double area = cross2(tri[0], tri[1], tri[2]);
        if (area == 0.0) {
            *why = "a triangle has no area in it";
            break;
        }
        size_t covered = 0;
        if (covers_again(tri, hit, (size_t)size, (size_t)size, &covered))
            *why = "two triangles overlap in it";
        bare += covered == 0;
    }
    /* A set whose triangles mostly fall between texel centres (all of them inside one
       texel, say) would light them from its neighbours' texels, or none. */
    if (!*why && 2 * bare > n)
        *why = "most of its triangles cover no texel centre at this size";
    vdbgi_free(ctx, hit);
    if (*why) {
        vdbgi_unwrap_free(u);
        return VDBGI_OK;
    }
    u->chart_texels = (double)size * size;
    *usable = true;
    return VDBGI_OK;
}
