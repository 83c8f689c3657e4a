/*
 * volume.c: baked probes to seed 000's bricked volume, stage by stage (fill,
 * coarsen, a layout's textures), and the error of the result. The same by
 * regions is volume_regions.c's; the figures volume_stats.c's; its file
 * volume_io.c's.
 */
#include "atlas.h"
#include "gifile.h"
#include "pack_write.h"
#include "util.h"
#include "volume_build.h"

#include <math.h>
#include <string.h>

static vdbgi_result resolve_desc(vdbgi_context *ctx, const vdbgi_convert_desc *desc, float *eps,
                                 float *sigmas, int *max_level, vdbgi_criterion *criterion,
                                 vdbgi_encoding *encoding, int *threads)
{
    const vdbgi_convert_desc none = {0};
    if (!desc)
        desc = &none;
    *eps = desc->eps == 0.0f && !desc->eps_is_set ? 0.1f : desc->eps;
    VDBGI_FAIL_IF(ctx, !(*eps >= 0.0f) || !isfinite(*eps), VDBGI_ERR_INVALID_ARG,
                  "eps must be >= 0 and finite (got %g)", (double)desc->eps);
    *sigmas = desc->noise_sigmas == 0.0f && !desc->noise_sigmas_is_set ? 1.0f : desc->noise_sigmas;
    VDBGI_FAIL_IF(ctx, !(*sigmas >= 0.0f) || !isfinite(*sigmas), VDBGI_ERR_INVALID_ARG,
                  "noise allowance must be >= 0 standard errors (got %g)",
                  (double)desc->noise_sigmas);
    *max_level = desc->max_level == 0 && !desc->max_level_is_set ? 3 : desc->max_level;
    VDBGI_FAIL_IF(ctx, *max_level < 0 || *max_level > 3, VDBGI_ERR_INVALID_ARG,
                  "max level must be in 0..3 (got %d)", desc->max_level);
    VDBGI_FAIL_IF(ctx, desc->terms != VDBGI_TERMS_KEEP && desc->terms != VDBGI_TERMS_DROP,
                  VDBGI_ERR_INVALID_ARG, "unknown terms setting %d", (int)desc->terms);
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
    VDBGI_FAIL_IF(ctx, desc->gi_version != 0 && (desc->gi_version < 6 || desc->gi_version > 8),
                  VDBGI_ERR_INVALID_ARG,
                  "a volume with L2 terms is written as .gi version 6, 7 or 8 (got %d)",
                  desc->gi_version);
    *threads = desc->threads ? desc->threads : vdbgi_core_count();
    return VDBGI_OK;
}

void vdbgi_volume_destroy(vdbgi_volume *v)
{
    if (!v)
        return;
    vdbgi_context *const ctx = v->ctx;
    vdbgi_textures_free(ctx, &v->tex);
    vdbgi_free(ctx, v->payload);
    vdbgi_free(ctx, v->file);
    if (v->filled)
        vdbgi_field_free(v->filled);
    vdbgi_free(ctx, v->filled);
    vdbgi_free(ctx, v);
}

int vdbgi_build_report(const vdbgi_convert_desc *desc, float done)
{
    return desc && desc->progress ? desc->progress(desc->progress_user, done) : 0;
}

/* The volume's settings (like: a read of the probes, for their lattice), and the mean
   irradiance of the valid probes: the scale of eps and of the error figures. */
static vdbgi_volume *volume_start(vdbgi_context *ctx, const vdbgi_probes *like,
                                  const vdbgi_lattice_stats *st, vdbgi_encoding encoding,
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
    double sum[VDBGI_COLOUR_SUMS];
    vdbgi_slab_sums_total(&st->colour, sum);
    for (int k = 0; k < 3; k++)
        v->mean_rgb[k] = info->valid_count ? (float)(sum[k] / (double)info->valid_count) : 0.0f;
    info->mean_irradiance = (v->mean_rgb[0] + v->mean_rgb[1] + v->mean_rgb[2]) / 3.0;
    /* Version 8's cost, as a share of the mean reading (no terms, or no light: none). */
    const double readings = 3.0 * VDBGI_LUMA2_NORMALS * (double)info->valid_count;
    info->luma2_error = sum[4] > 0.0 ? sqrt(sum[3] * readings) / sum[4] : 0.0;
    /* A dense RGBA8 grid over the probes' box at the same spacing, for comparison. */
    info->dense_rgba8_size = 4;
    for (int k = 0; k < 3; k++)
        info->dense_rgba8_size *= (size_t)(st->hi[k] - st->lo[k] + 1);
    return v;
}

vdbgi_result vdbgi_build_check_extent(vdbgi_context *ctx, const vdbgi_lattice_stats *st)
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

vdbgi_result vdbgi_build_place_indirection(vdbgi_volume *v, const int32_t *cells, size_t cell_count,
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
        info->ind_dims[k] = (uint32_t)dim;
        info->box_min[k] = (float)(v->lattice_origin[k] +
                                   spacing * ((double)v->origin_cell[k] * VDBGI_BRICK - 0.5));
        info->box_max[k] = (float)(info->box_min[k] + spacing * (double)dim * VDBGI_BRICK);
    }
    info->indirection_size = 4 * (size_t)info->ind_dims[0] * info->ind_dims[1] * info->ind_dims[2];
    return VDBGI_OK;
}

vdbgi_result vdbgi_build_lift_bricks(vdbgi_context *ctx, vdbgi_brick *bricks, size_t *brick_count,
                                     int32_t *cells, size_t *cell_count, const int32_t *top_only,
                                     size_t top_count)
{
    if (top_count == 0)
        return VDBGI_OK;
    size_t bound = 0;
    for (size_t i = 0; i < *brick_count; i++)
        bound += (size_t)1 << (2 * bricks[i].level);
    vdbgi_map vdbgi_volume_columns = {0}, tops = {0}, dropped = {0};
    int32_t *const lowest = vdbgi_calloc(ctx, bound ? bound : 1, sizeof(int32_t));
    vdbgi_result r =
        lowest ? vdbgi_map_init(ctx, &vdbgi_volume_columns, bound + 64) : VDBGI_ERR_OUT_OF_MEMORY;
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
                r = vdbgi_map_insert(&vdbgi_volume_columns, column, &c, &added);
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
            key[1] == lowest[vdbgi_map_find(&vdbgi_volume_columns, column)]) {
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
    vdbgi_map_free(&vdbgi_volume_columns);
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
    VDBGI_TRY(vdbgi_textures_alloc(v->ctx, &v->tex, info->ind_dims, info->atlas_dims));
    VDBGI_TRY(vdbgi_atlas_fill(v, bricks, brick_count, threads));
    for (size_t i = 0; i < brick_count; i++)
        info->bricks[bricks[i].level]++;
    return VDBGI_OK;
}

vdbgi_result vdbgi_build_step_done(vdbgi_context *ctx, const vdbgi_convert_desc *desc, float done,
                                   double *t, const char *what)
{
    const double now = vdbgi_now();
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "%s in %.3f s (%.1f MiB held, at most %.1f MiB so far)", what,
              now - *t, (double)__atomic_load_n(&ctx->memory_held, __ATOMIC_RELAXED) / 1048576.0,
              (double)vdbgi_context_memory_peak(ctx) / 1048576.0);
    *t = now;
    VDBGI_FAIL_IF(ctx, vdbgi_build_report(desc, done), VDBGI_ERR_CANCELLED, "conversion cancelled");
    return VDBGI_OK;
}

vdbgi_result vdbgi_build_start(vdbgi_context *ctx, const vdbgi_probes *like,
                               const vdbgi_lattice_stats *st, const vdbgi_convert_desc *desc,
                               vdbgi_build_plan *bp, vdbgi_volume **out)
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
    bp->terms = like->sh && cp->layout == VDBGI_LAYOUT_COMPACT &&
                !(desc && desc->terms == VDBGI_TERMS_DROP);
    VDBGI_FAIL_IF(ctx, !bp->terms && desc && desc->gi_version, VDBGI_ERR_INVALID_ARG,
                  ".gi version %d holds L2 terms, and this volume has none (the scalar basis, the "
                  "seed layout or probes baked without sh2)",
                  desc->gi_version);
    vdbgi_volume *const v = volume_start(ctx, like, st, encoding, cp->layout, cp->max_level);
    if (!v)
        return VDBGI_ERR_OUT_OF_MEMORY;
    if (!bp->terms)
        v->info.luma2_error = 0.0; /* no terms to hold in any form */
    /* Terms 4-8 in luminance (version 8) where that moves a reading by little. */
    v->version = !bp->terms                                     ? 5
                 : desc && desc->gi_version                     ? (uint32_t)desc->gi_version
                 : v->info.luma2_error <= VDBGI_LUMA2_TOLERANCE ? 8
                                                                : 7;
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

vdbgi_result vdbgi_build_fill(vdbgi_context *ctx, const vdbgi_probes *p, const vdbgi_build_plan *bp,
                              vdbgi_field *field, int32_t **cells, size_t *cell_count,
                              int32_t **top_only, size_t *top_count, size_t *unreached)
{
    float *joined = NULL;
    if (bp->terms) {
        if (!(joined = vdbgi_alloc(ctx, 27 * sizeof(float) * (p->count ? p->count : 1))))
            return VDBGI_ERR_OUT_OF_MEMORY;
        for (size_t i = 0; i < p->count; i++) {
            memcpy(&joined[27 * i], &p->rgb[3 * i], 3 * sizeof(float));
            vdbgi_terms_decode(&p->sh[24 * i], &p->rgb[3 * i], &joined[27 * i + 3]);
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

size_t vdbgi_build_points_within(const vdbgi_field *f, int32_t z0, int32_t z1)
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
    vdbgi_lattice_stats st;
    vdbgi_error_sums e = {0};
    vdbgi_build_plan bp;
    vdbgi_volume *v = NULL;
    int32_t *cells = NULL, *top_only = NULL, z[2];
    size_t cell_count = 0, brick_count = 0, top_count = 0;
    vdbgi_brick *bricks = NULL;
    vdbgi_stats_init(&st);
    vdbgi_stats_add(&st, probes);
    vdbgi_stats_valid_z(&st, z);
    vdbgi_result r = vdbgi_build_check_extent(ctx, &st);
    if (r == VDBGI_OK &&
        (r = vdbgi_slab_sums_init(ctx, &st.colour, z, VDBGI_COLOUR_SUMS)) == VDBGI_OK) {
        vdbgi_stats_add_colours(&st, probes);
        r = vdbgi_build_start(ctx, probes, &st, desc, &bp, &v);
    }
    if (r != VDBGI_OK)
        goto fail;
    vdbgi_volume_info *const info = &v->info;
    if (!(v->filled = vdbgi_calloc(ctx, 1, sizeof(*v->filled)))) {
        r = VDBGI_ERR_OUT_OF_MEMORY;
        goto fail;
    }
    if ((r = vdbgi_build_fill(ctx, probes, &bp, v->filled, &cells, &cell_count, &top_only,
                              &top_count, &info->unreached_count)) != VDBGI_OK)
        goto fail;
    info->filled_count = vdbgi_build_points_within(v->filled, INT32_MIN, INT32_MAX);
    if ((r = vdbgi_build_step_done(ctx, desc, 0.3f, &t, "fill")) != VDBGI_OK ||
        (r = vdbgi_coarsen(ctx, v->filled, probes, cells, cell_count, &bp.cp, &bricks,
                           &brick_count)) != VDBGI_OK ||
        (r = vdbgi_build_lift_bricks(ctx, bricks, &brick_count, cells, &cell_count, top_only,
                                     top_count)) != VDBGI_OK ||
        (r = vdbgi_build_place_indirection(v, cells, cell_count, probes->spacing)) != VDBGI_OK ||
        (r = vdbgi_build_step_done(ctx, desc, 0.6f, &t, "pyramid and coarsening")) != VDBGI_OK ||
        (r = lay_out(v, bricks, brick_count, probes, bp.cp.threads)) != VDBGI_OK ||
        (r = vdbgi_build_step_done(ctx, desc, 0.8f, &t, "sampling and encoding")) != VDBGI_OK ||
        (r = vdbgi_error_sums_init(ctx, &e, z, info->valid_count)) != VDBGI_OK ||
        (r = vdbgi_error_measure(v, probes, bp.cp.threads, &e)) != VDBGI_OK)
        goto fail;
    vdbgi_error_figures(info, &e);
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "error measurement in %.3f s", vdbgi_now() - t);
    if ((r = vdbgi_volume_seal(v)) != VDBGI_OK)
        goto fail;
    info->seconds = vdbgi_now() - t0;
    vdbgi_build_report(desc, 1.0f);
fail:
    vdbgi_free(ctx, st.colour.v);
    vdbgi_error_sums_free(ctx, &e);
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
