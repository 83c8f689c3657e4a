/* volume_stats.c: sums over the lattice slab by slab, its extents, and a conversion's
   error figures (the shader's view of the valid probes against their values). */
#include "volume_stats.h"
#include "encode.h"
#include "util.h"

#include <math.h>
#include <string.h>

/* Probes i0 <= i < i1: what the shader reads at each valid one, into got (3 floats a probe). */
typedef struct sample_job {
    const vdbgi_volume *v;
    const vdbgi_probes *p;
    float *got;
    size_t i0, i1;
} sample_job;

static void *sample_worker(void *arg)
{
    const sample_job *const job = arg;
    const vdbgi_probes *const p = job->p;
    const vdbgi_volume_view view = vdbgi_volume_view_of(job->v);
    for (size_t i = job->i0; i < job->i1; i++) {
        if (p->backface[i] > p->invalid_threshold)
            continue;
        float pos[3];
        for (int k = 0; k < 3; k++)
            pos[k] = (float)(job->v->lattice_origin[k] + p->spacing * p->ijk[3 * i + k]);
        vdbgi_sampler_sample(&view, pos, &job->got[3 * i]);
    }
    return NULL;
}

/* ---- sums that do not depend on how the lattice is read ------------------- */

vdbgi_result vdbgi_slab_sums_init(vdbgi_context *ctx, vdbgi_slab_sums *s, const int32_t z[2],
                                  int width)
{
    s->first = vdbgi_floor_div(z[0], VDBGI_REGION_STEP);
    s->count = (size_t)(vdbgi_floor_div(z[1], VDBGI_REGION_STEP) - s->first) + 1;
    s->width = width;
    s->v = vdbgi_calloc(ctx, s->count * (size_t)width, sizeof(double));
    return s->v ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
}

static double *slab_at(const vdbgi_slab_sums *s, int32_t z)
{
    return &s->v[(size_t)(vdbgi_floor_div(z, VDBGI_REGION_STEP) - s->first) * (size_t)s->width];
}

void vdbgi_slab_sums_total(const vdbgi_slab_sums *s, double *out)
{
    for (int k = 0; k < s->width; k++)
        out[k] = 0.0;
    for (size_t i = 0; i < s->count; i++)
        for (int k = 0; k < s->width; k++)
            out[k] += s->v[i * (size_t)s->width + k];
}

void vdbgi_stats_init(vdbgi_lattice_stats *st)
{
    memset(st, 0, sizeof(*st));
    for (int k = 0; k < 3; k++) {
        st->lo[k] = st->cell_lo[k] = INT32_MAX;
        st->hi[k] = st->cell_hi[k] = INT32_MIN;
    }
}

void vdbgi_stats_add(vdbgi_lattice_stats *st, const vdbgi_probes *p)
{
    st->probes += p->count;
    for (size_t i = 0; i < p->count; i++) {
        const int32_t *const ijk = &p->ijk[3 * i];
        for (int k = 0; k < 3; k++) {
            st->lo[k] = ijk[k] < st->lo[k] ? ijk[k] : st->lo[k];
            st->hi[k] = ijk[k] > st->hi[k] ? ijk[k] : st->hi[k];
        }
        if (p->backface[i] > p->invalid_threshold)
            continue;
        st->valid++;
        for (int k = 0; k < 3; k++) {
            const int32_t c = vdbgi_floor_div(ijk[k], VDBGI_BRICK);
            st->cell_lo[k] = c < st->cell_lo[k] ? c : st->cell_lo[k];
            st->cell_hi[k] = c > st->cell_hi[k] ? c : st->cell_hi[k];
        }
    }
}

/*
 * Probe i's L2 reading with every term in colour against version 8's, whose terms 4-8 are
 * each channel's L0 times the term's luminance over L0's (pack_write.c): into sum[3] the
 * squared channel differences and into sum[4] the channels read, over the six axes and
 * the eight diagonals.
 */
static void add_luma2_deviation(const vdbgi_probes *p, size_t i, double *sum)
{
    static const float d = 0.57735027f;
    static const float normals[VDBGI_LUMA2_NORMALS][3] = {
        {1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0}, {0, 0, 1},   {0, 0, -1},  {d, d, d},
        {d, d, -d}, {d, -d, d}, {d, -d, -d}, {-d, d, d}, {-d, d, -d}, {-d, -d, d}, {-d, -d, -d}};
    const float *const c0 = &p->rgb[3 * i];
    float terms[24], sh[VDBGI_SH2_TERMS][3], luma[VDBGI_SH2_TERMS][3];
    vdbgi_terms_decode(&p->sh[24 * i], c0, terms);
    const float y0 = vdbgi_luminance(c0);
    for (int c = 0; c < 3; c++)
        sh[0][c] = luma[0][c] = c0[c];
    for (int t = 1; t < VDBGI_SH2_TERMS; t++) {
        const float *const ct = &terms[3 * (t - 1)];
        const float y = vdbgi_luminance(ct);
        for (int c = 0; c < 3; c++) {
            sh[t][c] = ct[c];
            luma[t][c] = t < 4 ? ct[c] : y0 > 0.0f ? c0[c] * (y / y0) : 0.0f;
        }
    }
    for (int n = 0; n < VDBGI_LUMA2_NORMALS; n++) {
        float a[3], b[3];
        vdbgi_sh2_eval((const float(*)[3])sh, normals[n], a);
        vdbgi_sh2_eval((const float(*)[3])luma, normals[n], b);
        for (int c = 0; c < 3; c++) {
            sum[3] += (double)(a[c] - b[c]) * (a[c] - b[c]);
            sum[4] += a[c];
        }
    }
}

void vdbgi_stats_add_colours(vdbgi_lattice_stats *st, const vdbgi_probes *p)
{
    for (size_t i = 0; i < p->count; i++) {
        if (p->backface[i] > p->invalid_threshold)
            continue;
        double *const sum = slab_at(&st->colour, p->ijk[3 * i + 2]);
        for (int k = 0; k < 3; k++)
            sum[k] += p->rgb[3 * i + k];
        if (p->sh)
            add_luma2_deviation(p, i, sum);
    }
}

void vdbgi_stats_valid_z(const vdbgi_lattice_stats *st, int32_t z[2])
{
    z[0] = st->valid ? st->cell_lo[2] * VDBGI_BRICK : 0;
    z[1] = st->valid ? st->cell_hi[2] * VDBGI_BRICK + VDBGI_BRICK - 1 : 0;
}

vdbgi_result vdbgi_error_sums_init(vdbgi_context *ctx, vdbgi_error_sums *e, const int32_t z[2],
                                   size_t valid)
{
    memset(e, 0, sizeof(*e));
    e->top_cap = valid - (size_t)(0.99 * (double)(valid ? valid - 1 : 0));
    e->top = vdbgi_alloc(ctx, (e->top_cap ? e->top_cap : 1) * sizeof(double));
    const vdbgi_result r = vdbgi_slab_sums_init(ctx, &e->sq, z, 1);
    return e->top ? r : VDBGI_ERR_OUT_OF_MEMORY;
}

void vdbgi_error_sums_free(vdbgi_context *ctx, vdbgi_error_sums *e)
{
    vdbgi_free(ctx, e->sq.v);
    vdbgi_free(ctx, e->top);
}

static void top_push(vdbgi_error_sums *e, double x)
{
    double *const h = e->top;
    size_t i;
    if (e->top_count < e->top_cap) {
        for (i = e->top_count++; i > 0 && h[(i - 1) / 2] > x; i = (i - 1) / 2)
            h[i] = h[(i - 1) / 2];
        h[i] = x;
        return;
    }
    if (e->top_cap == 0 || x <= h[0])
        return;
    for (i = 0;;) { /* the root gives way to x: sift down */
        size_t c = 2 * i + 1;
        if (c >= e->top_count)
            break;
        if (c + 1 < e->top_count && h[c + 1] < h[c])
            c++;
        if (h[c] >= x)
            break;
        h[i] = h[c];
        i = c;
    }
    h[i] = x;
}

vdbgi_result vdbgi_error_measure(vdbgi_volume *v, const vdbgi_probes *p, int threads,
                                 vdbgi_error_sums *e)
{
    float *const got = vdbgi_alloc(v->ctx, 3 * sizeof(float) * (p->count ? p->count : 1));
    if (!got)
        return VDBGI_ERR_OUT_OF_MEMORY;
    enum { MAX_JOBS = 64 };
    sample_job jobs[MAX_JOBS];
    const int nt = threads < 1 ? 1 : threads > MAX_JOBS ? MAX_JOBS : threads;
    for (int t = 0; t < nt; t++)
        jobs[t] = (sample_job){v, p, got, p->count * (size_t)t / (size_t)nt,
                               p->count * (size_t)(t + 1) / (size_t)nt};
    vdbgi_run_threads(nt, sample_worker, jobs, sizeof(jobs[0]));
    for (size_t i = 0; i < p->count; i++) {
        if (p->backface[i] > p->invalid_threshold)
            continue;
        double err = 0.0, *const sq = slab_at(&e->sq, p->ijk[3 * i + 2]);
        for (int k = 0; k < 3; k++) {
            const double d = (double)got[3 * i + k] - (double)p->rgb[3 * i + k];
            *sq += d * d;
            err = fmax(err, fabs(d));
        }
        e->n++;
        e->worst = fmax(e->worst, err);
        top_push(e, err);
    }
    vdbgi_free(v->ctx, got);
    return VDBGI_OK;
}

void vdbgi_error_figures(vdbgi_volume_info *info, const vdbgi_error_sums *e)
{
    double sq;
    vdbgi_slab_sums_total(&e->sq, &sq);
    info->rmse = e->n ? sqrt(sq / (3.0 * (double)e->n)) : 0.0;
    info->max_error = e->worst;
    info->p99 = e->n ? e->top[0] : 0.0;
}
