/*
 * volume.c: baked probes to seed 000's bricked volume, stage by stage (fill,
 * coarsen, a layout's textures), and the error of the result. Its file is
 * volume_io.c's.
 */
#include "atlas.h"
#include "gifile.h"
#include "packed.h"
#include "util.h"

#include <math.h>
#include <string.h>

static vdbgi_result resolve_desc(vdbgi_context *ctx, const vdbgi_convert_desc *desc, float *eps,
                                 float *sigmas, int *max_level, vdbgi_criterion *criterion,
                                 vdbgi_encoding *encoding, int *threads)
{
    const vdbgi_convert_desc none = {0};
    if (!desc)
        desc = &none;
    *eps = desc->eps == 0.0f ? 0.1f : desc->eps == VDBGI_ZERO ? 0.0f : desc->eps;
    VDBGI_FAIL_IF(ctx, !(*eps >= 0.0f) || !isfinite(*eps), VDBGI_ERR_INVALID_ARG,
                  "eps must be >= 0 and finite (got %g)", (double)desc->eps);
    *sigmas = desc->noise_sigmas == 0.0f         ? 1.0f
              : desc->noise_sigmas == VDBGI_ZERO ? 0.0f
                                                 : desc->noise_sigmas;
    VDBGI_FAIL_IF(ctx, !(*sigmas >= 0.0f) || !isfinite(*sigmas), VDBGI_ERR_INVALID_ARG,
                  "noise allowance must be >= 0 standard errors (got %g)",
                  (double)desc->noise_sigmas);
    *max_level = desc->max_level == 0 ? 3 : desc->max_level == VDBGI_ZERO ? 0 : desc->max_level;
    VDBGI_FAIL_IF(ctx, *max_level < 0 || *max_level > 3, VDBGI_ERR_INVALID_ARG,
                  "max level must be in 0..3 (got %d)", desc->max_level);
    VDBGI_FAIL_IF(ctx,
                  desc->criterion < VDBGI_CRITERION_AUTO || desc->criterion > VDBGI_CRITERION_RMSE,
                  VDBGI_ERR_INVALID_ARG, "unknown criterion %d", (int)desc->criterion);
    *criterion = desc->criterion == VDBGI_CRITERION_AUTO ? VDBGI_CRITERION_INTERP : desc->criterion;
    VDBGI_FAIL_IF(ctx,
                  desc->encoding != VDBGI_ENCODING_RGBM && desc->encoding != VDBGI_ENCODING_RGB9E5,
                  VDBGI_ERR_INVALID_ARG, "unknown encoding %d", (int)desc->encoding);
    *encoding = desc->encoding;
    VDBGI_FAIL_IF(ctx, desc->fill < VDBGI_FILL_AUTO || desc->fill > VDBGI_FILL_DARKEST,
                  VDBGI_ERR_INVALID_ARG, "unknown fill %d", (int)desc->fill);
    VDBGI_FAIL_IF(ctx, desc->layout < VDBGI_LAYOUT_DEFAULT || desc->layout > VDBGI_LAYOUT_COMPACT,
                  VDBGI_ERR_INVALID_ARG, "unknown layout %d", (int)desc->layout);
    VDBGI_FAIL_IF(ctx, desc->threads < 0, VDBGI_ERR_INVALID_ARG,
                  "thread count must be >= 0 (got %d)", desc->threads);
    VDBGI_FAIL_IF(ctx, desc->term_bits != 0 && (desc->term_bits < 4 || desc->term_bits > 8),
                  VDBGI_ERR_INVALID_ARG, "L2 terms keep 4 to 8 bits of each ratio (got %d)",
                  desc->term_bits);
    VDBGI_FAIL_IF(ctx, desc->gi_version != 0 && desc->gi_version != 6 && desc->gi_version != 7,
                  VDBGI_ERR_INVALID_ARG,
                  "a volume with L2 terms is written as .gi version 6 or 7 (got %d)",
                  desc->gi_version);
    *threads = desc->threads ? desc->threads : vdbgi_core_count();
    return VDBGI_OK;
}

vdbgi_volume_view vdbgi_volume_view_of(const vdbgi_volume *v)
{
    vdbgi_volume_view view;
    memset(&view, 0, sizeof(view));
    view.encoding = (uint32_t)v->info.encoding;
    view.layout = (uint32_t)v->info.layout;
    view.rgbm_range = v->info.rgbm_range;
    for (int k = 0; k < 3; k++) {
        view.box_min[k] = v->info.box_min[k];
        view.box_max[k] = v->info.box_max[k];
        view.ind_dims[k] = v->info.indirection_dims[k];
        view.atlas_dims[k] = v->info.atlas_dims[k];
    }
    view.indirection = v->tex.indirection;
    view.atlas = v->tex.atlas;
    view.sh = v->tex.sh;
    return view;
}

void vdbgi_volume_sample(const vdbgi_volume *v, const float pos[3], float rgb[3])
{
    const vdbgi_volume_view view = vdbgi_volume_view_of(v);
    vdbgi_sampler_sample(&view, pos, rgb);
}

void vdbgi_volume_sample_normal(const vdbgi_volume *v, const float pos[3], const float n[3],
                                float rgb[3])
{
    const vdbgi_volume_view view = vdbgi_volume_view_of(v);
    vdbgi_sampler_sample_normal(&view, pos, n, rgb);
}

/* Column (x, z)'s run: the cells from its lowest to its highest that are not 0,0,0,0. */
static uint32_t column_run(const vdbgi_volume *v, uint32_t x, uint32_t z, uint32_t *ymin)
{
    const uint32_t *const d = v->info.indirection_dims;
    uint32_t lo = d[1], hi = 0;
    for (uint32_t y = 0; y < d[1]; y++) {
        const uint8_t *const t = &v->tex.indirection[4 * (((size_t)z * d[1] + y) * d[0] + x)];
        if (t[0] | t[1] | t[2] | t[3]) {
            lo = lo == d[1] ? y : lo;
            hi = y;
        }
    }
    *ymin = lo == d[1] ? 0 : lo;
    return lo == d[1] ? 0 : hi - lo + 1;
}

/*
 * The runtime's indirection (docs/format.md): two texels a column (its run,
 * and where the run starts in the list), then the runs' texels, in a 2D
 * texture at most VDBGI_COLUMNS_ROW texels wide. Writes it to out unless NULL
 * or shorter than capacity (then returns 0); returns its bytes, 0 (dims 0)
 * above VDBGI_COLUMNS_ROW^2 texels.
 */
static size_t columns(const vdbgi_volume *v, uint8_t *out, size_t capacity, uint32_t dims[2])
{
    const uint32_t *const d = v->info.indirection_dims;
    const size_t n = (size_t)d[0] * d[2];
    size_t total = 2 * n;
    uint32_t ymin;
    for (uint32_t z = 0; z < d[2]; z++)
        for (uint32_t x = 0; x < d[0]; x++)
            total += column_run(v, x, z, &ymin);
    dims[0] = dims[1] = 0;
    if (total > (size_t)VDBGI_COLUMNS_ROW * VDBGI_COLUMNS_ROW)
        return 0;
    const size_t rows = (total + VDBGI_COLUMNS_ROW - 1) / VDBGI_COLUMNS_ROW;
    dims[0] = (uint32_t)((total + rows - 1) / rows);
    dims[1] = (uint32_t)rows;
    const size_t size = 4 * (size_t)dims[0] * dims[1];
    if (!out)
        return size;
    if (capacity < size)
        return 0;
    memset(out, 0, size);
    size_t offset = 0;
    for (uint32_t z = 0; z < d[2]; z++)
        for (uint32_t x = 0; x < d[0]; x++) {
            const uint32_t count = column_run(v, x, z, &ymin);
            uint8_t *const head = &out[8 * ((size_t)z * d[0] + x)];
            const uint8_t h[8] = {(uint8_t)ymin,           (uint8_t)(ymin >> 8),
                                  (uint8_t)count,          (uint8_t)(count >> 8),
                                  (uint8_t)offset,         (uint8_t)(offset >> 8),
                                  (uint8_t)(offset >> 16), 0};
            memcpy(head, h, sizeof(h));
            for (uint32_t k = 0; k < count; k++)
                memcpy(&out[4 * (2 * n + offset + k)],
                       &v->tex.indirection[4 * (((size_t)z * d[1] + ymin + k) * d[0] + x)], 4);
            offset += count;
        }
    return size;
}

void vdbgi_volume_get_info(const vdbgi_volume *v, vdbgi_volume_info *info)
{
    *info = v->info;
    info->columns_size = columns(v, NULL, 0, info->columns_dims);
    info->sh_size = v->info.basis == VDBGI_BASIS_SH2 ? 6 * v->info.atlas_size : 0;
}

size_t vdbgi_volume_copy_columns(const vdbgi_volume *v, void *buffer, size_t capacity)
{
    uint32_t dims[2];
    return columns(v, buffer, capacity, dims);
}

void vdbgi_volume_destroy(vdbgi_volume *v)
{
    if (!v)
        return;
    vdbgi_context *const ctx = v->ctx;
    vdbgi_textures_free(ctx, &v->tex);
    vdbgi_free(ctx, v->payload);
    vdbgi_free(ctx, v->file);
    vdbgi_field_free(&v->filled);
    vdbgi_free(ctx, v);
}

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

/*
 * A sum over the lattice adds each VDBGI_REGION_STEP-point z slab's terms in
 * probe order, then the slabs in z order. A region is whole slabs, and its
 * probes come in the whole read's order, so a conversion region by region
 * adds exactly what the whole one does.
 */
typedef struct slab_sums {
    int32_t first; /* the first slab's index */
    size_t count;
    int width; /* doubles a slab */
    double *v;
} slab_sums;

static vdbgi_result slab_sums_init(vdbgi_context *ctx, slab_sums *s, const int32_t z[2], int width)
{
    s->first = vdbgi_floor_div(z[0], VDBGI_REGION_STEP);
    s->count = (size_t)(vdbgi_floor_div(z[1], VDBGI_REGION_STEP) - s->first) + 1;
    s->width = width;
    s->v = vdbgi_calloc(ctx, s->count * (size_t)width, sizeof(double));
    return s->v ? VDBGI_OK : VDBGI_ERR_OUT_OF_MEMORY;
}

static double *slab_at(const slab_sums *s, int32_t z)
{
    return &s->v[(size_t)(vdbgi_floor_div(z, VDBGI_REGION_STEP) - s->first) * (size_t)s->width];
}

static void slab_sums_total(const slab_sums *s, double *out)
{
    for (int k = 0; k < s->width; k++)
        out[k] = 0.0;
    for (size_t i = 0; i < s->count; i++)
        for (int k = 0; k < s->width; k++)
            out[k] += s->v[i * (size_t)s->width + k];
}

/* What the conversion needs of the whole lattice before it fills any of it. */
typedef struct lattice_stats {
    size_t probes, valid;
    int32_t lo[3], hi[3];           /* every probe's index */
    int32_t cell_lo[3], cell_hi[3]; /* the valid probes' cells */
    slab_sums colour;               /* the valid probes' colours */
} lattice_stats;

static void stats_init(lattice_stats *st)
{
    memset(st, 0, sizeof(*st));
    for (int k = 0; k < 3; k++) {
        st->lo[k] = st->cell_lo[k] = INT32_MAX;
        st->hi[k] = st->cell_hi[k] = INT32_MIN;
    }
}

/* Counts and extents. */
static void stats_add(lattice_stats *st, const vdbgi_probes *p)
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

/* The valid probes' colours into st->colour, allocated once check_extent bounds its slabs. */
static void stats_add_colours(lattice_stats *st, const vdbgi_probes *p)
{
    for (size_t i = 0; i < p->count; i++) {
        if (p->backface[i] > p->invalid_threshold)
            continue;
        double *const sum = slab_at(&st->colour, p->ijk[3 * i + 2]);
        for (int k = 0; k < 3; k++)
            sum[k] += p->rgb[3 * i + k];
    }
}

/* The z range of the valid probes' cells, which the sums over them cover. */
static void valid_z(const lattice_stats *st, int32_t z[2])
{
    z[0] = st->valid ? st->cell_lo[2] * VDBGI_BRICK : 0;
    z[1] = st->valid ? st->cell_hi[2] * VDBGI_BRICK + VDBGI_BRICK - 1 : 0;
}

/* The error figures, summed as they come (a region's probes, or all). */
typedef struct error_sums {
    slab_sums sq; /* squared channel errors */
    double worst;
    size_t n;
    /* The largest errors seen, a min-heap of at most top_cap: once every valid probe is in,
       its root is the one vdbgi_quantile's 0.99 picks. */
    double *top;
    size_t top_count, top_cap;
} error_sums;

static vdbgi_result error_sums_init(vdbgi_context *ctx, error_sums *e, const int32_t z[2],
                                    size_t valid)
{
    memset(e, 0, sizeof(*e));
    e->top_cap = valid - (size_t)(0.99 * (double)(valid ? valid - 1 : 0));
    e->top = vdbgi_alloc(ctx, (e->top_cap ? e->top_cap : 1) * sizeof(double));
    const vdbgi_result r = slab_sums_init(ctx, &e->sq, z, 1);
    return e->top ? r : VDBGI_ERR_OUT_OF_MEMORY;
}

static void error_sums_free(vdbgi_context *ctx, error_sums *e)
{
    vdbgi_free(ctx, e->sq.v);
    vdbgi_free(ctx, e->top);
}

static void top_push(error_sums *e, double x)
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

/*
 * The shader's view of the valid probes p against their values (which the
 * fill kept): sampled over threads, summed on one in probe order, so the
 * figures do not depend on the thread count.
 */
static vdbgi_result measure_error(vdbgi_volume *v, const vdbgi_probes *p, int threads,
                                  error_sums *e)
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

static void error_figures(vdbgi_volume_info *info, const error_sums *e)
{
    double sq;
    slab_sums_total(&e->sq, &sq);
    info->rmse = e->n ? sqrt(sq / (3.0 * (double)e->n)) : 0.0;
    info->max_error = e->worst;
    info->p99 = e->n ? e->top[0] : 0.0;
}

static int report(const vdbgi_convert_desc *desc, float done)
{
    return desc && desc->progress ? desc->progress(desc->progress_user, done) : 0;
}

/* The volume's settings (like: a read of the probes, for their lattice), and the mean
   irradiance of the valid probes: the scale of eps and of the error figures. */
static vdbgi_volume *volume_start(vdbgi_context *ctx, const vdbgi_probes *like,
                                  const lattice_stats *st, vdbgi_encoding encoding,
                                  vdbgi_layout layout, int max_level)
{
    vdbgi_volume *const v = vdbgi_calloc(ctx, 1, sizeof(*v));
    if (!v)
        return NULL;
    v->ctx = ctx;
    vdbgi_volume_info *const info = &v->info;
    info->encoding = encoding;
    info->layout = layout;
    info->rgbm_range = VDBGI_RGBM_RANGE;
    info->spacing = (float)like->spacing;
    info->max_level = (uint32_t)max_level;
    info->probe_count = st->probes;
    info->valid_count = st->valid;
    memcpy(v->lattice_origin, like->origin, sizeof(v->lattice_origin));
    double sum[3];
    slab_sums_total(&st->colour, sum);
    for (int k = 0; k < 3; k++)
        v->mean_rgb[k] = info->valid_count ? (float)(sum[k] / (double)info->valid_count) : 0.0f;
    info->mean_irradiance = (v->mean_rgb[0] + v->mean_rgb[1] + v->mean_rgb[2]) / 3.0;
    /* A dense RGBA8 grid over the probes' box at the same spacing, for comparison. */
    info->dense_rgba8_size = 4;
    for (int k = 0; k < 3; k++)
        info->dense_rgba8_size *= (size_t)(st->hi[k] - st->lo[k] + 1);
    return v;
}

/*
 * The indirection's size from the valid probes alone, before the fill spends
 * memory on a lattice the texture limit refuses anyway: the same cells
 * place_indirection will count (the valid probes' cells, one cell of margin,
 * the corner aligned to 8 cells).
 */
static vdbgi_result check_extent(vdbgi_context *ctx, const lattice_stats *st)
{
    const int32_t *const lo = st->cell_lo, *const hi = st->cell_hi;
    const size_t valid = st->valid;
    double cells = 1.0;
    for (int k = 0; k < 3 && lo[k] <= hi[k]; k++) {
        const int64_t dim = (int64_t)hi[k] + 1 - (int64_t)vdbgi_floor_div(lo[k] - 1, 8) * 8 + 1;
        VDBGI_FAIL_IF(ctx, dim > VDBGI_MAX_TEXTURE_DIM, VDBGI_ERR_OUT_OF_MEMORY,
                      "the indirection texture would be %lld cells along %c, above the "
                      "%d-texel limit of 3D textures: raise the probe spacing",
                      (long long)dim, "xyz"[k], VDBGI_MAX_TEXTURE_DIM);
        cells *= (double)dim;
    }
    /*
     * The indirection and the packer's grids cost ~30 bytes a cell: a lattice of
     * a few probes spread thousands of spacings apart asked for gigabytes. A
     * scene's own lattice holds a probe in far more than one cell in 64.
     */
    VDBGI_FAIL_IF(ctx, cells > VDBGI_SPARSE_CELLS && cells > 64.0 * (double)valid, VDBGI_ERR_FORMAT,
                  "%zu valid probes spread over %.0f cells of the indirection (more than 64 a "
                  "probe, and more than %d): too sparse a lattice to convert",
                  valid, cells, VDBGI_SPARSE_CELLS);
    return VDBGI_OK;
}

/* The indirection covers the occupied cells from a corner aligned to level-3 blocks. */
static vdbgi_result place_indirection(vdbgi_volume *v, const int32_t *cells, size_t cell_count,
                                      double spacing)
{
    vdbgi_volume_info *const info = &v->info;
    int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
    for (size_t c = 0; c < cell_count; c++)
        for (int k = 0; k < 3; k++) {
            lo[k] = cells[3 * c + k] < lo[k] ? cells[3 * c + k] : lo[k];
            hi[k] = cells[3 * c + k] > hi[k] ? cells[3 * c + k] : hi[k];
        }
    for (int k = 0; k < 3; k++) {
        v->origin_cell[k] = vdbgi_floor_div(lo[k], 8) * 8;
        const int64_t dim = (int64_t)hi[k] - v->origin_cell[k] + 1;
        VDBGI_FAIL_IF(v->ctx, dim > VDBGI_MAX_TEXTURE_DIM, VDBGI_ERR_OUT_OF_MEMORY,
                      "the indirection texture would be %lld cells along %c, above the "
                      "%d-texel limit of 3D textures: raise the probe spacing",
                      (long long)dim, "xyz"[k], VDBGI_MAX_TEXTURE_DIM);
        info->indirection_dims[k] = (uint32_t)dim;
        info->box_min[k] = (float)(v->lattice_origin[k] +
                                   spacing * ((double)v->origin_cell[k] * VDBGI_BRICK - 0.5));
        info->box_max[k] = (float)(info->box_min[k] + spacing * (double)dim * VDBGI_BRICK);
    }
    info->indirection_size = 4 * (size_t)info->indirection_dims[0] * info->indirection_dims[1] *
                             info->indirection_dims[2];
    return VDBGI_OK;
}

/*
 * The lift (docs/format.md): drop each level-0 brick that is the lowest of its
 * column and whose cell's filter reads valid probes only on its top face
 * (top_only, from the fill); the lookup reads the brick above it at its bottom
 * plane there. Done after coarsening, so that the coarse bricks and their tests
 * see every occupied cell as before, and a cell that a coarse brick covers, or
 * that has any brick below it, keeps what it has. The dropped cells leave cells.
 */
static vdbgi_result lift_bricks(vdbgi_context *ctx, vdbgi_brick *bricks, size_t *brick_count,
                                int32_t *cells, size_t *cell_count, const int32_t *top_only,
                                size_t top_count)
{
    if (top_count == 0)
        return VDBGI_OK;
    size_t bound = 0;
    for (size_t i = 0; i < *brick_count; i++)
        bound += (size_t)1 << (2 * bricks[i].level);
    vdbgi_map columns = {0}, tops = {0}, dropped = {0};
    int32_t *const lowest = vdbgi_calloc(ctx, bound ? bound : 1, sizeof(int32_t));
    vdbgi_result r = lowest ? vdbgi_map_init(ctx, &columns, bound + 64) : VDBGI_ERR_OUT_OF_MEMORY;
    if (r == VDBGI_OK)
        r = vdbgi_map_init(ctx, &tops, top_count + 64);
    if (r == VDBGI_OK)
        r = vdbgi_map_init(ctx, &dropped, 64);
    /* Each column's lowest cell under any brick. */
    for (size_t i = 0; i < *brick_count && r == VDBGI_OK; i++) {
        const int32_t span = 1 << bricks[i].level, *const key = bricks[i].key;
        for (int32_t dz = 0; dz < span && r == VDBGI_OK; dz++)
            for (int32_t dx = 0; dx < span && r == VDBGI_OK; dx++) {
                const int32_t column[3] = {key[0] * span + dx, 0, key[2] * span + dz};
                size_t c;
                bool added;
                r = vdbgi_map_insert(&columns, column, &c, &added);
                if (r == VDBGI_OK && (added || key[1] * span < lowest[c]))
                    lowest[c] = key[1] * span;
            }
    }
    for (size_t t = 0; t < top_count && r == VDBGI_OK; t++) {
        size_t i;
        r = vdbgi_map_insert(&tops, &top_only[3 * t], &i, NULL);
    }
    size_t kept = 0;
    for (size_t i = 0; i < *brick_count && r == VDBGI_OK; i++) {
        const int32_t *const key = bricks[i].key, column[3] = {key[0], 0, key[2]};
        if (bricks[i].level == 0 && vdbgi_map_find(&tops, key) >= 0 &&
            key[1] == lowest[vdbgi_map_find(&columns, column)]) {
            size_t d;
            r = vdbgi_map_insert(&dropped, key, &d, NULL);
            continue;
        }
        bricks[kept++] = bricks[i];
    }
    if (r == VDBGI_OK) {
        *brick_count = kept;
        size_t n = 0;
        for (size_t c = 0; c < *cell_count; c++)
            if (vdbgi_map_find(&dropped, &cells[3 * c]) < 0)
                memmove(&cells[3 * n++], &cells[3 * c], 3 * sizeof(int32_t));
        *cell_count = n;
    }
    vdbgi_map_free(&columns);
    vdbgi_map_free(&tops);
    vdbgi_map_free(&dropped);
    vdbgi_free(ctx, lowest);
    return r;
}

/*
 * Slot 0 is an all-zero brick: an empty cell (indirection 0,0,0,0) reads
 * black from it. The compact layout's textures come from its file, as a
 * reader rebuilds them.
 */
static vdbgi_result lay_out(vdbgi_volume *v, vdbgi_brick *bricks, size_t brick_count,
                            const vdbgi_probes *probes, int threads)
{
    vdbgi_volume_info *const info = &v->info;
    if (info->layout == VDBGI_LAYOUT_COMPACT) {
        uint8_t *payload = NULL;
        size_t size = 0;
        VDBGI_TRY(vdbgi_pack_write(v, bricks, brick_count, probes, threads, &payload, &size));
        v->payload = payload;
        v->payload_size = size;
        return VDBGI_OK;
    }
    VDBGI_TRY(vdbgi_atlas_dims(v->ctx, brick_count + 1, info->layout, info->atlas_dims));
    info->brick_count = (uint32_t)brick_count;
    info->atlas_size = 4 * (size_t)info->atlas_dims[0] * info->atlas_dims[1] * info->atlas_dims[2];
    VDBGI_TRY(vdbgi_textures_alloc(v->ctx, &v->tex, info->indirection_dims, info->atlas_dims));
    VDBGI_TRY(vdbgi_atlas_fill(v, bricks, brick_count, threads));
    for (size_t i = 0; i < brick_count; i++)
        info->bricks[bricks[i].level]++;
    return VDBGI_OK;
}

/* Log a step's time and report progress; VDBGI_ERR_CANCELLED if the caller asks to stop. */
static vdbgi_result step_done(vdbgi_context *ctx, const vdbgi_convert_desc *desc, float done,
                              double *t, const char *what)
{
    const double now = vdbgi_now();
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "%s in %.3f s (%.1f MiB held, at most %.1f MiB so far)", what,
              now - *t, (double)__atomic_load_n(&ctx->memory_held, __ATOMIC_RELAXED) / 1048576.0,
              (double)vdbgi_context_memory_peak(ctx) / 1048576.0);
    *t = now;
    VDBGI_FAIL_IF(ctx, report(desc, done), VDBGI_ERR_CANCELLED, "conversion cancelled");
    return VDBGI_OK;
}

/* What a conversion settled before it reads any value. */
typedef struct build_plan {
    vdbgi_coarsen_params cp;
    vdbgi_fill_params fp;
    bool terms; /* L2 terms go through with L0 */
} build_plan;

/*
 * desc resolved against probes like (a read of them: their settings) and
 * the lattice's statistics (checked by check_extent), and the volume started.
 */
static vdbgi_result build_start(vdbgi_context *ctx, const vdbgi_probes *like,
                                const lattice_stats *st, const vdbgi_convert_desc *desc,
                                build_plan *bp, vdbgi_volume **out)
{
    *out = NULL;
    memset(bp, 0, sizeof(*bp));
    vdbgi_coarsen_params *const cp = &bp->cp;
    float eps = 0.0f;
    vdbgi_encoding encoding = VDBGI_ENCODING_RGBM;
    VDBGI_TRY(resolve_desc(ctx, desc, &eps, &cp->sigmas, &cp->max_level, &cp->criterion, &encoding,
                           &cp->threads));
    /*
     * A fixed Fibonacci set gives every probe the same directions: its error is a bias
     * shared by neighbours, not noise, and its standard error is no measure of it. The
     * default allowance applies to random and adaptive bakes only.
     */
    if (like->sampling == VDBGI_SAMPLING_FIBONACCI && !like->adaptive &&
        (!desc || desc->noise_sigmas == 0.0f))
        cp->sigmas = 0.0f;
    VDBGI_FAIL_IF(ctx, !like->rgb, VDBGI_ERR_FORMAT, "probes have no values: bake them first");
    VDBGI_FAIL_IF(ctx, st->probes == 0, VDBGI_ERR_FORMAT, "the grid holds no probes");
    cp->layout =
        desc && desc->layout == VDBGI_LAYOUT_SEED ? VDBGI_LAYOUT_SEED : VDBGI_LAYOUT_COMPACT;
    bp->terms = like->sh && cp->layout == VDBGI_LAYOUT_COMPACT && !(desc && desc->scalar_only);
    VDBGI_FAIL_IF(ctx, !bp->terms && desc && desc->gi_version, VDBGI_ERR_INVALID_ARG,
                  ".gi version %d holds L2 terms, and this volume has none (the scalar basis, the "
                  "seed layout or probes baked without sh2)",
                  desc->gi_version);
    vdbgi_volume *const v = volume_start(ctx, like, st, encoding, cp->layout, cp->max_level);
    if (!v)
        return VDBGI_ERR_OUT_OF_MEMORY;
    v->version = !bp->terms                 ? 5
                 : desc && desc->gi_version ? (uint32_t)desc->gi_version
                                            : VDBGI_GI_VERSION;
    if (bp->terms) {
        v->info.basis = VDBGI_BASIS_SH2;
        v->info.term_bits = desc && desc->term_bits ? desc->term_bits : VDBGI_TERM_BITS;
    }
    cp->tolerance = eps * (float)v->info.mean_irradiance;
    memcpy(cp->fallback, v->mean_rgb, sizeof(cp->fallback));
    bp->fp = vdbgi_fill_params_default(like->invalid_threshold, desc ? desc->fill : VDBGI_FILL_AUTO,
                                       cp->threads);
    bp->fp.filter_below = cp->layout == VDBGI_LAYOUT_COMPACT ? 0 : 1; /* compact: no apron */
    bp->fp.lift = cp->layout == VDBGI_LAYOUT_COMPACT;
    *out = v;
    return VDBGI_OK;
}

/*
 * The probes p filled into *field, L2 terms with L0 as one field of nine
 * colours a point, with the cells the fill occupied (tree order) and those
 * it reads on their top face only; unreached counts the points of
 * bp->fp.core_z.
 */
static vdbgi_result fill_probes(vdbgi_context *ctx, const vdbgi_probes *p, const build_plan *bp,
                                vdbgi_field *field, int32_t **cells, size_t *cell_count,
                                int32_t **top_only, size_t *top_count, size_t *unreached)
{
    float *joined = NULL;
    if (bp->terms) {
        if (!(joined = vdbgi_alloc(ctx, 27 * sizeof(float) * (p->count ? p->count : 1))))
            return VDBGI_ERR_OUT_OF_MEMORY;
        for (size_t i = 0; i < p->count; i++) {
            memcpy(&joined[27 * i], &p->rgb[3 * i], 3 * sizeof(float));
            memcpy(&joined[27 * i + 3], &p->sh[24 * i], 24 * sizeof(float));
        }
    }
    const vdbgi_fill_input in = {.count = p->count,
                                 .ijk = p->ijk,
                                 .values = joined ? joined : p->rgb,
                                 .backface = p->backface,
                                 .channels = joined ? 9 : 1,
                                 .signed_terms = joined != NULL};
    const vdbgi_result r = vdbgi_field_fill(ctx, &in, &bp->fp, field, cells, cell_count, top_only,
                                            top_count, unreached);
    vdbgi_free(ctx, joined);
    return r;
}

/* The field's points with z0 <= z < z1. */
static size_t points_within(const vdbgi_field *f, int32_t z0, int32_t z1)
{
    size_t n = 0;
    for (size_t li = 0; li < f->leaf_count; li++)
        n += vdbgi_mask_count_z(f->leaves[li].mask, f->leaves[li].origin[2], z0, z1);
    return n;
}

vdbgi_result vdbgi_volume_build(vdbgi_context *ctx, const vdbgi_probes *probes,
                                const vdbgi_convert_desc *desc, vdbgi_volume **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_FAIL_IF(ctx, !probes, VDBGI_ERR_INVALID_ARG, "no probes given");
    VDBGI_FAIL_IF(ctx, !probes->rgb, VDBGI_ERR_FORMAT, "probes have no values: bake them first");
    const double t0 = vdbgi_now();
    double t = t0;
    lattice_stats st;
    error_sums e = {0};
    build_plan bp;
    vdbgi_volume *v = NULL;
    int32_t *cells = NULL, *top_only = NULL, z[2];
    size_t cell_count = 0, brick_count = 0, top_count = 0;
    vdbgi_brick *bricks = NULL;
    stats_init(&st);
    stats_add(&st, probes);
    valid_z(&st, z);
    vdbgi_result r = check_extent(ctx, &st);
    if (r == VDBGI_OK && (r = slab_sums_init(ctx, &st.colour, z, 3)) == VDBGI_OK) {
        stats_add_colours(&st, probes);
        r = build_start(ctx, probes, &st, desc, &bp, &v);
    }
    if (r != VDBGI_OK)
        goto fail;
    vdbgi_volume_info *const info = &v->info;
    if ((r = fill_probes(ctx, probes, &bp, &v->filled, &cells, &cell_count, &top_only, &top_count,
                         &info->unreached_count)) != VDBGI_OK)
        goto fail;
    info->filled_count = points_within(&v->filled, INT32_MIN, INT32_MAX);
    if ((r = step_done(ctx, desc, 0.3f, &t, "fill")) != VDBGI_OK ||
        (r = vdbgi_coarsen(ctx, &v->filled, probes, cells, cell_count, &bp.cp, &bricks,
                           &brick_count)) != VDBGI_OK ||
        (r = lift_bricks(ctx, bricks, &brick_count, cells, &cell_count, top_only, top_count)) !=
            VDBGI_OK ||
        (r = place_indirection(v, cells, cell_count, probes->spacing)) != VDBGI_OK ||
        (r = step_done(ctx, desc, 0.6f, &t, "pyramid and coarsening")) != VDBGI_OK ||
        (r = lay_out(v, bricks, brick_count, probes, bp.cp.threads)) != VDBGI_OK ||
        (r = step_done(ctx, desc, 0.8f, &t, "sampling and encoding")) != VDBGI_OK ||
        (r = error_sums_init(ctx, &e, z, info->valid_count)) != VDBGI_OK ||
        (r = measure_error(v, probes, bp.cp.threads, &e)) != VDBGI_OK)
        goto fail;
    error_figures(info, &e);
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "error measurement in %.3f s", vdbgi_now() - t);
    info->seconds = vdbgi_now() - t0;
    report(desc, 1.0f);
fail:
    vdbgi_free(ctx, st.colour.v);
    error_sums_free(ctx, &e);
    vdbgi_free(ctx, cells);
    vdbgi_free(ctx, top_only);
    vdbgi_free(ctx, bricks);
    if (r != VDBGI_OK) {
        vdbgi_volume_destroy(v);
        return r;
    }
    *out = v;
    return VDBGI_OK;
}

/* ---- region by region ------------------------------------------------------ */

/* Append n triples (or bricks) to a growing array: *items holds *count of *capacity. */
static vdbgi_result append(vdbgi_context *ctx, void **items, size_t *count, size_t *capacity,
                           const void *more, size_t n, size_t size)
{
    if (*count + n > *capacity) {
        size_t grown = *capacity ? 2 * *capacity : 1024;
        while (grown < *count + n)
            grown *= 2;
        void *const bigger = vdbgi_alloc(ctx, grown * size);
        if (!bigger)
            return VDBGI_ERR_OUT_OF_MEMORY;
        if (*count)
            memcpy(bigger, *items, *count * size);
        vdbgi_free(ctx, *items);
        *items = bigger, *capacity = grown;
    }
    if (n)
        memcpy((char *)*items + *count * size, more, n * size);
    *count += n;
    return VDBGI_OK;
}

/* Keep the cells (triples) whose points lie in z0 <= z < z1, in their order; returns how many. */
static size_t keep_cells(int32_t *cells, size_t count, int32_t z0, int32_t z1)
{
    size_t n = 0;
    for (size_t c = 0; c < count; c++) {
        const int32_t z = cells[3 * c + 2] * VDBGI_BRICK;
        if (z >= z0 && z < z1)
            memmove(&cells[3 * n++], &cells[3 * c], 3 * sizeof(int32_t));
    }
    return n;
}

/* The regions of a conversion, and what it keeps of the lattice between its passes. */
typedef struct regions {
    vdbgi_context *ctx;
    vdbgi_probe_file *file;
    const vdbgi_convert_desc *desc;
    int32_t first, end, size; /* regions first + k size, up to end */
    int halo;                 /* points read either side of a region for its fill */
    int pass;                 /* 0..3, for progress */
    vdbgi_brick *bricks;
    int32_t *cells;
    size_t brick_count, brick_capacity, cell_count, cell_capacity;
    size_t occupied; /* the cells the fills occupied, before the lift */
} regions;

/*
 * The points region z0 answers for: its own slab, and past the lattice's
 * first and last slabs whatever lies beyond (a cell's rim, a + border).
 */
static void region_core(const regions *rg, int32_t z0, int32_t core[2])
{
    core[0] = z0 == rg->first ? INT32_MIN : z0;
    core[1] = z0 + rg->size >= rg->end ? INT32_MAX : z0 + rg->size;
}

/* Region k's probes, with halo points either side; progress says how far the pass is. */
static vdbgi_result region_read(regions *rg, int32_t z0, int halo, vdbgi_probes **p)
{
    const float done = (float)(z0 - rg->first) / (float)(rg->end - rg->first);
    VDBGI_FAIL_IF(rg->ctx, report(rg->desc, 0.25f * ((float)rg->pass + done)), VDBGI_ERR_CANCELLED,
                  "conversion cancelled");
    return vdbgi_probe_file_read(rg->file, z0 - halo, z0 + rg->size + halo, p);
}

/*
 * Region z0 read with its halo into *p and, where it holds a valid probe,
 * filled with fp (else *field stays empty: every lookup misses).
 */
static vdbgi_result region_fill(regions *rg, int32_t z0, const build_plan *bp, vdbgi_probes **p,
                                vdbgi_field *field, int32_t **cells, size_t *cell_count,
                                int32_t **top_only, size_t *top_count, size_t *unreached)
{
    VDBGI_TRY(region_read(rg, z0, rg->halo, p));
    if ((*p)->invalid_count == (*p)->count)
        return VDBGI_OK;
    return fill_probes(rg->ctx, *p, bp, field, cells, cell_count, top_only, top_count, unreached);
}

/* Pass 1 for one region: its cells' bricks, coarsened and lifted, and its counts. */
static vdbgi_result region_bricks(regions *rg, vdbgi_volume *v, const build_plan *bp, int32_t z0)
{
    vdbgi_context *const ctx = rg->ctx;
    vdbgi_probes *p = NULL;
    vdbgi_field field = {0};
    int32_t *cells = NULL, *top_only = NULL;
    vdbgi_brick *bricks = NULL;
    size_t cell_count = 0, top_count = 0, brick_count = 0, unreached = 0;
    build_plan own = *bp;
    int32_t core[2];
    region_core(rg, z0, core);
    memcpy(own.fp.core_z, core, sizeof(core));
    vdbgi_result r = region_fill(rg, z0, &own, &p, &field, &cells, &cell_count, &top_only,
                                 &top_count, &unreached);
    if (r != VDBGI_OK || !field.leaf_count) /* no valid probe near: nothing to fill */
        goto done;
    v->info.unreached_count += unreached;
    v->info.filled_count += points_within(&field, core[0], core[1]);
    /*
     * The interpolation test of a block reads one point past its far faces where a
     * cell holds it: the coarsening sees the next region's first plane of cells too,
     * and the bricks it makes there are dropped (that region makes them again).
     */
    const int32_t next = core[1] == INT32_MAX ? INT32_MAX : core[1] + VDBGI_BRICK;
    cell_count = keep_cells(cells, cell_count, core[0], next);
    top_count = keep_cells(top_only, top_count, core[0], core[1]);
    for (size_t c = 0; c < cell_count; c++)
        rg->occupied += cells[3 * c + 2] * VDBGI_BRICK < core[1];
    if ((r = vdbgi_coarsen(ctx, &field, p, cells, cell_count, &bp->cp, &bricks, &brick_count)) !=
        VDBGI_OK)
        goto done;
    size_t kept = 0;
    for (size_t i = 0; i < brick_count; i++)
        if (bricks[i].key[2] * (VDBGI_BRICK << bricks[i].level) < core[1])
            bricks[kept++] = bricks[i];
    brick_count = kept;
    cell_count = keep_cells(cells, cell_count, core[0], core[1]);
    if ((r = lift_bricks(ctx, bricks, &brick_count, cells, &cell_count, top_only, top_count)) !=
            VDBGI_OK ||
        (r = append(ctx, (void **)&rg->bricks, &rg->brick_count, &rg->brick_capacity, bricks,
                    brick_count, sizeof(*bricks))) != VDBGI_OK)
        goto done;
    r = append(ctx, (void **)&rg->cells, &rg->cell_count, &rg->cell_capacity, cells, cell_count,
               3 * sizeof(int32_t));
done:
    vdbgi_free(ctx, cells);
    vdbgi_free(ctx, top_only);
    vdbgi_free(ctx, bricks);
    vdbgi_field_free(&field);
    vdbgi_probes_destroy(p);
    return r;
}

/* Pass 2 for one region: the stored points of its owner cells, from its field. */
static vdbgi_result region_values(regions *rg, vdbgi_pack_writer *w, const build_plan *bp,
                                  int32_t z0)
{
    vdbgi_context *const ctx = rg->ctx;
    vdbgi_probes *p = NULL;
    vdbgi_field field = {0};
    int32_t *cells = NULL, *top_only = NULL;
    size_t cell_count = 0, top_count = 0, unreached = 0;
    vdbgi_result r =
        region_fill(rg, z0, bp, &p, &field, &cells, &cell_count, &top_only, &top_count, &unreached);
    /* Points with no field near take their brick's mean, as in the whole conversion. */
    int32_t core[2];
    region_core(rg, z0, core);
    if (r == VDBGI_OK)
        vdbgi_pack_writer_values(w, &field, p, core[0], core[1]);
    vdbgi_free(ctx, cells);
    vdbgi_free(ctx, top_only);
    vdbgi_field_free(&field);
    vdbgi_probes_destroy(p);
    return r;
}

vdbgi_result vdbgi_volume_build_regions(vdbgi_context *ctx, vdbgi_probe_file *file,
                                        int32_t region_points, const vdbgi_convert_desc *desc,
                                        vdbgi_volume **out)
{
    return vdbgi_volume_build_regions_halo(ctx, file, region_points, VDBGI_REGION_HALO, desc, out);
}

vdbgi_result vdbgi_volume_build_regions_halo(vdbgi_context *ctx, vdbgi_probe_file *file,
                                             int32_t region_points, int halo,
                                             const vdbgi_convert_desc *desc, vdbgi_volume **out)
{
    VDBGI_FAIL_IF(ctx, !out, VDBGI_ERR_INVALID_ARG, "no output pointer given");
    *out = NULL;
    VDBGI_FAIL_IF(ctx, !file, VDBGI_ERR_INVALID_ARG, "no probe file given");
    VDBGI_FAIL_IF(ctx,
                  region_points < VDBGI_REGION_STEP || region_points % VDBGI_REGION_STEP != 0 ||
                      region_points > VDBGI_MAX_INDEX,
                  VDBGI_ERR_INVALID_ARG,
                  "a region is a multiple of %d lattice points thick, up to %d (got %d)",
                  VDBGI_REGION_STEP, VDBGI_MAX_INDEX, region_points);
    VDBGI_FAIL_IF(ctx, desc && desc->layout == VDBGI_LAYOUT_SEED, VDBGI_ERR_INVALID_ARG,
                  "a conversion region by region writes the compact layout only");
    const double t0 = vdbgi_now();
    double t = t0;
    int32_t lo[3], hi[3];
    vdbgi_probe_file_extent(file, lo, hi);
    /*
     * A lattice the indirection cannot hold is refused before a pass over its regions
     * (OpenVDB's clipped read also fills every empty tile its box cuts across x and y).
     * Unlike the whole conversion, invalid probes count: they are read.
     */
    const int64_t most = 4 * (VDBGI_MAX_TEXTURE_DIM + 16);
    for (int k = 0; k < 3; k++) {
        const int64_t span = (int64_t)hi[k] - lo[k] + 1;
        VDBGI_FAIL_IF(ctx, span > most, VDBGI_ERR_OUT_OF_MEMORY,
                      "the probes span %lld lattice points along %c, more than the %lld the "
                      "indirection texture's %d-texel limit holds: raise the probe spacing",
                      (long long)span, "xyz"[k], (long long)most, VDBGI_MAX_TEXTURE_DIM);
    }
    const int32_t z[2] = {lo[2], hi[2]};
    regions rg = {.ctx = ctx, .file = file, .desc = desc, .size = region_points, .halo = halo};
    rg.first = vdbgi_floor_div(z[0], VDBGI_REGION_STEP) * VDBGI_REGION_STEP;
    rg.end = z[1] + 1;
    lattice_stats st;
    error_sums e = {0};
    build_plan bp;
    vdbgi_volume *v = NULL;
    vdbgi_probes *like = NULL, *p = NULL;
    vdbgi_pack_writer *w = NULL;
    uint8_t *payload = NULL;
    size_t payload_size = 0;
    /* Pass 0: what the whole lattice's fill and coarsening need to know first. */
    stats_init(&st);
    vdbgi_result r = slab_sums_init(ctx, &st.colour, z, 3);
    for (int32_t z0 = rg.first; r == VDBGI_OK && z0 < rg.end; z0 += rg.size) {
        if ((r = region_read(&rg, z0, 0, &p)) != VDBGI_OK)
            break;
        stats_add(&st, p);
        stats_add_colours(&st, p); /* the guard above bounds the slabs */
        if (!like) {               /* the lattice's settings, from its first read */
            like = p;
            continue;
        }
        vdbgi_probes_destroy(p);
    }
    p = NULL;
    if (r != VDBGI_OK || (r = check_extent(ctx, &st)) != VDBGI_OK ||
        (r = build_start(ctx, like, &st, desc, &bp, &v)) != VDBGI_OK ||
        (r = step_done(ctx, desc, 0.25f, &t, "statistics")) != VDBGI_OK)
        goto fail;
    const double spacing = like->spacing;
    vdbgi_probes_destroy(like); /* a region's arrays: not to be held through the passes */
    like = NULL;
    /* Pass 1: bricks, region by region; then the indirection over all their cells. */
    rg.pass = 1;
    for (int32_t z0 = rg.first; r == VDBGI_OK && z0 < rg.end; z0 += rg.size)
        r = region_bricks(&rg, v, &bp, z0);
    /* The whole fill's refusal of a sparse lattice, over all the regions' cells. */
    if (r == VDBGI_OK)
        r = vdbgi_fill_check_sparse(ctx, st.valid, rg.occupied, VDBGI_BRICK, st.valid);
    if (r != VDBGI_OK || (r = place_indirection(v, rg.cells, rg.cell_count, spacing)) != VDBGI_OK ||
        (r = step_done(ctx, desc, 0.5f, &t, "fill, pyramid and coarsening")) != VDBGI_OK)
        goto fail;
    /* Pass 2: every stored point's value; then the payload and the textures, whole. */
    rg.pass = 2;
    if ((r = vdbgi_pack_writer_create(v, rg.bricks, rg.brick_count, bp.cp.threads, &w)) != VDBGI_OK)
        goto fail;
    for (int32_t z0 = rg.first; r == VDBGI_OK && z0 < rg.end; z0 += rg.size)
        r = region_values(&rg, w, &bp, z0);
    if (r != VDBGI_OK || (r = vdbgi_pack_writer_finish(w, &payload, &payload_size)) != VDBGI_OK)
        goto fail;
    v->payload = payload, v->payload_size = payload_size;
    if ((r = step_done(ctx, desc, 0.75f, &t, "sampling and encoding")) != VDBGI_OK ||
        (r = error_sums_init(ctx, &e, z, v->info.valid_count)) != VDBGI_OK)
        goto fail;
    /* Pass 3: the error figures. */
    rg.pass = 3;
    for (int32_t z0 = rg.first; r == VDBGI_OK && z0 < rg.end; z0 += rg.size) {
        if ((r = region_read(&rg, z0, 0, &p)) == VDBGI_OK)
            r = measure_error(v, p, bp.cp.threads, &e);
        vdbgi_probes_destroy(p);
        p = NULL;
    }
    if (r != VDBGI_OK)
        goto fail;
    error_figures(&v->info, &e);
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "error measurement in %.3f s", vdbgi_now() - t);
    v->info.seconds = vdbgi_now() - t0;
    report(desc, 1.0f);
fail:
    vdbgi_pack_writer_destroy(w);
    vdbgi_probes_destroy(like);
    vdbgi_free(ctx, st.colour.v);
    error_sums_free(ctx, &e);
    vdbgi_free(ctx, rg.cells);
    vdbgi_free(ctx, rg.bricks);
    if (r != VDBGI_OK) {
        vdbgi_volume_destroy(v);
        return r;
    }
    *out = v;
    return VDBGI_OK;
}

/* meshoptimizer's way: a NULL buffer asks the size, a short one gets nothing. */
static size_t copy_bytes(const void *src, size_t size, void *buffer, size_t capacity)
{
    if (!buffer)
        return size;
    if (capacity < size)
        return 0;
    memcpy(buffer, src, size);
    return size;
}

size_t vdbgi_volume_copy_indirection(const vdbgi_volume *v, void *buffer, size_t capacity)
{
    return copy_bytes(v->tex.indirection, v->info.indirection_size, buffer, capacity);
}

size_t vdbgi_volume_copy_atlas(const vdbgi_volume *v, void *buffer, size_t capacity)
{
    return copy_bytes(v->tex.atlas, v->info.atlas_size, buffer, capacity);
}
