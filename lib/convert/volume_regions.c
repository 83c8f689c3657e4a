/* volume_regions.c: a conversion region by region of z, to the whole conversion's bytes. */
#include "gifile.h"
#include "pack_write.h"
#include "util.h"
#include "volume_build.h"

#include <math.h>
#include <string.h>

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
    VDBGI_FAIL_IF(rg->ctx, vdbgi_build_report(rg->desc, 0.25f * ((float)rg->pass + done)),
                  VDBGI_ERR_CANCELLED, "conversion cancelled");
    return vdbgi_probe_file_read(rg->file, z0 - halo, z0 + rg->size + halo, p);
}

/*
 * Region z0 read with its halo into *p and, where it holds a valid probe,
 * filled with fp (else *field stays empty: every lookup misses).
 */
static vdbgi_result region_fill(regions *rg, int32_t z0, const vdbgi_build_plan *bp,
                                vdbgi_probes **p, vdbgi_field *field, int32_t **cells,
                                size_t *cell_count, int32_t **top_only, size_t *top_count,
                                size_t *unreached)
{
    VDBGI_TRY(region_read(rg, z0, rg->halo, p));
    if ((*p)->invalid_count == (*p)->count)
        return VDBGI_OK;
    return vdbgi_build_fill(rg->ctx, *p, bp, field, cells, cell_count, top_only, top_count,
                            unreached);
}

/* Pass 1 for one region: its cells' bricks, coarsened and lifted, and its counts. */
static vdbgi_result region_bricks(regions *rg, vdbgi_volume *v, const vdbgi_build_plan *bp,
                                  int32_t z0)
{
    vdbgi_context *const ctx = rg->ctx;
    vdbgi_probes *p = NULL;
    vdbgi_field field = {0};
    int32_t *cells = NULL, *top_only = NULL;
    vdbgi_brick *bricks = NULL;
    size_t cell_count = 0, top_count = 0, brick_count = 0, unreached = 0;
    vdbgi_build_plan own = *bp;
    int32_t core[2];
    region_core(rg, z0, core);
    memcpy(own.fp.core_z, core, sizeof(core));
    vdbgi_result r = region_fill(rg, z0, &own, &p, &field, &cells, &cell_count, &top_only,
                                 &top_count, &unreached);
    if (r != VDBGI_OK || !field.leaf_count) /* no valid probe near: nothing to fill */
        goto done;
    v->info.unreached_count += unreached;
    v->info.filled_count += vdbgi_build_points_within(&field, core[0], core[1]);
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
    if ((r = vdbgi_build_lift_bricks(ctx, bricks, &brick_count, cells, &cell_count, top_only,
                                     top_count)) != VDBGI_OK ||
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
static vdbgi_result region_values(regions *rg, vdbgi_pack_writer *w, const vdbgi_build_plan *bp,
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
    vdbgi_lattice_stats st;
    vdbgi_error_sums e = {0};
    vdbgi_build_plan bp;
    vdbgi_volume *v = NULL;
    vdbgi_probes *like = NULL, *p = NULL;
    vdbgi_pack_writer *w = NULL;
    uint8_t *payload = NULL;
    size_t payload_size = 0;
    /* Pass 0: what the whole lattice's fill and coarsening need to know first. */
    vdbgi_stats_init(&st);
    vdbgi_result r = vdbgi_slab_sums_init(ctx, &st.colour, z, VDBGI_COLOUR_SUMS);
    for (int32_t z0 = rg.first; r == VDBGI_OK && z0 < rg.end; z0 += rg.size) {
        if ((r = region_read(&rg, z0, 0, &p)) != VDBGI_OK)
            break;
        vdbgi_stats_add(&st, p);
        vdbgi_stats_add_colours(&st, p); /* the guard above bounds the slabs */
        if (!like) {                     /* the lattice's settings, from its first read */
            like = p;
            continue;
        }
        vdbgi_probes_destroy(p);
    }
    p = NULL;
    if (r != VDBGI_OK || (r = vdbgi_build_check_extent(ctx, &st)) != VDBGI_OK ||
        (r = vdbgi_build_start(ctx, like, &st, desc, &bp, &v)) != VDBGI_OK ||
        (r = vdbgi_build_step_done(ctx, desc, 0.25f, &t, "statistics")) != VDBGI_OK)
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
    if (r != VDBGI_OK ||
        (r = vdbgi_build_place_indirection(v, rg.cells, rg.cell_count, spacing)) != VDBGI_OK ||
        (r = vdbgi_build_step_done(ctx, desc, 0.5f, &t, "fill, pyramid and coarsening")) !=
            VDBGI_OK)
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
    if ((r = vdbgi_build_step_done(ctx, desc, 0.75f, &t, "sampling and encoding")) != VDBGI_OK ||
        (r = vdbgi_error_sums_init(ctx, &e, z, v->info.valid_count)) != VDBGI_OK)
        goto fail;
    /* Pass 3: the error figures. */
    rg.pass = 3;
    for (int32_t z0 = rg.first; r == VDBGI_OK && z0 < rg.end; z0 += rg.size) {
        if ((r = region_read(&rg, z0, 0, &p)) == VDBGI_OK)
            r = vdbgi_error_measure(v, p, bp.cp.threads, &e);
        vdbgi_probes_destroy(p);
        p = NULL;
    }
    if (r != VDBGI_OK)
        goto fail;
    vdbgi_error_figures(&v->info, &e);
    vdbgi_log(ctx, VDBGI_LOG_DEBUG, "error measurement in %.3f s", vdbgi_now() - t);
    if ((r = vdbgi_volume_seal(v)) != VDBGI_OK)
        goto fail;
    v->info.seconds = vdbgi_now() - t0;
    vdbgi_build_report(desc, 1.0f);
fail:
    vdbgi_pack_writer_destroy(w);
    vdbgi_probes_destroy(like);
    vdbgi_free(ctx, st.colour.v);
    vdbgi_error_sums_free(ctx, &e);
    vdbgi_free(ctx, rg.cells);
    vdbgi_free(ctx, rg.bricks);
    if (r != VDBGI_OK) {
        vdbgi_volume_destroy(v);
        return r;
    }
    *out = v;
    return VDBGI_OK;
}
